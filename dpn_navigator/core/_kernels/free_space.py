"""
Surely-free space: the cells whose disc lies inside one scan's polygon, marked.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import math

import numpy as np

from .codes import SCAN_INSIDE
from .jit import kernel
from .raster import fill_inside, mark_discs, mark_uncovered_edge_bands
from .scan_window import scan_points, scan_window


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
                     free_bound, last_hit, free_fresh_after):
    """
    Mark the surely-free cells of a scan whose update left them (``defer_free``).

    The arguments are those of that `update_window` call, its ``cell_input`` and ``extent``
    as it filled them; ``seen_free`` becomes what the call would have made it.
    """
    n_rows, n_cols = cell_input.shape
    not_free = not_surely_free(n_rows, n_cols, row0, col0, x0, y0, resolution, vertices_x,
                               vertices_y, hit_beams, safety_radius, free_radius, free_bound)
    if free_fresh_after > -math.inf:
        mark_recent_hits(not_free, row0, col0, last_hit, free_fresh_after)
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


#: Relative and absolute slack [1, m] of the reach searched around a cell (`near_polygon`): far
#: above the rounding of the tests it must not miss.
_REACH_SLACK = 1e-6
_REACH_SLACK_ABS = 1e-9

#: `surely_free_update` marks the window as the label update does (`not_surely_free`) when
#: its cells to test would take more than this many tests per vertex at most: marking costs
#: about 30-40 tests' time per vertex (a disc of 0.2 m on 0.1 m cells, the edge bands).
_TESTS_PER_BEAM = 32.0


@kernel
def near_edge(cx, cy, vertices_x, vertices_y, a, radius):
    """
    Tell whether the centre ``(cx, cy)`` lies in edge ``a``'s band: `raster.in_band`'s test.

    The same expressions, the square root taken only for centres that project onto the edge.
    """
    xa = vertices_x[a]
    ya = vertices_y[a]
    ex = vertices_x[a + 1] - xa
    ey = vertices_y[a + 1] - ya
    length2 = ex * ex + ey * ey
    if not length2 > 0.0:
        return False
    dot = (cx - xa) * ex + (cy - ya) * ey
    if not 0.0 <= dot <= length2:
        return False
    cross = (cx - xa) * ey - (cy - ya) * ex
    return abs(cross) / math.sqrt(length2) <= radius


@kernel
def near_vertex(cx, cy, vertices_x, vertices_y, k, bound):
    """Tell whether the centre ``(cx, cy)`` passes vertex ``k``'s disc test ``<= bound``."""
    dx = cx - vertices_x[k]
    dy = cy - vertices_y[k]
    return dx * dx + dy * dy <= bound


