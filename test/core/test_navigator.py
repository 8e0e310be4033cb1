"""Closed-loop tests of the navigator: ray-cast scans, a unicycle robot, the real core."""

import ast
import math
from pathlib import Path

from dpn_navigator.benchmark.protocol import NOT_GETTING_STUCK_OFF
from dpn_navigator.core import (CellLabel, Navigator, NavigatorConfig, NavigatorStatus,
                                ReplanCause)
from dpn_navigator.core import navigator as navigator_module
from dpn_navigator.core.navigator import touches_blocked
import numpy as np
import pytest
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN, ray_cast

TRUTH_RES = 0.05
RANGE_MAX = 10.0
DT = 0.1


def walled_room(size=12.0):
    """Make a square room with a 0.3 m thick border wall, as a ground-truth grid at 5 cm."""
    n = int(round(size / TRUTH_RES))
    occupied = np.zeros((n, n), dtype=bool)
    occupied[:6, :] = occupied[-6:, :] = occupied[:, :6] = occupied[:, -6:] = True
    return occupied


def add_box(occupied, x0, y0, x1, y1):
    rows = slice(int(y0 / TRUTH_RES), int(y1 / TRUTH_RES))
    occupied[rows, int(x0 / TRUTH_RES):int(x1 / TRUTH_RES)] = True


def drive(navigator, occupied, pose, steps, stop_when=None):
    """Run the closed loop; return the final pose, the outputs and the closest wall distance."""
    outputs = []
    x, y, yaw = pose
    occupied_rc = np.argwhere(occupied)
    wall_xy = (occupied_rc[:, ::-1] + 0.5) * TRUTH_RES
    clearance = math.inf
    for step in range(steps):
        ranges = ray_cast(occupied, (x, y, yaw), TRUTH_RES, RANGE_MAX)
        out = navigator.step(step * DT, (x, y, yaw), ranges, ANGLE_MIN, ANGLE_INCREMENT,
                             RANGE_MIN, RANGE_MAX)
        outputs.append(out)
        v, w = out.command.linear, out.command.angular
        x += v * math.cos(yaw) * DT
        y += v * math.sin(yaw) * DT
        yaw += w * DT
        clearance = min(clearance, float(np.min(np.hypot(wall_xy[:, 0] - x, wall_xy[:, 1] - y))))
        if stop_when is not None and stop_when(out):
            break
    return (x, y, yaw), outputs, clearance


def config(**kwargs):
    return NavigatorConfig(width=12.0, height=12.0, **kwargs)


def config_before_31(**kwargs):
    """Return the configuration without issue 31's parts (test_not_getting_stuck.py's)."""
    return config(**NOT_GETTING_STUCK_OFF, **kwargs)


def round_the_wall(proximity_cost):
    """Drive from (2, 2) to (9, 2) round a wall with a gap at the top; return the navigator too."""
    occupied = walled_room()
    add_box(occupied, 5.0, 0.0, 5.5, 8.0)
    navigator = Navigator(config_before_31(obstacle_proximity_cost=proximity_cost))
    navigator.set_goal(9.0, 2.0)
    pose, outputs, clearance = drive(
        navigator, occupied, (2.0, 2.0, 0.0), 600,
        stop_when=lambda out: out.status is NavigatorStatus.GOAL_REACHED)
    return navigator, pose, outputs, clearance


@pytest.mark.parametrize('proximity_cost', [0.0, 1.0])
def test_reaches_a_goal_behind_a_wall_without_touching_it(proximity_cost):
    navigator, pose, outputs, clearance = round_the_wall(proximity_cost)
    assert outputs[-1].status is NavigatorStatus.GOAL_REACHED
    assert math.hypot(pose[0] - 9.0, pose[1] - 2.0) <= 0.3
    assert clearance > 0.35                          # the Husky's half width is 0.335 m
    assert navigator.replans >= 1
    labels = navigator.grid.labels
    assert np.count_nonzero(labels == CellLabel.STEADY_OBSTACLE) > 20
    assert np.count_nonzero(labels == CellLabel.EXPLORED) > 100
    for out in outputs:
        assert 0.0 <= out.command.linear <= 1.0 and abs(out.command.angular) <= 1.5


def test_touches_blocked_marks_free_8_neighbours_only():
    blocked = np.array([[1, 0, 0, 0],
                        [0, 0, 0, 0],
                        [0, 0, 0, 1]], dtype=bool)
    np.testing.assert_array_equal(touches_blocked(blocked), [[0, 1, 0, 0],
                                                             [1, 1, 1, 1],
                                                             [0, 0, 1, 0]])


