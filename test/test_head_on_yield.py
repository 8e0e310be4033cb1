"""
Tests of the head-on yield state: corridor widths, passing places, the decision, and a scene.

The unit tests use literal label grids at 0.5 m and a stand-in for the grid's motion tracks;
the scene drives one scripted wanderer head-on down a 1.8 m corridor with a side bay in the
pybullet world, with the state on and off.

"""

import math
from types import SimpleNamespace

from dpn_navigator.core import (CellLabel, FollowerConfig, GridGeometry, Navigator,
                                NavigatorConfig, NavigatorStatus, ReplanCause)
from dpn_navigator.core.head_on_yield import HeadOnYield, WATCH_TIME, YieldConfig
from dpn_navigator.core.passing_places import corridor_widths, passing_place
import numpy as np
from numpy.testing import assert_allclose, assert_array_equal
import pytest

E, S, M = CellLabel.EXPLORED, CellLabel.STEADY_OBSTACLE, CellLabel.MOBILE_OBSTACLE
RES = 0.5
R = 0.6
GEOMETRY = GridGeometry(12.0, 5.0, RES)          # 10 rows x 24 columns
ON = YieldConfig(corridor_width=2.5)


def corridor_labels(free_rows=(2,), bay_cols=(4, 7), bay_rows=(3, 8)):
    """Walls everywhere but a corridor along ``free_rows`` and a bay above it."""
    labels = np.full(GEOMETRY.shape, S, dtype=np.uint8)
    labels[list(free_rows), 1:23] = E
    if bay_cols is not None:
        labels[bay_rows[0]:bay_rows[1], bay_cols[0]:bay_cols[1]] = E
    return labels


def centre(row, col):
    x, y = GEOMETRY.cell_to_world(row, col)
    return float(x), float(y)


def corridor_path(row=2, first=1, last=22):
    cells = np.array([(row, col) for col in range(first, last + 1)], dtype=np.int64)
    x, y = GEOMETRY.cell_to_world(cells[:, 0], cells[:, 1])
    return np.column_stack((x, y))


def tracks(*objects, stamp):
    """Make a stand-in for ``MotionTracks``: ``(id, x, y)`` per object, seen at ``stamp``."""
    return SimpleNamespace(
        ids=np.array([o[0] for o in objects], dtype=np.int64),
        positions=np.array([o[1:] for o in objects], dtype=np.float64).reshape(-1, 2),
        last_seen=np.full(len(objects), stamp))


def footprint_at(x, y):
    rows, cols = GEOMETRY.cell_window(x - 0.35, x + 0.35, y - 0.35, y + 0.35)
    xc, yc = GEOMETRY.window_centres(rows, cols)
    return rows, cols, np.hypot(xc[None, :] - x, yc[:, None] - y) <= 0.35


def watched(robot, start_x, end_x, config=ON, speed_time=1.0, y=None):
    """Return a `HeadOnYield` that saw one object move from ``start_x`` to ``end_x`` in 1 s."""
    state = HeadOnYield(config, GEOMETRY, R, FollowerConfig())
    y = centre(2, 0)[1] if y is None else y
    state.observe(0.0, robot, tracks((7, start_x, y), stamp=0.0))
    state.observe(speed_time, robot, tracks((7, end_x, y), stamp=speed_time))
    return state


# -- corridor widths ------------------------------------------------------------------------


def walls_across(width, shift=0.0):
    """Steady cells of a corridor along x between walls ``width`` apart, as f1 labels them."""
    geometry = GridGeometry(10.0, 8.0, RES)
    _, y = geometry.cell_to_world(np.arange(geometry.rows), 0)
    low, high = 1.0 + shift, 1.0 + shift + width
    # f1: within r of a hit on either wall surface, or inside a wall.
    steady_rows = (y <= low + R) | (y >= high - R)
    steady = np.repeat(steady_rows[:, None], geometry.cols, axis=1)
    free_rows = np.flatnonzero(~steady_rows)
    return steady, free_rows


@pytest.mark.parametrize('width, shift', [(1.6, 0.0), (1.8, 0.0), (2.0, 0.0), (2.0, 0.25),
                                          (3.0, 0.0), (4.0, 0.1), (5.0, 0.0)])
def test_corridor_width_is_the_wall_to_wall_width_within_a_cell(width, shift):
    steady, free_rows = walls_across(width, shift)
    for row in free_rows:
        cells = np.array([(row, col) for col in range(2, 15)])
        widths = corridor_widths(steady, cells, RES, R, limit=10.0)
        assert_allclose(widths, widths[0])                 # the same all along
        assert abs(widths[0] - width) <= RES + 1e-9, (row, widths[0])


