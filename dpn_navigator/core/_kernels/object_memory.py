"""
The object memory's kernels: small objects' steady cells anchored and forgotten.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import math

import numpy as np

from .codes import EXPLORED, NON_EXPLORED, SCAN_NONE, STEADY_OBSTACLE
from .jit import kernel
from .raster import box_end, box_first, disc_rows, mark_discs


@kernel
def mark_near_hits(labels, anchored, listed, cells, count, row0, col0, n_rows, n_cols, x0, y0,
                   resolution, hits_x, hits_y, long, small_object, safety_radius,
                   safety_bound):
    """
    Anchor the window cells near hits of long segments, then list the provisional ones.

    ``anchored`` and ``listed`` are updated in place; ``cells[:count]`` is the list of
    provisional cells (flat grid indices), grown into a new array when full. Returns
    ``(cells, count)``.
    """
    grid_cols = labels.shape[1]
    if n_rows * n_cols > 0 and hits_x.shape[0] > 0:
        hit_count = hits_x.shape[0]
        no_extent = np.zeros((0, 2), dtype=np.int64)
        mark_discs(anchored[row0:row0 + n_rows, col0:col0 + n_cols], True, hits_x, hits_y,
                   hit_count, long, row0, col0, x0, y0, resolution, safety_radius,
                   safety_bound, no_extent)
        # List the steady, unanchored cells near hits of small objects, in grid order: the
        # columns [extent[i, 0], extent[i, 1]) of row i of the discs' box hold those of the
        # row. The box (window rows [box_row, box_row + box_rows), likewise columns) holds
        # every disc, with a cell to spare.
        box_row = n_rows
        box_row_end = 0
        box_col = n_cols
        box_col_end = 0
        for k in range(hit_count):
            if small_object[k]:
                first_row, end_row = disc_rows(hits_y[k], safety_radius, row0, n_rows, y0,
                                               resolution)
                box_row = min(box_row, first_row)
                box_row_end = max(box_row_end, end_row)
                box_col = min(box_col, box_first(col0, n_cols, x0, resolution,
                                                 hits_x[k] - safety_radius))
                box_col_end = max(box_col_end, box_end(col0, n_cols, x0, resolution,
                                                       hits_x[k] + safety_radius))
        box_rows = max(box_row_end - box_row, 0)
        box_cols = max(box_col_end - box_col, 0)
        near = np.zeros((box_rows, box_cols), dtype=np.bool_)
        extent = np.empty((box_rows, 2), dtype=np.int64)
        extent[:, 0] = box_cols
        extent[:, 1] = 0
        if box_rows * box_cols > 0:
            mark_discs(near, True, hits_x, hits_y, hit_count, small_object, row0 + box_row,
                       col0 + box_col, x0, y0, resolution, safety_radius, safety_bound,
                       extent)
        for i in range(box_rows):
            row = row0 + box_row + i
            for j in range(extent[i, 0], extent[i, 1]):
                col = col0 + box_col + j
                if (near[i, j] and labels[row, col] == STEADY_OBSTACLE and not anchored[row, col]
                        and not listed[row, col]):
                    if count == cells.shape[0]:
                        grown = np.empty(2 * cells.shape[0], dtype=np.int64)
                        grown[:count] = cells[:count]
                        cells = grown
                    cells[count] = row * grid_cols + col
                    count += 1
                    listed[row, col] = True
    return cells, count


@kernel
def forget_due(labels, seen_free, last_hit, anchored, listed, cells, count, row0, col0,
               cell_input, x0, y0, resolution, laser_x, laser_y, keep_within, stamp, memory):
    """
    Forget the listed cells that are due; drop those no longer provisional.

    ``labels`` and ``listed`` are updated in place, the kept cells compacted to the front of
    ``cells``. Returns ``(count, forgotten, row_lo, row_hi, col_lo, col_hi)``: the cells kept,
    how many this scan forgot and the half-open box around them.
    """
    n_rows, n_cols = cell_input.shape
    grid_cols = labels.shape[1]
    forgotten = 0
    row_lo = labels.shape[0]
    row_hi = 0
    col_lo = grid_cols
    col_hi = 0
    kept = 0
    for k in range(count):
        flat = cells[k]
        row = flat // grid_cols
        col = flat - row * grid_cols
        if labels[row, col] != STEADY_OBSTACLE or anchored[row, col]:
            listed[row, col] = False
            continue
        i = row - row0
        j = col - col0
        # The conditions in the order of their cost; each is free of side effects.
        if (stamp - last_hit[row, col] >= memory
                and (not (0 <= i < n_rows and 0 <= j < n_cols) or cell_input[i, j] == SCAN_NONE)
                and math.hypot(x0 + (float(col) + 0.5) * resolution - laser_x,
                               y0 + (float(row) + 0.5) * resolution - laser_y) > keep_within):
            labels[row, col] = EXPLORED if seen_free[row, col] else NON_EXPLORED
            listed[row, col] = False
            forgotten += 1
            row_lo = min(row_lo, row)
            row_hi = max(row_hi, row + 1)
            col_lo = min(col_lo, col)
            col_hi = max(col_hi, col + 1)
            continue
        cells[kept] = flat
        kept += 1
    return kept, forgotten, row_lo, row_hi, col_lo, col_hi
