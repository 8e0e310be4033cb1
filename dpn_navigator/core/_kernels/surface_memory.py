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
def surface_hits(hit_time, filled, hits_x, hits_y, x0, y0, resolution, now, drain,
                 surface_time, capacity, period):
    """
    ``SurfaceMemory.on_surface`` then ``SurfaceMemory.add`` for one scan's hits.

    A hit is on a known surface when a cell within one row and column of its own holds at
    least ``surface_time`` of hit time at ``now``; then each cell hit gains ``period`` once
    (up to ``capacity``) and is stamped ``now``. Returns the (K,) bool array.
    """
    rows, cols = hit_time.shape
    count = hits_x.shape[0]
    known = np.zeros(count, dtype=np.bool_)
    hit_rows = np.empty(count, dtype=np.int64)
    hit_cols = np.empty(count, dtype=np.int64)
    for k in range(count):
        row = int(math.floor((hits_y[k] - y0) / resolution))
        col = int(math.floor((hits_x[k] - x0) / resolution))
        hit_rows[k] = row
        hit_cols[k] = col
        for r in range(row - 1, row + 2):
            for c in range(col - 1, col + 2):
                if (0 <= r < rows and 0 <= c < cols
                        and bucket_level(hit_time, filled, r, c, now, drain) >= surface_time):
                    known[k] = True
    for k in range(count):
        row = hit_rows[k]
        col = hit_cols[k]
        if not (0 <= row < rows and 0 <= col < cols) or filled[row, col] == now:
            continue
        hit_time[row, col] = min(bucket_level(hit_time, filled, row, col, now, drain) + period,
                                 capacity)
        filled[row, col] = now
    return known
