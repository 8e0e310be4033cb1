"""
Giving way (``core/planning/give_way.py``): a mutual wait with a polite agent ends.

The scene: a 2 m corridor with a 4 x 4 m room off it behind the robot; an agent walks down the
corridor towards the robot and, like the benchmark's P3-ATs, stops while the robot stands in
its way and plans around it after its patience, which does not help while the robot stands
ahead on that way too. Without giving way the two wait for each other to the end.
The place search (`find_place`) is tested on small literal label grids.
"""

import dataclasses
import math

from dpn_navigator.core import astar, CellLabel, Navigator, NavigatorConfig, NavigatorStatus
from dpn_navigator.core.planning.give_way import find_place, flood, GiveWay
import numpy as np
from numpy.testing import assert_array_equal
import pytest
from scripted_robot import carve, DT, Robot, solid, TRUTH_RES

#: The scripted agent's planning grid [m].
PLAN_RES = 0.25

E, S, M, U = (CellLabel.EXPLORED, CellLabel.STEADY_OBSTACLE, CellLabel.MOBILE_OBSTACLE,
              CellLabel.NON_EXPLORED)


def corridor_with_room():
    """Make a 2 m corridor (y 0.3-2.3, x 0.3-15.7) with a room (x 2-6, y 2.3-6.3) north of it."""
    occupied = solid(16.0, 7.0)
    carve(occupied, 0.3, 0.3, 15.7, 2.3)
    carve(occupied, 2.0, 2.3, 6.0, 6.3)
    return occupied


class PoliteAgent:
    """
    A disc walking to its goal at ``speed`` [m/s] that stops while the robot is in its way.

    In its way: the robot's centre ahead of it by at most ``look_ahead`` plus both radii, and
    less than both radii plus 0.1 m beside its line of travel. Stopped longer than
    ``patience``, it plans again around the robot's disc (both radii plus 0.1 m): the
    benchmark's P3-AT rules, on a 0.25 m grid of the truth with A*, and the same goal.
    """

    def __init__(self, base, start, goal, radius=0.35, speed=0.5, look_ahead=1.5,
                 robot_radius=0.6, patience=2.0):
        self.xy = np.array(start, dtype=float)
        self.goal = np.array(goal, dtype=float)
        self.waypoints = [self.goal]
        self.radius = radius
        self.speed = speed
        self.reach = look_ahead + radius + robot_radius
        self.side = radius + robot_radius + 0.1
        self.patience = patience
        self.stopped = 0.0
        self.waited = 0.0
        # The planning grid: a 0.25 m cell is clear when no wall lies within the agent's
        # radius plus a margin of its centre (blocks of 5 x 5 truth cells, grown by 2).
        step = int(round(PLAN_RES / TRUTH_RES))
        rows, cols = base.shape[0] // step, base.shape[1] // step
        coarse = base[:rows * step, :cols * step].reshape(rows, step, cols, step).any(axis=(1, 3))
        grown = coarse.copy()
        for d_row in range(-2, 3):
            for d_col in range(-2, 3):
                grown |= np.roll(np.roll(coarse, d_row, axis=0), d_col, axis=1)
        self.walls = grown

    def _plan_around(self, robot_xy):
        blocked = self.walls.copy()
        rr, cc = np.indices(blocked.shape)
        blocked |= np.hypot((cc + 0.5) * PLAN_RES - robot_xy[0],
                            (rr + 0.5) * PLAN_RES - robot_xy[1]) < self.side
        start = (int(self.xy[1] / PLAN_RES), int(self.xy[0] / PLAN_RES))
        goal = (int(self.goal[1] / PLAN_RES), int(self.goal[0] / PLAN_RES))
        blocked[start] = False
        cells = astar(blocked, start, goal, cut_corners=False)
        if cells is not None:
            self.waypoints = [np.array([(c + 0.5) * PLAN_RES, (r + 0.5) * PLAN_RES])
                              for r, c in cells[1:-1]] + [self.goal]

    def step(self, robot_xy):
        if not self.waypoints:
            return
        to_next = self.waypoints[0] - self.xy
        distance = float(np.hypot(*to_next))
        if distance < 1e-9:
            self.waypoints.pop(0)
            return
        ux, uy = to_next / distance
        rx, ry = robot_xy[0] - self.xy[0], robot_xy[1] - self.xy[1]
        along, beside = rx * ux + ry * uy, abs(rx * uy - ry * ux)
        if 0.0 < along <= self.reach and beside < self.side:
            self.stopped += DT
            self.waited += DT
            if self.stopped >= self.patience:
                self.stopped = 0.0
                self._plan_around(robot_xy)
            return
        self.stopped = 0.0
        self.xy = self.xy + min(self.speed * DT, distance) * np.array([ux, uy])

    def draw(self, base):
        """Return ``base`` with the agent's disc occupied."""
        occupied = base.copy()
        rows, cols = np.indices(base.shape)
        disc = np.hypot((cols + 0.5) * TRUTH_RES - self.xy[0],
                        (rows + 0.5) * TRUTH_RES - self.xy[1]) <= self.radius
        occupied[disc] = True
        return occupied


