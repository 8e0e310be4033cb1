"""
The fine free evidence's kernels: the hits the fine grid shows surely free, and moving.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import numpy as np

from .jit import kernel
from .motion_evidence import moving_hits


@kernel
def fine_hit_evidence(seen_free, x0, y0, resolution, hits_x, hits_y):
    """
    `FineEvidence.evidence` compiled: whether each hit's fine cell was once surely seen free.

    A hit's cell is ``GridGeometry.world_to_cell``'s, ``floor((x - x0) / resolution)``; hits
    off the grid show nothing. Returns ``(evidence, found)``: the ``(K,)`` bools and whether
    any is True.
    """
    rows, cols = seen_free.shape
    count = hits_x.shape[0]
    evidence = np.zeros(count, dtype=np.bool_)
    found = False
    for k in range(count):
        col = np.floor((hits_x[k] - x0) / resolution)
        row = np.floor((hits_y[k] - y0) / resolution)
        if 0.0 <= row < rows and 0.0 <= col < cols and seen_free[int(row), int(col)]:
            evidence[k] = True
            found = True
    return evidence, found


@kernel
def fine_moving_hits(seen_free, x0, y0, resolution, hits_x, hits_y, hit_beams, segment_gap,
                     object_size, min_hits, laser_x, laser_y, beam_count, bridge_beams):
    """
    `FineEvidence.moving_hits` compiled: each hit's fine cell looked up, then the object rule.

    The cells as `fine_hit_evidence` looks them up.
    """
    evidence, found = fine_hit_evidence(seen_free, x0, y0, resolution, hits_x, hits_y)
    if not found:
        return evidence
    return moving_hits(hits_x, hits_y, hit_beams, evidence, segment_gap, object_size,
                       min_hits, laser_x, laser_y, beam_count, bridge_beams)
