"""Tests of the turn sweep: turns in place that would swing the robot's corners into a hit."""

import math

from dpn_navigator.core import Navigator, NavigatorConfig
from dpn_navigator.core.control.path_follower import STOP, VelocityCommand
from dpn_navigator.core.control.turn_sweep import (advance_hits, find_turn_place, seen_through,
                                                   sweep_hits, TurnSweep)
from dpn_navigator.core.pose2d import wrap_angle
from dpn_navigator.core.scan_polygon import scan_points
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


def test_turn_sweep_moves_to_a_turn_place_waits_or_lets_the_turn_through():
    sweep = TurnSweep(2.0, LENGTH, WIDTH, MARGIN)
    turn = VelocityCommand(0.0, -1.5, turn=-1.2)
    sweep.add_scan(0.0, (0.0, 0.0), np.array([[0.0, 0.55]]))       # beside, left
    step = sweep.check(turn, (0.0, 0.0, 0.0))
    assert step != turn and step != STOP and sweep.spots == 1       # on to a turn place
    assert sweep.check(VelocityCommand(0.5, 0.3), (0.0, 0.0, 0.0)) == VelocityCommand(0.5, 0.3)
    # Hemmed in ahead, behind and on both sides: no turn place, the robot waits.
    ring = 0.62 * np.column_stack((np.cos(np.linspace(-math.pi, math.pi, 73)),
                                   np.sin(np.linspace(-math.pi, math.pi, 73))))
    sweep.add_scan(0.5, (0.0, 0.0), ring)
    assert sweep.check(turn, (0.0, 0.0, 0.0)) is STOP
    assert sweep.waits == 1
    # Far from the hits, the turn goes through.
    assert sweep.check(turn, (5.0, 5.0, 0.0)) == turn


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
                                    {'speed': math.inf}, {'spot_distance': -0.1}])
def test_bad_turn_sweep_parameters_raise(kwargs):
    values = {'memory': 2.0, 'length': LENGTH, 'width': WIDTH, 'margin': MARGIN}
    values.update(kwargs)
    name = next(iter(kwargs))
    with pytest.raises(ValueError, match=name):
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


def test_with_the_sweep_the_robot_moves_to_a_turn_place_and_arrives_untouched():
    navigator, touched = drive_with_contacts(2.0)
    assert not touched
    assert navigator.status.name == 'GOAL_REACHED'
    assert navigator.turn_sweep.spots > 0


# --- Kept hits by space: seen through, out of reach, and past the memory on the grid's walls.

@pytest.mark.parametrize('point, ranges_value, expected', [
    ((2.0, 0.0), 3.0, True),            # the beam ends beyond the point: seen through
    ((2.0, 0.0), 2.05, False),          # within the tolerance: the same surface
    ((2.0, 0.0), 1.0, False),           # the beam ends before it: hidden
    ((2.0, 0.0), math.inf, True),       # no return within range_max: seen through
    ((2.0, 0.0), math.nan, False),      # no reading: no news
    ((2.0, 0.0), 0.05, False),          # below range_min: no reading
    ((-2.0, 0.0), 3.0, False),          # behind the 180-degree fan
])
def test_seen_through_compares_the_point_with_its_beam(point, ranges_value, expected):
    ranges = np.full(640, ranges_value)
    got = seen_through(np.array([point]), (0.0, 0.0, 0.0), ranges, ANGLE_MIN, ANGLE_INCREMENT,
                       RANGE_MIN, 10.0)
    assert got.tolist() == [expected]