@kernel
def near_polygon(cx, cy, vertices_x, vertices_y, theta0, angle_increment, radius, bound):
    """
    Tell whether a centre is marked by `not_surely_free` with every vertex selected.

    That is, whether it passes some vertex's disc test or lies in some edge's band, with the
    same floating-point tests (the vertices but the closing repeat, the edges of positive
    length). Only the vertices and edges that can lie within ``radius`` are tested: the
    polygon's vertices are the laser (vertex 0) and one per beam, beam ``b`` (vertex ``b + 1``)
    along ``theta0 + b * angle_increment`` from it, so a point within ``radius`` of a centre
    at ``d > radius`` from the laser lies within ``asin(radius / d)`` of the centre's
    bearing, and on an edge between beams whose bearings hold it (``angle_increment`` below
    pi). The beams searched reach one more on each side, and the reach a slack more, than
    that needs. Each side of the centre's bearing is searched from it outwards, so that the
    usual answer (near the beam's own end) comes first.
    """
    count = vertices_x.shape[0] - 1                     # vertices but the closing repeat
    beams = count - 1
    lx = vertices_x[0]
    ly = vertices_y[0]
    if near_vertex(cx, cy, vertices_x, vertices_y, 0, bound):
        return True
    dx = cx - lx
    dy = cy - ly
    distance = math.sqrt(dx * dx + dy * dy)
    reach = radius * (1.0 + _REACH_SLACK) + _REACH_SLACK_ABS
    if not distance > reach * (1.0 + 1e-3):
        # Right at the laser's disc: every vertex and edge.
        for k in range(count):
            if (near_vertex(cx, cy, vertices_x, vertices_y, k, bound)
                    or near_edge(cx, cy, vertices_x, vertices_y, k, radius)):
                return True
        return False
    # The bearings of points within reach, with a slack for the rounding of the vertices
    # (relative to the coordinates, over the points' least distance from the laser).
    spread = (math.asin(reach / distance) + 1e-9
              + 1e-14 * (abs(lx) + abs(ly) + distance + radius) / (distance - reach))
    bearing = math.atan2(dy, dx) - theta0
    bearing -= 2.0 * math.pi * math.floor((bearing + math.pi) / (2.0 * math.pi))
    turns = int((angle_increment * beams) / (2.0 * math.pi)) + 2
    for turn in range(-1, turns):
        centre = bearing + 2.0 * math.pi * turn
        low = math.floor((centre - spread) / angle_increment) - 1.0
        high = math.ceil((centre + spread) / angle_increment) + 1.0
        if high < 0.0 or low > beams - 1.0:
            continue
        first = int(max(low, 0.0))
        last = int(min(high, beams - 1.0))
        # Edge `first` joins beam first - 1 (or the laser) to beam first; beam b's own
        # vertex b + 1 and edge b + 1 (to the next beam, or to the laser) below.
        if near_edge(cx, cy, vertices_x, vertices_y, first, radius):
            return True
        middle = int(min(max(math.floor(centre / angle_increment + 0.5), float(first)),
                         float(last)))
        for step in range(max(last - middle, middle - first) + 1):
            b = middle + step
            if b <= last and (near_vertex(cx, cy, vertices_x, vertices_y, b + 1, bound)
                              or near_edge(cx, cy, vertices_x, vertices_y, b + 1, radius)):
                return True
            b = middle - step
            if step > 0 and b >= first and (
                    near_vertex(cx, cy, vertices_x, vertices_y, b + 1, bound)
                    or near_edge(cx, cy, vertices_x, vertices_y, b + 1, radius)):
                return True
    return False


@kernel
def inside_around(cell_input, i, j):
    """Tell whether the window's cells around ``(i, j)`` (those in the window) are all f2."""
    n_rows, n_cols = cell_input.shape
    for k in range(max(i - 1, 0), min(i + 2, n_rows)):
        for m in range(max(j - 1, 0), min(j + 2, n_cols)):
            if cell_input[k, m] != SCAN_INSIDE:
                return False
    return True


@kernel
def polygon_window(shape, ranges, x, y, yaw, angle_min, angle_increment, range_min, range_max,
                   x0, y0, resolution, radius):
    """
    Return a scan's polygon and its f2 cells in the window the free space can change.

    Returns ``(vertices_x, vertices_y, row0, col0, cell_input, extent)``: the polygon's
    vertices [m], the window's first row and column in a grid of ``shape`` (the window of
    `points_update` with reach ``radius``), its (n_rows, n_cols) uint8 cells filled by
    `fill_inside`, and each row's (n_rows, 2) int64 extent of inside cells. An empty window
    has ``n_rows`` or ``n_cols`` 0 and nothing filled.
    """
    vertices_x, vertices_y, _, _, _ = scan_points(
        ranges, x, y, yaw, angle_min, angle_increment, range_min, range_max)
    row0, row_end, col0, col_end = scan_window(shape, vertices_x, vertices_y, radius,
                                               x0, y0, resolution)
    n_rows = row_end - row0
    n_cols = col_end - col0
    cell_input = np.zeros((max(n_rows, 0), max(n_cols, 0)), dtype=np.uint8)
    extent = np.empty((max(n_rows, 0), 2), dtype=np.int64)
    if n_rows > 0 and n_cols > 0:
        extent[:, 0] = n_cols
        extent[:, 1] = 0
        fill_inside(cell_input, row0, col0, x0, y0, resolution, vertices_x, vertices_y,
                    extent)
    return vertices_x, vertices_y, row0, col0, cell_input, extent