def test_proximity_cost_keeps_the_robot_farther_from_a_wall_end():
    clearances = []
    for proximity_cost in (0.0, 1.0):
        _, _, outputs, clearance = round_the_wall(proximity_cost)
        assert outputs[-1].status is NavigatorStatus.GOAL_REACHED
        clearances.append(clearance)
    assert clearances[1] > clearances[0] + 0.2, clearances


def block_behind(navigator, x0, x1, label):
    """Label the columns between x0 and x1 [m]: a wanderer seen there, since gone."""
    geometry = navigator.grid.geometry
    _, c0 = geometry.world_to_cell(x0, 0.0)
    _, c1 = geometry.world_to_cell(x1, 0.0)
    navigator.grid.labels[:, c0:c1 + 1] = label


@pytest.mark.parametrize(('forget_after', 'label', 'unblocked_at', 'forgotten_as'), [
    (0.0, CellLabel.MOBILE_OBSTACLE, None, None),    # the paper's navigator waits for ever
    (2.0, CellLabel.MOBILE_OBSTACLE, 2.0, CellLabel.EXPLORED),
    # A wanderer first seen in unexplored space is labelled steady: forgotten one period later.
    (2.0, CellLabel.STEADY_OBSTACLE, 4.0, CellLabel.NON_EXPLORED),
])
def test_obstacles_out_of_view_are_forgotten_when_stuck(forget_after, label, unblocked_at,
                                                        forgotten_as):
    occupied = walled_room()
    # Ghost expiry and object memory would clear the bands on their own: this test is about
    # forgetting.
    navigator = Navigator(config_before_31(forget_obstacles_after=forget_after,
                                           mobile_expiry=0.0, object_memory=0.0))
    navigator.set_goal(2.0, 6.0)                     # behind the robot, which looks east
    block_behind(navigator, 3.5, 4.5, label)
    geometry = navigator.grid.geometry
    navigator.grid.labels[geometry.world_to_cell(5.25, 6.25)] = \
        CellLabel.MOBILE_OBSTACLE                    # 0.8 m behind the robot, out of view
    outputs = []
    for step in range(60):                           # 6 s, standing still
        ranges = ray_cast(occupied, (6.0, 6.0, 0.0), TRUTH_RES, RANGE_MAX)
        outputs.append(navigator.step(step * DT, (6.0, 6.0, 0.0), ranges, ANGLE_MIN,
                                      ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX))
        if outputs[-1].status is NavigatorStatus.ACTIVE:
            break
    assert outputs[0].status is NavigatorStatus.NO_PATH
    if unblocked_at is None:
        assert all(out.status is NavigatorStatus.NO_PATH for out in outputs)
        assert navigator.forgets == 0
        return
    assert outputs[-1].status is NavigatorStatus.ACTIVE
    assert (len(outputs) - 1) * DT == pytest.approx(unblocked_at, abs=0.55)  # a retry period
    assert navigator.forgets == round(unblocked_at / forget_after)
    labels = navigator.grid.labels
    # Out of view, the band is forgotten; in view, the east wall is labelled again at once.
    assert labels[geometry.world_to_cell(4.0, 6.0)] == forgotten_as
    assert labels[geometry.world_to_cell(11.75, 6.0)] == CellLabel.STEADY_OBSTACLE
    # Within 2 r of the robot, obstacles are kept: it may turn beside them before it sees them.
    assert labels[geometry.world_to_cell(5.25, 6.25)] == CellLabel.MOBILE_OBSTACLE
    pose, outputs, _ = drive(navigator, occupied, (6.0, 6.0, 0.0), 400,
                             stop_when=lambda out: out.status is NavigatorStatus.GOAL_REACHED)
    assert outputs[-1].status is NavigatorStatus.GOAL_REACHED


def test_unreachable_goal_stops_the_robot_and_recovers_when_the_way_opens():
    occupied = walled_room()
    add_box(occupied, 7.0, 0.0, 7.5, 12.0)           # a wall right across the room
    navigator = Navigator(config())
    navigator.set_goal(10.0, 6.0)
    pose, outputs, _ = drive(navigator, occupied, (2.0, 6.0, 0.0), 300,
                             stop_when=lambda out: out.status is NavigatorStatus.NO_PATH)
    assert outputs[-1].status is NavigatorStatus.NO_PATH
    assert 'no path' in outputs[-1].reason
    assert (outputs[-1].command.linear, outputs[-1].command.angular) == (0.0, 0.0)
    # While blocked, the robot stays put and keeps retrying.
    pose, outputs, _ = drive(navigator, occupied, pose, 10)
    assert all(out.command.linear == 0.0 for out in outputs)
    assert all(out.status is NavigatorStatus.NO_PATH for out in outputs)
    # The obstacle leaves (it was mobile after all): the cells are seen free and a path appears.
    occupied[:, int(7.0 / TRUTH_RES):int(7.5 / TRUTH_RES)] = False
    occupied[:6, :] = occupied[-6:, :] = True
    pose, outputs, _ = drive(navigator, occupied, pose, 400,
                             stop_when=lambda out: out.status is NavigatorStatus.GOAL_REACHED)
    assert outputs[-1].status is NavigatorStatus.GOAL_REACHED


