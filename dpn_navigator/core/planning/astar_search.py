"""
Optimal A* on an 8-connected occupancy grid.

Cells are ``(row, col)``, row-major like ``nav_msgs/OccupancyGrid``. A move goes to one of the
eight neighbours of a cell; it costs 1 along a row or column and sqrt(2) along a diagonal. A
diagonal move from ``(r, c)`` to ``(r + dr, c + dc)`` may cut past one blocked cell but not
squeeze between two: it is forbidden when both ``(r + dr, c)`` and ``(r, c + dc)`` are blocked.
With ``cut_corners=False`` it is forbidden when either is blocked, so that a robot following
the path centre to centre never passes a blocked cell closer than half a cell's diagonal.
The target of every move must be free.

The search is a compiled kernel (numba, ``core/_kernels/astar.py``) that works out the legal
moves and the heuristic of each cell as it reaches it, so a call costs about as much as the
cells it expands, not the size of the grid.

"""

import math
import operator

import numpy as np

from .._kernels import astar as astar_kernels


#: Cost of a move along a row or a column [cells].
ORTHOGONAL_STEP_COST = 1.0
#: Cost of a diagonal move [cells].
DIAGONAL_STEP_COST = math.sqrt(2.0)


# Mantissa bits of a float64, counting the implicit one.
_FLOAT_BITS = 53

# Search state of a cell in the kernel.
_UNSEEN, _OPEN, _CLOSED = 0, 1, 2


def astar(blocked, start, goal, cell_cost=None, cut_corners=True):
    """
    Find a least-cost 8-connected path between two cells of an occupancy grid.

    Parameters
    ----------
    blocked : (rows, cols) array_like of bool
        True (or nonzero) where a cell cannot be entered. Integer and finite float arrays are
        read as ``blocked != 0``.
    start, goal : (int, int)
        Cells ``(row, col)`` to plan from and to. ``start`` may be blocked (say by the
        inflated footprint of the robot that stands there): the path may leave it, but no
        other cell of the path is blocked.
    cell_cost : (rows, cols) array_like of float, optional
        Extra cost of entering each cell [cells], finite and non-negative, e.g. a penalty
        for cells next to obstacles. A move then costs its step cost plus the extra cost of
        the cell it enters. None (the default) is the same as all zeros.
    cut_corners : bool
        Whether a diagonal move may pass one blocked cell (True, the default) or needs both
        cells beside it free.

    Returns
    -------
    path : list of (int, int) or None
        Cells from ``start`` to ``goal`` inclusive, each an 8-neighbour of the one before,
        with least total cost (1 per orthogonal move, sqrt(2) per diagonal move, see
        `path_cost`, plus the ``cell_cost`` of every cell entered). ``[start]`` when
        ``start == goal`` (blocked or not); otherwise None when ``goal`` is blocked or cannot
        be reached.

    Raises
    ------
    ValueError
        If ``blocked`` is not a non-empty 2-D array of bool or numbers, if ``start`` or
        ``goal`` is not a pair of integers inside the grid, or if ``cell_cost`` is not a
        finite, non-negative array of the grid's shape.

    Notes
    -----
    A* with the octile distance as heuristic, which is admissible and consistent for these
    move costs, and a binary heap with lazy deletion, ordered by ``(f, h, cell)`` with
    ``cell = row * cols + col``: ties in f are broken towards the smaller heuristic, which on
    open ground expands little more than the path itself, and then towards the smaller flat
    index. That order is total, so the path does not depend on how the heap is built (it is
    the path of the `heapq` version this kernel replaced, kept in the tests as the oracle).
    Moves and the heuristic are worked out for each cell as the search reaches it: nothing is
    prepared over the whole grid but its input checks and the search's own state arrays
    (allocated zeroed, which the operating system does lazily for large grids).

    For the ties to be exact the search adds costs in fixed point: the diagonal cost is
    sqrt(2) rounded to a multiple of ``2**-m``, with ``m`` as large as lets every g, h and f
    on the grid fit the float64 mantissa (``m = 36`` for 200 x 200, 31 for 1000 x 1000), and
    each extra cell cost is rounded to a multiple of ``2**-m`` too. Sums are then exact and
    equal-cost paths compare equal. Two paths of ``a`` and ``a'`` orthogonal and ``b`` and
    ``b'`` diagonal moves are still ordered as under sqrt(2) whenever
    ``|b - b'| * (|a - a'| + sqrt(2) * |b - b'|) < 2**(m + 1)``, which holds for every pair
    of paths on grids of up to about 100 000 cells: there the path is exactly optimal. On
    larger grids it is within ``|b - b'| * 2**-(m + 1)`` of optimal, the size of the float64
    rounding error of summing that many steps.

    Examples
    --------
    >>> blocked = np.array([[0, 0, 0],
    ...                     [1, 1, 0],
    ...                     [0, 0, 0]], dtype=bool)
    >>> astar(blocked, (0, 0), (2, 0))
    [(0, 0), (0, 1), (1, 2), (2, 1), (2, 0)]
    >>> astar(blocked, (0, 0), (1, 0)) is None
    True

    """
    grid = _as_blocked_grid(blocked)
    start = _as_cell(start, grid.shape, 'start')
    goal = _as_cell(goal, grid.shape, 'goal')
    max_extra = 0.0
    if cell_cost is not None:
        cell_cost, max_extra = _as_cell_cost(cell_cost, grid.shape)
    return astar_checked(grid, start, goal, cell_cost, max_extra, cut_corners)


