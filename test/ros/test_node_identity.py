"""
The dpn node publishes the same bytes as its numpy twin on recorded scans.

Two nodes in one process, the node as it is and one with the numpy parts of
``numpy_node_parts`` swapped in, are fed the same odometry and scans (a hall with walking
boxes, the laser standing for ten scans at a time) by calling their callbacks, on a clock that
advances 0.1 s a scan. Every message each publishes is compared field by field, each float by
its bits (the serialized bytes themselves differ in their uninitialised padding): the map and
its updates, the plan, the markers, the commands, the pose in use and the status (less its
timings); and the hits the turn sweep keeps.
"""

from array import array

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from dpn_navigator.ros.conversions import make_laser_scan, pose_to_odometry, seconds_to_time
from dpn_navigator.ros.dpn_node import DpnNode
import numpy as np
from numpy.testing import assert_array_equal
from numpy_node_parts import numpy_node
import pytest
from rclpy.parameter import Parameter
from rclpy.publisher import Publisher
from scan_scenes import (ANGLE_INCREMENT, ANGLE_MIN, free_pose, hall, moving_box_world,
                         RANGE_MAX, RANGE_MIN, ray_cast)
from sim_stand_in import BARE_ROBOT

TIMING_KEYS = {'scan_to_map_ms_median'}


def walking_scenes(count, size=30.0, boxes=8):
    """Poses and ranges of ``count`` scans in a hall with walking boxes, ten at each pose."""
    rng = np.random.default_rng(3)
    static = hall(size, 30, rng)
    scenes = []
    for step in range(count):
        world = moving_box_world(static, step, 5, boxes=boxes)
        if step % 10 == 0:
            pose = free_pose(world, rng)
        scenes.append((pose, ray_cast(world, pose)))
    return scenes


def fields(value):
    """Return a message as nested tuples of its fields, floats as their bits (``float.hex``)."""
    if hasattr(value, 'get_fields_and_field_types'):
        return tuple((name, fields(getattr(value, name)))
                     for name in value.get_fields_and_field_types())
    if isinstance(value, array):
        return value.typecode, value.tobytes()
    if isinstance(value, np.ndarray):
        return value.dtype.str, value.tobytes()
    if isinstance(value, (list, tuple)):
        return tuple(fields(item) for item in value)
    if isinstance(value, float):
        return value.hex()
    return value


def comparable(msg):
    """Return what must be equal of a published message: all its fields, less clock and names."""
    if isinstance(msg, DiagnosticArray):          # stamped by the node's real clock
        msg = msg.status[0]
    if isinstance(msg, DiagnosticStatus):
        # Name and hardware id hold the node's namespace, which differs.
        return (msg.level, msg.message,
                [(kv.key, kv.value) for kv in msg.values if kv.key not in TIMING_KEYS])
    return fields(msg)


@pytest.fixture
def published(monkeypatch):
    """Record every message published in the test, with the publisher that sent it."""
    record = []
    original = Publisher.publish

    def publish(self, msg):
        record.append((self, msg.__class__.__name__, comparable(msg)))
        return original(self, msg)

    monkeypatch.setattr(Publisher, 'publish', publish)
    return record


@pytest.mark.parametrize('resolution, mobile_value, map_period', [
    (0.05, 99, 1.0),        # 600 x 600 cells, full maps every 10 scans, updates between
    (0.5, 100, 0.3),        # 60 x 60; mobile and steady cells share a value
])
def test_node_publishes_the_bytes_of_its_numpy_twin(ros_context, published, resolution,
                                                    mobile_value, map_period):
    overrides = [BARE_ROBOT,
                 Parameter('map_width', value=30.0), Parameter('map_height', value=30.0),
                 Parameter('resolution', value=resolution),
                 Parameter('use_default_goal', value=True),
                 Parameter('goal_x', value=27.0), Parameter('goal_y', value=3.0),
                 Parameter('map_publish_period', value=map_period),
                 Parameter('map_mobile_value', value=mobile_value),
                 # The hall fills the map: a growing map would swap the twin's map buffer.
                 Parameter('map_growth_step', value=0.0)]
    nodes = [DpnNode(context=ros_context, namespace=name, parameter_overrides=overrides)
             for name in ('fast', 'twin')]
    numpy_node(nodes[1])
    clock = [100.0]
    for node in nodes:
        node.now_seconds = node.stop_guard.clock_seconds = lambda: clock[0]
        # The stop guard's thread would add zero commands at moments of its own: what is
        # compared here is what the callbacks publish (the guard has tests of its own).
        node.stop_guard.close()
    published.clear()           # and what it sent before it was closed
    try:
        for pose, ranges in walking_scenes(80):
            clock[0] += 0.1
            stamp = seconds_to_time(clock[0])
            for node in nodes:
                node.on_odom(pose_to_odometry(pose, (0.0, 0.0), stamp))
                node.on_scan(make_laser_scan(ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN,
                                             RANGE_MAX, stamp))
            # What the turn sweep holds after a scan (these scenes seldom make it intervene).
            assert_array_equal(*(node.navigator.turn_sweep.kept for node in nodes))
        sent = [[(kind, data) for publisher, kind, data in published
                 if publisher in list(node.publishers) and kind != 'ParameterEvent']
                for node in nodes]
        assert nodes[0].navigator.replans > 3
    finally:
        for node in nodes:
            node.destroy_node()
    kinds = [kind for kind, _ in sent[0]]
    for kind, least in (('OccupancyGrid', 3), ('OccupancyGridUpdate', 10), ('Path', 3),
                        ('MarkerArray', 3), ('Twist', 80), ('Odometry', 80)):
        assert kinds.count(kind) >= least, kind
    assert [kind for kind, _ in sent[1]] == kinds
    for index, ((kind, fast), (_, twin)) in enumerate(zip(*sent)):
        assert fast == twin, f'message {index} ({kind}) differs'
