"""
Trails: mobile cells that a followed object left behind go back to explored.

Every scan marks, in the grid's ``cell_track``, the cells within the safety radius of a hit of a
followed object (``motion_tracks``) with that object's track, and lists them. A listed cell that
is still mobile and still marked goes back to explored, unmarked, once the scan does not see it
(f1 = f2 = 0) and sees its object at least ``trail_distance`` from it: the object has moved on.

`update_trails` is one compiled kernel per scan over the scan's window and the listed cells;
the numpy implementation it replaced is the oracle of the tests
(``test/numpy_label_grid.NumpyExtrasLabelGrid``).

"""

import math

import numpy as np

from .cell_label import CellLabel, ScanInput
from .jit import kernel
from .label_kernel import _mark_discs, squared_bound

_EXPLORED = int(CellLabel.EXPLORED)
_MOBILE = int(CellLabel.MOBILE_OBSTACLE)
_HIT = int(ScanInput.HIT)
_NONE = int(ScanInput.NONE)


def update_trails(cell_track, labels, marked, geometry, window, hits_x, hits_y, hit_ids,
                  track_ids, positions, last_seen, stamp, safety_radius, trail_distance):
    """
    Mark the cells of the followed objects' hits, then clear the trails they left.

    Parameters
    ----------
    cell_track : (rows, cols) ndarray of int64
        Track of each cell's last marking hit, -1 for none; updated in place.
    labels : (rows, cols) ndarray of uint8
        The grid's labels after the scan's update; trail cells are set to explored.
    marked : (M,) ndarray of int64
        Flat indices of the cells that may hold a mark (repeats allowed): every cell of
        ``cell_track`` that holds one is among them.
    geometry : GridGeometry
        The grid's geometry.
    window : (slice, slice, (n_rows, n_cols) ndarray of uint8)
        The scan's window and FSM input (``LabelGrid.last_window``), not empty.
    hits_x, hits_y : (K,) ndarray of float64
        The scan's hits [m].
    hit_ids : (K,) ndarray of int64
        The track each hit's segment continued, -1 for none (``MotionTracks.hit_ids``).
    track_ids : (T,) ndarray of int64
        The tracks (``MotionTracks.ids``).
    positions : (T, 2) ndarray of float64
        Their positions [m].
    last_seen : (T,) ndarray of float64
        When a segment last continued each [s].
    stamp : float
        The scan's time [s].
    safety_radius, trail_distance : float
        f1's ``r`` and ``LabelRule.trail_distance`` [m].

    Returns
    -------
    marked : (M',) ndarray of int64
        The cells that may hold a mark now.
    cleared : (slice, slice)
        A box around the cells set to explored (empty slices when none).

    """
    rows, cols, cell_input = window
    x0, y0 = geometry.origin
    marked, row_lo, row_hi, col_lo, col_hi = _update_trails(
        cell_track, labels, marked, rows.start, cols.start, cell_input, x0, y0,
        geometry.resolution, hits_x, hits_y, hit_ids, track_ids, positions, last_seen,
        float(stamp), float(safety_radius), squared_bound(float(safety_radius)),
        float(trail_distance))
    return marked, (slice(row_lo, max(row_lo, row_hi)), slice(col_lo, max(col_lo, col_hi)))


@kernel
def _update_trails(cell_track, labels, marked, row0, col0, cell_input, x0, y0, resolution,
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
        if 0 <= i < n_rows and 0 <= j < n_cols and cell_input[i, j] == _HIT:
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
        _mark_discs(window, track, hits_x, hits_y, count, selected, row0, col0, x0, y0,
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
                if cell_input[i, j] == _HIT and window[i, j] >= 0:
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
        if mark < 0 or labels[row, col] != _MOBILE:
            cell_track[row, col] = -1
            continue
        i = row - row0
        j = col - col0
        out_of_view = not (0 <= i < n_rows and 0 <= j < n_cols) or cell_input[i, j] == _NONE
        trail = False
        t = seen_index[mark - first_id] if first_id <= mark < first_id + seen_index.shape[0] \
            else -1
        if t >= 0:
            centre_x = x0 + (float(col) + 0.5) * resolution
            centre_y = y0 + (float(row) + 0.5) * resolution
            trail = out_of_view and math.hypot(centre_x - positions[t, 0],
                                               centre_y - positions[t, 1]) >= trail_distance
        if trail:
            labels[row, col] = _EXPLORED
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
