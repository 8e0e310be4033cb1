"""
The space-time oracle's search against its brute-force twin on tiny grids.

``spacetime_reference`` walks the time-expanded graph layer by layer with no heuristic; the
search must find a plan exactly as cheap, and the plan must obey every rule (checked move by
move). The static time to the goal is checked against a Bellman-Ford twin.
"""

import math

from dpn_navigator.benchmark.baselines.spacetime_search import spacetime_plan, \
    static_time_to_goal
from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
from spacetime_reference import plan_cost, reference_best_cost, reference_time_to_goal


@st.composite
def instances(draw):
    rows = draw(st.integers(2, 4))
    cols = draw(st.integers(2, 5))
    horizon = draw(st.integers(1, 7))
    walls = np.array(draw(st.lists(st.booleans(), min_size=rows * cols,
                                   max_size=rows * cols)), dtype=bool).reshape(rows, cols)
    # Agents: sparse blocked cells over time.
    blocked = np.array(draw(st.lists(st.integers(0, 3), min_size=(horizon + 1) * rows * cols,
                                     max_size=(horizon + 1) * rows * cols)),
                       dtype=np.int64).reshape(horizon + 1, rows, cols) == 0
    free = np.argwhere(~walls)
    if len(free) == 0:
        walls[0, 0] = False
        free = np.argwhere(~walls)
    start = tuple(int(v) for v in free[draw(st.integers(0, len(free) - 1))])
    goal = tuple(int(v) for v in free[draw(st.integers(0, len(free) - 1))])
    straight = draw(st.integers(1, 2))
    diagonal = draw(st.integers(straight, 3))
    margin = draw(st.integers(0, 1))
    return walls, blocked, start, goal, straight, diagonal, margin


@settings(max_examples=300)
@given(instances())
def test_static_time_to_goal_matches_bellman_ford(instance):
    walls, _, _, goal, straight, diagonal, _ = instance
    expected = np.array(reference_time_to_goal(walls.tolist(), goal, straight, diagonal),
                        dtype=float)
    np.testing.assert_array_equal(static_time_to_goal(walls, goal, straight, diagonal),
                                  expected)


@settings(max_examples=400)
@given(instances())
def test_plan_is_legal_and_as_cheap_as_the_exhaustive_search(instance):
    walls, blocked, start, goal, straight, diagonal, margin = instance
    to_go = static_time_to_goal(walls, goal, straight, diagonal)
    plan, cost = spacetime_plan(walls, blocked, start, goal, to_go, straight, diagonal,
                                margin)
    best = reference_best_cost(walls.tolist(), blocked.tolist(), start, goal, straight,
                               diagonal, margin)
    if plan is None:
        assert math.isinf(best) and math.isinf(cost)
        return
    assert cost == best
    assert plan_cost(walls.tolist(), blocked.tolist(), plan, start, goal, straight, diagonal,
                     margin) == cost


def test_waiting_beats_the_detour():
    """A corridor with a side loop: the agent holds the corridor's cell at steps 0-3."""
    walls = np.array([[0, 0, 0, 0, 0],
                      [0, 1, 1, 1, 0],
                      [0, 0, 0, 0, 0]], dtype=bool)
    # Straight along row 2 from (2, 0) to (2, 4): 4 steps; the loop over row 0: 8 steps (no
    # diagonal past the wall).
    blocked = np.zeros((13, 3, 5), dtype=bool)
    blocked[0:3, 2, 2] = True
    to_go = static_time_to_goal(walls, (2, 4), 1, 2)
    plan, cost = spacetime_plan(walls, blocked, (2, 0), (2, 4), to_go, 1, 2, margin=0)
    # A move needs both cells free from its start to its end: (2, 2) is entered from step 3
    # on, reached at 4; the goal at 6, after two waits.
    assert cost == 6
    cells = [(r, c) for r, c, _ in plan]
    assert all(r == 2 for r, _ in cells) and len(cells) == 7 and cells[-1] == (2, 4)
    # Held until step 9, the corridor would take 12 steps: the loop (8) wins.
    blocked[0:10, 2, 2] = True
    plan, cost = spacetime_plan(walls, blocked, (2, 0), (2, 4), to_go, 1, 2, margin=0)
    assert any(r == 0 for r, _, _ in plan) and cost == 8


def test_no_plan_when_the_goal_is_walled_off():
    walls = np.array([[0, 1, 0]], dtype=bool)
    to_go = static_time_to_goal(walls, (0, 2), 1, 2)
    plan, cost = spacetime_plan(walls, np.zeros((4, 1, 3), dtype=bool), (0, 0), (0, 2), to_go,
                                1, 2)
    assert plan is None and math.isinf(cost)


def test_horizon_end_is_priced_by_the_time_left():
    walls = np.zeros((1, 8), dtype=bool)
    to_go = static_time_to_goal(walls, (0, 7), 1, 2)
    plan, cost = spacetime_plan(walls, np.zeros((4, 1, 8), dtype=bool), (0, 0), (0, 7), to_go,
                                1, 2)
    assert plan[-1] == (0, 3, 3) and cost == 7


def test_an_agent_beside_the_robot_does_not_pin_it_to_its_cell():
    """The start cell is blocked from step 1 on (an agent stands within reach): it leaves."""
    walls = np.zeros((1, 5), dtype=bool)
    blocked = np.zeros((9, 1, 5), dtype=bool)
    blocked[:, 0, 0] = True                      # the agent's reach covers the robot's cell
    to_go = static_time_to_goal(walls, (0, 4), 1, 2)
    plan, cost = spacetime_plan(walls, blocked, (0, 0), (0, 4), to_go, 1, 2, margin=1)
    assert cost == 4 and plan[0] == (0, 0, 0) and plan[1] == (0, 1, 1)
    # Waiting in the blocked start cell is still no plan: with the way out blocked too, none.
    blocked[:, 0, 1] = True
    plan, cost = spacetime_plan(walls, blocked, (0, 0), (0, 4), to_go, 1, 2, margin=1)
    assert plan is None and math.isinf(cost)
