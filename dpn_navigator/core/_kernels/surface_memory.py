"""
The intermittent surfaces' kernel: which hits lie on known surfaces, then the buckets filled.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import math

import numpy as np

from .jit import kernel


@kernel
def bucket_level(hit_time, filled, row, col, now, drain):
    """Return the hit time of cell ``(row, col)`` at ``now`` [s], drained since filled."""
    age = max(now - filled[row, col], 0.0)
    return max(hit_time[row, col] - age * drain, 0.0)


@kernel
def surface_known(hit_time, filled, hits_x, hits_y, x0, y0, resolution, now, drain,
                  surface_time):
    """
    ``SurfaceMemory.on_surface``: which hits lie within one place of a known surface.

    A hit is on a known surface when a cell within one row and column of its own holds at
    least ``surface_time`` of hit time at ``now``. Returns the (K,) bool array.
    """
    rows, cols = hit_time.shape
    count = hits_x.shape[0]
    known = np.zeros(count, dtype=np.bool_)
    for k in range(count):
        row = int(math.floor((hits_y[k] - y0) / resolution))
        col = int(math.floor((hits_x[k] - x0) / resolution))
        for r in range(row - 1, row + 2):
            for c in range(col - 1, col + 2):
                if (0 <= r < rows and 0 <= c < cols
                        and bucket_level(hit_time, filled, r, c, now, drain) >= surface_time):
                    known[k] = True
    return known


@kernel
def surface_fill(hit_time, filled, hits_x, hits_y, fill, x0, y0, resolution, now, drain,
                 capacity, period):
    """
    ``SurfaceMemory.fill``: each place hit by a hit marked in ``fill`` gains ``period`` once.

    Up to ``capacity``; the place is stamped ``now``.
    """
    rows, cols = hit_time.shape
    for k in range(hits_x.shape[0]):
        if not fill[k]:
            continue
        row = int(math.floor((hits_y[k] - y0) / resolution))
        col = int(math.floor((hits_x[k] - x0) / resolution))
        if not (0 <= row < rows and 0 <= col < cols) or filled[row, col] == now:
            continue
        hit_time[row, col] = min(bucket_level(hit_time, filled, row, col, now, drain) + period,
                                 capacity)
        filled[row, col] = now