def test_seen_through_finds_the_beam_on_the_points_bearing_in_a_turned_laser():
    ranges = np.full(640, 1.0)
    ranges[600] = 5.0                                  # one long beam, 78.75 degrees left
    bearing = ANGLE_MIN + 600 * ANGLE_INCREMENT
    laser = (1.0, 2.0, 0.7)
    on_beam = (1.0 + 2.0 * math.cos(0.7 + bearing), 2.0 + 2.0 * math.sin(0.7 + bearing))
    beside = (1.0 + 2.0 * math.cos(0.7 + bearing - 0.02),
              2.0 + 2.0 * math.sin(0.7 + bearing - 0.02))
    got = seen_through(np.array([on_beam, beside]), laser, ranges, ANGLE_MIN, ANGLE_INCREMENT,
                       RANGE_MIN, 10.0)
    assert got.tolist() == [True, False]
    assert seen_through(np.empty((0, 2)), laser, ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN,
                        10.0).shape == (0,)


def test_kept_hits_outlive_the_memory_where_the_grid_holds_an_obstacle():
    sweep = TurnSweep(2.0, LENGTH, WIDTH, MARGIN)
    turn = VelocityCommand(0.0, 1.5, turn=1.0)
    sweep.add_scan(0.0, (0.0, 0.0), np.array([[0.0, -0.55]]))      # beside, right
    sweep.add_scan(30.0, (0.0, 0.0), np.empty((0, 2)))             # 30 s later, not seen
    assert sweep.kept.shape == (1, 2)
    pose = (0.0, 0.0, 0.0)
    assert sweep.check(turn, pose, obstacle=lambda xy: np.ones(len(xy), bool)) != turn
    assert sweep.check(turn, pose, obstacle=lambda xy: np.zeros(len(xy), bool)) == turn
    assert sweep.check(turn, pose) == turn                         # no grid: time only


def test_kept_hits_are_dropped_when_seen_through_or_out_of_reach():
    sweep = TurnSweep(2.0, LENGTH, WIDTH, MARGIN)
    sweep.add_scan(0.0, (0.0, 0.0), np.array([[0.5, 0.0], [-0.3, 0.55], [0.51, 0.005]]))
    assert sweep.kept.shape == (2, 2)                  # two hits in one 2 cm cell: the newer
    ranges = np.full(640, 3.0)                         # sees through the one ahead
    sweep.add_scan(0.1, (0.0, 0.0), np.empty((0, 2)),
                   view=((0.0, 0.0, 0.0), ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, 10.0))
    np.testing.assert_allclose(sweep.kept, [[-0.3, 0.55]])     # behind the fan: kept
    sweep.add_scan(0.2, (sweep.reach + 1.0, 0.0), np.empty((0, 2)))
    assert sweep.kept.shape == (0, 2)


def turn_touches(x, y, yaw, turn, occupied):
    """Tell whether the box touches ``occupied`` anywhere on a turn in place (1 degree steps)."""
    steps = max(1, int(math.ceil(abs(turn) / math.radians(1.0))))
    return any(box_touches(x, y, yaw + turn * k / steps, occupied) for k in range(steps + 1))


def truth_obstacle(occupied):
    """Return ``obstacle(xy)``: whether each point's 0.5 m cell holds truth (a grid's wall)."""
    def obstacle(xy):
        rr = np.clip((xy[:, 1] / TRUTH_RES).astype(int), 0, occupied.shape[0] - 1)
        cc = np.clip((xy[:, 0] / TRUTH_RES).astype(int), 0, occupied.shape[1] - 1)
        near = np.zeros(len(xy), dtype=bool)
        for dr in range(-5, 6):                        # within a 0.5 m cell's reach
            for dc in range(-5, 6):
                near |= occupied[np.clip(rr + dr, 0, occupied.shape[0] - 1),
                                 np.clip(cc + dc, 0, occupied.shape[1] - 1)]
        return near
    return obstacle


def scan_into(sweep, stamp, pose, occupied):
    """Ray-cast a scan at ``pose`` (laser at the base) and fold it into ``sweep``."""
    ranges = ray_cast(occupied, pose, TRUTH_RES, RANGE_MAX)
    points = scan_points(pose, ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX)
    sweep.add_scan(stamp, pose[:2], np.column_stack((points.hits_x, points.hits_y)),
                   view=(pose, ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX))


