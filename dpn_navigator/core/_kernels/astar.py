"""
The A* kernel: octile search on an 8-connected grid with a binary heap.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import numpy as np

from .jit import kernel

#: A cell's state in the search.
_UNSEEN, _OPEN, _CLOSED = 0, 1, 2


# Entries of the kernel's binary heap at first; it doubles when full.
_INITIAL_HEAP = 1024


# Moves in the order the search tries them: along rows and columns, then diagonals.
_ORTHOGONAL_MOVES = ((0, 1), (1, 0), (0, -1), (-1, 0))


_DIAGONAL_MOVES = ((1, 1), (1, -1), (-1, 1), (-1, -1))


@kernel
def search(blocked, rows, cols, source, target, extra, has_extra, cut_corners, diag_cost,
           scale, unscale, state, g_score, parent):
    """
    Run the A* loop of `astar` (see its notes); return the path as flat cell indices.

    Parameters
    ----------
    blocked : (rows * cols,) ndarray of bool
        The grid, row-major.
    rows, cols : int
        Its shape.
    source, target : int
        Flat indices of start and goal (distinct; the goal free).
    extra : (rows * cols,) ndarray of float64
        Extra cost of entering each cell, read when ``has_extra``; rounded to a multiple of
        ``unscale`` as it is read.
    has_extra : bool
        Whether there are extra cell costs.
    cut_corners : bool
        The corner rule of `astar`.
    diag_cost : float
        Fixed-point sqrt(2) (`_fixed_point_diagonal_cost`).
    scale, unscale : float
        ``2**m`` and ``2**-m`` for its ``m`` fraction bits.
    state : (rows * cols,) ndarray of uint8
        All ``_UNSEEN``; scratch.
    g_score : (rows * cols,) ndarray of float64
        Scratch, read only where ``state`` is not ``_UNSEEN``.
    parent : (rows * cols,) ndarray of int64
        Scratch, likewise.

    Returns
    -------
    path : (N,) ndarray of int64
        Flat indices from ``source`` to ``target``; empty when there is no path.

    """
    goal_row = target // cols
    goal_col = target - goal_row * cols
    heap_f = np.empty(_INITIAL_HEAP, dtype=np.float64)
    heap_h = np.empty(_INITIAL_HEAP, dtype=np.float64)
    heap_cell = np.empty(_INITIAL_HEAP, dtype=np.int64)
    size = 0
    h_source = octile(source // cols, source % cols, goal_row, goal_col, diag_cost)
    heap_f[0] = h_source
    heap_h[0] = h_source
    heap_cell[0] = source
    size = 1
    state[source] = _OPEN
    g_score[source] = 0.0
    while size > 0:
        cur = heap_cell[0]
        size -= 1
        if size > 0:
            sift_down(heap_f, heap_h, heap_cell, size, heap_f[size], heap_h[size],
                      heap_cell[size])
        if state[cur] == _CLOSED:  # a stale entry
            continue
        if cur == target:
            return trace_back(parent, source, target)
        state[cur] = _CLOSED
        g_cur = g_score[cur]
        row = cur // cols
        col = cur - row * cols
        for k in range(8):
            if k < 4:
                drow, dcol = _ORTHOGONAL_MOVES[k]
            else:
                drow, dcol = _DIAGONAL_MOVES[k - 4]
            nrow = row + drow
            ncol = col + dcol
            if nrow < 0 or nrow >= rows or ncol < 0 or ncol >= cols:
                continue
            nxt = nrow * cols + ncol
            if blocked[nxt] or state[nxt] == _CLOSED:
                continue
            if k < 4:
                g_next = g_cur + 1.0
            else:
                beside_row = blocked[nrow * cols + col]
                beside_col = blocked[row * cols + ncol]
                if cut_corners:
                    if beside_row and beside_col:
                        continue
                elif beside_row or beside_col:
                    continue
                g_next = g_cur + diag_cost
            if has_extra:
                g_next = g_next + np.rint(extra[nxt] * scale) * unscale
            if state[nxt] == _OPEN and not g_next < g_score[nxt]:
                continue
            state[nxt] = _OPEN
            g_score[nxt] = g_next
            parent[nxt] = cur
            h_next = octile(nrow, ncol, goal_row, goal_col, diag_cost)
            if size == len(heap_cell):
                heap_f = grown(heap_f)
                heap_h = grown(heap_h)
                heap_cell = grown(heap_cell)
            sift_up(heap_f, heap_h, heap_cell, size, g_next + h_next, h_next, nxt)
            size += 1
    return np.empty(0, dtype=np.int64)


@kernel
def octile(row, col, goal_row, goal_col, diag_cost):
    """Octile distance from a cell to the goal with diagonal moves of ``diag_cost`` [cells]."""
    drow = float(abs(row - goal_row))
    dcol = float(abs(col - goal_col))
    return min(drow, dcol) * (diag_cost - 2.0) + drow + dcol


@kernel
def before(f_a, h_a, cell_a, f_b, h_b, cell_b):
    """Tell whether heap entry a comes before b: ``(f, h, cell)`` in lexicographic order."""
    if f_a != f_b:
        return f_a < f_b
    if h_a != h_b:
        return h_a < h_b
    return cell_a < cell_b


@kernel
def sift_up(heap_f, heap_h, heap_cell, pos, f, h, cell):
    """Put an entry into the free slot ``pos`` at the end of the heap and restore its order."""
    while pos > 0:
        up = (pos - 1) >> 1
        if not before(f, h, cell, heap_f[up], heap_h[up], heap_cell[up]):
            break
        heap_f[pos] = heap_f[up]
        heap_h[pos] = heap_h[up]
        heap_cell[pos] = heap_cell[up]
        pos = up
    heap_f[pos] = f
    heap_h[pos] = h
    heap_cell[pos] = cell


@kernel
def sift_down(heap_f, heap_h, heap_cell, size, f, h, cell):
    """Put an entry into the free root of a heap of ``size`` entries and restore its order."""
    pos = 0
    while True:
        child = 2 * pos + 1
        if child >= size:
            break
        right = child + 1
        if right < size and before(heap_f[right], heap_h[right], heap_cell[right],
                                   heap_f[child], heap_h[child], heap_cell[child]):
            child = right
        if not before(heap_f[child], heap_h[child], heap_cell[child], f, h, cell):
            break
        heap_f[pos] = heap_f[child]
        heap_h[pos] = heap_h[child]
        heap_cell[pos] = heap_cell[child]
        pos = child
    heap_f[pos] = f
    heap_h[pos] = h
    heap_cell[pos] = cell


@kernel
def grown(values):
    """Return a copy of ``values`` twice as long (the tail uninitialised)."""
    bigger = np.empty(2 * len(values), dtype=values.dtype)
    # An element loop: a slice assignment here took numba 4 CPU-s more to compile.
    for k in range(len(values)):
        bigger[k] = values[k]
    return bigger


@kernel
def trace_back(parent, source, target):
    """Follow ``parent`` links from ``target`` to ``source``; return the cells in path order."""
    length = 1
    cur = target
    while cur != source:
        cur = parent[cur]
        length += 1
    path = np.empty(length, dtype=np.int64)
    cur = target
    for k in range(length - 1, -1, -1):
        path[k] = cur
        cur = parent[cur]
    return path


@kernel
def largest_if_finite_and_non_negative(values):
    """Return the largest of ``values``, or -1.0 if one is NaN, infinite or negative."""
    largest = 0.0
    for value in values:
        if not (0.0 <= value < np.inf):
            return -1.0
        if value > largest:
            largest = value
    return largest
