"""
The per-scan label kernels: f1 and f2 over the scan's window, the FSM, free and motion evidence.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import math

import numpy as np

from .codes import (EXPLORED, MOBILE_OBSTACLE, NON_EXPLORED, SCAN_HIT, SCAN_INSIDE, SCAN_NONE,
                    STEADY_OBSTACLE)
from .jit import kernel
from .raster import disc_box, fill_inside, mark_discs, mark_uncovered_edge_bands



@kernel
def moving_hits(hits_x, hits_y, hit_beams, evidence, segment_gap, object_size, min_hits,
                laser_x, laser_y, beam_count):
    """``moving_objects.moving_object_hits`` as a loop, with the same arithmetic."""
    count = hits_x.shape[0]
    moving = np.zeros(count, dtype=np.bool_)
    segment = np.zeros(count, dtype=np.int64)
    arc = np.zeros(count, dtype=np.float64)
    for k in range(1, count):
        dx = hits_x[k] - hits_x[k - 1]
        dy = hits_y[k] - hits_y[k - 1]
        step = math.sqrt(dx * dx + dy * dy)
        cut = step > segment_gap or hit_beams[k] - hit_beams[k - 1] != 1
        segment[k] = segment[k - 1] + (1 if cut else 0)
        arc[k] = arc[k - 1] + step
    # Evidence counts for nothing in a free-standing segment of fewer than min_hits hits.
    if min_hits > 1 and count > 0:
        evidence = evidence.copy()
        start = 0
        for k in range(1, count + 1):
            if k == count or segment[k] != segment[k - 1]:
                if k - start < min_hits and free_standing(
                        hits_x, hits_y, hit_beams, start, k, laser_x, laser_y, beam_count):
                    evidence[start:k] = False
                start = k
    # The nearest hit with evidence at or before each hit, then at or after it.
    last = -1
    for k in range(count):
        if evidence[k]:
            last = k
        if last >= 0 and segment[last] == segment[k] and arc[k] - arc[last] <= object_size:
            moving[k] = True
    last = -1
    for k in range(count - 1, -1, -1):
        if evidence[k]:
            last = k
        if last >= 0 and segment[last] == segment[k] and arc[last] - arc[k] <= object_size:
            moving[k] = True
    return moving


@kernel
def free_standing(hits_x, hits_y, hit_beams, start, stop, laser_x, laser_y, beam_count):
    """
    Tell whether the segment of hits ``start:stop`` stands free: both its ends are open.

    An end is open when the beam just outside it exists and returns nothing, or a hit farther
    from the laser than the end (``motion_tracks``' open sides, the same arithmetic).
    """
    count = hits_x.shape[0]
    distance_first = math.hypot(hits_x[start] - laser_x, hits_y[start] - laser_y)
    distance_last = math.hypot(hits_x[stop - 1] - laser_x, hits_y[stop - 1] - laser_y)
    if start > 0 and hit_beams[start - 1] == hit_beams[start] - 1:
        open_before = math.hypot(hits_x[start - 1] - laser_x,
                                 hits_y[start - 1] - laser_y) > distance_first
    else:
        open_before = hit_beams[start] > 0
    if stop < count and hit_beams[stop] == hit_beams[stop - 1] + 1:
        open_after = math.hypot(hits_x[stop] - laser_x,
                                hits_y[stop] - laser_y) > distance_last
    else:
        open_after = hit_beams[stop - 1] < beam_count - 1
    return open_before and open_after


@kernel
def hit_evidence(seen_free, hits_x, hits_y, x0, y0, resolution, radius, bound):
    """Tell for each hit whether a cell once surely seen free lies within ``radius``."""
    rows, cols = seen_free.shape
    count = hits_x.shape[0]
    evidence = np.zeros(count, dtype=np.bool_)
    # Every disc searched in its box, small or not: a box row is read whole, without branches.
    reach = int(math.ceil(radius / resolution)) + 1
    dx2 = np.empty(2 * reach + 1)
    for k in range(count):
        evidence[k] = disc_holds(seen_free, hits_x[k], hits_y[k], x0, y0, resolution, bound,
                                 reach, dx2)
    return evidence


@kernel
def disc_holds(cells, px, py, x0, y0, resolution, bound, reach, dx2):
    """
    Tell whether a True cell of ``cells`` passes ``dx*dx + dy*dy <= bound`` around a point.

    The cells searched are those of `disc_box` with ``reach``, a row at a time: each row's
    test is or-ed over the whole row of the box, which runs on vectors. ``dx2`` holds at
    least ``2 * reach + 1`` values.
    """
    first_row, end_row, first_col, end_col = disc_box(
        px, py, 0, cells.shape[0], 0, cells.shape[1], x0, y0, resolution, reach)
    for j in range(first_col, end_col):
        dx = (x0 + (float(j) + 0.5) * resolution) - px
        dx2[j - first_col] = dx * dx
    for i in range(first_row, end_row):
        dy = (y0 + (float(i) + 0.5) * resolution) - py
        dy2 = dy * dy
        if dy2 > bound:
            continue
        found = False
        for j in range(first_col, end_col):
            found |= cells[i, j] & (dx2[j - first_col] + dy2 <= bound)
        if found:
            return True
    return False


@kernel
def scan_points(ranges, x, y, yaw, angle_min, angle_increment, range_min, range_max):
    """
    ``scan_polygon.scan_points`` as a loop: the closed polygon and the hits of a scan.

    Beam ``i`` points along ``yaw + (angle_min + i * angle_increment)``; ``math.cos`` and
    ``math.sin`` are the C library's, as in the literal twin.
    """
    beams = ranges.shape[0]
    vertices_x = np.empty(beams + 2)
    vertices_y = np.empty(beams + 2)
    vertices_x[0] = vertices_x[beams + 1] = x
    vertices_y[0] = vertices_y[beams + 1] = y
    hit_beams = np.empty(beams, dtype=np.int64)
    hit_count = 0
    for i in range(beams):
        reading = ranges[i]
        theta = yaw + (angle_min + float(i) * angle_increment)
        if reading >= range_min and reading < range_max:     # False for NaN
            reach = reading
            hit_beams[hit_count] = i
            hit_count += 1
        elif reading >= range_max:                           # True for +inf
            reach = range_max
        else:
            reach = 0.0
        vertices_x[i + 1] = x + reach * math.cos(theta)
        vertices_y[i + 1] = y + reach * math.sin(theta)
    hit_beams = hit_beams[:hit_count].copy()
    hits_x = np.empty(hit_count)
    hits_y = np.empty(hit_count)
    for k in range(hit_count):
        hits_x[k] = vertices_x[hit_beams[k] + 1]
        hits_y[k] = vertices_y[hit_beams[k] + 1]
    return vertices_x, vertices_y, hits_x, hits_y, hit_beams


@kernel
def window_bound(low, origin, resolution, margin, count):
    """``GridGeometry.cell_window``'s bound of one axis (``margin`` negative for the low end)."""
    index = np.floor((low - origin) / resolution) + margin
    return int(min(max(index, 0.0), float(count)))


@kernel
def scan_window(shape, vertices_x, vertices_y, reach, x0, y0, resolution):
    """
    ``GridGeometry.cell_window`` of the polygon's box widened by ``reach`` [m], margin 1.

    Returns the half-open ``(row0, row_end, col0, col_end)`` on a grid of ``shape``.
    """
    rows, cols = shape
    row0 = window_bound(vertices_y.min() - reach, y0, resolution, -1.0, rows)
    row_end = max(row0, window_bound(vertices_y.max() + reach, y0, resolution, 2.0, rows))
    col0 = window_bound(vertices_x.min() - reach, x0, resolution, -1.0, cols)
    col_end = max(col0, window_bound(vertices_x.max() + reach, x0, resolution, 2.0, cols))
    return row0, row_end, col0, col_end


@kernel
def not_surely_free(n_rows, n_cols, row0, col0, x0, y0, resolution, vertices_x, vertices_y,
                    hit_beams, safety_radius, free_radius, free_bound):
    """
    Mark the window cells that a scan cannot show surely free: near a vertex or an edge.

    Returns the window's ``(n_rows, n_cols)`` marks: every vertex's disc of ``free_radius``
    and every edge band beyond the ends' discs (`mark_uncovered_edge_bands`). Within the
    safety radius a hit's disc holds only f1 cells, which are never marked free, so then only
    the vertices that are not hits need theirs.
    """
    not_free = np.zeros((n_rows, n_cols), dtype=np.bool_)
    # Every vertex but the closing repeat of the first.
    not_hit = np.zeros(0, dtype=np.bool_)
    if free_radius <= safety_radius:
        not_hit = np.ones(vertices_x.shape[0], dtype=np.bool_)
        for k in range(hit_beams.shape[0]):
            not_hit[hit_beams[k] + 1] = False
    mark_discs(not_free, True, vertices_x, vertices_y, vertices_x.shape[0] - 1, not_hit,
               row0, col0, x0, y0, resolution, free_radius, free_bound,
               np.zeros((0, 2), dtype=np.int64))
    # Every vertex's disc of free_radius is marked or f1: the bands need only the rest.
    mark_uncovered_edge_bands(not_free, row0, col0, x0, y0, resolution, vertices_x,
                              vertices_y, free_radius)
    return not_free


@kernel
def mark_free_row(row_free, row_input, row_not_free):
    """Set ``row_free`` on the f2 cells of a row run not in ``row_not_free``; no branches."""
    for j in range(row_free.shape[0]):
        row_free[j] = row_free[j] | ((row_input[j] == SCAN_INSIDE) & (not row_not_free[j]))


@kernel
def mark_free_window(seen_free, row0, col0, cell_input, extent, x0, y0, resolution,
                     vertices_x, vertices_y, hit_beams, safety_radius, free_radius,
                     free_bound):
    """
    Mark the surely-free cells of a scan whose update left them (``defer_free``).

    The arguments are those of that `update_window` call, its ``cell_input`` and ``extent``
    as it filled them; ``seen_free`` becomes what the call would have made it.
    """
    n_rows, n_cols = cell_input.shape
    not_free = not_surely_free(n_rows, n_cols, row0, col0, x0, y0, resolution, vertices_x,
                               vertices_y, hit_beams, safety_radius, free_radius, free_bound)
    mark_free_rows(seen_free, row0, col0, cell_input, extent, not_free)


@kernel
def mark_free_rows(seen_free, row0, col0, cell_input, extent, not_free):
    """`mark_free_row` over each window row's f2 columns ``[extent[i, 0], extent[i, 1])``."""
    for i in range(cell_input.shape[0]):
        first = extent[i, 0]
        end = extent[i, 1]
        if first < end:
            mark_free_row(seen_free[row0 + i, col0 + first:col0 + end],
                          cell_input[i, first:end], not_free[i, first:end])


@kernel
def update_window(labels, seen_free, last_hit, listed, transition, row0, col0, cell_input, x0, y0,
                  resolution, vertices_x, vertices_y, hits_x, hits_y, hit_beams,
                  safety_radius, safety_bound, free_on, free_radius, free_bound, objects_on,
                  evidence_radius, evidence_bound, segment_gap, object_size, min_hits,
                  expiry_on, stamp, path, new_mobile, extra_moving, moving_known, defer_free,
                  extent):
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
                                 vertices_x.shape[0] - 2)
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
                evidence_radius, evidence_bound, segment_gap, object_size, min_hits, expiry_on,
                stamp, path, extra_moving):
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
        object_size, min_hits, expiry_on, stamp, path, extra_moving, False, False)
    return replan, row0, row_end, col0, col_end, cell_input, new_mobile


