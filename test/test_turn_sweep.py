"""Tests of the turn sweep: turns in place that would swing the robot's corners into a hit."""

import math

from dpn_navigator.core import Navigator, NavigatorConfig
from dpn_navigator.core.path_follower import STOP, VelocityCommand
from dpn_navigator.core.turn_sweep import advance_hits, sweep_hits, TurnSweep
import numpy as np
import pytest
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN, ray_cast
from test_navigator import add_box, walled_room

LENGTH, WIDTH, MARGIN = 0.99, 0.67, 0.05
TRUTH_RES = 0.05
RANGE_MAX = 10.0
DT = 0.1


def box_touches(x, y, yaw, occupied):
    """Tell whether the robot's box at ``(x, y, yaw)`` covers an occupied truth cell's centre."""
    rows, cols = np.nonzero(occupied)
    px, py = (cols + 0.5) * TRUTH_RES - x, (rows + 0.5) * TRUTH_RES - y
    forward = math.cos(yaw) * px + math.sin(yaw) * py
    left = -math.sin(yaw) * px + math.cos(yaw) * py
    return bool(((np.abs(forward) <= LENGTH / 2) & (np.abs(left) <= WIDTH / 2)).any())


@pytest.mark.parametrize('point, angle, hit', [
    ((0.0, 0.55), math.pi / 2, True),     # beside, inside the corners' circle: a corner hits
    ((0.0, 0.55), 0.1, False),            # a small turn does not reach it yet
    ((1.0, 0.0), 2 * math.pi, False),     # beyond the circle: never
    ((0.56, 0.0), 0.5, True),             # just ahead: the front corners reach it
    ((0.56, 0.0), -0.5, True),
    ((0.0, 0.36), 0.5, True),             # within the margin beside: the side itself reaches it
    ((0.0, 0.36), 0.3, False),            # ... only after about 0.37 rad
])
def test_sweep_hits_points_the_turning_box_reaches(point, angle, hit):
    assert sweep_hits(np.array([point]), angle, LENGTH, WIDTH, MARGIN) is hit


def test_sweep_ignores_points_inside_the_box_and_zero_turns():
    assert not sweep_hits(np.array([[0.1, 0.1]]), 1.0, LENGTH, WIDTH, MARGIN)
    assert not sweep_hits(np.array([[0.0, 0.55]]), 0.0, LENGTH, WIDTH, MARGIN)
    assert not sweep_hits(np.empty((0, 2)), 1.0, LENGTH, WIDTH, MARGIN)


def test_advance_hits_only_what_lies_ahead_within_the_distance():
    assert advance_hits(np.array([[0.7, 0.2]]), 0.3, LENGTH, WIDTH, MARGIN)
    assert not advance_hits(np.array([[0.9, 0.2]]), 0.3, LENGTH, WIDTH, MARGIN)   # too far
    assert not advance_hits(np.array([[0.7, 0.5]]), 0.3, LENGTH, WIDTH, MARGIN)   # beside
    assert not advance_hits(np.array([[-0.7, 0.0]]), 0.3, LENGTH, WIDTH, MARGIN)  # behind


def test_turn_sweep_creeps_waits_or_lets_the_turn_through():
    sweep = TurnSweep(2.0, LENGTH, WIDTH, MARGIN)
    turn = VelocityCommand(0.0, -1.5, turn=-1.2)
    sweep.add_scan(0.0, (0.0, 0.0), np.array([[0.0, 0.55]]))       # beside, left
    assert sweep.check(turn, (0.0, 0.0, 0.0)) == VelocityCommand(sweep.creep_speed, 0.0)
    assert sweep.check(VelocityCommand(0.5, 0.3), (0.0, 0.0, 0.0)) == VelocityCommand(0.5, 0.3)
    sweep.add_scan(0.5, (0.0, 0.0), np.array([[0.7, 0.0]]))        # and ahead
    assert sweep.check(turn, (0.0, 0.0, 0.0)) is STOP
    assert (sweep.creeps, sweep.waits) == (1, 1)
    # Seen from a pose turned by 90 degrees, the hits are ahead-right and ahead-left-far.
    assert sweep.check(turn, (5.0, 5.0, 0.0)) == turn                # far away: turn


