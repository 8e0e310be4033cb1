"""
The per-scan label update: f1, f2 and the FSM over the scan's window, and the ghost expiry.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import math

import numpy as np

from .codes import EXPLORED, MOBILE_OBSTACLE, NON_EXPLORED, SCAN_HIT, SCAN_INSIDE, SCAN_NONE, STEADY_OBSTACLE
from .free_space import mark_free_row, mark_recent_hits, not_surely_free
from .jit import kernel
from .motion_evidence import hit_evidence, moving_hits
from .raster import fill_inside, mark_discs
from .scan_window import scan_points, scan_window


@kernel
def update_window(labels, seen_free, last_hit, listed, transition, row0, col0, cell_input, x0, y0,
                  resolution, vertices_x, vertices_y, hits_x, hits_y, hit_beams,
                  safety_radius, safety_bound, free_on, free_radius, free_bound, objects_on,
                  evidence_radius, evidence_bound, segment_gap, object_size, min_hits,
                  bridge_beams, expiry_on, stamp, path, new_mobile, extra_moving, moving_known,
                  defer_free, extent, free_fresh_after):
    """
    Fold one scan into the window ``labels[row0:row0 + n_rows, col0:col0 + n_cols]``.

    Parameters
    ----------
    labels : (rows, cols) ndarray of uint8
        The grid's labels, updated in place.
    seen_free : (rows, cols) ndarray of bool
        Cells once surely seen free, updated in place; read only with ``free_on``.
    last_hit : (rows, cols) ndarray of float64
        Stamp of each cell's last hit, updated in place; only with ``expiry_on``.
    listed : (rows, cols) ndarray of bool
        Cells in the grid's list of mobile cells; set here for the cells this scan makes
        mobile (with ``expiry_on``), which are also written to ``new_mobile``.
    row0, col0 : int
        The window's first row and column.
    cell_input : (n_rows, n_cols) ndarray of uint8
        Filled with the window's FSM input (``ScanInput``).
    x0, y0, resolution : float
        The grid's origin and cell side [m].
    vertices_x, vertices_y : (L + 2,) ndarray of float64
        The closed scan polygon [m].
    hits_x, hits_y : (K,) ndarray of float64
        Hit points [m].
    hit_beams : (K,) ndarray of int64
        Their beams.
    safety_radius, safety_bound : float
        f1's ``r`` [m] and its ``squared_radius_bound``.
    free_on, objects_on, expiry_on : bool
        Which parts of the ``LabelRule`` are on.
    free_radius, free_bound, evidence_radius, evidence_bound : float
        The free-evidence and motion-evidence radii [m] and their squared bounds.
    segment_gap, object_size : float
        As in ``LabelRule`` [m].
    min_hits : int
        ``LabelRule.object_min_hits``: evidence counts for nothing in a free-standing segment
        of fewer hits.
    bridge_beams : int
        ``LabelRule.segment_bridge_beams``: segments go on across that many beams without a
        hit.
    stamp : float
        The scan's time [s]; read with ``expiry_on``.
    path : (N, 2) ndarray of int64
        The planned path's cells (may be empty).
    new_mobile : (n_rows * n_cols,) ndarray of int64
        Receives the flat grid indices of the cells newly listed.
    extra_moving : (K,) ndarray of bool
        Hits to count as moving besides those the object rule finds (empty: none).
    moving_known : bool
        ``extra_moving`` holds every moving hit, the object rule's included (as `scan_hits`
        finds them): the rule's evidence is not looked for again.
    defer_free : bool
        Leave ``seen_free`` alone (with ``free_on``): `mark_free_window` marks this scan's
        surely-free cells later. No label of this scan depends on them.
    extent : (n_rows, 2) ndarray of int64
        Receives the columns ``[first, end)`` of each window row that f2 filled.
    free_fresh_after : float
        The burn-in (``LabelRule.free_burn_in``): a cell whose ``last_hit`` is later than this
        [s] is not marked surely free; ``-inf`` turns it off.

    Returns
    -------
    replan : bool
        A path cell went from free to an obstacle.
    new_count : int
        How many entries of ``new_mobile`` were written.

    """
    n_rows, n_cols = cell_input.shape
    grid_cols = labels.shape[1]
    # extent[i]: the columns [first, end) of row i that f2 filled; hit_extent[i] those of
    # its f1 cells (which may lie within the first).
    extent[:, 0] = n_cols
    extent[:, 1] = 0
    hit_extent = extent.copy()
    cell_input[...] = SCAN_NONE
    fill_inside(cell_input, row0, col0, x0, y0, resolution, vertices_x, vertices_y, extent)
    no_selection = np.zeros(0, dtype=np.bool_)
    no_extent = np.zeros((0, 2), dtype=np.int64)
    mark_discs(cell_input, SCAN_HIT, hits_x, hits_y, hits_x.shape[0], no_selection, row0, col0,
               x0, y0, resolution, safety_radius, safety_bound, hit_extent)
    near_moving = np.zeros((0, 0), dtype=np.bool_)      # read only with objects_on
    if objects_on:
        if moving_known:
            moving = extra_moving
        else:
            evidence = hit_evidence(seen_free, hits_x, hits_y, x0, y0, resolution,
                                    evidence_radius, evidence_bound)
            moving = moving_hits(hits_x, hits_y, hit_beams, evidence, segment_gap,
                                 object_size, min_hits, vertices_x[0], vertices_y[0],
                                 vertices_x.shape[0] - 2, bridge_beams)
        if not moving_known and extra_moving.shape[0] == moving.shape[0]:
            for k in range(moving.shape[0]):
                if extra_moving[k]:
                    moving[k] = True
        near_moving = np.zeros((n_rows, n_cols), dtype=np.bool_)
        mark_discs(near_moving, True, hits_x, hits_y, hits_x.shape[0], moving, row0, col0,
                   x0, y0, resolution, safety_radius, safety_bound, no_extent)
    mark_free = free_on and not defer_free
    not_free = np.zeros((0, 0), dtype=np.bool_)         # read only with mark_free
    if mark_free:
        not_free = not_surely_free(n_rows, n_cols, row0, col0, x0, y0, resolution,
                                   vertices_x, vertices_y, hit_beams, safety_radius,
                                   free_radius, free_bound)
        if free_fresh_after > -math.inf:
            mark_recent_hits(not_free, row0, col0, last_hit, free_fresh_after)
    # The path's labels before the update, for the replan flag.
    path_before = np.empty(path.shape[0], dtype=np.uint8)
    for k in range(path.shape[0]):
        path_before[k] = labels[path[k, 0], path[k, 1]]
    new_count = 0
    for i in range(n_rows):
        row = row0 + i
        # f2 (INSIDE) cells: explored under every rule; surely seen free when the rule keeps
        # that and no edge band or vertex disc marked them. Written without branches, so that
        # the loop runs on vectors; f1 (HIT) and no-input cells are written back unchanged.
        first = extent[i, 0]
        end = extent[i, 1]
        if first < end:
            row_labels = labels[row, col0 + first:col0 + end]
            row_input = cell_input[i, first:end]
            for j in range(end - first):
                row_labels[j] = EXPLORED if row_input[j] == SCAN_INSIDE else row_labels[j]
            if mark_free:
                mark_free_row(seen_free[row, col0 + first:col0 + end], row_input,
                              not_free[i, first:end])
        # f1 (HIT) cells, which no cell above changed.
        if not (free_on or expiry_on):
            # The paper's rule: the FSM table alone.
            for j in range(hit_extent[i, 0], hit_extent[i, 1]):
                if cell_input[i, j] == SCAN_HIT:
                    col = col0 + j
                    labels[row, col] = transition[(labels[row, col] << 2) | SCAN_HIT]
            continue
        for j in range(hit_extent[i, 0], hit_extent[i, 1]):
            if cell_input[i, j] != SCAN_HIT:
                continue
            col = col0 + j
            old = labels[row, col]
            if old == NON_EXPLORED:
                new = STEADY_OBSTACLE
            elif old == EXPLORED:
                new = MOBILE_OBSTACLE
            else:
                new = old
            if objects_on:
                new = MOBILE_OBSTACLE if near_moving[i, j] else STEADY_OBSTACLE
            elif free_on and old == EXPLORED and not seen_free[row, col]:
                new = STEADY_OBSTACLE
            if expiry_on:
                last_hit[row, col] = stamp
                if new == MOBILE_OBSTACLE and not listed[row, col]:
                    listed[row, col] = True
                    new_mobile[new_count] = row * grid_cols + col
                    new_count += 1
            labels[row, col] = new
    replan = False
    for k in range(path.shape[0]):
        before = path_before[k]
        if before == NON_EXPLORED or before == EXPLORED:
            if labels[path[k, 0], path[k, 1]] >= STEADY_OBSTACLE:
                replan = True
    return replan, new_count


@kernel
def expire_listed(labels, last_hit, listed, cells, count, stamp, mobile_expiry, row0, col0,
                  cell_input):
    """
    Expire the listed mobile cells that are stale and out of view; drop non-mobile ones.

    Returns the count of cells kept (compacted to the front of ``cells``), the earliest
    ``last_hit`` among them (``inf`` when none), and the half-open box ``(row_lo, row_hi,
    col_lo, col_hi)`` of the cells expired (empty when none).
    """
    grid_rows, grid_cols = labels.shape
    n_rows, n_cols = cell_input.shape
    kept = 0
    earliest = math.inf
    row_lo = grid_rows
    row_hi = 0
    col_lo = grid_cols
    col_hi = 0
    for k in range(count):
        flat = cells[k]
        row = flat // grid_cols
        col = flat - row * grid_cols
        if labels[row, col] != MOBILE_OBSTACLE:
            listed[row, col] = False
            continue
        i = row - row0
        j = col - col0
        in_view = 0 <= i < n_rows and 0 <= j < n_cols and cell_input[i, j] != SCAN_NONE
        if not in_view and stamp - last_hit[row, col] >= mobile_expiry:
            labels[row, col] = EXPLORED
            listed[row, col] = False
            row_lo = min(row_lo, row)
            row_hi = max(row_hi, row + 1)
            col_lo = min(col_lo, col)
            col_hi = max(col_hi, col + 1)
            continue
        cells[kept] = flat
        kept += 1
        earliest = min(earliest, last_hit[row, col])
    return kept, earliest, row_lo, row_hi, col_lo, col_hi


@kernel
def scan_update(labels, seen_free, last_hit, listed, transition, ranges, x, y, yaw, angle_min,
                angle_increment, range_min, range_max, x0, y0, resolution, reach,
                safety_radius, safety_bound, free_on, free_radius, free_bound, objects_on,
                evidence_radius, evidence_bound, segment_gap, object_size, min_hits,
                bridge_beams, expiry_on, stamp, path, extra_moving, free_fresh_after):
    """
    Find the scan's points, then run `points_update` with them (nothing deferred).

    Returns ``(replan, row0, row_end, col0, col_end, cell_input, new_mobile)``.
    """
    vertices_x, vertices_y, hits_x, hits_y, hit_beams = scan_points(
        ranges, x, y, yaw, angle_min, angle_increment, range_min, range_max)
    replan, row0, row_end, col0, col_end, cell_input, new_mobile, _ = points_update(
        labels, seen_free, last_hit, listed, transition, vertices_x, vertices_y, hits_x, hits_y,
        hit_beams, x0, y0, resolution, reach, safety_radius, safety_bound, free_on,
        free_radius, free_bound, objects_on, evidence_radius, evidence_bound, segment_gap,
        object_size, min_hits, bridge_beams, expiry_on, stamp, path, extra_moving, False, False,
        free_fresh_after)
    return replan, row0, row_end, col0, col_end, cell_input, new_mobile


@kernel
def points_update(labels, seen_free, last_hit, listed, transition, vertices_x, vertices_y, hits_x,
                  hits_y, hit_beams, x0, y0, resolution, reach, safety_radius, safety_bound,
                  free_on, free_radius, free_bound, objects_on, evidence_radius,
                  evidence_bound, segment_gap, object_size, min_hits, bridge_beams, expiry_on,
                  stamp, path, extra_moving, moving_known, defer_free, free_fresh_after):
    """
    Find the scan's window from its points, then run `update_window` over it.

    Returns ``(replan, row0, row_end, col0, col_end, cell_input, new_mobile, extent)``, the
    last f2's columns per window row (for `mark_free_window` after ``defer_free``); an empty
    window (the scan misses the grid) changes nothing.
    """
    row0, row_end, col0, col_end = scan_window(labels.shape, vertices_x, vertices_y, reach,
                                               x0, y0, resolution)
    n_rows = row_end - row0
    n_cols = col_end - col0
    if n_rows == 0 or n_cols == 0:
        return (False, 0, 0, 0, 0, np.zeros((0, 0), dtype=np.uint8),
                np.zeros(0, dtype=np.int64), np.zeros((0, 2), dtype=np.int64))
    cell_input = np.empty((n_rows, n_cols), dtype=np.uint8)
    new_mobile = np.empty(n_rows * n_cols if expiry_on else 0, dtype=np.int64)
    extent = np.empty((n_rows, 2), dtype=np.int64)
    replan, new_count = update_window(
        labels, seen_free, last_hit, listed, transition, row0, col0, cell_input, x0, y0, resolution,
        vertices_x, vertices_y, hits_x, hits_y, hit_beams, safety_radius, safety_bound,
        free_on, free_radius, free_bound, objects_on, evidence_radius, evidence_bound,
        segment_gap, object_size, min_hits, bridge_beams, expiry_on, stamp, path, new_mobile,
        extra_moving, moving_known, defer_free, extent, free_fresh_after)
    return (replan, row0, row_end, col0, col_end, cell_input, new_mobile[:new_count].copy(),
            extent)
