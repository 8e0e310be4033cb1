"""
Tests of the A* planner: literal grids, the corner rule, every error, and two twins.

The Dijkstra twin (`legal_moves`, `dijkstra_cost`) is written straight from the definition of
the moves and shares no code with the planner: it checks costs. The heapq A* the compiled
kernel replaced (`astar_reference.reference_astar`) checks that the kernel returns the very
same path, cell for cell. No ROS is needed: run ``python -m pytest test/core/test_astar.py``
from the repository root (with ``test/`` importable, as pytest makes it).

"""

import doctest
import heapq
import math
import os
import subprocess
import sys

from astar_reference import reference_astar
from dpn_navigator.core.planning import astar_search as astar_module
from dpn_navigator.core.planning.astar_search import astar, path_cost
from grid_worlds import maze_grid, random_grid
from hypothesis import event, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
import numpy as np
import pytest

SQRT2 = math.sqrt(2.0)


def grid_from_text(text):
    """
    Parse a picture of a grid, rows split by whitespace: ``#`` blocked, ``.`` free.

    Returns
    -------
    blocked : (rows, cols) ndarray of bool

    """
    lines = text.split()
    return np.array([[char == '#' for char in line] for line in lines], dtype=bool)


def legal_moves(blocked, cell, cut_corners=True):
    """
    Yield ``(next_cell, step_cost)`` for every move the planner may make from ``cell``.

    Written straight from the definition: 8 neighbours inside the grid, a free target, cost 1
    or sqrt(2), and no diagonal move between two blocked cells.

    """
    rows, cols = blocked.shape
    row, col = cell
    for drow in (-1, 0, 1):
        for dcol in (-1, 0, 1):
            nrow, ncol = row + drow, col + dcol
            if (drow, dcol) == (0, 0) or not (0 <= nrow < rows and 0 <= ncol < cols):
                continue
            if blocked[nrow, ncol]:
                continue
            if drow and dcol and blocked[nrow, col] and blocked[row, ncol]:
                continue
            if drow and dcol and not cut_corners and (blocked[nrow, col] or blocked[row, ncol]):
                continue
            yield (nrow, ncol), (SQRT2 if drow and dcol else 1.0)


def dijkstra_cost(blocked, start, goal, cell_cost=None, cut_corners=True):
    """
    Least path cost from ``start`` to ``goal`` by plain Dijkstra, or None if unreachable.

    With ``cell_cost``, entering a cell costs its value on top of the step.
    """
    dist = {start: 0.0}
    done = set()
    heap = [(0.0, start)]
    while heap:
        cost, cell = heapq.heappop(heap)
        if cell in done:
            continue
        if cell == goal:
            return cost
        done.add(cell)
        for nxt, step in legal_moves(blocked, cell, cut_corners):
            if cell_cost is not None:
                step += float(cell_cost[nxt])
            if cost + step < dist.get(nxt, math.inf):
                dist[nxt] = cost + step
                heapq.heappush(heap, (cost + step, nxt))
    return None


def assert_legal_path(blocked, start, goal, path):
    """Check that ``path`` runs from ``start`` to ``goal`` by legal moves; return its cost."""
    assert path[0] == start
    assert path[-1] == goal
    assert all(isinstance(index, int) for cell in path for index in cell)
    assert not any(blocked[cell] for cell in path[1:])
    total = 0.0
    for here, there in zip(path[:-1], path[1:]):
        moves = dict(legal_moves(blocked, here))
        assert there in moves, f'illegal move {here} -> {there}'
        total += moves[there]
    assert path_cost(path) == pytest.approx(total, rel=1e-12)
    return total


WALL_WITH_GAP = """
...
##.
...
"""

SQUEEZE = """
..#.
.#..
....
"""

U_TURN = """
.....
####.
.....
.####
.....
"""