def meet_in_corridor(config, seconds=90.0):
    """Run the scene: robot east from (1.2, 1.3) to (14, 1.3), the agent west from (14.5, 1.3)."""
    base = corridor_with_room()
    navigator = Navigator(config)
    navigator.set_goal(14.0, 1.3)
    agent = PoliteAgent(base, (14.5, 1.3), (0.9, 1.3))
    robot = Robot(navigator, agent.draw(base), (1.2, 1.3, 0.0))
    closest = math.inf
    for _ in range(int(round(seconds / DT))):
        agent.step(robot.pose[:2])
        robot.occupied = agent.draw(base)
        out = robot.step()
        closest = min(closest, math.dist(robot.pose[:2], agent.xy))
        if out.status is NavigatorStatus.GOAL_REACHED:
            break
    return robot, agent, out, closest


def test_the_robot_gives_way_in_the_room_and_both_go_on():
    config = NavigatorConfig(width=16.0, height=7.0)
    robot, agent, out, closest = meet_in_corridor(config)
    assert out.status is NavigatorStatus.GOAL_REACHED, (robot.stamp, robot.pose, out.reason)
    assert robot.navigator.give_way.given >= 1
    assert max(y for _, y, _ in robot.trace) > 2.3, 'it did not step into the room'
    assert agent.xy[0] < 2.0, 'the agent did not get past'
    assert closest > agent.radius + 0.5                     # no contact with the agent
    assert robot.stamp < 75.0


def test_without_giving_way_both_wait_to_the_end():
    # The held-out town episode of issue 30: 120 s of mutual wait by the goal.
    config = NavigatorConfig(width=16.0, height=7.0, give_way_time=0.0)
    robot, agent, out, _ = meet_in_corridor(config, seconds=60.0)
    assert out.status is not NavigatorStatus.GOAL_REACHED
    assert robot.navigator.give_way is None
    assert agent.waited > 30.0
    assert robot.pose[0] < agent.xy[0]


def test_the_paper_navigator_does_not_give_way():
    from dpn_navigator.benchmark.protocol import NAVIGATORS
    config = dataclasses.replace(NavigatorConfig(width=16.0, height=7.0), **NAVIGATORS['paper'])
    assert config.give_way_time == 0.0
    assert Navigator(config).give_way is None


# find_place on literal grids --------------------------------------------------------------


def test_flood_counts_four_connected_steps_through_passable_cells():
    passable = np.array([[1, 1, 0],
                         [0, 1, 1],
                         [1, 0, 1]], dtype=bool)
    seeds = np.zeros((3, 3), dtype=bool)
    seeds[0, 0] = True
    expected = [[0, 1, -1],
                [-1, 2, 3],
                [-1, -1, 4]]
    assert_array_equal(flood(passable, seeds), expected)


def test_in_a_corridor_with_a_side_room_the_place_is_in_the_room():
    # Rows are y, columns x (0.5 m cells); the corridor is row 1, the room rows 2-5 at
    # columns 5-7; the agent (mobile) stands at columns 13-14, the robot at column 11.
    labels = np.full((7, 20), S, dtype=np.uint8)
    labels[1, :] = E
    labels[2:6, 5:8] = E
    labels[1, 13:15] = M
    way = find_place(labels, labels == M, (1, 11), safety_radius=0.6, resolution=0.5,
                     search_distance=6.0)
    assert way is not None
    assert tuple(way[0]) == (1, 11)
    place = tuple(way[-1])
    # Deep enough in the room that the robot's body and the agent's clear the corridor.
    assert place[0] >= 4 and 5 <= place[1] <= 7, place
    steps = np.abs(np.diff(way, axis=0)).sum(axis=1)
    assert_array_equal(steps, 1)


def test_in_a_corridor_without_a_side_the_robot_finds_no_place():
    labels = np.full((3, 30), S, dtype=np.uint8)
    labels[1, :] = E
    labels[1, 25:27] = M
    assert find_place(labels, labels == M, (1, 22), 0.6, 0.5, 6.0) is None


def test_a_short_pocket_behind_the_robot_is_a_place():
    # The corridor ends 2 m behind the robot: the agent has nowhere to go there, and the
    # robot backs into the pocket.
    labels = np.full((3, 30), S, dtype=np.uint8)
    labels[1, 2:] = E
    labels[1, 11:13] = M
    way = find_place(labels, labels == M, (1, 8), 0.6, 0.5, 6.0)
    assert way is not None and way[-1][1] < 8


def test_in_a_wide_hall_the_robot_steps_aside_a_little():
    labels = np.full((14, 14), E, dtype=np.uint8)
    labels[[0, -1], :] = S
    labels[:, [0, -1]] = S
    labels[6:8, 10:12] = M
    way = find_place(labels, labels == M, (7, 7), 0.6, 0.5, 6.0)
    assert way is not None
    assert len(way) - 1 <= 6                                  # within 3 m
    assert math.dist(way[-1], (6.5, 10.5)) >= math.dist((7, 7), (6.5, 10.5))


