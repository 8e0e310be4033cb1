"""Tests of the drive guard: a forward drive whose arc would bring the robot's box onto a hit."""

import math

from dpn_navigator.benchmark.protocol import NAVIGATORS
from dpn_navigator.core import Navigator, NavigatorConfig
from dpn_navigator.core.control.drive_guard import arc_hits, arc_poses, DriveGuard
from dpn_navigator.core.control.path_follower import STOP, VelocityCommand
import numpy as np
from numpy.testing import assert_allclose
import pytest

LENGTH, WIDTH, MARGIN = 0.99, 0.67, 0.05


def test_arc_poses_follow_a_straight_line_and_a_circle():
    straight = arc_poses(0.0, 0.3)
    assert_allclose(straight[-1], [0.3, 0.0, 0.0])
    assert np.all(np.diff(straight[:, 0]) > 0.0) and straight.shape == (6, 3)
    radius = 2.0
    quarter = arc_poses(1.0 / radius, math.pi * radius / 2)
    assert_allclose(quarter[-1], [radius, radius, math.pi / 2], atol=1e-12)
    right = arc_poses(-1.0 / radius, math.pi * radius / 2)
    assert_allclose(right[-1], [radius, -radius, -math.pi / 2], atol=1e-12)
    # Every pose lies on the circle about (0, radius).
    assert_allclose(np.hypot(quarter[:, 0], quarter[:, 1] - radius), radius)


@pytest.mark.parametrize('point, curvature, hit', [
    ((0.8, 0.0), 0.0, True),           # ahead, within 0.3 m of the widened front
    ((0.9, 0.0), 0.0, False),          # ahead, beyond it
    ((0.6, 0.45), 0.0, False),         # beside the straight way
    ((0.6, 0.45), 2.0, True),          # ... but on the way of a left curve
    ((0.6, -0.45), 2.0, False),        # a left curve leaves the right side
    ((0.6, -0.45), -2.0, True),        # a right one does not
    ((-0.7, 0.0), 0.0, False),         # behind
    ((0.1, 0.1), 0.0, False),          # inside the box: its own body, not counted
])
def test_arc_hits_what_the_box_meets_along_the_arc(point, curvature, hit):
    assert arc_hits(np.array([point]), curvature, 0.3, LENGTH, WIDTH, MARGIN) is hit


def test_a_point_within_the_margin_beside_counts_only_when_the_box_itself_reaches_it():
    beside = np.array([[0.0, 0.36]])          # within the widened side, outside the box
    assert not arc_hits(beside, 0.0, 0.3, LENGTH, WIDTH, MARGIN)     # driving along it
    assert arc_hits(beside, 4.0, 0.3, LENGTH, WIDTH, MARGIN)         # curving into it
    assert not arc_hits(np.empty((0, 2)), 0.0, 0.3, LENGTH, WIDTH, MARGIN)


def test_a_clear_command_and_a_turn_in_place_pass_unchanged():
    guard = DriveGuard(0.3, LENGTH, WIDTH, MARGIN)
    wall_far = np.array([[3.0, y] for y in np.linspace(-2.0, 2.0, 41)])
    command = VelocityCommand(1.0, 0.2)
    assert guard.check(command, wall_far) is command
    turn = VelocityCommand(0.0, 1.0, turn=0.5)
    assert guard.check(turn, np.array([[0.6, 0.0]])) is turn
    assert (guard.steered, guard.turned, guard.stopped) == (0, 0, 0)


def test_a_blocked_arc_is_replaced_by_the_nearest_clear_one_at_the_guard_speed():
    guard = DriveGuard(0.3, LENGTH, WIDTH, MARGIN, speed=0.2)
    # A body ahead and to the right: straight on meets it; a left curve clears it.
    body = np.array([[0.75, y] for y in np.linspace(-0.6, -0.1, 11)])
    out = guard.check(VelocityCommand(0.8, 0.0), body)
    assert out.linear == pytest.approx(0.2) and out.angular > 0.0
    assert not arc_hits(body, out.angular / out.linear, 0.3, LENGTH, WIDTH, MARGIN)
    # The nearest clear curvature: the next one towards straight is blocked.
    step = 4.0 / 16
    assert arc_hits(body, out.angular / out.linear - step, 0.3, LENGTH, WIDTH, MARGIN)
    assert guard.steered == 1