def astar_checked(blocked, start, goal, cell_cost, max_cell_cost, cut_corners):
    """
    Run `astar` on inputs its caller has already checked, without looking at the whole grid.

    For callers that keep valid inputs as state (the navigator's planning masks): nothing is
    checked here, so that a call costs about as much as the search.

    Parameters
    ----------
    blocked : (rows, cols) ndarray of bool
        C-contiguous.
    start, goal : (int, int)
        Cells inside the grid.
    cell_cost : (rows, cols) or (rows * cols,) ndarray of float64, or None
        C-contiguous, finite and non-negative.
    max_cell_cost : float
        The largest value of ``cell_cost`` (0 without one); it sets the fixed point of the
        costs (see `astar`), so it must be the one `astar` would find for the same paths.
    cut_corners : bool
        As for `astar`.

    Returns
    -------
    path : list of (int, int) or None
        As from `astar`.

    """
    grid = blocked
    if start == goal:
        return [start]
    if grid[goal]:
        return None
    rows, cols = grid.shape
    if cell_cost is None:
        extra_flat = np.zeros(1, dtype=np.float64)  # never read
    else:
        extra_flat = cell_cost.reshape(-1)
    diag_cost, bits = _fixed_point_diagonal_cost(rows, cols, max_cell_cost)
    flat_path = astar_kernels.search(np.ascontiguousarray(grid).reshape(-1), rows, cols,
                                     start[0] * cols + start[1], goal[0] * cols + goal[1],
                                     extra_flat, cell_cost is not None, bool(
                                         cut_corners), diag_cost,
                                     math.ldexp(1.0, bits), math.ldexp(1.0, -bits),
                                     np.zeros(rows * cols, dtype=np.uint8),
                                     np.empty(rows * cols, dtype=np.float64),
                                     np.empty(rows * cols, dtype=np.int64))
    if len(flat_path) == 0:
        return None
    path_rr, path_cc = np.divmod(flat_path, cols)
    return list(zip(path_rr.tolist(), path_cc.tolist()))


def warm_up_astar():
    """Compile (or load from the cache) the A* kernels with one tiny search."""
    astar(np.zeros((2, 2), dtype=bool), (0, 0), (1, 1), cell_cost=np.zeros((2, 2)))


def path_cost(path):
    """
    Total step cost of an 8-connected path.

    Parameters
    ----------
    path : (N, 2) array_like of int
        Cells ``(row, col)`` in order, each an 8-neighbour of the one before, such as a path
        returned by `astar`.

    Returns
    -------
    cost : float
        ``n_orthogonal + sqrt(2) * n_diagonal`` [cells]; 0.0 for a path of zero or one cell.

    Raises
    ------
    ValueError
        If ``path`` is not a sequence of integer pairs, or if two consecutive cells are not
        8-neighbours.

    Examples
    --------
    >>> path_cost([(0, 0), (0, 1), (1, 2)]) == 1.0 + math.sqrt(2.0)
    True

    """
    try:
        cells = np.asarray(path)
    except (TypeError, ValueError) as exc:
        raise ValueError(f'path must be a sequence of (row, col) pairs: {exc}') from exc
    if cells.size == 0:
        return 0.0
    if cells.ndim != 2 or cells.shape[1] != 2 or cells.dtype.kind not in 'iu':
        raise ValueError(
            'path must be a sequence of (row, col) integer pairs, got an array of shape '
            f'{cells.shape} and dtype {cells.dtype}')
    steps = np.abs(np.diff(cells.astype(np.int64), axis=0))
    bad = np.flatnonzero(steps.max(axis=1, initial=0) != 1)
    if len(bad):
        k = int(bad[0])
        raise ValueError(
            f'path step {k} from {tuple(cells[k].tolist())} to {tuple(cells[k + 1].tolist())}'
            ' is not a move to an 8-neighbour')
    n_diagonal = int(np.count_nonzero(steps.min(axis=1, initial=1) == 1))
    n_orthogonal = len(steps) - n_diagonal
    return ORTHOGONAL_STEP_COST * n_orthogonal + DIAGONAL_STEP_COST * n_diagonal


