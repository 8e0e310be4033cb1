"""
Surely-free space: the cells whose disc lies inside one scan's polygon, marked.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

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
