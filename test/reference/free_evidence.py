"""
Conservative free space: the cells a scan surely saw empty.

f2 calls a cell explored when its centre lies inside the scan polygon, yet the polygon's edges
run straight from hit to hit. At grazing incidence the hits on a wall are metres apart, and the
edge between two of them cuts right along the wall, so cells within the safety radius ``r`` of
the wall are called explored although the wall is there; a closer look later hits them and the
paper's FSM turns them into *mobile* obstacles. Following the rule of DUFOMap (Duberg et al.,
RA-L 2024) and Dynablox (Schmid et al., RA-L 2023), space seen empty and then occupied is
dynamic only when it was *surely* seen empty. In 2-D:

    a cell is **surely free** in a scan when its centre is inside the scan polygon (f2) and no
    point of the polygon's boundary lies within ``radius`` of the centre, i.e. the whole disc of
    that radius around the centre lies inside the polygon.

"Within ``radius`` of the boundary" is decided per polygon edge ``(a, b)`` exactly as the
literal twin in the tests writes it: the centre ``c`` is within ``radius`` of vertex ``a`` or
``b`` (eq. 1-2's test, ``sqrt(dx * dx + dy * dy) <= radius``), or its projection falls on the
edge and its distance from the edge's line is at most ``radius``::

    ex, ey = xb - xa, yb - ya;  length2 = ex * ex + ey * ey  (> 0)
    dot = (cx - xa) * ex + (cy - ya) * ey
    cross = (cx - xa) * ey - (cy - ya) * ex
    0 <= dot <= length2  and  abs(cross) / sqrt(length2) <= radius

The vertex discs are found as f1's runs (``hit_runs``); the edge bands by evaluating that exact
expression on the cells of a conservative box around each (edge, row) pair, so the work grows
with the polygon's perimeter, not with the window's area.

"""

import math

from dpn_navigator.core.cell_label import ScanInput
import numpy as np
from scan_features import hit_runs, run_cover

#: Slack of the candidate boxes [m]: far more than the rounding of their bounds.
_BOX_SLACK = 1e-6


def edge_band_positions(centres, vertices_x, vertices_y, radius):
    """
    Window positions of the cells that lie in the band of some polygon edge.

    Parameters
    ----------
    centres : ((n_cols,) ndarray, (n_rows,) ndarray)
        The window's centre coordinates [m], from ``GridGeometry.window_centres``.
    vertices_x, vertices_y : (V + 1,) ndarray of float64
        The closed polygon [m], first vertex repeated at the end.
    radius : float
        Band half width [m], finite and non-negative.

    Returns
    -------
    positions : (P,) ndarray of int64
        Flat window positions ``local_row * n_cols + local_col``; repeats possible.

    """
    x_centres, y_centres = centres
    n_cols = x_centres.shape[0]
    xa, ya = vertices_x[:-1], vertices_y[:-1]
    ex = vertices_x[1:] - xa
    ey = vertices_y[1:] - ya
    length2 = ex * ex + ey * ey
    keep = length2 > 0.0
    xa, ya, ex, ey, length2 = xa[keep], ya[keep], ex[keep], ey[keep], length2[keep]
    reach = radius + _BOX_SLACK
    # Window rows whose centre is within reach of the edge's y extent.
    first_row = np.searchsorted(y_centres, np.minimum(ya, ya + ey) - reach, side='left')
    last_row = np.searchsorted(y_centres, np.maximum(ya, ya + ey) + reach, side='right')
    spans = np.maximum(last_row - first_row, 0)
    edge = np.repeat(np.arange(xa.shape[0]), spans)
    local_row = (np.arange(edge.shape[0])
                 - np.repeat(np.cumsum(spans) - spans - first_row, spans))
    cy = y_centres[local_row]
    xa, ya, ex, ey = xa[edge], ya[edge], ex[edge], ey[edge]
    # The part of the edge within reach of the row in y: parameters t_lo..t_hi of a + t e.
    with np.errstate(divide='ignore', invalid='ignore'):
        t_1 = (cy - reach - ya) / ey
        t_2 = (cy + reach - ya) / ey
    flat = ey == 0.0
    t_lo = np.where(flat, 0.0, np.clip(np.minimum(t_1, t_2), 0.0, 1.0))
    t_hi = np.where(flat, 1.0, np.clip(np.maximum(t_1, t_2), 0.0, 1.0))
    x_lo = np.minimum(xa + t_lo * ex, xa + t_hi * ex) - reach
    x_hi = np.maximum(xa + t_lo * ex, xa + t_hi * ex) + reach
    first_col = np.searchsorted(x_centres, x_lo, side='left')
    widths = np.maximum(np.searchsorted(x_centres, x_hi, side='right') - first_col, 0)
    pair = np.repeat(np.arange(local_row.shape[0]), widths)
    local_col = (np.arange(pair.shape[0])
                 - np.repeat(np.cumsum(widths) - widths - first_col, widths))
    cx = x_centres[local_col]
    cy = cy[pair]
    xa, ya, ex, ey = xa[pair], ya[pair], ex[pair], ey[pair]
    length2 = ex * ex + ey * ey
    dot = (cx - xa) * ex + (cy - ya) * ey
    cross = (cx - xa) * ey - (cy - ya) * ex
    in_band = (dot >= 0.0) & (dot <= length2) & (np.abs(cross) / np.sqrt(length2) <= radius)
    return local_row[pair][in_band] * n_cols + local_col[in_band]


def surely_free(geometry, rows, cols, points, radius, cell_input, safety_radius):
    """
    Cells of a window whose whole ``radius`` disc lies inside the scan polygon.

    Parameters
    ----------
    geometry : GridGeometry
        The grid.
    rows, cols : slice
        The window, non-empty.
    points : ScanPoints
        The scan's polygon and hits in the map frame.
    radius : float
        Disc radius [m], finite and non-negative.
    cell_input : (n_rows, n_cols) ndarray of uint8
        The window's FSM input (``scan_input``); only ``INSIDE`` cells can be surely free.
    safety_radius : float
        f1's ``r`` [m] that ``cell_input`` was found with.

    Returns
    -------
    free : (n_rows, n_cols) ndarray of bool

    """
    if not (math.isfinite(radius) and radius >= 0.0):
        raise ValueError(f'radius must be finite and >= 0, got {radius!r} m')
    centres = geometry.window_centres(rows, cols)
    free = (cell_input == ScanInput.INSIDE).ravel()
    if not free.any():
        return free.reshape(cell_input.shape)
    vertices_x = points.vertices_x[:-1]
    vertices_y = points.vertices_y[:-1]
    if radius <= safety_radius:
        # Cells within r of a hit have f1 = 1 and are not INSIDE: only the vertices that are
        # not hits (no return, invalid beams, the laser itself) need their discs.
        not_hit = np.ones(vertices_x.shape[0], dtype=bool)
        not_hit[points.hit_beams + 1] = False
        vertices_x = vertices_x[not_hit]
        vertices_y = vertices_y[not_hit]
    starts, ends = hit_runs(geometry, rows, cols, centres, vertices_x, vertices_y, radius)
    free &= ~run_cover(starts, ends, cell_input.shape).ravel()
    free[edge_band_positions(centres, points.vertices_x, points.vertices_y, radius)] = False
    return free.reshape(cell_input.shape)