@pytest.mark.parametrize('text, start, goal, expected', [
    ('...', (0, 0), (0, 2), [(0, 0), (0, 1), (0, 2)]),
    ('... ... ...', (0, 0), (2, 2), [(0, 0), (1, 1), (2, 2)]),
    ('... ... ...', (2, 1), (0, 1), [(2, 1), (1, 1), (0, 1)]),
    ('. . . .', (3, 0), (0, 0), [(3, 0), (2, 0), (1, 0), (0, 0)]),
    # Cuts past one blocked cell at each bend, which is allowed.
    (WALL_WITH_GAP, (0, 0), (2, 0), [(0, 0), (0, 1), (1, 2), (2, 1), (2, 0)]),
    # The direct diagonal squeezes between two blocked cells; the way round is three diagonals.
    (SQUEEZE, (0, 1), (1, 2), [(0, 1), (1, 0), (2, 1), (1, 2)]),
    (U_TURN, (0, 0), (4, 0), [(0, 0), (0, 1), (0, 2), (0, 3), (1, 4), (2, 3), (2, 2), (2, 1),
                              (3, 0), (4, 0)]),
])
def test_literal_grids_give_the_known_path(text, start, goal, expected):
    blocked = grid_from_text(text)
    assert astar(blocked, start, goal) == expected
    assert astar(blocked, goal, start) == expected[::-1]


@pytest.mark.parametrize('text, start, goal, expected_cost', [
    ('... ...', (0, 0), (1, 2), 1.0 + SQRT2),
    ('..... ..... .....', (0, 0), (2, 4), 2.0 + 2.0 * SQRT2),
    (WALL_WITH_GAP, (0, 0), (2, 0), 2.0 + 2.0 * SQRT2),
    (SQUEEZE, (0, 1), (1, 2), 3.0 * SQRT2),
    (U_TURN, (0, 0), (4, 0), 6.0 + 3.0 * SQRT2),
    ('.#... .#.#. .#.#. ...#.', (0, 0), (0, 4), 4.0 + 3.0 * SQRT2),
])
def test_literal_grids_give_the_known_cost(text, start, goal, expected_cost):
    blocked = grid_from_text(text)
    path = astar(blocked, start, goal)
    assert assert_legal_path(blocked, start, goal, path) == pytest.approx(expected_cost)
    assert path_cost(path) == pytest.approx(expected_cost, rel=1e-15)


SYMMETRIES = [
    pytest.param(lambda a: a, id='identity'),
    pytest.param(lambda a: a[::-1], id='flip-rows'),
    pytest.param(lambda a: a[:, ::-1], id='flip-cols'),
    pytest.param(lambda a: a[::-1, ::-1], id='rotate-180'),
    pytest.param(lambda a: a.T, id='transpose'),
]


def transform_cell(transform, shape, cell):
    """Where ``cell`` of a grid of ``shape`` lands when the grid is transformed."""
    index = np.zeros(shape, dtype=bool)
    index[cell] = True
    return tuple(int(i) for i in np.argwhere(transform(index))[0])


@pytest.mark.parametrize('transform', SYMMETRIES)
def test_diagonal_between_two_blocked_cells_is_forbidden(transform):
    blocked = transform(grid_from_text('.# #.'))
    start = transform_cell(transform, (2, 2), (0, 0))
    goal = transform_cell(transform, (2, 2), (1, 1))
    assert astar(blocked, start, goal) is None
    assert astar(blocked, goal, start) is None


@pytest.mark.parametrize('transform', SYMMETRIES)
@pytest.mark.parametrize('text', ['.# ..', '.. #.'])
def test_diagonal_past_one_blocked_cell_is_allowed(transform, text):
    blocked = transform(grid_from_text(text))
    start = transform_cell(transform, (2, 2), (0, 0))
    goal = transform_cell(transform, (2, 2), (1, 1))
    assert astar(blocked, start, goal) == [start, goal]


@pytest.mark.parametrize('transform', SYMMETRIES)
def test_squeeze_forces_the_detour_in_every_orientation(transform):
    blocked = transform(grid_from_text(SQUEEZE))
    start = transform_cell(transform, (3, 4), (0, 1))
    goal = transform_cell(transform, (3, 4), (1, 2))
    path = astar(blocked, start, goal)
    assert assert_legal_path(blocked, start, goal, path) == pytest.approx(3.0 * SQRT2)