def test_obstacle_appearing_on_the_path_triggers_a_replan():
    occupied = walled_room()
    # No ghost expiry: the box's cells, behind the robot at the goal, stay as they were seen.
    navigator = Navigator(config(mobile_expiry=0.0, object_memory=0.0))
    navigator.set_goal(10.0, 6.0)
    pose, outputs, _ = drive(navigator, occupied, (2.0, 6.0, 0.0), 5)
    assert outputs[0].replanned and navigator.replans == 1
    add_box(occupied, 5.0, 5.0, 6.0, 7.0)            # something steps onto the path
    pose, outputs, clearance = drive(
        navigator, occupied, pose, 300,
        stop_when=lambda out: out.status is NavigatorStatus.GOAL_REACHED)
    assert any(out.replanned for out in outputs)
    assert outputs[-1].status is NavigatorStatus.GOAL_REACHED
    assert clearance > 0.35
    box_cells = navigator.grid.labels[10:14, 10:12]
    assert np.any(box_cells == CellLabel.MOBILE_OBSTACLE)   # seen over explored cells


def test_without_a_goal_the_robot_stays_idle():
    navigator = Navigator(config())
    out = navigator.step(0.0, (2.0, 2.0, 0.0), np.full(640, 3.0), ANGLE_MIN, ANGLE_INCREMENT,
                         RANGE_MIN, RANGE_MAX)
    assert out.status is NavigatorStatus.IDLE
    assert (out.command.linear, out.command.angular) == (0.0, 0.0)
    assert np.any(navigator.grid.labels != CellLabel.NON_EXPLORED)   # it still maps


@pytest.mark.parametrize('goal, message', [((13.0, 2.0), 'outside the map'),
                                           ((math.nan, 2.0), 'finite')])
def test_bad_goal_raises(goal, message):
    navigator = Navigator(config())
    with pytest.raises(ValueError, match=message):
        navigator.set_goal(*goal)
    assert navigator.status is NavigatorStatus.IDLE


def test_bad_scan_raises_and_leaves_the_navigator_unchanged():
    navigator = Navigator(config())
    navigator.set_goal(10.0, 6.0)
    with pytest.raises(ValueError, match='angle_increment'):
        navigator.step(0.0, (2.0, 6.0, 0.0), np.full(640, 3.0), ANGLE_MIN, 0.0, RANGE_MIN,
                       RANGE_MAX)
    with pytest.raises(ValueError, match='pose must be finite'):
        navigator.step(0.0, (2.0, math.nan, 0.0), np.full(640, 3.0), ANGLE_MIN,
                       ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX)
    assert navigator.path is None and navigator.replans == 0
    assert np.all(navigator.grid.labels == CellLabel.NON_EXPLORED)


@pytest.mark.parametrize('kwargs, message', [
    ({'safety_radius': -0.1}, 'safety_radius'),
    ({'max_path_deviation': 0.0}, 'max_path_deviation'),
    ({'obstacle_proximity_cost': -1.0}, 'obstacle_proximity_cost'),
    ({'obstacle_proximity_cost': math.nan}, 'obstacle_proximity_cost'),
    ({'forget_obstacles_after': -1.0}, 'forget_obstacles_after'),
    ({'laser_offset': (0.0, math.inf, 0.0)}, 'laser_offset must be finite'),
])
def test_bad_config_raises(kwargs, message):
    with pytest.raises(ValueError, match=message):
        config(**kwargs)


def test_deferring_the_evidence_changes_no_decision_across_forgetting():
    # Stuck behind a band of steady cells, with the object memory on and a small object in
    # view: the forgetting writes labels (and settles first, as the object memory's deferred
    # listing reads them). A navigator that defers the evidence, as the node does, decides
    # and labels as one that does not.
    occupied = walled_room()
    add_box(occupied, 8.5, 4.0, 8.8, 4.3)           # a small object in view: listed
    navigators = [Navigator(config_before_31(forget_obstacles_after=2.0)) for _ in range(2)]
    for navigator in navigators:
        navigator.set_goal(2.0, 6.0)
        block_behind(navigator, 3.5, 4.5, CellLabel.STEADY_OBSTACLE)
    stepped, deferred = navigators
    pose = (6.0, 6.0, 0.0)
    listed = 0
    for step in range(60):
        ranges = ray_cast(occupied, pose, TRUTH_RES, RANGE_MAX)
        scan = (ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX)
        expected = stepped.step(step * DT, pose, *scan)
        deferred.observe(pose, *scan, stamp=step * DT, defer_evidence=True)
        assert deferred.decide(step * DT, pose) == expected
        np.testing.assert_array_equal(deferred.grid.labels, stepped.grid.labels)
        if step % 2:
            deferred.settle()
        listed = max(listed, stepped.grid.object_memory.provisional.size)
    assert stepped.forgets >= 1 and deferred.forgets == stepped.forgets
    assert listed > 0


