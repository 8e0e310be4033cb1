"""
The planning masks' kernels: the blocked mask and the proximity cost refreshed in a box.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import numpy as np

from .jit import kernel


#: Cells of a row compared at once before any is looked at alone.
_CHUNK = 64


@kernel
def refresh_blocked(labels, blocked, row_lo, row_hi, col_lo, col_hi, first_blocked, flipped):
    """
    Set ``blocked[rows, cols]`` to ``labels >= first_blocked``; list the cells that flipped.

    Each ``_CHUNK`` cells of a row are first compared at once (a vectorised pass); ``flipped``
    (int64) is grown as needed.
    Returns the flat indices of the flipped cells and their count.
    """
    n_cols = labels.shape[1]
    count = 0
    for r in range(row_lo, row_hi):
        label_row = labels[r, col_lo:col_hi]
        blocked_row = blocked[r, col_lo:col_hi]
        for start in range(0, label_row.shape[0], _CHUNK):
            stop = min(start + _CHUNK, label_row.shape[0])
            differ = False
            for c in range(start, stop):
                differ |= (label_row[c] >= first_blocked) != blocked_row[c]
            if not differ:
                continue
            for c in range(start, stop):
                now_blocked = label_row[c] >= first_blocked
                if now_blocked != blocked_row[c]:
                    blocked_row[c] = now_blocked
                    if count == flipped.shape[0]:
                        grown = np.empty(2 * count + 16, dtype=np.int64)
                        grown[:count] = flipped[:count]
                        flipped = grown
                    flipped[count] = r * n_cols + col_lo + c
                    count += 1
    return flipped, count


@kernel
def recost_around(blocked, cost, cells, proximity_cost):
    """
    Recompute ``cost`` on the cells of ``cells`` (flat indices) and their 8 neighbours.

    A cell costs ``proximity_cost`` when it is free and a neighbour is blocked, else 0.
    Returns the change in the number of cells with a cost.
    """
    n_rows, n_cols = blocked.shape
    change = 0
    for cell in cells:
        row, col = cell // n_cols, cell % n_cols
        for r in range(max(row - 1, 0), min(row + 2, n_rows)):
            for c in range(max(col - 1, 0), min(col + 2, n_cols)):
                touching = False
                if not blocked[r, c]:
                    for rr in range(max(r - 1, 0), min(r + 2, n_rows)):
                        for cc in range(max(c - 1, 0), min(c + 2, n_cols)):
                            touching |= blocked[rr, cc]
                value = proximity_cost if touching else 0.0
                if value != cost[r, c]:
                    change += (value != 0.0) - (cost[r, c] != 0.0)
                    cost[r, c] = value
    return change
