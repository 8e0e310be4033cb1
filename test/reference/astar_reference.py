"""
The heapq A* that `dpn_navigator.core.astar` replaced: the oracle of its compiled kernel.

This is the core's A* as it was before the kernel (main at e53c505), unchanged but for its
name, `reference_astar`, and for using the core's own input checks, step costs and fixed-point
diagonal cost: plain Python over flat cell indices, with numpy working out for the whole grid
up front which moves are legal from each cell, and the heuristic. The tests check
that the kernel returns the very same path (not only the same cost) on every instance, and
``tools/bench_core.py`` times the two against each other.

Cells are ``(row, col)``, row-major. A move goes to one of the eight neighbours of a cell; it
costs 1 along a row or column and sqrt(2) along a diagonal. A diagonal move from ``(r, c)`` to
``(r + dr, c + dc)`` is forbidden when both ``(r + dr, c)`` and ``(r, c + dc)`` are blocked
(with ``cut_corners=False``: when either is). The target of every move must be free.

"""

from array import array
import heapq
import math

# Input checks and the fixed-point diagonal cost are the core's own: what this twin checks is
# the search.
from dpn_navigator.core.planning.astar_search import (_as_blocked_grid, _as_cell, _as_cell_cost,
                                                      _fixed_point_diagonal_cost,
                                                      ORTHOGONAL_STEP_COST)
import numpy as np

# Bit k of a cell's orthogonal (diagonal) move mask is set when move k of this tuple is legal.
_ORTHOGONAL_MOVES = ((0, 1), (1, 0), (0, -1), (-1, 0))
_DIAGONAL_MOVES = ((1, 1), (1, -1), (-1, 1), (-1, -1))

# g-score of an expanded cell: below every real cost, so no move improves on it.
_CLOSED = -1.0


def reference_astar(blocked, start, goal, cell_cost=None, cut_corners=True):
    """
    Find a least-cost 8-connected path as `dpn_navigator.core.astar` did before its kernel.

    Parameters, result and errors are those of `dpn_navigator.core.astar`.

    Notes
    -----
    A* with the octile distance as heuristic and a binary heap (`heapq`) with lazy deletion,
    ordered by ``(f, h, flat index)``. Before the loop, numpy works out for the whole grid which
    moves are legal from each cell (inside the grid, free target, corner rule) as two 4-bit
    masks, and the heuristic of each cell; the loop then walks a tuple of flat-index offsets
    per cell, with no bounds or obstacle checks. Costs add in the core's fixed point.

    Examples
    --------
    >>> blocked = np.array([[0, 0, 0],
    ...                     [1, 1, 0],
    ...                     [0, 0, 0]], dtype=bool)
    >>> reference_astar(blocked, (0, 0), (2, 0))
    [(0, 0), (0, 1), (1, 2), (2, 1), (2, 0)]

    """
    grid = _as_blocked_grid(blocked)
    start = _as_cell(start, grid.shape, 'start')
    goal = _as_cell(goal, grid.shape, 'goal')
    extra_cost = None if cell_cost is None else _as_cell_cost(cell_cost, grid.shape)[0]
    if start == goal:
        return [start]
    if grid[goal]:
        return None
    rows, cols = grid.shape
    ortho_mask, diag_mask = _move_masks(grid, cut_corners)
    ortho_moves = _move_offsets(_ORTHOGONAL_MOVES, cols)
    diag_moves = _move_offsets(_DIAGONAL_MOVES, cols)
    max_extra = 0.0 if extra_cost is None else float(extra_cost.max())
    diag_cost, bits = _fixed_point_diagonal_cost(rows, cols, max_extra)
    heuristic = _octile_distance(rows, cols, goal, diag_cost)
    if extra_cost is not None:
        # The same fixed point as the diagonal cost, so that sums stay exact.
        extra = memoryview(np.ldexp(np.round(np.ldexp(extra_cost, bits)), -bits).ravel())
        return _search_with_cell_cost(start, goal, cols, ortho_mask, diag_mask, ortho_moves,
                                      diag_moves, diag_cost, heuristic, extra)
    # Without cell costs the loop below runs on its own: folding it into
    # `_search_with_cell_cost` with zero costs made it about 20 % slower (200x200, corner to
    # corner: 9.6 against 8.0 ms on random obstacles, 9.0 against 7.3 ms in a maze), and the
    # wanderers of the simulator plan with it on every walk.

    source = start[0] * cols + start[1]
    target = goal[0] * cols + goal[1]
    g_score = [math.inf] * (rows * cols)
    parent = array('l', [0]) * (rows * cols)
    g_score[source] = 0.0
    push = heapq.heappush
    pop = heapq.heappop
    open_heap = [(heuristic[source], heuristic[source], source)]
    while open_heap:
        cur = pop(open_heap)[2]
        g_cur = g_score[cur]
        if g_cur < 0.0:  # closed already: a stale entry
            continue
        if cur == target:
            return _trace_back(parent, source, target, cols)
        g_score[cur] = _CLOSED
        g_next = g_cur + ORTHOGONAL_STEP_COST
        for offset in ortho_moves[ortho_mask[cur]]:
            nxt = cur + offset
            if g_next < g_score[nxt]:
                g_score[nxt] = g_next
                parent[nxt] = cur
                h_next = heuristic[nxt]
                push(open_heap, (g_next + h_next, h_next, nxt))
        g_next = g_cur + diag_cost
        for offset in diag_moves[diag_mask[cur]]:
            nxt = cur + offset
            if g_next < g_score[nxt]:
                g_score[nxt] = g_next
                parent[nxt] = cur
                h_next = heuristic[nxt]
                push(open_heap, (g_next + h_next, h_next, nxt))
    return None