def test_with_no_clear_arc_the_robot_turns_the_commands_way_or_stops():
    guard = DriveGuard(0.3, LENGTH, WIDTH, MARGIN)
    front = np.array([[0.65, y] for y in np.linspace(-1.0, 1.0, 41)])   # a wall across
    out = guard.check(VelocityCommand(0.5, -0.3), front)
    assert out.linear == 0.0 and out.angular < 0.0 and out.turn < 0.0
    assert guard.turned == 1
    # Boxed in on every side: no turn either.
    ring = np.array([[0.62 * math.cos(a), 0.62 * math.sin(a)]
                     for a in np.linspace(0.0, 2.0 * math.pi, 90, endpoint=False)])
    assert guard.check(VelocityCommand(0.5, 0.3), ring) == STOP
    assert guard.check(VelocityCommand(0.5, 0.0), front) == STOP     # no way to turn
    assert guard.stopped == 2
    guard.reset()
    assert (guard.steered, guard.turned, guard.stopped) == (0, 0, 0)


@pytest.mark.parametrize('kwargs', [
    {'distance': 0.0}, {'distance': math.nan}, {'length': -1.0}, {'width': math.inf},
    {'margin': -0.1}, {'speed': 0.0}, {'max_angular_speed': 0.0},
])
def test_bad_drive_guard_parameters_raise(kwargs):
    arguments = {'distance': 0.3, 'length': LENGTH, 'width': WIDTH, **kwargs}
    with pytest.raises(ValueError):
        DriveGuard(**arguments)


def body_in_robot_frame(x, y, yaw, centre, radius, count=72):
    """Return the outline of a round body as points in the frame of a robot at (x, y, yaw)."""
    angles = np.linspace(0.0, 2.0 * math.pi, count, endpoint=False)
    dx = centre[0] + radius * np.cos(angles) - x
    dy = centre[1] + radius * np.sin(angles) - y
    return np.column_stack((math.cos(yaw) * dx + math.sin(yaw) * dy,
                            -math.sin(yaw) * dx + math.cos(yaw) * dy))


def drive_past_a_standing_body(guard, seconds=3.0, dt=0.1):
    """
    Drive a robot along a left curve that passes too close to a body standing ahead-right.

    The geometry of held-out seed 1, narrow_passages, task 1, 2 wanderers: a P3-AT (here a
    0.28 m disc) 0.95 m from the robot's centre, 0.86 m ahead and 0.41 m to the right; the
    follower asked for 0.5 m/s curving left at 0.7 rad/s, and the front corner struck it.
    Returns whether the box ever touched the body, and the end pose.
    """
    centre, radius = (0.857, -0.411), 0.28
    x = y = yaw = 0.0
    touched = False
    for _ in range(int(round(seconds / dt))):
        command = VelocityCommand(0.5, 0.7)
        if guard is not None:
            command = guard.check(command, body_in_robot_frame(x, y, yaw, centre, radius))
        for _ in range(10):                                 # 10 ms integration steps
            x += command.linear * math.cos(yaw) * dt / 10
            y += command.linear * math.sin(yaw) * dt / 10
            yaw += command.angular * dt / 10
            outline = body_in_robot_frame(x, y, yaw, centre, radius)
            touched |= bool(((np.abs(outline[:, 0]) <= LENGTH / 2)
                             & (np.abs(outline[:, 1]) <= WIDTH / 2)).any())
    return touched, (x, y, yaw)


def test_the_held_out_contact_is_made_without_the_guard_and_avoided_with_it():
    touched, _ = drive_past_a_standing_body(None)
    assert touched
    guard = DriveGuard(0.3, LENGTH, WIDTH, MARGIN, max_angular_speed=1.5)
    touched, end = drive_past_a_standing_body(guard)
    assert not touched
    assert guard.turned > 0 and guard.steered > 0 and guard.stopped == 0
    assert math.hypot(end[0], end[1]) > 0.4                 # it got on, past the body


def test_the_navigator_builds_the_guard_by_default_and_not_in_paper():
    navigator = Navigator(NavigatorConfig(width=12.0, height=12.0))
    assert navigator.drive_guard is not None
    assert navigator.turn_sweep.reach >= navigator.drive_guard.reach
    for options in ({'drive_guard_distance': 0.0}, {'turn_sweep_memory': 0.0},
                    NAVIGATORS['paper']):
        assert Navigator(NavigatorConfig(width=12.0, height=12.0,
                                         **options)).drive_guard is None
    with pytest.raises(ValueError, match='drive_guard_distance'):
        NavigatorConfig(width=12.0, height=12.0, drive_guard_distance=-0.1)


def test_the_kept_hits_within_the_guards_reach_are_those_it_would_count():
    from dpn_navigator.core.control.turn_sweep import TurnSweep
    sweep = TurnSweep(2.0, LENGTH, WIDTH, MARGIN)
    rng = np.random.default_rng(3)
    hits = rng.uniform(-2.0, 2.0, size=(400, 2))
    sweep.add_scan(0.0, (0.0, 0.0), hits)
    pose = (0.2, -0.1, 0.7)
    every = sweep.points(pose)
    near = sweep.points(pose, within=1.0)
    assert 0 < near.shape[0] < every.shape[0]
    assert_allclose(near, every[np.hypot(every[:, 0], every[:, 1]) <= 1.0])