@kernel
def points_update(labels, seen_free, last_hit, listed, transition, vertices_x, vertices_y, hits_x,
                  hits_y, hit_beams, x0, y0, resolution, reach, safety_radius, safety_bound,
                  free_on, free_radius, free_bound, objects_on, evidence_radius,
                  evidence_bound, segment_gap, object_size, min_hits, expiry_on, stamp, path,
                  extra_moving, moving_known, defer_free):
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
        segment_gap, object_size, min_hits, expiry_on, stamp, path, new_mobile, extra_moving,
        moving_known, defer_free, extent)
    return (replan, row0, row_end, col0, col_end, cell_input, new_mobile[:new_count].copy(),
            extent)


@kernel
def surely_free_update(seen_free, ranges, x, y, yaw, angle_min, angle_increment, range_min,
                       range_max, x0, y0, resolution, radius, bound):
    """
    Mark the cells whose disc of ``radius`` lies inside the scan's polygon as surely free.

    Exactly the ``seen_free`` of `update_window` under a rule with only the conservative free
    space on and a safety radius equal to ``radius``: f2 cells that no vertex's disc and no
    edge band reaches (a hit's f1 disc is its vertex's disc). Nothing else is computed.
    """
    vertices_x, vertices_y, _, _, _ = scan_points(
        ranges, x, y, yaw, angle_min, angle_increment, range_min, range_max)
    # The window of `points_update` with reach = radius.
    row0, row_end, col0, col_end = scan_window(seen_free.shape, vertices_x, vertices_y, radius,
                                               x0, y0, resolution)
    n_rows = row_end - row0
    n_cols = col_end - col0
    if n_rows == 0 or n_cols == 0:
        return
    cell_input = np.zeros((n_rows, n_cols), dtype=np.uint8)
    extent = np.empty((n_rows, 2), dtype=np.int64)
    extent[:, 0] = n_cols
    extent[:, 1] = 0
    fill_inside(cell_input, row0, col0, x0, y0, resolution, vertices_x, vertices_y, extent)
    # Every vertex's disc, hits included (their f1 discs): a safety radius of 0 selects them
    # all.
    not_free = not_surely_free(n_rows, n_cols, row0, col0, x0, y0, resolution, vertices_x,
                               vertices_y, np.zeros(0, dtype=np.int64), 0.0, radius, bound)
    mark_free_rows(seen_free, row0, col0, cell_input, extent, not_free)