def test_kept_hits_expire_and_a_clock_restart_keeps_only_the_new_scan():
    sweep = TurnSweep(2.0, LENGTH, WIDTH, MARGIN)
    turn = VelocityCommand(0.0, 1.5, turn=1.0)
    sweep.add_scan(10.0, (0.0, 0.0), np.array([[0.0, 0.55]]))
    sweep.add_scan(11.5, (0.0, 0.0), np.empty((0, 2)))
    assert sweep.check(turn, (0.0, 0.0, 0.0)) != turn               # kept 1.5 s
    sweep.add_scan(12.5, (0.0, 0.0), np.empty((0, 2)))
    assert sweep.check(turn, (0.0, 0.0, 0.0)) == turn               # gone after 2 s
    sweep.add_scan(20.0, (0.0, 0.0), np.array([[0.0, 0.55]]))
    sweep.add_scan(1.0, (0.0, 0.0), np.empty((0, 2)))               # time went back
    assert sweep.check(turn, (0.0, 0.0, 0.0)) == turn


@pytest.mark.parametrize('kwargs', [{'memory': 0.0}, {'length': -1.0}, {'margin': -0.1},
                                    {'creep_speed': math.inf}])
def test_bad_turn_sweep_parameters_raise(kwargs):
    values = {'memory': 2.0, 'length': LENGTH, 'width': WIDTH, 'margin': MARGIN}
    values.update(kwargs)
    with pytest.raises(ValueError):
        TurnSweep(**values)


def parked_beside():
    """
    Place a robot facing north at (6, 6), an object parked left of it, a goal 4 m east.

    The robot must turn right by 90 degrees; its rear-left corner swings into the object
    (a 0.5 m box whose centre is 0.75 m left of the robot's and 0.1 m behind, as a P3-AT
    stopped beside the Husky in the benchmark's u_turn episode).
    """
    occupied = walled_room()
    add_box(occupied, 6.0 - 0.75 - 0.25, 5.9 - 0.25, 6.0 - 0.75 + 0.25, 5.9 + 0.25)
    return occupied, (6.0, 6.0, math.pi / 2), (10.0, 6.0)


def drive_with_contacts(sweep_memory, steps=200):
    occupied, pose, goal = parked_beside()
    navigator = Navigator(NavigatorConfig(width=12.0, height=12.0,
                                          turn_sweep_memory=sweep_memory))
    navigator.set_goal(*goal)
    x, y, yaw = pose
    touched = False
    for step in range(steps):
        ranges = ray_cast(occupied, (x, y, yaw), TRUTH_RES, RANGE_MAX)
        out = navigator.step(step * DT, (x, y, yaw), ranges, ANGLE_MIN, ANGLE_INCREMENT,
                             RANGE_MIN, RANGE_MAX)
        if out.command.goal_reached or out.status.name == 'GOAL_REACHED':
            break
        v, w = out.command.linear, out.command.angular
        x, y, yaw = x + v * math.cos(yaw) * DT, y + v * math.sin(yaw) * DT, yaw + w * DT
        touched |= box_touches(x, y, yaw, occupied)
    return navigator, touched


def test_without_the_sweep_the_turn_in_place_hits_the_parked_object():
    navigator, touched = drive_with_contacts(0.0)
    assert touched
    assert navigator.turn_sweep is None


def test_with_the_sweep_the_robot_creeps_clear_turns_and_arrives_untouched():
    navigator, touched = drive_with_contacts(2.0)
    assert not touched
    assert navigator.status.name == 'GOAL_REACHED'
    assert navigator.turn_sweep.creeps > 0