def test_corridor_width_across_a_diagonal_path_and_its_limit():
    # A corridor running at 45 degrees: free where |row - col| <= 1.
    rr, cc = np.indices((20, 20))
    steady = np.abs(rr - cc) > 1
    cells = np.array([(k, k) for k in range(3, 17)])
    widths = corridor_widths(steady, cells, RES, R, limit=10.0)
    # The first wall cells across lie sqrt(2) cells from the path on either side.
    assert_allclose(widths, 2.0 * math.sqrt(2.0) * RES + 2 * R - RES)
    open_hall = np.zeros((20, 20), dtype=bool)
    assert_array_equal(corridor_widths(open_hall, cells, RES, R, limit=2.5), 2.5)


def test_corridor_width_of_a_one_cell_path_and_bad_input():
    steady, free_rows = walls_across(1.8)
    one = corridor_widths(steady, [(free_rows[0], 5)], RES, R, limit=5.0)
    assert one.shape == (1,) and abs(one[0] - 1.8) <= 0.25
    with pytest.raises(ValueError, match='2-D mask'):
        corridor_widths(steady[0], [(1, 1)], RES, R, 5.0)
    with pytest.raises(ValueError, match=r'non-empty \(N, 2\)'):
        corridor_widths(steady, np.zeros((0, 2), dtype=int), RES, R, 5.0)


# -- passing places -----------------------------------------------------------------------


def test_passing_place_is_the_nearest_candidate_by_route_without_cut_corners():
    passable = np.array([[1, 1, 1, 1],
                         [0, 0, 1, 1],
                         [1, 1, 1, 0]], dtype=bool)
    candidate = np.zeros_like(passable)
    candidate[2, 0] = candidate[1, 3] = True
    route = passing_place(passable, candidate, (0, 0), RES, search_distance=10.0)
    # (0,0) -> (0,1) -> (0,2) -> (1,3): the diagonal is allowed, both cells beside it free.
    assert_array_equal(route, [(0, 0), (0, 1), (0, 2), (1, 3)])
    # Without (1, 3) the next is (2, 0), round the wall; (1,2) -> (2,1) would cut a corner.
    candidate[1, 3] = False
    route = passing_place(passable, candidate, (0, 0), RES, search_distance=10.0)
    assert_array_equal(route, [(0, 0), (0, 1), (0, 2), (1, 2), (2, 2), (2, 1), (2, 0)])
    assert passing_place(passable, candidate, (0, 0), RES, search_distance=2.5) is None
    assert passing_place(passable, candidate, (5, 0), RES, search_distance=10.0) is None


# -- configuration ------------------------------------------------------------------------


@pytest.mark.parametrize('kwargs, message', [
    ({'corridor_width': -1.0}, 'yield_corridor_width'),
    ({'wait_max': math.nan}, 'yield_wait_max'),
    ({'corridor_width': 2.5, 'trigger_distance': 0.0}, 'yield_trigger_distance must be positive'),
    ({'corridor_width': 2.5, 'side_clearance': 0.0}, 'yield_side_clearance must be positive'),
])
def test_bad_yield_config_raises(kwargs, message):
    with pytest.raises(ValueError, match=message):
        YieldConfig(**kwargs)
    with pytest.raises(ValueError, match=message):
        NavigatorConfig(width=5.0, height=5.0, **{f'yield_{k}': v for k, v in kwargs.items()})


def test_the_state_is_off_by_default():
    assert not YieldConfig().enabled
    assert not NavigatorConfig(width=5.0, height=5.0).yield_config().enabled
    # Off, it takes no parameter check beyond >= 0: zero distances are fine.
    assert not YieldConfig(trigger_distance=0.0).enabled


# -- the decision -------------------------------------------------------------------------


def test_an_object_coming_head_on_in_a_narrow_corridor_is_an_encounter():
    robot = (*centre(2, 1), 0.0)
    state = watched(robot, 7.75, 7.25)
    labels = corridor_labels()
    encounter = state.encounter(1.0, robot, labels, corridor_path(), False,
                                footprint_at(*robot[:2]))
    assert encounter is not None and encounter.track_id == 7
    assert encounter.velocity == pytest.approx((-0.5, 0.0))
    assert encounter.distance == pytest.approx(7.25 - robot[0])
    assert encounter.width == pytest.approx(1.7)
    assert_allclose(encounter.route_xy[[0, -1]], [robot[:2], (7.25, robot[1])])
    # The place must lie beside the first half of the route, or behind the robot.
    half = encounter.line_xy[:, 0] <= robot[0] + 0.5 * encounter.distance
    assert_array_equal(encounter.reachable, half)


