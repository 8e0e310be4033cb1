"""
Objects seen to move: the hits of one scan grouped into objects, and which of them moved.

A wandering robot is not a cell but a compact object. Where one of its hits lands in a cell the
map once surely saw empty (see ``free_evidence``), the object has moved into that space, and so
every hit of the same object is a hit on a moving obstacle, even where it lands in space never
seen before. The scan is cut into segments the usual way for a laser: consecutive valid beams
whose hit points are at most ``segment_gap`` apart belong to one segment (more than
``bridge_beams`` invalid or no-return beams between two hits end a segment). A hit belongs to a
moving object when a hit with motion evidence lies in its segment at most ``object_size`` away
along the segment; the bound keeps a wall that a wanderer touches from being taken along with
it.

"""

import numpy as np


def scan_segments(hits_x, hits_y, hit_beams, segment_gap, bridge_beams=0):
    """
    Segment ids and arc positions of a scan's hits.

    Parameters
    ----------
    hits_x, hits_y : (K,) ndarray of float64
        Hit points in beam order [m].
    hit_beams : (K,) ndarray of int64
        Beam index of each hit, increasing.
    segment_gap : float
        Largest distance between consecutive hits of one segment [m].
    bridge_beams : int
        Most beams without a hit between consecutive hits of one segment
        (``segment_bridge_beams``; 0: every such beam ends a segment).

    Returns
    -------
    segment : (K,) ndarray of int64
        Segment id of each hit, non-decreasing from 0.
    arc : (K,) ndarray of float64
        Distance along the chain of hits from the first hit [m].

    """
    dx = np.diff(hits_x)
    dy = np.diff(hits_y)
    step = np.sqrt(dx * dx + dy * dy)
    cut = (step > segment_gap) | (np.diff(hit_beams) - 1 > bridge_beams)
    segment = np.concatenate(([0], np.cumsum(cut))).astype(np.int64)
    arc = np.concatenate(([0.0], np.cumsum(step)))
    return segment[:hits_x.shape[0]], arc[:hits_x.shape[0]]


def free_standing_segments(laser_xy, hits_x, hits_y, hit_beams, beam_count, segment):
    """
    Tell which scan segments stand free: both ends open.

    An end is open when the beam just outside it exists and returns nothing, or a hit farther
    from the laser than the end: the segment stands in front of what is around it.

    Parameters
    ----------
    laser_xy : (float, float)
        Laser position [m].
    hits_x, hits_y : (K,) ndarray of float64
        Hit points in beam order [m], K >= 1.
    hit_beams : (K,) ndarray of int64
        Beam index of each hit, increasing.
    beam_count : int
        Beams in the scan.
    segment : (K,) ndarray of int64
        Segment id of each hit (`scan_segments`).

    Returns
    -------
    free : (S,) ndarray of bool
        Per segment.

    """
    count = segment.shape[0]
    first = np.concatenate(([0], np.flatnonzero(np.diff(segment)) + 1))
    last = np.concatenate((first[1:] - 1, [count - 1]))
    distance = np.hypot(hits_x - laser_xy[0], hits_y - laser_xy[1])
    before = np.maximum(first - 1, 0)
    after = np.minimum(last + 1, count - 1)
    before_is_hit = (first > 0) & (hit_beams[before] == hit_beams[first] - 1)
    after_is_hit = (last + 1 < count) & (hit_beams[after] == hit_beams[last] + 1)
    open_before = np.where(before_is_hit, distance[before] > distance[first],
                           hit_beams[first] > 0)
    open_after = np.where(after_is_hit, distance[after] > distance[last],
                          hit_beams[last] < beam_count - 1)
    return open_before & open_after


def moving_object_hits(hits_x, hits_y, hit_beams, evidence, segment_gap, object_size,
                       min_hits=0, laser_xy=(0.0, 0.0), beam_count=0, bridge_beams=0):
    """
    Tell which hits belong to an object seen to move.

    Parameters
    ----------
    hits_x, hits_y : (K,) ndarray of float64
        Hit points in beam order [m].
    hit_beams : (K,) ndarray of int64
        Beam index of each hit, increasing.
    evidence : (K,) ndarray of bool
        Hits that show motion (they landed where space was surely empty).
    segment_gap : float
        Largest distance between consecutive hits of one object [m].
    object_size : float
        Largest distance along the segment from a hit with evidence [m].
    min_hits : int
        Evidence counts for nothing in a free-standing segment (`free_standing_segments`) of
        fewer hits (``LabelRule.object_min_hits``); 0 or 1: in every segment.
    laser_xy : (float, float)
        Laser position [m]; read when ``min_hits`` > 1.
    beam_count : int
        Beams in the scan; read when ``min_hits`` > 1.
    bridge_beams : int
        Segments go on across this many beams without a hit (``segment_bridge_beams``).

    Returns
    -------
    moving : (K,) ndarray of bool
        True for the hits of moving objects; ``evidence`` implies ``moving``.

    """
    count = hits_x.shape[0]
    if count == 0 or not evidence.any():
        return np.zeros(count, dtype=bool)
    segment, arc = scan_segments(hits_x, hits_y, hit_beams, segment_gap, bridge_beams)
    if min_hits > 1:
        thin = ((np.bincount(segment) < min_hits)
                & free_standing_segments(laser_xy, hits_x, hits_y, hit_beams, beam_count,
                                         segment))
        evidence = evidence & ~thin[segment]
    index = np.arange(count)
    # The nearest hit with evidence before and after each hit (-1 / count when none).
    before = np.maximum.accumulate(np.where(evidence, index, -1))
    after = np.minimum.accumulate(np.where(evidence, index, count)[::-1])[::-1]
    has_before = before >= 0
    has_after = after < count
    before_ok = np.zeros(count, dtype=bool)
    after_ok = np.zeros(count, dtype=bool)
    b = before[has_before]
    before_ok[has_before] = ((segment[b] == segment[has_before])
                             & (arc[has_before] - arc[b] <= object_size))
    a = after[has_after]
    after_ok[has_after] = ((segment[a] == segment[has_after])
                           & (arc[a] - arc[has_after] <= object_size))
    return before_ok | after_ok
