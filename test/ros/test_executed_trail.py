"""The dpn node's executed path: the same markers as a list trail, memory allocated once."""

import math
import tracemalloc

from builtin_interfaces.msg import Time
from dpn_navigator.ros.navigator_markers import (ExecutedTrail, extend_trail, navigator_markers,
                                                 NavigatorMarkers, TRAIL_STEP)
import numpy as np
import pytest


def drive(rng, steps, start=(5.0, 5.0)):
    """Yield positions [m] of a random walk: most steps past TRAIL_STEP, some short of it."""
    xy = np.array(start)
    for _ in range(steps):
        xy = xy + rng.normal(0.0, 1.5 * TRAIL_STEP, 2)
        yield (float(xy[0]), float(xy[1]))


def test_executed_trail_keeps_what_a_list_trail_keeps_and_its_markers_are_equal():
    # Against extend_trail on a list with the same bound: the same points in the same order,
    # through resets and a full trail that drops its oldest points; the node's markers equal
    # navigator_markers built from the list on every step.
    rng = np.random.default_rng(7)
    capacity = 40
    trail, reference = ExecutedTrail(capacity), []
    cached = NavigatorMarkers('map', min_period=0.0)
    path, goal = None, (3.0, 4.0)
    for step, xy in enumerate(drive(rng, 400)):
        if step in (0, 150, 151, 300):                   # a new goal starts it over
            start = xy if step != 150 else None
            trail.reset(start)
            reference.clear()
            if start is not None:
                extend_trail(reference, start, capacity)
        if step % 23 == 5:
            path = rng.uniform(0.0, 10.0, (int(rng.integers(0, 12)), 2))
        due = not reference or math.dist(reference[-1], xy) >= TRAIL_STEP
        assert trail.extend(xy) == due
        extend_trail(reference, xy, capacity)
        assert list(trail) == reference
        assert len(trail) <= capacity
        stamp = Time(sec=step, nanosec=3)
        got = cached.messages(path, trail, goal, stamp, float(step))
        want = navigator_markers(path, reference, goal, stamp)
        assert got == want
    assert len(reference) == capacity                   # the bound was reached


def test_executed_trail_rejects_a_capacity_below_two():
    with pytest.raises(ValueError, match='at least 2 points'):
        ExecutedTrail(1)


def traced_growth(extend, reset, messages, rng, steps):
    """Return the bytes still allocated after ``steps`` positions, resets and markers."""
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        for step, xy in enumerate(drive(rng, steps)):
            if step % 2500 == 2499:
                reset()
            extend(xy)
            if step % 5 == 0:
                messages(step)
        return tracemalloc.get_traced_memory()[0] - before
    finally:
        tracemalloc.stop()


def test_executed_trail_memory_stays_flat_while_driving():
    # 6,000 positions, the trail full twice and started over twice, the markers built every
    # fifth: what stays allocated is the lists' own arrays of pointers, not the ~110 B a point
    # of a list of tuples (the marker's points being reused).
    capacity = 2000
    goal = (1.0, 1.0)

    trail = ExecutedTrail(capacity)
    markers = NavigatorMarkers('map')
    flat = traced_growth(trail.extend, trail.reset,
                         lambda step: markers.messages(None, trail, goal, Time(sec=step),
                                                       float(step)),
                         np.random.default_rng(1), 6000)

    # The measure sees the growth it is meant to catch: the list trail the node had.
    reference = []
    reference_markers = NavigatorMarkers('map')
    grown = traced_growth(lambda xy: extend_trail(reference, xy, capacity), reference.clear,
                          lambda step: reference_markers.messages(None, reference, goal,
                                                                  Time(sec=step), float(step)),
                          np.random.default_rng(1), 6000)
    # About 110 B a point kept alone, 56 B after the rest of the suite (allocators' free
    # lists warm): the measure still sees it.
    assert grown > 40 * capacity, grown
    # The points list and the spares' list: 8 B a point each at most, over-allocation aside.
    assert flat < 24 * capacity and flat < grown / 2, (flat, grown)


def test_the_node_drives_its_trail_with_the_points_it_made_at_start(ros_context):
    # The dpn node fed 3,000 odometry poses at 50 Hz (a goal set: the trail grows), a
    # new goal half way: the trail holds the newest points, every one of them made at start,
    # and what stays allocated is a small fraction of the ~110 B a point a list trail kept.
    from dpn_navigator.ros.conversions import pose_to_odometry
    from dpn_navigator.ros.dpn_node import DpnNode
    from rclpy.parameter import Parameter
    overrides = [Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
                 Parameter('use_default_goal', value=True), Parameter('goal_x', value=10.0),
                 Parameter('goal_y', value=6.0), Parameter('pose_source', value='odom')]
    dpn = DpnNode(context=ros_context, parameter_overrides=overrides)
    try:
        assert isinstance(dpn.trail, ExecutedTrail)
        made = {id(point) for point in dpn.trail._spare + dpn.trail.points}
        poses = [(1.0 + 0.06 * (k % 150), 1.0 + 0.06 * (k // 150), 0.0) for k in range(3000)]
        messages = [pose_to_odometry(pose, (0.3, 0.0), Time(sec=k // 50,
                                                            nanosec=20_000_000 * (k % 50)),
                                     frame_id='odom')
                    for k, pose in enumerate(poses)]
        tracemalloc.start()
        try:
            for k, msg in enumerate(messages[:1500]):
                dpn.on_odom(msg)
            before = tracemalloc.get_traced_memory()[0]
            dpn.set_goal(9.0, 6.0, via='test')             # starts the trail over
            for msg in messages[1500:]:
                dpn.on_odom(msg)
            grown = tracemalloc.get_traced_memory()[0] - before
        finally:
            tracemalloc.stop()
        assert len(dpn.trail) > 1400
        assert dpn.trail[-1] == poses[-1][:2]
        assert {id(point) for point in dpn.trail._spare + dpn.trail.points} == made
        assert grown < 40 * len(dpn.trail), grown
    finally:
        dpn.destroy_node()