@pytest.mark.parametrize('case', ['receding', 'slow', 'wide', 'far', 'off_the_path',
                                  'no_tracks', 'not_seen_lately'])
def test_no_encounter(case):
    robot = (*centre(2, 1), 0.0)
    start_x, end_x, labels, path_xy = 7.75, 7.25, corridor_labels(), corridor_path()
    if case == 'receding':
        start_x, end_x = 7.25, 7.75
    elif case == 'slow':
        start_x = 7.30                                # 0.05 m/s
    elif case == 'wide':
        labels = corridor_labels(free_rows=(1, 2, 3, 4))   # about 2.7 m wall to wall
    elif case == 'far':
        start_x, end_x = 10.25, 9.75                  # 9 m away
    state = watched(robot, start_x, end_x)
    stamp = 1.0
    if case == 'off_the_path':
        path_xy = np.array([robot[:2], (robot[0], 4.0)])   # the path turns off at once
    elif case == 'no_tracks':
        state.observe(1.1, robot, None)
    elif case == 'not_seen_lately':
        stamp = 1.6
    assert state.encounter(stamp, robot, labels, path_xy, False,
                           footprint_at(*robot[:2])) is None
    if case == 'off_the_path':                        # ... but with no path it concerns us
        assert state.encounter(stamp, robot, labels, None, True,
                               footprint_at(*robot[:2])) is not None


def test_start_picks_a_bay_off_the_line_and_the_robot_leaves_once_the_corridor_is_clear():
    robot = (*centre(2, 1), 0.0)
    state = watched(robot, 7.75, 7.25)
    labels = corridor_labels()
    footprint = footprint_at(*robot[:2])
    route = state.start(1.0, robot, labels, corridor_path(), False, footprint)
    assert route is not None and state.active and state.count == 1
    assert_array_equal(route[0], (2, 1))
    assert np.all(np.abs(np.diff(route, axis=0)).max(axis=1) == 1)      # 8-connected
    assert np.all(labels[route[1:, 0], route[1:, 1]] == E)
    place = centre(*route[-1])
    assert 4 <= route[-1][1] < 7 and place[1] - robot[1] >= ON.side_clearance
    assert state.start(1.0, robot, labels, corridor_path(), False, footprint) is None
    # On the way: the follower drives along the route.
    step = state.step(1.1, robot, labels, footprint)
    assert not step.done and step.route is None and 'passing place' in step.reason
    # At the place, facing away from the corridor: it turns in place towards it.
    at_place = (*place, math.pi / 2)
    step = state.step(5.0, at_place, labels, footprint_at(*place))
    assert step.command.linear == 0.0 and step.command.angular < 0.0
    facing = (*place, -math.pi / 2)
    step = state.step(5.1, facing, labels, footprint_at(*place))
    assert not step.done and step.command.linear == step.command.angular == 0.0
    # The object still on the route ahead of the bay keeps it waiting ...
    state.observe(5.1 + WATCH_TIME, facing, tracks((7, 3.25, robot[1]), stamp=5.1 + WATCH_TIME))
    assert not state.step(5.1 + WATCH_TIME, facing, labels, footprint_at(*place)).done
    # ... until it has gone past the bay, away from the way ahead.
    state.observe(9.0, facing, tracks((7, 0.75, robot[1]), stamp=9.0))
    step = state.step(9.0, facing, labels, footprint_at(*place))
    assert step.done and not state.active


def test_the_robot_leaves_after_wait_max_and_when_the_route_closes():
    robot = (*centre(2, 1), 0.0)
    config = YieldConfig(corridor_width=2.5, wait_max=4.0)
    labels = corridor_labels()
    state = watched(robot, 7.75, 7.25, config=config)
    assert state.start(1.0, robot, labels, corridor_path(), False,
                       footprint_at(*robot[:2])) is not None
    step = state.step(5.0, robot, labels, footprint_at(*robot[:2]))
    assert step.done and 'yield_wait_max' in step.reason
    state = watched(robot, 7.75, 7.25)
    assert state.start(1.0, robot, labels, corridor_path(), False,
                       footprint_at(*robot[:2])) is not None
    closed = labels.copy()
    closed[2, 3] = M                                    # something stepped into the way
    step = state.step(1.1, robot, closed, footprint_at(*robot[:2]))
    assert step.done and 'no passing place' in step.reason


