"""
The paper's two per-cell scan functions, f1 and f2, evaluated over a window of the grid.

Both are decided with exactly the floating-point expressions of the equations, so the result
equals a cell-by-cell evaluation. The work, though, grows with the number of beams and window
rows, not with their product with the cells: each function is found as runs of cells along the
window's rows, and the runs are expanded once into the FSM input.

Positions below are flat indices into the window, ``local_row * n_cols + local_col``.

"""

import math

from dpn_navigator.core.cell_label import LABEL_DTYPE, ScanInput
from dpn_navigator.core.grid_geometry import squared_radius_bound  # noqa: F401 (re-exported)
import numpy as np


def hit_runs(geometry, rows, cols, centres, hits_x, hits_y, safety_radius, return_hits=False):
    """
    Find f1 (eq. 1-2) as runs of cells within the safety radius of each hit point.

    Along one row the cells with ``sqrt(dx*dx + dy*dy) <= r`` are contiguous (every step of the
    expression is monotone in ``|dx|``). Their ends are estimated from the circle and then
    corrected by evaluating the exact test one cell either side.

    Parameters
    ----------
    geometry : GridGeometry
        The grid.
    rows, cols : slice
        The window, non-empty.
    centres : ((n_cols,) ndarray, (n_rows,) ndarray)
        The window's centre coordinates [m], from ``GridGeometry.window_centres``.
    hits_x, hits_y : (K,) ndarray of float64
        Map-frame hit points [m].
    safety_radius : float
        ``r`` [m], finite and non-negative.
    return_hits : bool
        Also return which hit each run belongs to.

    Returns
    -------
    starts, ends : (R,) ndarray of int64
        Half-open runs ``[start, end)`` of window positions with f1 = 1; runs may overlap.
    hit_index : (R,) ndarray of int64
        Only with ``return_hits``: the index into ``hits_x`` of each run's hit.

    """
    res = geometry.resolution
    x0, y0 = geometry.origin
    n_cols = cols.stop - cols.start
    x_centres, y_centres = centres
    slack = safety_radius + res
    near = ((hits_x >= x_centres[0] - slack) & (hits_x <= x_centres[-1] + slack)
            & (hits_y >= y_centres[0] - slack) & (hits_y <= y_centres[-1] + slack))
    near_index = np.flatnonzero(near)
    hx = hits_x[near][:, None]                                   # (K, 1)
    hy = hits_y[near][:, None]
    # Rows whose centre can lie within r of the hit, one spare on each side for rounding.
    first_row = np.ceil((hy - safety_radius - y0) / res - 0.5).astype(np.int64) - 1
    rr = first_row + np.arange(math.floor(2.0 * safety_radius / res) + 3)   # (K, S)
    _, centre_y = geometry.cell_to_world(rr, 0)
    dy = centre_y - hy
    dy2 = dy * dy
    half_chord = np.sqrt(np.maximum(safety_radius * safety_radius - dy2, 0.0))
    first = np.ceil((hx - half_chord - x0) / res - 0.5).astype(np.int64)
    last = np.floor((hx + half_chord - x0) / res - 0.5).astype(np.int64)
    # The estimate is off by at most one cell: settle each end with the exact test, evaluated
    # for the four candidate columns first - 1, first, last, last + 1 at once.
    candidates = np.stack((first - 1, first, last, last + 1))     # (4, K, S)
    centre_x, _ = geometry.cell_to_world(0, candidates)
    dx = centre_x - hx
    within = dx * dx + dy2 <= squared_radius_bound(safety_radius)
    first = np.where(within[0], first - 1, np.where(within[1], first, first + 1))
    last = np.where(within[3], last + 1, np.where(within[2], last, last - 1))
    first = np.maximum(first, cols.start)
    last = np.minimum(last, cols.stop - 1)
    keep = (first <= last) & (rr >= rows.start) & (rr < rows.stop)
    row_base = (rr[keep] - rows.start) * n_cols - cols.start
    if return_hits:
        hit_index = np.broadcast_to(near_index[:, None], keep.shape)[keep]
        return row_base + first[keep], row_base + last[keep] + 1, hit_index
    return row_base + first[keep], row_base + last[keep] + 1


def run_cover(starts, ends, shape):
    """
    Mark the window cells that lie in at least one run.

    Parameters
    ----------
    starts, ends : (R,) ndarray of int64
        Half-open runs ``[start, end)`` of flat window positions, as from ``hit_runs``; runs
        may overlap.
    shape : (int, int)
        The window's ``(n_rows, n_cols)``.

    Returns
    -------
    covered : (n_rows, n_cols) ndarray of bool

    """
    size = shape[0] * shape[1]
    open_runs = np.cumsum(np.bincount(starts, minlength=size + 1)
                          - np.bincount(ends, minlength=size + 1))
    return (open_runs[:size] > 0).reshape(shape)