def _search_with_cell_cost(start, goal, cols, ortho_mask, diag_mask, ortho_moves, diag_moves,
                           diag_cost, heuristic, extra):
    """Run the A* loop of `reference_astar` with an extra cost per cell entered."""
    source = start[0] * cols + start[1]
    target = goal[0] * cols + goal[1]
    g_score = [math.inf] * len(heuristic)
    parent = array('l', [0]) * len(heuristic)
    g_score[source] = 0.0
    push = heapq.heappush
    pop = heapq.heappop
    open_heap = [(heuristic[source], heuristic[source], source)]
    while open_heap:
        cur = pop(open_heap)[2]
        g_cur = g_score[cur]
        if g_cur < 0.0:  # closed already: a stale entry
            continue
        if cur == target:
            return _trace_back(parent, source, target, cols)
        g_score[cur] = _CLOSED
        for moves, step in ((ortho_moves[ortho_mask[cur]], ORTHOGONAL_STEP_COST),
                            (diag_moves[diag_mask[cur]], diag_cost)):
            g_step = g_cur + step
            for offset in moves:
                nxt = cur + offset
                g_next = g_step + extra[nxt]
                if g_next < g_score[nxt]:
                    g_score[nxt] = g_next
                    parent[nxt] = cur
                    h_next = heuristic[nxt]
                    push(open_heap, (g_next + h_next, h_next, nxt))
    return None


def _move_masks(grid, cut_corners=True):
    """
    Which moves are legal from each cell, as two flat bit masks.

    Parameters
    ----------
    grid : (rows, cols) ndarray of bool
        True where blocked.
    cut_corners : bool
        Whether a diagonal move needs one (True) or both (False) of the cells beside it free.

    Returns
    -------
    ortho_mask, diag_mask : bytes of length rows * cols
        Bit k of byte ``r * cols + c`` is set when move k of ``_ORTHOGONAL_MOVES``
        (``_DIAGONAL_MOVES``) from ``(r, c)`` stays in the grid, ends on a free cell and, for a
        diagonal move, does not pass between two blocked cells (with ``cut_corners=False``: beside
        any blocked cell). The state of ``(r, c)`` itself
        does not matter.

    """
    rows, cols = grid.shape
    free = np.zeros((rows + 2, cols + 2), dtype=np.uint8)  # a blocked border: no bounds checks
    free[1:-1, 1:-1] = ~grid

    def shifted(dr, dc):
        return free[1 + dr:rows + 1 + dr, 1 + dc:cols + 1 + dc]

    ortho_mask = np.zeros((rows, cols), dtype=np.uint8)
    for bit, (dr, dc) in enumerate(_ORTHOGONAL_MOVES):
        ortho_mask |= shifted(dr, dc) << bit
    diag_mask = np.zeros((rows, cols), dtype=np.uint8)
    for bit, (dr, dc) in enumerate(_DIAGONAL_MOVES):
        beside = (shifted(dr, 0) | shifted(0, dc)) if cut_corners else \
            (shifted(dr, 0) & shifted(0, dc))
        diag_mask |= (shifted(dr, dc) & beside) << bit
    return ortho_mask.tobytes(), diag_mask.tobytes()


def _move_offsets(moves, cols):
    """Flat-index offsets of the legal moves for each of the 16 values of a 4-bit move mask."""
    offsets = [dr * cols + dc for dr, dc in moves]
    return [tuple(offset for bit, offset in enumerate(offsets) if mask >> bit & 1)
            for mask in range(1 << len(moves))]


def _octile_distance(rows, cols, goal, diag_cost):
    """
    Octile distance of every cell to ``goal``, with diagonal moves of ``diag_cost``.

    Returns
    -------
    distance : (rows * cols,) memoryview of float64
        ``drow + dcol + (diag_cost - 2) * min(drow, dcol)`` for the cell ``r * cols + c``, where
        ``drow = |r - goal_row|`` and ``dcol = |c - goal_col|`` [cells]. Indexing a memoryview
        yields Python floats as fast as a list does, without building a million of them.

    """
    drow = np.abs(np.arange(rows, dtype=np.float64) - goal[0])
    dcol = np.abs(np.arange(cols, dtype=np.float64) - goal[1])
    distance = np.minimum.outer(drow, dcol)
    distance *= diag_cost - 2.0
    distance += drow[:, np.newaxis]
    distance += dcol
    return memoryview(distance.ravel())


def _trace_back(parent, source, target, cols):
    """Follow ``parent`` links from ``target`` to ``source``; return the cells in path order."""
    flat = [target]
    cur = target
    while cur != source:
        cur = parent[cur]
        flat.append(cur)
    flat.reverse()
    return [divmod(index, cols) for index in flat]
