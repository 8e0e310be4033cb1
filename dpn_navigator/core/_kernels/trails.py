"""
The trail marks' kernel: the cells a followed object leaves, marked and reset.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import math

import numpy as np

from .codes import EXPLORED, MOBILE_OBSTACLE, SCAN_HIT, SCAN_NONE
from .jit import kernel
from .raster import mark_discs


@kernel
def update_trails(cell_track, labels, marked, row0, col0, cell_input, x0, y0, resolution,
                  hits_x, hits_y, hit_ids, track_ids, positions, last_seen, stamp,
                  safety_radius, safety_bound, trail_distance):
    """
    `update_trails` after unpacking: returns ``(marked, row_lo, row_hi, col_lo, col_hi)``.

    The marks of one scan are made track by track in increasing number, each overwriting the
    last, as the numpy implementation did.
    """
    n_rows, n_cols = cell_input.shape
    grid_cols = labels.shape[1]
    window = cell_track[row0:row0 + n_rows, col0:col0 + n_cols]
    # Marks are of the last hit: the scan's f1 cells lose theirs. Only listed cells hold one.
    for k in range(marked.shape[0]):
        row = marked[k] // grid_cols
        col = marked[k] - row * grid_cols
        i = row - row0
        j = col - col0
        if 0 <= i < n_rows and 0 <= j < n_cols and cell_input[i, j] == SCAN_HIT:
            window[i, j] = -1
    # The marks, track by track in increasing number; extent[i] holds the columns marked in
    # window row i.
    count = hit_ids.shape[0]
    selected = np.zeros(count, dtype=np.bool_)
    extent = np.empty((n_rows, 2), dtype=np.int64)
    extent[:, 0] = n_cols
    extent[:, 1] = 0
    done = -1
    while True:
        track = -1
        for k in range(count):
            if hit_ids[k] > done and (track < 0 or hit_ids[k] < track):
                track = hit_ids[k]
        if track < 0:
            break
        for k in range(count):
            selected[k] = hit_ids[k] == track
        mark_discs(window, track, hits_x, hits_y, count, selected, row0, col0, x0, y0,
                   resolution, safety_radius, safety_bound, extent)
        done = track
    # List the cells marked now (hit cells, all reset above), in window order.
    listed = marked
    if done >= 0:
        new = 0
        for i in range(n_rows):
            new += max(extent[i, 1] - extent[i, 0], 0)
        listed = np.empty(marked.shape[0] + new, dtype=np.int64)
        listed[:marked.shape[0]] = marked
        new = marked.shape[0]
        for i in range(n_rows):
            for j in range(extent[i, 0], extent[i, 1]):
                if cell_input[i, j] == SCAN_HIT and window[i, j] >= 0:
                    listed[new] = (row0 + i) * grid_cols + col0 + j
                    new += 1
        listed = listed[:new]
    # Clear the trails of the tracks this scan saw.
    seen = False
    for t in range(track_ids.shape[0]):
        seen = seen or last_seen[t] == stamp
    if not seen or not listed.shape[0]:
        return listed, 0, 0, 0, 0
    # The tracks seen now by id (ids are unique): seen_index[id - first_id], -1 for none.
    first_id = track_ids.min()
    seen_index = np.full(track_ids.max() - first_id + 1, -1, dtype=np.int64)
    for t in range(track_ids.shape[0]):
        if last_seen[t] == stamp:
            seen_index[track_ids[t] - first_id] = t
    # Each cell once, in the order of its first entry: a cell kept is flagged as visited by
    # writing -2 - mark into cell_track until the end of the pass (marks are >= 0).
    kept_cells = np.empty(listed.shape[0], dtype=np.int64)
    kept = 0
    row_lo = labels.shape[0]
    row_hi = 0
    col_lo = grid_cols
    col_hi = 0
    for k in range(listed.shape[0]):
        flat = listed[k]
        row = flat // grid_cols
        col = flat - row * grid_cols
        mark = cell_track[row, col]
        if mark <= -2:
            continue                                # a repeat of a cell kept above
        if mark < 0 or labels[row, col] != MOBILE_OBSTACLE:
            cell_track[row, col] = -1
            continue
        i = row - row0
        j = col - col0
        out_of_view = not (0 <= i < n_rows and 0 <= j < n_cols) or cell_input[i, j] == SCAN_NONE
        trail = False
        t = seen_index[mark - first_id] if first_id <= mark < first_id + seen_index.shape[0] \
            else -1
        if t >= 0:
            centre_x = x0 + (float(col) + 0.5) * resolution
            centre_y = y0 + (float(row) + 0.5) * resolution
            trail = out_of_view and math.hypot(centre_x - positions[t, 0],
                                               centre_y - positions[t, 1]) >= trail_distance
        if trail:
            labels[row, col] = EXPLORED
            cell_track[row, col] = -1
            row_lo = min(row_lo, row)
            row_hi = max(row_hi, row + 1)
            col_lo = min(col_lo, col)
            col_hi = max(col_hi, col + 1)
            continue
        cell_track[row, col] = -2 - mark
        kept_cells[kept] = flat
        kept += 1
    for k in range(kept):
        row = kept_cells[k] // grid_cols
        col = kept_cells[k] - row * grid_cols
        cell_track[row, col] = -2 - cell_track[row, col]
    return kept_cells[:kept].copy(), row_lo, row_hi, col_lo, col_hi