def two_route_grid(k, m):
    """
    Build a grid with two corridors from ``start`` to ``goal`` whose costs are close.

    Below runs a V of ``2 k`` diagonal moves, each with a free cell on its outer side so that the
    corner rule lets it pass. Above runs a bump ``m`` rows high: ``m - 1`` moves up, a diagonal,
    ``2 k - 2`` moves along the top row, a diagonal and ``m - 1`` moves down.

    Returns
    -------
    blocked : (m + k + 1, 2 k + 1) ndarray of bool
    start, goal : (int, int)
    v_cost, bump_cost : float
        Costs of the two corridors [cells].

    """
    free = np.zeros((m + k + 1, 2 * k + 1), dtype=bool)
    last = 2 * k
    for i in range(k + 1):
        free[m + i, [i, last - i]] = True
    for i in range(k):
        free[m + i + 1, [i, last - i]] = True
    free[:m + 1, [0, last]] = True
    free[0, :] = True
    v_cost = 2 * k * SQRT2
    bump_cost = 2 * (m - 1) + (2 * k - 2) + 2 * SQRT2
    return ~free, (m, 0), (m, last), v_cost, bump_cost


@pytest.mark.parametrize('k, m, v_wins', [
    # The bump wins by 0.14; with a diagonal cost below 1.4 the V would.
    (6, 3, False),
    # The V wins by 0.20; with a diagonal cost above 10 / 7 = 1.4286 the bump would.
    (8, 4, True),
])
def test_the_diagonal_costs_exactly_sqrt2(k, m, v_wins):
    blocked, start, goal, v_cost, bump_cost = two_route_grid(k, m)
    assert (v_cost < bump_cost) == v_wins
    assert abs(v_cost - bump_cost) < 0.25
    path = astar(blocked, start, goal)
    assert assert_legal_path(blocked, start, goal, path) == pytest.approx(min(v_cost, bump_cost))
    assert all(row >= m for row, _ in path) == v_wins
    assert dijkstra_cost(blocked, start, goal) == pytest.approx(min(v_cost, bump_cost))


@pytest.mark.parametrize('text, start, goal', [
    ('.#. .#. .#.', (0, 0), (2, 2)),
    ('... ### ...', (2, 1), (0, 1)),
    ('.#. #.. ...', (0, 0), (2, 2)),
    ('..#. .#.. #...', (0, 0), (2, 3)),
])
def test_unreachable_goal_gives_none(text, start, goal):
    assert astar(grid_from_text(text), start, goal) is None


@pytest.mark.parametrize('text, cell', [
    ('.', (0, 0)),
    ('#', (0, 0)),
    ('... .#. ...', (1, 1)),
    ('... ... ...', (2, 0)),
])
def test_start_equal_to_goal_gives_the_start(text, cell):
    assert astar(grid_from_text(text), cell, cell) == [cell]


@pytest.mark.parametrize('goal', [(0, 1), (1, 1), (2, 2)])
def test_blocked_goal_gives_none(goal):
    blocked = np.zeros((3, 3), dtype=bool)
    blocked[goal] = True
    assert astar(blocked, (0, 0), goal) is None


def test_blocked_start_may_be_left():
    blocked = grid_from_text('... .#. ...')
    path = astar(blocked, (1, 1), (1, 0))
    assert path == [(1, 1), (1, 0)]
    path = astar(blocked, (1, 1), (2, 2))
    assert path == [(1, 1), (2, 2)]


def test_blocked_start_walled_in_gives_none():
    blocked = grid_from_text('### ### ...')
    assert astar(blocked, (0, 1), (2, 1)) is None
    assert astar(blocked, (1, 1), (2, 2)) == [(1, 1), (2, 2)]


@pytest.mark.parametrize('convert', [
    pytest.param(lambda a: a.tolist(), id='nested-list'),
    pytest.param(lambda a: a.astype(np.uint8), id='uint8'),
    pytest.param(lambda a: a.astype(np.int8) * 100, id='int8-occupancy'),
    pytest.param(lambda a: a.astype(np.float32), id='float32'),
    pytest.param(np.asfortranarray, id='fortran-order'),
])
def test_bool_like_inputs_plan_like_bool(convert):
    blocked = grid_from_text(U_TURN)
    expected = astar(blocked, (0, 0), (4, 0))
    assert astar(convert(blocked), (0, 0), (4, 0)) == expected


