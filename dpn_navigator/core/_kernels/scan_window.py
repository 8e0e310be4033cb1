"""
A scan's points and the window of cells it can reach.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import math

import numpy as np

from .jit import kernel


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
