"""
Motion tracks: an object once seen to move stays a moving object while it is followed.

The evidence of ``moving_objects`` needs hits in space surely seen free. A wanderer that walks
away from the laser never gives it: its back lands where its own body stood a moment ago, space
never seen free. So a moving object is followed from scan to scan, at the level of objects:

- every scan segment (``moving_objects.scan_segments``) with hits that show motion starts or
  refreshes a **track** at the centroid of those hits, *confirmed* now;
- a compact, free-standing segment (below) is *seen to move* when a compact free-standing
  segment stood within ``reach`` of it ``min_age`` to ``history`` seconds ago at a place every
  beam now passes: the place it left is empty. A pillar's earlier centroid lies on or behind
  its surface, never in front of it, so a pillar is never seen to move this way;
- a **compact, free-standing** segment (its extent along the hits at most ``compact_size``,
  and the beams just outside it return farther or nothing, so it stands in front of what is
  around it) whose centroid lies within ``gate`` of a live track continues that track: all
  its hits are hits on a moving object. It moves the track but does not confirm it;
- a track dies when no segment continued it for ``lost_after`` seconds, or when nothing
  confirmed it for ``confirm_within`` seconds;
- *still objects* (``still_distance``): a compact segment standing where a compact
  free-standing one stood ``still_age`` to ``history`` seconds ago is not seen to move by the
  places near it left empty (a wanderer walked there, past the post), and does not continue
  a track never confirmed ``move_distance`` from where it started;
- *exclusive tracks* (``exclusive``): at most one segment of a scan continues a track.

The last rule bounds what a wrong association can cost: a pillar that a wanderer walked past
is taken for the wanderer for at most ``confirm_within`` seconds. A wall is never compact and
free-standing unless only a short piece of it shows between nearer objects, and then it is not
free-standing (a neighbouring beam returns nearer).

One compiled kernel per scan (`_track_update`) follows the objects. The bearings of the
places seen a moment ago are numpy's (``arctan2``, ``arcsin``: on this AVX-512 machine
numpy's SIMD routines, which differ from the C library's in the last bits), computed before
the call, so that the kernel decides exactly as the numpy implementation it replaced, the
oracle of the tests (``test/numpy_motion_tracks.py``).

"""

from dataclasses import dataclass
import math

import numpy as np

from .jit import kernel

#: Fewest hits of a scan segment that is a small object (``MotionTracks.hit_object``).
OBJECT_MIN_HITS = 3