def test_strided_view_and_numpy_integer_cells():
    blocked = np.zeros((7, 9), dtype=bool)
    blocked[2, :6] = True
    view = blocked[::2, ::3]  # (4, 3), row 1 blocked except (1, 2); not contiguous
    path = astar(view, (np.int64(0), np.int32(0)), (np.uint8(3), 0))
    assert_legal_path(np.ascontiguousarray(view), (0, 0), (3, 0), path)
    assert path_cost(path) == pytest.approx(dijkstra_cost(view, (0, 0), (3, 0)))


def test_input_is_not_modified():
    blocked = grid_from_text(U_TURN)
    before = blocked.copy()
    astar(blocked, (1, 0), (4, 0))
    np.testing.assert_array_equal(blocked, before)


@pytest.mark.parametrize('blocked, match', [
    (np.zeros(5, dtype=bool), r'2-D .* got 1 dimension'),
    (np.zeros((2, 2, 2), dtype=bool), r'2-D .* got 3 dimension'),
    (np.bool_(False), r'2-D .* got 0 dimension'),
    (np.zeros((0, 3), dtype=bool), r'empty grid of shape \(0, 3\)'),
    (np.zeros((3, 0), dtype=bool), r'empty grid'),
    ([[]], r'empty grid'),
    (np.array([['a', 'b']]), r'array of bool .* got dtype <U1'),
    (np.array([[None, 1]], dtype=object), r'got dtype object'),
    (np.ones((2, 2), dtype=complex), r'got dtype complex128'),
    (np.array([[0.0, np.nan]]), r'NaN or infinite'),
    ([[0, 1], [0]], r'could not convert'),
])
def test_bad_grid_raises(blocked, match):
    with pytest.raises(ValueError, match=match):
        astar(blocked, (0, 0), (0, 0))


@pytest.mark.parametrize('start, goal, match', [
    ((3, 0), (0, 0), r'start \(3, 0\) is outside the grid: row must be in \[0, 3\)'),
    ((0, 4), (0, 0), r'start \(0, 4\) is outside the grid: .* col in \[0, 4\)'),
    ((-1, 0), (0, 0), r'start \(-1, 0\) is outside'),
    ((0, 0), (2, -1), r'goal \(2, -1\) is outside'),
    ((0, 0), (10**20, 0), r'goal \(1{1}0{20}, 0\) is outside'),
    ((0.0, 1), (0, 0), r'start must be a \(row, col\) pair of integers, got \(0.0, 1\)'),
    ((0, 0), (1, np.float64(2.0)), r'goal must be a \(row, col\) pair of integers'),
    ((True, 0), (0, 0), r'start must be a \(row, col\) pair of integers'),
    ((0, 0), (np.bool_(True), 1), r'goal must be a \(row, col\) pair of integers'),
    ((0, 0, 0), (0, 0), r'start must be a \(row, col\) pair'),
    ((0, 0), (1,), r'goal must be a \(row, col\) pair'),
    (5, (0, 0), r'start must be a \(row, col\) pair'),
    (None, (0, 0), r'start must be a \(row, col\) pair'),
    ((0, 0), '12', r'goal must be a \(row, col\) pair of integers'),
])
def test_bad_cells_raise(start, goal, match):
    blocked = np.zeros((3, 4), dtype=bool)
    with pytest.raises(ValueError, match=match):
        astar(blocked, start, goal)


@pytest.mark.parametrize('path, expected', [
    ([], 0.0),
    ([(4, 2)], 0.0),
    ([(0, 0), (0, 1)], 1.0),
    ([(0, 0), (1, 1)], SQRT2),
    ([(2, 2), (1, 1), (1, 0), (0, 0)], 2.0 + SQRT2),
    (np.array([[5, 5], [6, 4], [7, 3]], dtype=np.uint16), 2.0 * SQRT2),
])
def test_path_cost(path, expected):
    assert path_cost(path) == pytest.approx(expected, rel=1e-15)