def _as_blocked_grid(blocked):
    """Check ``blocked`` and return it as a (rows, cols) ndarray of bool."""
    try:
        grid = np.asarray(blocked)
    except (TypeError, ValueError) as exc:
        raise ValueError(
            f'blocked must be a 2-D array of bool, could not convert it: {exc}') from exc
    if grid.ndim != 2:
        raise ValueError(
            f'blocked must be a 2-D (rows, cols) array, got {grid.ndim} dimension(s) of shape '
            f'{grid.shape}')
    if grid.size == 0:
        raise ValueError(f'blocked is an empty grid of shape {grid.shape}; give at least 1 x 1')
    kind = grid.dtype.kind
    if kind == 'b':
        return grid
    if kind in 'iu':
        return grid != 0
    if kind == 'f':
        if not np.isfinite(grid).all():
            raise ValueError('blocked holds NaN or infinite values; give a bool array')
        return grid != 0
    raise ValueError(f'blocked must be an array of bool (or numbers), got dtype {grid.dtype}')


def _as_cell_cost(cell_cost, shape):
    """
    Check ``cell_cost`` against the grid's shape.

    Returns
    -------
    cost : (rows * cols,) ndarray of float64
        Row-major, C-contiguous.
    max_cost : float
        Its largest value.

    """
    try:
        cost = np.asarray(cell_cost, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f'cell_cost must be an array of numbers: {exc}') from exc
    if cost.shape != shape:
        raise ValueError(f"cell_cost must have the grid's shape {shape}, got {cost.shape}")
    cost = np.ascontiguousarray(cost).reshape(-1)
    max_cost = astar_kernels.largest_if_finite_and_non_negative(cost)
    if max_cost < 0.0:
        raise ValueError('cell_cost must be finite and non-negative')
    return cost, max_cost


def _as_cell(cell, shape, name):
    """Check that ``cell`` is an integer pair inside a grid of ``shape``; return it as ints."""
    try:
        row, col = cell
    except (TypeError, ValueError):
        raise ValueError(f'{name} must be a (row, col) pair of integers, got {cell!r}') from None
    try:
        if isinstance(row, (bool, np.bool_)) or isinstance(col, (bool, np.bool_)):
            raise TypeError
        row = operator.index(row)
        col = operator.index(col)
    except TypeError:
        raise ValueError(f'{name} must be a (row, col) pair of integers, got {cell!r}') from None
    rows, cols = shape
    if not (0 <= row < rows and 0 <= col < cols):
        raise ValueError(
            f'{name} {(row, col)} is outside the grid: row must be in [0, {rows}) and col in '
            f'[0, {cols})')
    return (row, col)


def _fixed_point_diagonal_cost(rows, cols, max_extra=0.0):
    """
    Sqrt(2) rounded so that path costs on a (rows, cols) grid add exactly in float64.

    Every g, h and f of the search is a sum of at most ``rows * cols + rows + cols`` moves,
    each costing at most ``sqrt(2) + max_extra``, so at most ``max_cost`` below. With the
    diagonal cost (and every extra cell cost) a multiple of ``2**-m`` and
    ``max_cost * 2**m <= 2**52``, all of them are multiples of ``2**-m`` that float64 holds
    exactly, so their sums are exact too.

    Returns
    -------
    diag_cost : float
        The rounded sqrt(2).
    m : int
        The number of fraction bits.

    """
    max_cost = (DIAGONAL_STEP_COST + max_extra) * (rows * cols + rows + cols)
    m = _FLOAT_BITS - 1 - math.ceil(math.log2(max_cost))
    return math.ldexp(round(math.ldexp(DIAGONAL_STEP_COST, m)), -m), m
