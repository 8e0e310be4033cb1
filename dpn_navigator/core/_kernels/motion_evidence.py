"""
Motion evidence of the hits: which scan segments show motion, near space surely seen free.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import math

import numpy as np

from .jit import kernel
from .raster import disc_box


@kernel
def segment_cut(step, beam_step, segment_gap, bridge_beams):
    """
    Tell whether a scan segment ends between two consecutive hits.

    ``step`` [m] is the distance between the hits, ``beam_step`` the difference of their
    beams: a segment ends where the hits lie more than ``segment_gap`` [m] apart, or more
    than ``bridge_beams`` beams without a hit lie between them (``segment_bridge_beams``).
    """
    return step > segment_gap or beam_step - 1 > bridge_beams


@kernel
def moving_hits(hits_x, hits_y, hit_beams, evidence, segment_gap, object_size, min_hits,
                laser_x, laser_y, beam_count, bridge_beams):
    """``moving_objects.moving_object_hits`` as a loop, with the same arithmetic."""
    count = hits_x.shape[0]
    moving = np.zeros(count, dtype=np.bool_)
    segment = np.zeros(count, dtype=np.int64)
    arc = np.zeros(count, dtype=np.float64)
    for k in range(1, count):
        dx = hits_x[k] - hits_x[k - 1]
        dy = hits_y[k] - hits_y[k - 1]
        step = math.sqrt(dx * dx + dy * dy)
        cut = segment_cut(step, hit_beams[k] - hit_beams[k - 1], segment_gap, bridge_beams)
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
def narrow_segments(hits_x, hits_y, hit_beams, segment_gap, min_width, bridge_beams):
    """
    Tell for each hit whether it lies in a narrow segment (``object_min_width``).

    Segments as in `moving_hits` (`segment_cut`: a cut where consecutive hits lie more than
    ``segment_gap`` apart or more than ``bridge_beams`` beams without a hit lie between them);
    a segment is narrow when its first and last hits
    lie less than ``min_width`` [m] apart. Returns the (K,) bool array.
    """
    count = hits_x.shape[0]
    narrow = np.zeros(count, dtype=np.bool_)
    start = 0
    for k in range(1, count + 1):
        if k < count:
            dx = hits_x[k] - hits_x[k - 1]
            dy = hits_y[k] - hits_y[k - 1]
            step = math.sqrt(dx * dx + dy * dy)
            if not segment_cut(step, hit_beams[k] - hit_beams[k - 1], segment_gap,
                               bridge_beams):
                continue
        width = math.hypot(hits_x[k - 1] - hits_x[start], hits_y[k - 1] - hits_y[start])
        if width < min_width:
            narrow[start:k] = True
        start = k
    return narrow


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