@pytest.mark.parametrize('path, match', [
    ([(0, 0), (0, 2)], r'step 0 from \(0, 0\) to \(0, 2\) is not a move to an 8-neighbour'),
    ([(0, 0), (1, 1), (1, 1)], r'step 1 from \(1, 1\) to \(1, 1\) is not a move'),
    ([(0, 0), (1.0, 1.0)], r'integer pairs, got an array of shape \(2, 2\) and dtype float64'),
    ([0, 1, 2], r'integer pairs, got an array of shape \(3,\)'),
    (None, r'integer pairs, got an array of shape \(\) and dtype object'),
    ([(0, 0), (1,)], r'sequence of \(row, col\) pairs'),
])
def test_path_cost_rejects_bad_paths(path, match):
    with pytest.raises(ValueError, match=match):
        path_cost(path)


@pytest.mark.parametrize('seed', range(4))
@pytest.mark.parametrize('density', [0.0, 0.2, 0.4])
def test_optimal_on_seeded_larger_grids(seed, density):
    rng = np.random.default_rng(seed)
    blocked = rng.random((25, 30)) < density
    start = (int(rng.integers(25)), int(rng.integers(30)))
    goal = (int(rng.integers(25)), int(rng.integers(30)))
    blocked[goal] = False
    expected = dijkstra_cost(blocked, start, goal)
    path = astar(blocked, start, goal)
    if expected is None:
        assert path is None
    else:
        assert assert_legal_path(blocked, start, goal, path) == pytest.approx(expected, rel=1e-12)


@st.composite
def planning_problems(draw):
    """Draw ``(blocked, start, goal)``: a grid up to 12 x 12 at a density, two distinct cells."""
    rows = draw(st.integers(1, 12))
    cols = draw(st.integers(2, 12))
    percent_blocked = draw(st.sampled_from([0, 10, 20, 30, 45]))
    # Every cell drawn (no fill value); noise shrinks towards 0, so the grid towards free.
    noise = draw(hnp.arrays(np.int8, (rows, cols), elements=st.integers(0, 99),
                            fill=st.nothing()))
    blocked = noise >= 100 - percent_blocked
    # The start shrinks towards the first cell and the goal towards the last one.
    start_index = draw(st.integers(0, rows * cols - 1))
    goal_index = rows * cols - 1 - draw(st.integers(0, rows * cols - 2))
    if goal_index == start_index:
        goal_index -= 1
    start = divmod(start_index, cols)
    goal = divmod(goal_index, cols)
    if draw(st.integers(0, 4)):  # mostly a free goal, sometimes whatever the noise says
        blocked[goal] = False
    return blocked, start, goal


@settings(max_examples=400, deadline=None)
@given(planning_problems())
def test_matches_dijkstra_on_random_small_grids(problem):
    blocked, start, goal = problem
    expected = dijkstra_cost(blocked, start, goal)
    path = astar(blocked, start, goal)
    event('unreachable' if expected is None else f'path of {min(len(path), 6) // 3 * 3}+ cells')
    if expected is None:
        assert path is None
        return
    assert path is not None
    assert assert_legal_path(blocked, start, goal, path) == pytest.approx(expected, rel=1e-12)
    assert path_cost(path) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize('rows, cols', [(1, 1), (3, 7), (200, 200), (999, 999), (4096, 4096)])
def test_fixed_point_diagonal_cost_keeps_every_path_cost_exact(rows, cols):
    diag, bits = astar_module._fixed_point_diagonal_cost(rows, cols)
    assert diag.as_integer_ratio()[1] <= 2 ** bits
    numerator, denominator = diag.as_integer_ratio()
    assert denominator & (denominator - 1) == 0  # a power of two
    assert abs(diag - SQRT2) <= 0.5 / denominator
    assert abs(diag - SQRT2) < 2.0 ** -20
    # Every g, h and f is a + b * diag with a + b <= rows * cols + rows + cols moves. In units
    # of 1 / denominator that is at most numerator * (...), which must fit the 53-bit mantissa
    # for every sum to be exact.
    assert numerator * (rows * cols + rows + cols) <= 2 ** 53
    steps = min(1000, (rows * cols + rows + cols) // 2)
    total = 0.0
    for _ in range(steps):
        total += diag
        total += 1.0
    assert total == steps * diag + steps


def test_docstring_examples_run():
    result = doctest.testmod(astar_module)
    assert result.attempted >= 3
    assert result.failed == 0


def test_core_does_not_import_rclpy():
    # In a fresh interpreter: other test modules of the session may import rclpy themselves.
    code = 'import sys, dpn_navigator.core; print(sorted(sys.modules))'
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(path for path in sys.path if path))
    modules = subprocess.run([sys.executable, '-c', code], env=env, check=True,
                             capture_output=True, text=True).stdout
    assert 'dpn_navigator.core.navigator' in modules
    assert 'rclpy' not in modules