def crossing_toggles(rows, cols, centres, vertices_x, vertices_y):
    """
    Find f2's crossings: where the even-odd parity of each window row flips.

    A centre ``(x, y)`` is crossed by edge ``(a, b)`` when ``(y_a > y) != (y_b > y)`` and
    ``x < x_a + (x_b - x_a) * (y - y_a) / (y_b - y_a)`` (a ray cast along +x). Each edge is
    intersected only with the rows it spans. A crossing at ``x_cross`` crosses the row's centres
    ``0 .. k-1``, ``k`` the count of centres left of it, and is returned as position
    ``row * n_cols + k``. Every row holds an even number of crossings, so a centre is inside
    exactly when an odd number of positions lie at or before it.

    Parameters
    ----------
    rows, cols : slice
        The window, non-empty.
    centres : ((n_cols,) ndarray, (n_rows,) ndarray)
        The window's centre coordinates [m].
    vertices_x, vertices_y : (V + 1,) ndarray of float64
        The closed polygon's vertices in order [m], the first repeated at the end.

    Returns
    -------
    positions : (C,) ndarray of int64
        One position per crossing, unsorted, repeats kept.

    """
    n_cols = cols.stop - cols.start
    x_centres, y_centres = centres
    xa, xb = vertices_x[:-1], vertices_x[1:]
    ya, yb = vertices_y[:-1], vertices_y[1:]
    # Rows with y_low <= y < y_high are exactly those where (y_a > y) != (y_b > y).
    first_row = np.searchsorted(y_centres, np.minimum(ya, yb), side='left')
    spans = np.searchsorted(y_centres, np.maximum(ya, yb), side='left') - first_row
    crossings = int(spans.sum())
    edge = np.repeat(np.arange(xa.shape[0]), spans)
    row = np.arange(crossings) - np.repeat(np.cumsum(spans) - spans - first_row, spans)
    y = y_centres[row]
    xa = xa[edge]
    ya = ya[edge]
    x_cross = xa + (xb[edge] - xa) * (y - ya) / (yb[edge] - ya)
    return row * n_cols + np.searchsorted(x_centres, x_cross, side='left')


def scan_input(geometry, rows, cols, points, safety_radius, runs=None):
    """
    FSM input of every cell of a window: ``HIT`` where f1, else ``INSIDE`` where f2, else 0.

    Parameters
    ----------
    geometry : GridGeometry
        The grid.
    rows, cols : slice
        The window, non-empty.
    points : ScanPoints
        The scan's polygon vertices and hits in the map frame.
    safety_radius : float
        ``r`` [m].
    runs : (starts, ends, ...), optional
        f1's runs of these hits at ``safety_radius`` over this window, from ``hit_runs``, when
        the caller has them already.

    Returns
    -------
    scan_input : (n_rows, n_cols) ndarray of uint8
        ``ScanInput`` values.

    """
    n_rows = rows.stop - rows.start
    n_cols = cols.stop - cols.start
    centres = geometry.window_centres(rows, cols)
    if runs is None:
        runs = hit_runs(geometry, rows, cols, centres, points.hits_x, points.hits_y,
                        safety_radius)
    starts, ends = runs[0], runs[1]
    toggles = crossing_toggles(rows, cols, centres, points.vertices_x, points.vertices_y)
    # Events along the flat window: f1 coverage changes by +1/-1, f2 parity flips.
    position = np.concatenate((starts, ends, toggles))
    coverage_step = np.concatenate((np.ones_like(starts), -np.ones_like(ends),
                                    np.zeros_like(toggles)))
    order = np.argsort(position, kind='stable')
    position = position[order]
    coverage = np.cumsum(coverage_step[order])
    parity = np.cumsum(order >= starts.shape[0] + ends.shape[0]) & 1
    # The state after the last event at each position holds up to the next position.
    last_at = np.flatnonzero(np.diff(position, append=n_rows * n_cols + 1))
    code = np.where(coverage[last_at] > 0, ScanInput.HIT, parity[last_at]).astype(LABEL_DTYPE)
    lengths = np.diff(position[last_at], append=n_rows * n_cols)
    out = np.zeros(n_rows * n_cols, dtype=LABEL_DTYPE)
    if last_at.shape[0]:
        head = position[last_at[0]]
        out[head:] = np.repeat(code, lengths)
    return out.reshape(n_rows, n_cols)