@dataclass(frozen=True)
class TrackConfig:
    """
    How moving objects are followed; ``confirm_within`` 0 turns following off.

    Attributes
    ----------
    compact_size : float
        Largest extent of a segment that can be followed, along its hits [m].
    gate : float
        Largest distance from a track to the centroid of the segment that continues it [m].
    lost_after : float
        A track no segment continued for this long is dropped [s].
    confirm_within : float
        A track that no motion evidence confirmed for this long is dropped [s]; 0: off.
    vacated : bool
        See motion by the place a compact free-standing segment left (below).
    history : float
        How long the centroids of compact free-standing segments are kept [s].
    min_age : float
        Only centroids at least this old can show a segment near them moved [s].
    reach : float
        Largest distance from such a centroid to the segment it shows moving [m].
    free_margin : float
        Clearance every beam near the old centroid must pass it by (``seen_free_points``)
        [m].
    half_open_gate : float
        A compact segment with one open end (partly hidden by something nearer, as a wanderer
        passing a doorway is) continues a track within this distance [m]; 0: never. Tighter
        than ``gate``: such a segment may be a piece of wall beside the object.
    still_distance : float
        A compact segment whose centroid lies within this distance of a compact free-standing
        centroid ``still_age`` to ``history`` seconds old stood still [m]; 0: off. A still
        segment is not seen to move by a place left empty near it, and does not continue a
        track that never moved ``move_distance`` from where it started. A post next to the
        places a passing wanderer left stands where it stood.
    still_age : float
        Youngest centroid that shows a segment standing still [s]. A wanderer walks at 0.3
        m/s or more, but the centroid of the side it shows can stand for half a second while
        it turns (0.3 s lost 0.017 of recall on 8 episodes, 0.8 s 0.006).
    move_distance : float
        A track that motion evidence or a place left empty confirmed this far from where it
        started has moved [m]. Continuations alone do not count: where a cluster of static
        objects breaks into segments differently from scan to scan, a track jumps between
        them.
    min_hits : int
        A free-standing segment of fewer hits is no object (``LabelRule.object_min_hits``):
        it starts and continues no track, and its centroid is not remembered as a place an
        object stood; motion evidence in it counts for nothing (its moving hits, if any, start
        or confirm no track). 0 or 1: off. A thing thinner
        than about two beam spacings slips between the beams from one scan to the next, so
        the place it stood is seen empty. A segment with an end closed (partly hidden) is
        not concerned: its hits say nothing of its width.
    exclusive : bool
        One segment per track and scan: a segment whose nearest track within the gate another
        segment of the scan continued already does not continue it (with motion evidence, or
        seen to move, it starts a track of its own). Without it, a wanderer's evidence and a
        post next to it moved one track back and forth between them, and the post was
        followed as that wanderer.

    """

    compact_size: float = 1.0
    gate: float = 0.6
    lost_after: float = 1.0
    confirm_within: float = 0.0
    vacated: bool = True
    history: float = 1.5
    min_age: float = 0.3
    reach: float = 1.2
    free_margin: float = 0.15
    half_open_gate: float = 0.35
    still_distance: float = 0.0
    still_age: float = 0.8
    move_distance: float = 0.3
    min_hits: int = 0
    exclusive: bool = False

    def __post_init__(self):
        for name in ('compact_size', 'gate', 'lost_after', 'confirm_within', 'history',
                     'min_age', 'reach', 'free_margin', 'half_open_gate', 'still_distance',
                     'still_age', 'move_distance'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if isinstance(self.min_hits, bool) or not isinstance(self.min_hits, (int, np.integer)) \
                or self.min_hits < 0:
            raise ValueError(f'min_hits must be an integer >= 0, got {self.min_hits!r}')


class MotionTracks:
    """
    The moving objects being followed, in the map frame.

    Parameters
    ----------
    config : TrackConfig

    Attributes
    ----------
    positions : (T, 2) ndarray of float64
        Last position of each track [m].
    ids : (T,) ndarray of int64
        Each track's number, unique since the last ``reset``.
    last_seen, last_confirmed : (T,) ndarray of float64
        When a segment last continued each track, and when motion evidence last did [s].
    origins : (T, 2) ndarray of float64
        Where each track started [m].
    moved : (T,) ndarray of bool
        Whether motion evidence or an empty place confirmed each track ``move_distance`` or
        more from its origin.
    hit_ids : (K,) ndarray of int64
        For each hit of the latest scan, the number of the track its segment continued, -1
        for none.
    hit_long : (K,) ndarray of bool
        For each hit of the latest scan, whether its segment is longer than ``compact_size``.
    hit_object : (K,) ndarray of bool
        For each hit of the latest scan, whether its segment is a small object: at most
        ``compact_size`` long and at least ``OBJECT_MIN_HITS`` hits (a wall seen at grazing
        incidence breaks into segments of one or two hits).

    """

    def __init__(self, config):
        self.config = config
        self.reset()

    def reset(self):
        """Drop every track."""
        self._history_xy = np.zeros((0, 2))
        self._history_stamp = np.zeros(0)
        self.positions = np.zeros((0, 2))
        self.ids = np.zeros(0, dtype=np.int64)
        self.hit_ids = np.zeros(0, dtype=np.int64)
        self.hit_long = np.zeros(0, dtype=bool)
        self.hit_object = np.zeros(0, dtype=bool)
        self._next_id = 0
        self.last_seen = np.zeros(0)
        self.last_confirmed = np.zeros(0)
        self.origins = np.zeros((0, 2))
        self.moved = np.zeros(0, dtype=bool)
        self._last_stamp = -math.inf

    def update(self, stamp, laser_xy, hits_x, hits_y, hit_beams, beam_count, moving,
               segment_gap, first_angle=None, increment=None, beam_reach=None):
        """
        Follow the moving objects through one scan.

        Parameters
        ----------
        stamp : float
            Time of the scan [s].
        laser_xy : (float, float)
            Laser position [m].
        hits_x, hits_y : (K,) ndarray of float64
            Hit points in beam order [m].
        hit_beams : (K,) ndarray of int64
            Beam index of each hit, increasing.
        beam_count : int
            Beams in the scan.
        moving : (K,) ndarray of bool
            Hits on objects seen to move in this scan (``moving_object_hits``).
        segment_gap : float
            As in ``moving_object_hits`` [m].
        first_angle, increment : float, optional
            Map-frame bearing of beam 0 and the step between beams [rad].
        beam_reach : (L,) ndarray of float64, optional
            How far each beam saw free space [m]: its range, ``range_max`` for no return, 0
            for an invalid beam; without it no segment is seen to move by the place it left.

        Returns
        -------
        followed : (K,) ndarray of bool
            Hits of free-standing compact segments that continue a track (none of them in
            ``moving``).

        """
        stamp = float(stamp)
        if stamp < self._last_stamp:
            self.reset()                        # time went back: a restarted simulation
        self._last_stamp = stamp
        config = self.config
        vacated_on = config.vacated and beam_reach is not None
        if vacated_on:
            low, high, rho = _place_bearings(self._history_xy, laser_xy, first_angle,
                                             increment, config.free_margin)
        else:
            low = high = np.zeros(0, dtype=np.int64)
            rho = np.zeros(0)
            beam_reach = np.zeros(0)
        (followed, self.hit_ids, self.hit_long, self.hit_object, self.positions, self.ids,
         self.last_seen, self.last_confirmed, self.origins, self.moved, self._next_id,
         self._history_xy, self._history_stamp) = _track_update(
            self.positions, self.ids, self.last_seen, self.last_confirmed, self.origins,
            self.moved, self._next_id,
            self._history_xy, self._history_stamp, low, high, rho, stamp,
            float(laser_xy[0]), float(laser_xy[1]), np.ascontiguousarray(hits_x, np.float64),
            np.ascontiguousarray(hits_y, np.float64), np.ascontiguousarray(hit_beams, np.int64),
            int(beam_count), np.ascontiguousarray(moving, bool), float(segment_gap),
            float(config.compact_size), float(config.gate), float(config.lost_after),
            float(config.confirm_within), vacated_on, float(config.history),
            float(config.min_age), float(config.reach), float(config.free_margin),
            float(config.half_open_gate), float(config.still_distance),
            float(config.still_age), float(config.move_distance), int(config.min_hits),
            bool(config.exclusive), np.ascontiguousarray(beam_reach, np.float64))
        return followed


def _place_bearings(points_xy, laser_xy, first_angle, increment, margin):
    """
    Return the beams ``[low, high]`` passing within ``margin`` of each point, and its range.

    numpy's ``arctan2`` and ``arcsin``, as the numpy implementation used them (the kernel's
    would differ in the last bits); `_seen_free` decides with them.

    Returns
    -------
    low, high : (P,) ndarray of int64
    rho : (P,) ndarray of float64
        Distance from the laser [m].

    """
    dx = points_xy[:, 0] - laser_xy[0]
    dy = points_xy[:, 1] - laser_xy[1]
    rho = np.hypot(dx, dy)
    bearing = np.mod(np.arctan2(dy, dx) - first_angle + np.pi, 2.0 * np.pi) - np.pi
    centre = bearing / increment
    half = np.arcsin(np.minimum(1.0, margin / np.maximum(rho, margin))) / increment
    return (np.floor(centre - half).astype(np.int64), np.ceil(centre + half).astype(np.int64),
            rho)


@kernel
def _seen_free(low, high, rho, beam_reach, margin):
    """Tell whether every beam ``low..high`` reaches ``rho + margin`` (False off the fan)."""
    if low < 0 or high >= beam_reach.shape[0] or not rho > margin:
        return False
    least = beam_reach[low]
    for beam in range(low + 1, high + 1):
        least = min(least, beam_reach[beam])
    return least >= rho + margin


@kernel
def _continue(positions, ids, last_seen, last_confirmed, origins, moved, claimed, exclusive,
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
def _track_update(positions, ids, last_seen, last_confirmed, origins, moved, next_id,
                  history_xy,
                  history_stamp, place_low, place_high, place_rho, stamp, laser_x, laser_y,
                  hits_x, hits_y, hit_beams, beam_count, moving, segment_gap, compact_size,
                  gate, lost_after, confirm_within, vacated_on, history, min_age, reach,
                  free_margin, half_open_gate, still_distance, still_age, move_distance,
                  min_hits, exclusive, beam_reach):
    """
    `MotionTracks.update` after its time check, as one pass over the scan's segments.

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
        if step > segment_gap or hit_beams[k] - hit_beams[k - 1] != 1:
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
        track, tracks, next_id = _continue(
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
    # Compact free-standing segments next to a place such a segment left, now seen empty.
    candidate = np.zeros(segments, dtype=np.bool_)
    vacated = np.zeros(segments, dtype=np.bool_)
    for s in range(segments):
        candidate[s] = (small[s] and open_sides[s] == 2 and moving_count[s] == 0
                        and first[s + 1] - first[s] >= min_hits)
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
            if not _seen_free(place_low[h], place_high[h], place_rho[h], beam_reach,
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
        track, tracks, next_id = _continue(
            positions, ids, last_seen, last_confirmed, origins, moved, claimed, exclusive,
            tracks, next_id, centroid_x[s], centroid_y[s], stamp, vacated[s], gate, still[s],
            move_distance)
        if track >= 0:
            for k in range(first[s], first[s + 1]):
                followed[k] = True
                hit_ids[k] = ids[track]
    if half_open_gate > 0.0 and tracks > 0:
        for s in range(segments):
            if not (small[s] and open_sides[s] == 1 and moving_count[s] == 0):
                continue
            track, tracks, next_id = _continue(
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
                         and first[s + 1] - first[s] >= min_hits)
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