@settings(max_examples=300, deadline=None)
@given(planning_problems(), st.data(), st.booleans())
def test_matches_dijkstra_with_cell_costs(problem, data, cut_corners):
    blocked, start, goal = problem
    # Costs in quarter cells, as a proximity penalty would be, and some arbitrary fractions.
    cell_cost = data.draw(hnp.arrays(np.float64, blocked.shape, elements=st.sampled_from(
        [0.0, 0.25, 1.0, 2.0, 0.3, 1.7]), fill=st.nothing()))
    expected = dijkstra_cost(blocked, start, goal, cell_cost, cut_corners)
    path = astar(blocked, start, goal, cell_cost=cell_cost, cut_corners=cut_corners)
    if expected is None:
        assert path is None
        return
    assert_legal_path(blocked, start, goal, path)
    if not cut_corners:
        for (r0, c0), (r1, c1) in zip(path, path[1:]):
            if r0 != r1 and c0 != c1:                # a diagonal: both side cells free
                assert not blocked[r1, c0] and not blocked[r0, c1]
    paid = path_cost(path) + float(sum(cell_cost[cell] for cell in path[1:]))
    assert paid == pytest.approx(expected, rel=1e-9)


def test_cell_cost_steers_the_path_away_from_costly_cells():
    blocked = np.zeros((3, 5), dtype=bool)
    cost = np.zeros((3, 5))
    cost[1, 1:4] = 5.0                       # the straight row 1 is expensive
    path = astar(blocked, (1, 0), (1, 4), cell_cost=cost)
    assert all(cell[0] != 1 for cell in path[1:-1])
    assert astar(blocked, (1, 0), (1, 4)) == [(1, c) for c in range(5)]
    assert astar(blocked, (1, 0), (1, 4), cell_cost=np.zeros((3, 5))) == \
        [(1, c) for c in range(5)]


@pytest.mark.parametrize(('cell_cost', 'match'), [
    (np.zeros((2, 2)), "grid's shape"),
    (np.full((3, 5), -1.0), 'non-negative'),
    (np.full((3, 5), np.nan), 'finite'),
    ([['a'] * 5] * 3, 'array of numbers'),
])
def test_bad_cell_costs_raise(cell_cost, match):
    with pytest.raises(ValueError, match=match):
        astar(np.zeros((3, 5), dtype=bool), (0, 0), (2, 4), cell_cost=cell_cost)


def test_without_corner_cutting_a_diagonal_needs_both_side_cells_free():
    blocked = grid_from_text("""
        ..
        #.
    """)
    assert astar(blocked, (0, 0), (1, 1)) == [(0, 0), (1, 1)]
    assert astar(blocked, (0, 0), (1, 1), cut_corners=False) == [(0, 0), (0, 1), (1, 1)]


# -- the compiled kernel against the heapq A* it replaced: the same path, cell for cell -------

COST_VALUES = [0.0, 0.25, 1.0, 2.0, 0.3, 1.7]


def assert_same_as_reference(blocked, start, goal, cell_cost=None, cut_corners=True):
    """Check that `astar` and the reference return the same path; return it."""
    path = astar(blocked, start, goal, cell_cost=cell_cost, cut_corners=cut_corners)
    expected = reference_astar(blocked, start, goal, cell_cost=cell_cost,
                               cut_corners=cut_corners)
    assert path == expected
    return path