def test_with_no_mobile_cell_near_there_is_no_one_to_give_way_to():
    labels = np.full((7, 12), S, dtype=np.uint8)
    labels[1, :] = E
    labels[2:6, 1:4] = E
    labels[1, 11] = U
    assert find_place(labels, labels == M, (1, 2), 0.6, 0.5, 6.0) is None


@pytest.mark.parametrize('labels, cell, match', [
    (np.zeros(4, dtype=np.uint8), (0, 0), '2-D'),
    (np.zeros((3, 3), dtype=np.uint8), (3, 0), 'outside'),
])
def test_find_place_rejects_bad_input(labels, cell, match):
    with pytest.raises(ValueError, match=match):
        find_place(labels, labels == M, cell, 0.6, 0.5, 6.0)


@pytest.mark.parametrize('kwargs, match', [
    ({'wait_time': 0.0}, 'wait_time'),
    ({'search_distance': math.nan}, 'search_distance'),
    ({'hold_time': -1.0}, 'hold_time'),
])
def test_give_way_rejects_bad_settings(kwargs, match):
    settings = {'shape': (4, 4), 'wait_time': 10.0, 'search_distance': 6.0, 'hold_time': 10.0,
                **kwargs}
    with pytest.raises(ValueError, match=match):
        GiveWay(**settings)


def test_the_wait_counts_only_while_the_robot_stands_still():
    give_way = GiveWay((4, 4), wait_time=10.0, search_distance=6.0, hold_time=10.0)
    give_way.note(0.0, (1.0, 1.0))
    give_way.note(9.0, (1.2, 1.0))                      # within 0.3 m: still
    assert not give_way.due(9.5)
    assert give_way.due(10.0)
    give_way.note(10.5, (1.5, 1.0))                     # moved on
    assert not give_way.due(19.0)
    assert give_way.due(20.5)


def test_in_a_street_the_robot_steps_to_the_side_the_agent_is_not_on():
    # A street five cells wide (rows 1-5); the agent stands by the north side (rows 4-5), the
    # robot beside it in the middle (the held-out town episode).
    labels = np.full((7, 30), S, dtype=np.uint8)
    labels[1:6, :] = E
    labels[4:6, 14:16] = M
    way = find_place(labels, labels == M, (3, 15), 0.6, 0.5, 6.0)
    assert way is not None
    assert len(way) - 1 <= 2 and way[-1][0] < 3, way


def test_the_cells_seen_mobile_follow_the_map_as_it_grows():
    config = NavigatorConfig(width=10.0, height=10.0, map_growth_step=5.0)
    navigator = Navigator(config)
    labels = navigator.grid.labels
    labels[4, 6] = M
    window = (slice(0, labels.shape[0]), slice(0, labels.shape[1]))
    navigator.give_way.observe(labels, window, 3.0)
    navigator.set_goal(-4.0, 5.0)                         # off the map, west: it grows
    geometry = navigator.grid.geometry
    assert navigator.give_way.last_mobile.shape == geometry.shape
    row, col = geometry.world_to_cell(6 * 0.5 + 0.25, 4 * 0.5 + 0.25)
    assert navigator.give_way.last_mobile[row, col] == 3.0
    last_mobile = navigator.give_way.last_mobile
    assert np.isinf(last_mobile).sum() == last_mobile.size - 1


def test_a_path_through_an_agent_cell_crosses_it_and_one_beside_it_does_not():
    give_way = GiveWay((5, 5), wait_time=10.0, search_distance=6.0, hold_time=10.0)
    labels = np.full((5, 5), E, dtype=np.uint8)
    labels[2, 2] = M
    labels[4, 4] = S                                       # a wall: never mobile
    give_way.observe(labels, (slice(0, 5), slice(0, 5)), 1.0)
    labels[2, 2] = S                                       # the agent stands: steady now
    through = np.array([[2, 0], [2, 1], [2, 2], [2, 3]])
    beside = np.array([[1, 0], [1, 1], [1, 2], [1, 3]])
    assert give_way.crosses_agents(through, labels, stamp=30.0)
    assert not give_way.crosses_agents(beside, labels, stamp=30.0)
    assert not give_way.crosses_agents(np.array([[4, 4]]), labels, stamp=30.0)
    # Mobile longer ago than the memory: a wall now, not an agent.
    assert not give_way.crosses_agents(through, labels, stamp=1.0 + 61.0)


@pytest.mark.parametrize('yaw, expected', [(0.0, 0.0), (math.pi / 2, -math.pi / 2),
                                           (math.pi, math.pi)])
def test_the_facing_error_turns_the_robot_towards_the_agents(yaw, expected):
    give_way = GiveWay((5, 5), wait_time=10.0, search_distance=6.0, hold_time=10.0)
    give_way.agents_xy = (3.0, 1.0)
    assert abs(give_way.facing_error((1.0, 1.0, yaw))) == pytest.approx(abs(expected))
