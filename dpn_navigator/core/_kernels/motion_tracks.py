"""
The motion tracks' kernels: objects followed from scan to scan.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import math

import numpy as np

from .jit import kernel
from .motion_evidence import segment_cut


#: Fewest hits of a scan segment that is a small object (``MotionTracks.hit_object``).
OBJECT_MIN_HITS = 3


@kernel
def seen_free_between(low, high, rho, beam_reach, margin):
    """Tell whether every beam ``low..high`` reaches ``rho + margin`` (False off the fan)."""
    if low < 0 or high >= beam_reach.shape[0] or not rho > margin:
        return False
    least = beam_reach[low]
    for beam in range(low + 1, high + 1):
        least = min(least, beam_reach[beam])
    return least >= rho + margin


@kernel
def continue_tracks(positions, ids, last_seen, last_confirmed, origins, moved, claimed, exclusive,
                    count, next_id, x, y, stamp, confirmed, gate, still, move_distance):
    """
    Move the nearest of ``count`` tracks within ``gate`` to ``(x, y)``, or start one.

    A track starts only when ``confirmed``; a ``still`` segment does not continue a track that
    has not moved (been confirmed ``move_distance`` or more from where it started), and no
    segment one that is ``claimed`` (then marked, when exclusive; else all False). The arrays
    have room for one more track. Returns ``(index or -1, count, next_id)``.
    """
    if count:
        nearest = 0
        least = math.hypot(positions[0, 0] - x, positions[0, 1] - y)
        for t in range(1, count):
            distance = math.hypot(positions[t, 0] - x, positions[t, 1] - y)
            if distance < least:
                least = distance
                nearest = t
        if least <= gate and not claimed[nearest]:
            if still and not moved[nearest]:
                return -1, count, next_id
            claimed[nearest] = exclusive
            positions[nearest, 0] = x
            positions[nearest, 1] = y
            if confirmed and math.hypot(x - origins[nearest, 0],
                                        y - origins[nearest, 1]) >= move_distance:
                moved[nearest] = True
            last_seen[nearest] = stamp
            if confirmed:
                last_confirmed[nearest] = stamp
            return nearest, count, next_id
    if not confirmed:
        return -1, count, next_id
    positions[count, 0] = x
    positions[count, 1] = y
    origins[count, 0] = x
    origins[count, 1] = y
    moved[count] = False
    claimed[count] = exclusive
    ids[count] = next_id
    last_seen[count] = stamp
    last_confirmed[count] = stamp
    return count, count + 1, next_id + 1


@kernel
def track_update(positions, ids, last_seen, last_confirmed, origins, moved, next_id,
                 history_xy,
                 history_stamp, place_low, place_high, place_rho, stamp, laser_x, laser_y,
                 hits_x, hits_y, hit_beams, beam_count, moving, segment_gap, compact_size,
                 gate, lost_after, confirm_within, vacated_on, history, min_age, reach,
                 free_margin, half_open_gate, still_distance, still_age, move_distance,
                 min_hits, exclusive, beam_reach, surface, bridge_beams):
    """
    `MotionTracks.update` after its time check, as one pass over the scan's segments.

    ``surface`` (K,) bool marks hits on known surfaces (or is empty: none); a segment with at
    least half its hits on them continues no track, is not seen to move by a place left empty
    and is not remembered as a place an object stood. ``bridge_beams``: the segments go on
    across that many beams without a hit (`motion_evidence.segment_cut`).

    Returns ``(followed, hit_ids, hit_long, hit_object, positions, ids, last_seen,
    last_confirmed, origins, moved, next_id, history_xy, history_stamp)``, the state arrays
    new.
    """
    count = hits_x.shape[0]
    followed = np.zeros(count, dtype=np.bool_)
    hit_ids = np.full(count, -1, dtype=np.int64)
    hit_long = np.zeros(count, dtype=np.bool_)
    hit_object = np.zeros(count, dtype=np.bool_)
    if confirm_within == 0.0:
        return (followed, hit_ids, hit_long, hit_object, positions, ids, last_seen,
                last_confirmed, origins, moved, next_id, history_xy, history_stamp)
    # Drop the tracks lost or unconfirmed for too long; room for one new track per segment.
    tracks = 0
    room = positions.shape[0] + count
    new_positions = np.empty((room, 2))
    new_ids = np.empty(room, dtype=np.int64)
    new_seen = np.empty(room)
    new_confirmed = np.empty(room)
    new_origins = np.empty((room, 2))
    new_moved = np.empty(room, dtype=np.bool_)
    for t in range(positions.shape[0]):
        if (stamp - last_seen[t] <= lost_after
                and stamp - last_confirmed[t] <= confirm_within):
            new_positions[tracks] = positions[t]
            new_ids[tracks] = ids[t]
            new_seen[tracks] = last_seen[t]
            new_confirmed[tracks] = last_confirmed[t]
            new_origins[tracks] = origins[t]
            new_moved[tracks] = moved[t]
            tracks += 1
    positions, ids, last_seen, last_confirmed = (new_positions, new_ids, new_seen,
                                                 new_confirmed)
    origins, moved = new_origins, new_moved
    claimed = np.zeros(room, dtype=np.bool_)      # continued by a segment of this scan
    if count == 0:
        return (followed, hit_ids, hit_long, hit_object, positions[:tracks].copy(),
                ids[:tracks].copy(), last_seen[:tracks].copy(), last_confirmed[:tracks].copy(),
                origins[:tracks].copy(), moved[:tracks].copy(), next_id, history_xy,
                history_stamp)
    # Segments (moving_objects.scan_segments): first[s]:stop[s] are the hits of segment s.
    first = np.empty(count + 1, dtype=np.int64)
    arc = np.zeros(count)
    segments = 1
    first[0] = 0
    for k in range(1, count):
        dx = hits_x[k] - hits_x[k - 1]
        dy = hits_y[k] - hits_y[k - 1]
        step = math.sqrt(dx * dx + dy * dy)
        arc[k] = arc[k - 1] + step
        if segment_cut(step, hit_beams[k] - hit_beams[k - 1], segment_gap, bridge_beams):
            first[segments] = k
            segments += 1
    first[segments] = count
    # Their summary (segment_summary) and motion evidence.
    centroid_x = np.zeros(segments)
    centroid_y = np.zeros(segments)
    small = np.zeros(segments, dtype=np.bool_)
    open_sides = np.zeros(segments, dtype=np.int64)
    moving_count = np.zeros(segments, dtype=np.int64)
    moving_x = np.zeros(segments)
    moving_y = np.zeros(segments)
    for s in range(segments):
        start = first[s]
        stop = first[s + 1]
        for k in range(start, stop):
            centroid_x[s] += hits_x[k]
            centroid_y[s] += hits_y[k]
            if moving[k]:
                moving_count[s] += 1
                moving_x[s] += hits_x[k]
                moving_y[s] += hits_y[k]
        centroid_x[s] /= stop - start
        centroid_y[s] /= stop - start
        small[s] = arc[stop - 1] - arc[start] <= compact_size
        distance_first = math.hypot(hits_x[start] - laser_x, hits_y[start] - laser_y)
        distance_last = math.hypot(hits_x[stop - 1] - laser_x, hits_y[stop - 1] - laser_y)
        if start > 0 and hit_beams[start - 1] == hit_beams[start] - 1:
            open_sides[s] += math.hypot(hits_x[start - 1] - laser_x,
                                        hits_y[start - 1] - laser_y) > distance_first
        else:
            open_sides[s] += hit_beams[start] > 0
        if stop < count and hit_beams[stop] == hit_beams[stop - 1] + 1:
            open_sides[s] += math.hypot(hits_x[stop] - laser_x,
                                        hits_y[stop] - laser_y) > distance_last
        else:
            open_sides[s] += hit_beams[stop - 1] < beam_count - 1
    # Segments with motion evidence start or confirm a track at their moving hits' centroid.
    for s in range(segments):
        if moving_count[s] == 0 or (open_sides[s] == 2
                                    and first[s + 1] - first[s] < min_hits):
            continue
        track, tracks, next_id = continue_tracks(
            positions, ids, last_seen, last_confirmed, origins, moved, claimed, exclusive,
            tracks, next_id, moving_x[s] / moving_count[s], moving_y[s] / moving_count[s],
            stamp, True, gate, False, move_distance)
        for k in range(first[s], first[s + 1]):
            if moving[k]:
                hit_ids[k] = ids[track]
    for s in range(segments):
        size = first[s + 1] - first[s]
        for k in range(first[s], first[s + 1]):
            hit_long[k] = not small[s]
            hit_object[k] = small[s] and size >= OBJECT_MIN_HITS
    # Segments lying on known surfaces (at least half their hits).
    on_surface = np.zeros(segments, dtype=np.bool_)
    if surface.shape[0] == count:
        for s in range(segments):
            known = 0
            for k in range(first[s], first[s + 1]):
                known += surface[k]
            on_surface[s] = 2 * known >= first[s + 1] - first[s]
    # Compact free-standing segments next to a place such a segment left, now seen empty.
    candidate = np.zeros(segments, dtype=np.bool_)
    vacated = np.zeros(segments, dtype=np.bool_)
    for s in range(segments):
        candidate[s] = (small[s] and open_sides[s] == 2 and moving_count[s] == 0
                        and first[s + 1] - first[s] >= min_hits and not on_surface[s])
    # Compact segments standing where a compact free-standing one stood a while ago: still.
    still = np.zeros(segments, dtype=np.bool_)
    if still_distance > 0.0:
        for h in range(history_stamp.shape[0]):
            age = stamp - history_stamp[h]
            if not (age >= still_age and age <= history):
                continue
            for s in range(segments):
                if (small[s] and moving_count[s] == 0
                        and math.hypot(history_xy[h, 0] - centroid_x[s],
                                       history_xy[h, 1] - centroid_y[s]) <= still_distance):
                    still[s] = True
    if vacated_on:
        for h in range(history_stamp.shape[0]):
            age = stamp - history_stamp[h]
            if not (age >= min_age and age <= history):
                continue
            if not seen_free_between(place_low[h], place_high[h], place_rho[h], beam_reach,
                                     free_margin):
                continue
            for s in range(segments):
                if (candidate[s] and not still[s]
                        and math.hypot(history_xy[h, 0] - centroid_x[s],
                                       history_xy[h, 1] - centroid_y[s]) <= reach):
                    vacated[s] = True
    # They continue a track (starting one when vacated); with no track, only new ones start.
    any_track = tracks > 0
    for s in range(segments):
        if not candidate[s] or not (any_track or vacated[s]):
            continue
        track, tracks, next_id = continue_tracks(
            positions, ids, last_seen, last_confirmed, origins, moved, claimed, exclusive,
            tracks, next_id, centroid_x[s], centroid_y[s], stamp, vacated[s], gate, still[s],
            move_distance)
        if track >= 0:
            for k in range(first[s], first[s + 1]):
                followed[k] = True
                hit_ids[k] = ids[track]
    if half_open_gate > 0.0 and tracks > 0:
        for s in range(segments):
            if not (small[s] and open_sides[s] == 1 and moving_count[s] == 0
                    and not on_surface[s]):
                continue
            track, tracks, next_id = continue_tracks(
                positions, ids, last_seen, last_confirmed, origins, moved, claimed, exclusive,
                tracks, next_id, centroid_x[s], centroid_y[s], stamp, False, half_open_gate,
                still[s], move_distance)
            if track >= 0:
                for k in range(first[s], first[s + 1]):
                    followed[k] = True
                    hit_ids[k] = ids[track]
    # The history of compact free-standing centroids: the recent ones, then this scan's.
    kept = 0
    for h in range(history_stamp.shape[0]):
        kept += stamp - history_stamp[h] <= history
    remembered = np.zeros(segments, dtype=np.bool_)
    for s in range(segments):
        remembered[s] = (small[s] and open_sides[s] == 2
                         and first[s + 1] - first[s] >= min_hits and not on_surface[s])
        kept += remembered[s]
    new_xy = np.empty((kept, 2))
    new_stamp = np.empty(kept)
    kept = 0
    for h in range(history_stamp.shape[0]):
        if stamp - history_stamp[h] <= history:
            new_xy[kept] = history_xy[h]
            new_stamp[kept] = history_stamp[h]
            kept += 1
    for s in range(segments):
        if remembered[s]:
            new_xy[kept, 0] = centroid_x[s]
            new_xy[kept, 1] = centroid_y[s]
            new_stamp[kept] = stamp
            kept += 1
    return (followed, hit_ids, hit_long, hit_object, positions[:tracks].copy(),
            ids[:tracks].copy(), last_seen[:tracks].copy(), last_confirmed[:tracks].copy(),
            origins[:tracks].copy(), moved[:tracks].copy(), next_id, new_xy, new_stamp)