@kernel
def surely_free_update(seen_free, ranges, x, y, yaw, angle_min, angle_increment, range_min,
                       range_max, x0, y0, resolution, radius, bound, hit_stamp, fresh_after):
    """
    Mark the cells whose disc of ``radius`` lies inside the scan's polygon as surely free.

    Exactly the ``seen_free`` of `update_window` under a rule with only the conservative free
    space on and a safety radius equal to ``radius``: f2 cells that no vertex's disc and no
    edge band reaches (a hit's f1 disc is its vertex's disc); the cells
    `surely_free_update_by_marks` marks, tested in the tests against it and the literal twin.

    Only the cells that can change are tested: f2 cells not yet marked, and, with ``radius``
    at least 1.5 cells, whose eight neighbours in the window are f2 too (a centre farther than
    ``radius`` from every edge and vertex has its neighbours, at most ``sqrt(2)`` cells away,
    on the same side of every edge). Each is tested against the vertices and edges near its
    bearing (`near_polygon`), not the other way round: a stationary laser's scan marks few
    new cells, and most of the cells that stay unmarked lie next to the polygon's boundary.
    Scans whose beams lie half a turn or more apart take `surely_free_update_by_marks`, and
    scans that show much new space (more than ``_TESTS_PER_BEAM`` tests per vertex at most)
    mark their window as it does.

    The burn-in (``hit_stamp`` of ``seen_free``'s shape; a ``(1, 1)`` stand-in turns it off):
    a cell whose ``hit_stamp`` [s] is later than ``fresh_after`` [s] (a hit lay within
    ``radius`` of it then, `stamp_hits`) is not marked.
    """
    if not angle_increment < 0.5 * math.pi:
        surely_free_update_by_marks(seen_free, ranges, x, y, yaw, angle_min, angle_increment,
                                    range_min, range_max, x0, y0, resolution, radius, bound,
                                    hit_stamp, fresh_after)
        return
    burn_in = hit_stamp.shape == seen_free.shape
    vertices_x, vertices_y, row0, col0, cell_input, extent = polygon_window(
        seen_free.shape, ranges, x, y, yaw, angle_min, angle_increment, range_min, range_max,
        x0, y0, resolution, radius)
    n_rows, n_cols = cell_input.shape
    if n_rows == 0 or n_cols == 0:
        return
    around = radius >= 1.5 * resolution
    # The cells to test, and an estimate of the tests they take at most (the beams within
    # the bearings `near_polygon` searches), against that of marking the window.
    total = 0
    for i in range(n_rows):
        total += max(extent[i, 1] - extent[i, 0], 0)
    cells = np.empty(total, dtype=np.int64)
    count = 0
    tests = 0.0
    budget = _TESTS_PER_BEAM * vertices_x.shape[0]
    lx = vertices_x[0]
    ly = vertices_y[0]
    for i in range(n_rows):
        row = row0 + i
        cy = y0 + (float(row) + 0.5) * resolution
        for j in range(extent[i, 0], extent[i, 1]):
            if cell_input[i, j] != SCAN_INSIDE or seen_free[row, col0 + j]:
                continue
            if burn_in and hit_stamp[row, col0 + j] > fresh_after:
                continue
            if around and not inside_around(cell_input, i, j):
                continue
            cx = x0 + (float(col0 + j) + 0.5) * resolution
            distance = math.sqrt((cx - lx) * (cx - lx) + (cy - ly) * (cy - ly))
            tests += min(2.0 * radius / (max(distance, resolution) * angle_increment) + 4.0,
                         float(vertices_x.shape[0]))
            cells[count] = i * n_cols + j
            count += 1
    if tests > budget:
        # Much new space (a first scan, a turn into the unknown): the marks cost less.
        not_free = not_surely_free(n_rows, n_cols, row0, col0, x0, y0, resolution, vertices_x,
                                   vertices_y, np.zeros(0, dtype=np.int64), 0.0, radius,
                                   bound)
        if burn_in:
            mark_recent_hits(not_free, row0, col0, hit_stamp, fresh_after)
        mark_free_rows(seen_free, row0, col0, cell_input, extent, not_free)
        return
    theta0 = yaw + angle_min
    for k in range(count):
        i = cells[k] // n_cols
        j = cells[k] - i * n_cols
        cx = x0 + (float(col0 + j) + 0.5) * resolution
        cy = y0 + (float(row0 + i) + 0.5) * resolution
        if not near_polygon(cx, cy, vertices_x, vertices_y, theta0, angle_increment, radius,
                            bound):
            seen_free[row0 + i, col0 + j] = True


