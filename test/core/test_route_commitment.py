"""RouteCommitment and ExplorationMemory: what mobile and unknown cells cost, and switching."""

import math

from dpn_navigator.core import CellLabel, GridGeometry
from dpn_navigator.core.planning.exploration_memory import ExplorationMemory
from dpn_navigator.core.planning.route_commitment import RouteCommitment
import numpy as np
import pytest


def commitment(**kwargs):
    options = {'block_distance': 2.0, 'switch_margin': 1.0, 'wait_time': 4.0, 'speed': 1.0,
               'resolution': 0.5, 'blob_depth': 1.0}
    options.update(kwargs)
    return RouteCommitment(**options)


def test_far_mobile_cells_are_free_near_ones_cost_the_wait():
    geometry = GridGeometry(10.0, 1.0, 0.5, (0.0, 0.0))
    labels = np.full(geometry.shape, CellLabel.EXPLORED, dtype=np.uint8)
    labels[0, [2, 15]] = CellLabel.MOBILE_OBSTACLE           # 1.25 m and 7.75 m away
    labels[0, 16] = CellLabel.STEADY_OBSTACLE
    opened, cost = commitment().mobile_terms(labels, geometry, (0.0, 0.25))
    assert np.flatnonzero(opened[0]).tolist() == [2, 15]
    # 4 s at 1 m/s is 8 cells, spread over a blob of 1 m (2 cells).
    assert cost[0, 2] == pytest.approx(4.0) and cost[0, 15] == 0.0
    opened, cost = commitment(wait_time=0.0).mobile_terms(labels, geometry, (0.0, 0.25))
    assert np.flatnonzero(opened[0]).tolist() == [15] and not cost.any()


def test_route_cost_is_the_astar_charge_and_inf_when_blocked():
    route = commitment()
    path = np.array([(0, 0), (0, 1), (1, 2)])
    blocked = np.zeros((2, 3), dtype=bool)
    extra = np.zeros((2, 3))
    extra[1, 2] = 2.5
    assert route.route_cost(path, blocked, extra) == pytest.approx(1.0 + math.sqrt(2.0) + 2.5)
    blocked[0, 0] = True                                      # the start may be blocked
    assert math.isfinite(route.route_cost(path, blocked, None))
    blocked[0, 1] = True
    assert route.route_cost(path, blocked, None) == math.inf


def test_a_new_route_must_be_cheaper_by_the_margin():
    route = commitment()                                      # 1 m: 2 cells
    assert route.keep_current(10.0, 8.5)
    assert not route.keep_current(10.0, 7.9)
    assert not route.keep_current(math.inf, 50.0)
    assert (route.kept, route.switches) == (1, 2)


def test_the_robot_waits_in_front_of_a_mobile_cell_and_counts_the_wait():
    route = commitment()
    labels = np.full((1, 10), CellLabel.EXPLORED, dtype=np.uint8)
    path = np.array([(0, c) for c in range(10)])
    path_xy = np.column_stack((path[:, 1] * 0.5 + 0.25, np.full(10, 0.25)))
    labels[0, 4] = CellLabel.MOBILE_OBSTACLE                  # 2 m ahead: drive on
    assert not route.must_wait(path, path_xy, 0, labels, 0.0)
    assert route.must_wait(path, path_xy, 2, labels, 1.0)     # 1 m ahead: wait
    assert route.must_wait(path, path_xy, 2, labels, 3.5)
    assert route.waited == pytest.approx(2.5)
    labels[0, 4] = CellLabel.EXPLORED
    assert not route.must_wait(path, path_xy, 2, labels, 4.0)
    assert route.waited == 0.0


def test_cells_that_blocked_a_route_hold_back_plans_through_them_for_the_memory():
    route = commitment(block_memory=3.0)
    route.note_blockers([(2.25, 0.25), (2.25, 0.75)], 10.0)
    through = np.array([(1.25, 0.25), (1.75, 0.25), (2.25, 0.75), (2.75, 0.75)])
    past = np.array([(1.25, 0.25), (1.75, 1.25), (2.25, 1.25), (2.75, 1.25)])
    assert route.enters_blocker(through, 10.0)
    assert route.enters_blocker(through, 13.0)                # 3 s later: still
    assert not route.enters_blocker(through, 13.1)            # then no more
    assert not route.enters_blocker(past, 11.0)               # a plan beside them
    assert not route.enters_blocker(through, 9.0)             # the clock went back
    # The robot's own cell (a plan's first) is not entered.
    assert not route.enters_blocker(np.array([(2.25, 0.25), (2.75, 0.25)]), 11.0)
    # A new note keeps the recent ones and drops the old ones.
    route.note_blockers([(5.25, 0.25)], 12.0)
    assert route.enters_blocker(through, 12.5)
    route.note_blockers([(5.25, 0.75)], 14.0)
    assert not route.enters_blocker(through, 14.0)
    assert route.enters_blocker(np.array([(4.75, 0.25), (5.25, 0.25)]), 14.0)
    route.reset()                                             # a new goal
    assert not route.enters_blocker(np.array([(4.75, 0.25), (5.25, 0.75)]), 14.0)
    off = commitment()                                        # block_memory 0: nothing kept
    off.note_blockers([(2.25, 0.25)], 10.0)
    assert not off.enters_blocker(through, 10.0)


def test_bad_settings_raise():
    with pytest.raises(ValueError, match='block_distance'):
        commitment(block_distance=0.0)
    with pytest.raises(ValueError, match='wait_time'):
        commitment(wait_time=-1.0)
    with pytest.raises(ValueError, match='block_memory'):
        commitment(block_memory=math.inf)
    with pytest.raises(ValueError, match='unknown_cost'):
        ExplorationMemory((2, 2), math.nan, 1.0)


def test_unknown_cells_cost_and_forgotten_obstacles_cost_more():
    memory = ExplorationMemory((1, 4), 1.0, 20.0)
    labels = np.array([[CellLabel.NON_EXPLORED, CellLabel.STEADY_OBSTACLE,
                        CellLabel.EXPLORED, CellLabel.NON_EXPLORED]], dtype=np.uint8)
    memory.observe(labels, (slice(0, 1), slice(0, 4), None))
    labels[0, 1] = CellLabel.NON_EXPLORED                     # forgotten
    assert memory.cost(labels).tolist() == [[1.0, 20.0, 0.0, 1.0]]
    assert memory.max_cost == 20.0