def corner_behind():
    """
    Drive a robot east past a wall corner until the corner lies behind it, out of view.

    The wall block (x 2.0-4.5 m, top at y 5.6 m) passes 4.5 cm below the robot's right side;
    at the end, 9.5 s after it was first seen, its corner is 0.4 m behind and 0.4 m right of
    the robot's centre, within the circle its corners sweep and behind the 180-degree laser.
    """
    occupied = walled_room()
    add_box(occupied, 2.0, 4.8, 4.5, 5.6)
    sweep = TurnSweep(1.0, LENGTH, WIDTH, MARGIN)
    for step in range(20):
        scan_into(sweep, 0.5 * step, (2.95 + 0.1 * step, 5.98, 0.0), occupied)
    return occupied, sweep, (4.85, 5.98, 0.0)


@pytest.mark.parametrize('turn', [-2.1, 1.0])
def test_a_wall_corner_behind_after_a_creep_holds_the_turn(turn):
    occupied, sweep, pose = corner_behind()
    assert turn_touches(*pose, turn, occupied)            # the turn would hit the corner
    command = VelocityCommand(0.0, math.copysign(1.5, turn), turn=turn)
    # The hits on the corner are 9 s old, more than the memory: they count because the grid
    # holds the wall; by time alone (the sweep as first shipped) the turn would go through.
    assert sweep.check(command, pose) == command
    assert sweep.check(command, pose, truth_obstacle(occupied)) != command


def near_wall():
    """Place a robot heading 0.1 rad 0.55 m above a long wall; it wants to turn left 1.37 rad."""
    occupied = walled_room()
    add_box(occupied, 3.0, 5.0, 9.0, 5.45)
    return occupied, (6.0, 6.0, 0.1), 1.37


def turn_to_heading(sweep, occupied, pose, turn, steps=300):
    """
    Turn in place to ``pose``'s yaw plus ``turn`` through ``sweep`` (None: unchecked).

    Returns whether the heading was reached, whether the box touched the truth, and the pose.
    """
    x, y, yaw = pose
    heading = yaw + turn
    obstacle = truth_obstacle(occupied)
    touched = False
    for step in range(steps):
        if sweep is not None:
            scan_into(sweep, step * DT, (x, y, yaw), occupied)
        error = wrap_angle(heading - yaw)
        if abs(error) < 0.05:
            return True, touched, (x, y, yaw)
        command = VelocityCommand(0.0, float(np.clip(2.0 * error, -1.5, 1.5)), turn=error)
        if sweep is not None:
            command = sweep.check(command, (x, y, yaw), obstacle)
        v, w = command.linear, command.angular
        for _ in range(10):                                  # 10 ms integration steps
            x, y = x + v * math.cos(yaw) * DT / 10, y + v * math.sin(yaw) * DT / 10
            yaw += w * DT / 10
            touched |= box_touches(x, y, yaw, occupied)
    return False, touched, (x, y, yaw)


def test_find_turn_place_returns_a_place_the_turn_is_clear_from():
    occupied, pose, turn = near_wall()
    sweep = TurnSweep(2.0, LENGTH, WIDTH, MARGIN)
    scan_into(sweep, 0.0, pose, occupied)
    points = sweep.points(pose)
    assert sweep_hits(points, turn, LENGTH, WIDTH, MARGIN)
    place = find_turn_place(points, turn, LENGTH, WIDTH, MARGIN, 0.6)
    assert place is not None and 0.0 < math.hypot(*place) <= 0.6 + 1e-9
    bearing = math.atan2(place[1], place[0])
    x, y, yaw = pose
    there = (x + math.cos(yaw) * place[0] - math.sin(yaw) * place[1],
             y + math.sin(yaw) * place[0] + math.cos(yaw) * place[1], yaw + bearing)
    # The truth agrees: from the place, the rest of the turn touches nothing.
    assert not turn_touches(*there, wrap_angle(turn - bearing), occupied)
    assert find_turn_place(points, turn, LENGTH, WIDTH, MARGIN, 0.0) is None