@kernel
def surely_free_update_by_marks(seen_free, ranges, x, y, yaw, angle_min, angle_increment,
                                range_min, range_max, x0, y0, resolution, radius, bound,
                                hit_stamp, fresh_after):
    """
    `surely_free_update` as the label update marks it: every vertex's disc, every edge band.

    The twin `surely_free_update` equals (and the fallback for scans it does not take).
    Exactly the ``seen_free`` of `update_window` under a rule with only the conservative free
    space on and a safety radius equal to ``radius``: f2 cells that no vertex's disc and no
    edge band reaches (a hit's f1 disc is its vertex's disc). Nothing else is computed. The
    burn-in as in `surely_free_update`.
    """
    vertices_x, vertices_y, row0, col0, cell_input, extent = polygon_window(
        seen_free.shape, ranges, x, y, yaw, angle_min, angle_increment, range_min, range_max,
        x0, y0, resolution, radius)
    n_rows, n_cols = cell_input.shape
    if n_rows == 0 or n_cols == 0:
        return
    # Every vertex's disc, hits included (their f1 discs): a safety radius of 0 selects them
    # all.
    not_free = not_surely_free(n_rows, n_cols, row0, col0, x0, y0, resolution, vertices_x,
                               vertices_y, np.zeros(0, dtype=np.int64), 0.0, radius, bound)
    if hit_stamp.shape == seen_free.shape:
        mark_recent_hits(not_free, row0, col0, hit_stamp, fresh_after)
    mark_free_rows(seen_free, row0, col0, cell_input, extent, not_free)


@kernel
def mark_recent_hits(not_free, row0, col0, hit_stamp, fresh_after):
    """Add to a window's ``not_free`` marks the cells whose ``hit_stamp`` is after ``fresh_after``."""
    for i in range(not_free.shape[0]):
        for j in range(not_free.shape[1]):
            if hit_stamp[row0 + i, col0 + j] > fresh_after:
                not_free[i, j] = True


@kernel
def stamp_hits(hit_stamp, hits_x, hits_y, x0, y0, resolution, bound, stamp):
    """
    Stamp ``stamp`` [s] on every cell whose centre passes ``dx*dx + dy*dy <= bound`` of a hit.

    The burn-in's clock (`surely_free_update`): ``bound`` is that of the free radius, so the
    cells stamped are those a hit's disc keeps from being surely free in its own scan.
    """
    rows, cols = hit_stamp.shape
    # A centre k rows (or columns) from the hit's cell lies at least (k - 0.5) cells from it.
    reach = int(math.floor(math.sqrt(bound) / resolution + 0.5))
    for k in range(hits_x.shape[0]):
        row = int(math.floor((hits_y[k] - y0) / resolution))
        col = int(math.floor((hits_x[k] - x0) / resolution))
        for i in range(max(row - reach, 0), min(row + reach + 1, rows)):
            dy = (y0 + (float(i) + 0.5) * resolution) - hits_y[k]
            for j in range(max(col - reach, 0), min(col + reach + 1, cols)):
                dx = (x0 + (float(j) + 0.5) * resolution) - hits_x[k]
                if dx * dx + dy * dy <= bound:
                    hit_stamp[i, j] = stamp