@pytest.mark.parametrize('make_config', [config_before_31, config])
def test_observe_then_decide_is_the_same_as_step(make_config):
    occupied = walled_room()
    add_box(occupied, 5.0, 4.0, 6.0, 8.0)
    # Plain shortest paths (no proximity cost) hug the box's belt and get replanned often.
    stepped = Navigator(make_config(obstacle_proximity_cost=0.0))
    split = Navigator(make_config(obstacle_proximity_cost=0.0))
    # As the node does: the free evidence marked after the decision (or at the next scan).
    deferred = Navigator(make_config(obstacle_proximity_cost=0.0))
    for navigator in (stepped, split, deferred):
        navigator.set_goal(10.0, 6.0)
    pose = (2.0, 6.0, 0.0)
    for step in range(60):
        ranges = ray_cast(occupied, pose, TRUTH_RES, RANGE_MAX)
        scan = (ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX)
        expected = stepped.step(step * DT, pose, *scan)
        split.observe(pose, *scan, stamp=step * DT)
        got = split.decide(step * DT, pose)
        assert got == expected
        np.testing.assert_array_equal(split.grid.labels, stepped.grid.labels)
        deferred.observe(pose, *scan, stamp=step * DT, defer_evidence=True)
        assert deferred.decide(step * DT, pose) == expected
        np.testing.assert_array_equal(deferred.grid.labels, stepped.grid.labels)
        if step % 2:
            deferred.settle()
            np.testing.assert_array_equal(deferred.grid.seen_free, stepped.grid.seen_free)
        v, w = got.command.linear, got.command.angular
        pose = (pose[0] + v * math.cos(pose[2]) * DT, pose[1] + v * math.sin(pose[2]) * DT,
                pose[2] + w * DT)
    # Route commitment keeps the first route round the box; without it the robot replans.
    assert stepped.replans >= (2 if make_config is config_before_31 else 1)
    assert split.replans == stepped.replans


def test_each_plan_reports_its_cause():
    occupied = walled_room()
    navigator = Navigator(config())
    navigator.set_goal(10.0, 6.0)
    pose, outputs, _ = drive(navigator, occupied, (2.0, 6.0, 0.0), 5)
    assert outputs[0].replan_cause is ReplanCause.OTHER          # the first path
    assert all(out.replan_cause is ReplanCause.NONE for out in outputs[1:])
    add_box(occupied, 5.0, 5.0, 6.0, 7.0)                      # something steps onto the path
    _, outputs, _ = drive(navigator, occupied, pose, 20)
    assert outputs[0].replan_cause is ReplanCause.FLAG
    assert all((out.replan_cause is ReplanCause.NONE) == (not out.replanned)
               for out in outputs)
    # A wall right across the room: no path; the retries say so.
    occupied = walled_room()
    add_box(occupied, 7.0, 0.0, 7.5, 12.0)
    navigator = Navigator(config())
    navigator.set_goal(10.0, 6.0)
    _, outputs, _ = drive(navigator, occupied, (2.0, 6.0, 0.0), 300)
    causes = [out.replan_cause for out in outputs if out.replanned]
    assert causes[0] is ReplanCause.OTHER
    assert ReplanCause.NO_PATH_RETRY in causes
    assert len(causes) == navigator.replans


def test_labels_are_written_only_in_mapping():
    # The label grid owns its labels: outside core/mapping/ no module of the core assigns into
    # an array named labels (the navigator forgets through PlanningMap.forget_obstacles).
    core = Path(navigator_module.__file__).resolve().parent
    writers = []
    for path in sorted(core.rglob('*.py')):
        if 'mapping' in path.relative_to(core).parts or '_kernels' in path.parts:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            targets = node.targets if isinstance(node, ast.Assign) else (
                [node.target] if isinstance(node, ast.AugAssign) else [])
            for target in targets:
                base = target.value if isinstance(target, ast.Subscript) else None
                name = getattr(base, 'attr', getattr(base, 'id', None))
                if name == 'labels':
                    writers.append(f'{path.name}:{node.lineno}')
    assert writers == []