def test_beside_a_wall_the_robot_turns_from_a_turn_place_untouched():
    occupied, pose, turn = near_wall()
    reached, touched, _ = turn_to_heading(None, occupied, pose, turn)
    assert reached and touched                               # turning where it stands hits
    sweep = TurnSweep(2.0, LENGTH, WIDTH, MARGIN)
    reached, touched, end = turn_to_heading(sweep, occupied, pose, turn)
    assert reached and not touched
    assert sweep.spots >= 1 and sweep.waits == 0
    assert 0.0 < math.dist(end[:2], pose[:2]) <= 0.6 + 0.05


def test_the_navigator_counts_old_hits_on_the_grids_obstacle_cells():
    from dpn_navigator.core.cell_label import CellLabel
    navigator = Navigator(NavigatorConfig(width=12.0, height=12.0))
    assert navigator.turn_sweep is not None                    # on by default
    assert Navigator(NavigatorConfig(width=12.0, height=12.0,
                                     turn_sweep_memory=0.0)).turn_sweep is None
    labels = navigator.grid.labels
    rr, cc = navigator.grid.geometry.world_to_cell(np.array([3.2, 5.2]), np.array([4.1, 4.1]))
    labels[rr[0], cc[0]] = CellLabel.STEADY_OBSTACLE
    labels[rr[1], cc[1]] = CellLabel.MOBILE_OBSTACLE
    points = np.array([[3.2, 4.1], [5.2, 4.1], [7.2, 4.1], [-1.0, 4.1]])
    assert navigator._obstacle_at(points).tolist() == [True, True, False, False]


# --- Issue 32: a scan whose angle layout no sensor has (a 2-beam scan of 1e-30 rad steps).

#: The fuzzer's repro: 2 beams, angle_min 0, angle_increment = angle_max = 1e-30 rad.
TINY_STEP_SCAN = {'ranges': np.array([1.0, 1.0]), 'angle_min': 0.0, 'angle_increment': 1e-30,
                  'range_min': 0.1, 'range_max': 10.0}


def test_seen_through_rejects_an_angle_step_no_scanner_has():
    with pytest.raises(ValueError, match='angle_increment 1e-30 rad is below'):
        seen_through(np.array([[0.5, -0.5]]), (0.0, 0.0, 0.0), **TINY_STEP_SCAN)


@pytest.mark.parametrize('point', [(math.nan, 0.0), (0.0, math.inf), (-1e300, 1e-300)])
def test_seen_through_bounds_the_beam_index_on_both_sides(point):
    # A NaN bearing once became index -2**63, clamped from above only: IndexError.
    ranges = np.full(640, 3.0)
    got = seen_through(np.array([point, (2.0, 0.0)]), (0.0, 0.0, 0.0), ranges, ANGLE_MIN,
                       ANGLE_INCREMENT, RANGE_MIN, 10.0)
    assert got.tolist() == [False, True]


def test_the_navigator_rejects_the_tiny_step_scan_and_drives_on():
    occupied = walled_room()
    navigator = Navigator(NavigatorConfig(width=12.0, height=12.0))
    assert navigator.turn_sweep is not None
    navigator.set_goal(10.0, 6.0)
    pose = (2.0, 6.0, 0.0)
    scan = ray_cast(occupied, pose, 0.05, RANGE_MAX)
    navigator.step(0.0, pose, scan, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX)
    labels = navigator.grid.labels.copy()
    with pytest.raises(ValueError, match='angle_increment 1e-30 rad is below'):
        navigator.step(0.1, pose, angle_max=1e-30, **TINY_STEP_SCAN)
    np.testing.assert_array_equal(navigator.grid.labels, labels)
    # The next scans (the sweep reads the last good one) go through.
    for step in range(2, 4):
        out = navigator.step(0.1 * step, pose, scan, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN,
                             RANGE_MAX)
    assert out.status.value == 'active'