def test_no_bay_in_time_ahead_but_one_behind_the_robot():
    # The bay is 4.5 m ahead, the object 6.5 m: the robot would not get there first.
    robot = (*centre(2, 1), 0.0)
    labels = corridor_labels(bay_cols=(9, 12))
    state = watched(robot, 7.75, 7.25)
    assert state.start(1.0, robot, labels, corridor_path(), False, footprint_at(*robot[:2])) \
        is None
    # A robot further on has it behind: its line runs back along the corridor.
    robot = (*centre(2, 13), 0.0)
    state = watched(robot, 12.25 - 0.5, 11.25, config=YieldConfig(corridor_width=2.5))
    labels = corridor_labels(bay_cols=(9, 12))
    route = state.start(1.0, robot, labels, corridor_path(first=13), False,
                        footprint_at(*robot[:2]))
    assert route is not None and 9 <= route[-1][1] < 12 and route[-1][0] >= 5


# -- a scripted head-on encounter in the pybullet world ------------------------------------


def corridor_scene():
    """Make a 24 m corridor, 1.8 m wide, with a 2.5 m x 2.2 m bay 2.5 m from the start."""
    from sim_bridge.scenario import Scenario
    from sim_bridge.tasks import Task
    resolution = 0.1
    geometry = GridGeometry(24.0, 6.0, resolution)
    x, y = geometry.cell_to_world(*np.indices(geometry.shape))
    free = (x > 0.1) & (x < 23.9) & (y > 1.0) & (y < 2.8)
    free |= (x > 4.0) & (x < 6.5) & (y >= 2.75) & (y < 5.0)
    task = Task((1.5, 1.9, 0.0), (22.5, 1.9))
    return Scenario('corridor_with_bay', ~free, free, resolution, (0.0, 0.0), (task,))


def head_on(corridor_width, time_limit=90.0):
    """Drive the Husky down the corridor while a wanderer comes the other way."""
    from sim_bridge.husky import LASER_MOUNT
    from sim_bridge.wanderers import WandererConfig
    from sim_bridge.world import World, WorldConfig
    scenario = corridor_scene()
    task = scenario.tasks[0]
    config = NavigatorConfig(width=scenario.width, height=scenario.height,
                             origin=scenario.origin, laser_offset=LASER_MOUNT,
                             yield_corridor_width=corridor_width)
    # It never gives up and turns back: only the Husky can make room.
    wanderer = WandererConfig(speed_range=(0.5, 0.5), patience_range=(1e3, 1e3))
    outputs = []
    with World(scenario, WorldConfig(n_wanderers=1, seed=0, wanderer=wanderer),
               start=task.start) as world:
        world.script_wanderer(0, [(17.0, 1.9), (0.5, 1.9)])
        navigator = Navigator(config)
        navigator.set_goal(*task.goal)
        scan = world.scan()
        while world.time < time_limit:
            out = navigator.step(world.time, world.husky_pose, scan.ranges, scan.angle_min,
                                 scan.angle_increment, scan.range_min, scan.range_max)
            outputs.append((world.time, out, world.husky_pose, world.wanderer_positions[0]))
            if out.status is NavigatorStatus.GOAL_REACHED:
                break
            scan = world.advance(out.command.linear, out.command.angular)
        return navigator, outputs, world.contacts.events, world.time


def test_head_on_in_a_corridor_the_robot_yields_in_the_bay_and_gets_through():
    navigator, outputs, contacts, end = head_on(corridor_width=2.5)
    assert navigator.status is NavigatorStatus.GOAL_REACHED and contacts == 0
    assert navigator.yields == 1
    yielding = [(t, pose, w) for t, out, pose, w in outputs
                if out.status is NavigatorStatus.YIELDING]
    assert yielding
    # It waited in the bay while the wanderer went by, and only then drove on.
    deepest = max(pose[1] for _, pose, _ in yielding)
    assert deepest > 2.8 + 0.1
    passed = [t for t, _, w in yielding if w[0] < 4.0]
    assert passed and passed[0] < yielding[-1][0]
    causes = [out.replan_cause for _, out, _, _ in outputs]
    assert causes.count(ReplanCause.YIELD) == 2        # the route there, the plan after it
    assert sum(out.replanned for _, out, _, _ in outputs) == navigator.replans
    # Without the state the two stand face to face until the time runs out.
    navigator, outputs, contacts, off_end = head_on(corridor_width=0.0)
    assert navigator.status is not NavigatorStatus.GOAL_REACHED and contacts == 0
    assert navigator.yields == 0
    assert off_end >= end + 30.0
    assert all(out.status is not NavigatorStatus.YIELDING for _, out, _, _ in outputs)