@settings(max_examples=300, deadline=None)
@given(planning_problems(), st.data(), st.booleans(), st.booleans())
def test_same_path_as_the_reference_on_random_small_grids(problem, data, cut_corners,
                                                          with_cost):
    blocked, start, goal = problem
    cell_cost = None
    if with_cost:
        cell_cost = data.draw(hnp.arrays(np.float64, blocked.shape, elements=st.sampled_from(
            COST_VALUES), fill=st.nothing()))
    path = assert_same_as_reference(blocked, start, goal, cell_cost, cut_corners)
    event('no path' if path is None else 'a path')


@st.composite
def open_lattice_problems(draw):
    """Draw mostly open grids where many paths tie exactly, with sparse blocked cells."""
    rows = draw(st.integers(2, 10))
    cols = draw(st.integers(2, 10))
    blocked = np.zeros((rows, cols), dtype=bool)
    for cell in draw(st.lists(st.tuples(st.integers(0, rows - 1), st.integers(0, cols - 1)),
                              max_size=rows * cols // 6)):
        blocked[cell] = True
    start = (draw(st.integers(0, rows - 1)), draw(st.integers(0, cols - 1)))
    goal = (draw(st.integers(0, rows - 1)), draw(st.integers(0, cols - 1)))
    blocked[goal] = False
    return blocked, start, goal


@settings(max_examples=200, deadline=None)
@given(open_lattice_problems(), st.booleans(), st.sampled_from([None, 0.25, 1.0, 0.3]))
def test_same_path_as_the_reference_where_paths_tie(problem, cut_corners, ring_cost):
    # Open ground: the octile distance ties along many routes, so the tie-breaking (f, then h,
    # then the flat index) decides the path; a ring cost beside blocked cells, as the navigator's
    # proximity cost, adds exact fixed-point ties of its own.
    blocked, start, goal = problem
    cell_cost = None
    if ring_cost is not None:
        padded = np.pad(blocked, 1)
        near = np.zeros_like(blocked)
        for dr in range(3):
            for dc in range(3):
                near |= padded[dr:dr + blocked.shape[0], dc:dc + blocked.shape[1]]
        cell_cost = ring_cost * (near & ~blocked)
    assert_same_as_reference(blocked, start, goal, cell_cost, cut_corners)


@pytest.mark.parametrize('seed', range(3))
@pytest.mark.parametrize('kind', ['random', 'maze'])
@pytest.mark.parametrize('cut_corners', [True, False])
def test_same_path_as_the_reference_on_larger_grids(seed, kind, cut_corners):
    # 60 x 80: thousands of heap entries, so the kernel's heap grows past its first block.
    rng = np.random.default_rng(seed)
    blocked = maze_grid(61, 81, rng) if kind == 'maze' else random_grid(60, 80, 0.3, rng)
    cell_cost = rng.choice(COST_VALUES, size=blocked.shape) if seed else None
    goal = (blocked.shape[0] - 1, blocked.shape[1] - 1)
    path = assert_same_as_reference(blocked, (0, 0), goal, cell_cost, cut_corners)
    if kind == 'maze':
        assert path is not None and len(path) > 100


@pytest.mark.parametrize('text, start, goal, expected', [
    # Round the blocked middle cell above or below: equal f, equal h, so the smaller flat
    # index (the row above) wins.
    ('... .#. ...', (1, 0), (1, 2), [(1, 0), (0, 1), (1, 2)]),
    ('... .#. ...', (1, 2), (1, 0), [(1, 2), (0, 1), (1, 0)]),
    ('... .#. ...', (0, 1), (2, 1), [(0, 1), (1, 0), (2, 1)]),
])
def test_exact_ties_go_to_the_smaller_flat_index(text, start, goal, expected):
    blocked = grid_from_text(text)
    assert astar(blocked, start, goal) == expected
    assert reference_astar(blocked, start, goal) == expected


def test_cell_cost_is_not_modified():
    blocked = grid_from_text(U_TURN)
    cost = np.full(blocked.shape, 0.3)
    before = cost.copy()
    astar(blocked, (0, 0), (4, 0), cell_cost=cost, cut_corners=False)
    np.testing.assert_array_equal(cost, before)
