"""
The numpy motion tracks that the compiled ones replaced, kept as the oracle of the tests.

``NumpyMotionTracks`` is ``motion_tracks.MotionTracks`` of commit 1d9ead7: scan segments,
their summary and the places seen free as array operations, the tracks as object-level Python
loops; with the still-object rule (``TrackConfig.still_distance``) and exclusive tracks
(``TrackConfig.exclusive``) added since. The tests
compare the compiled tracks with it, track for track and hit for hit.

"""

import math

from dpn_navigator.core.mapping.motion_tracks import OBJECT_MIN_HITS
from moving_objects import scan_segments
import numpy as np


def segment_summary(laser_xy, hits_x, hits_y, hit_beams, beam_count, segment, arc):
    """
    Centroid, extent and standing of each scan segment.

    Parameters
    ----------
    laser_xy : (float, float)
        Laser position [m], map frame.
    hits_x, hits_y : (K,) ndarray of float64
        Hit points in beam order [m], ``K >= 1``.
    hit_beams : (K,) ndarray of int64
        Beam index of each hit, increasing.
    beam_count : int
        Beams in the scan.
    segment, arc : (K,) ndarray
        From ``scan_segments``.

    Returns
    -------
    centroid_x, centroid_y : (S,) ndarray of float64
        Mean hit of each segment [m].
    extent : (S,) ndarray of float64
        Arc length from its first to its last hit [m].
    open_sides : (S,) ndarray of int64
        How many of its two ends are open, 0 to 2: the beam just outside the end exists and
        returns nothing or a hit farther from the laser than the end. With 2 the segment is
        free-standing.

    """
    count = segment.shape[0]
    segments = int(segment[-1]) + 1
    sizes = np.bincount(segment, minlength=segments)
    centroid_x = np.bincount(segment, weights=hits_x, minlength=segments) / sizes
    centroid_y = np.bincount(segment, weights=hits_y, minlength=segments) / sizes
    first = np.concatenate(([0], np.flatnonzero(np.diff(segment)) + 1))
    last = np.concatenate((first[1:] - 1, [count - 1]))
    extent = arc[last] - arc[first]
    distance = np.hypot(hits_x - laser_xy[0], hits_y - laser_xy[1])
    # The hit just outside each end, when its beam is the next one (else nothing returned).
    before = first - 1
    after = last + 1
    before_is_hit = (before >= 0) & (hit_beams[np.maximum(before, 0)] == hit_beams[first] - 1)
    after_is_hit = ((after < count)
                    & (hit_beams[np.minimum(after, count - 1)] == hit_beams[last] + 1))
    open_before = np.where(before_is_hit,
                           distance[np.maximum(before, 0)] > distance[first],
                           hit_beams[first] > 0)
    open_after = np.where(after_is_hit,
                          distance[np.minimum(after, count - 1)] > distance[last],
                          hit_beams[last] < beam_count - 1)
    return centroid_x, centroid_y, extent, open_before.astype(np.int64) + open_after


def seen_free_points(points_xy, laser_xy, first_angle, increment, beam_reach, margin):
    """
    Tell which points the scan saw empty: every beam within ``margin`` of the point passes it.

    Parameters
    ----------
    points_xy : (P, 2) ndarray of float64
        Points [m], map frame.
    laser_xy : (float, float)
        Laser position [m].
    first_angle : float
        Map-frame bearing of beam 0 [rad].
    increment : float
        Angle between beams [rad], positive.
    beam_reach : (L,) ndarray of float64
        How far each beam saw free space [m]: its range, ``range_max`` for no return, 0 for
        an invalid beam.
    margin : float
        Clearance [m]: the beams whose bearing is within ``asin(margin / rho)`` of the
        point's, at range ``rho``, must all reach ``rho + margin``.

    Returns
    -------
    free : (P,) ndarray of bool

    """
    dx = points_xy[:, 0] - laser_xy[0]
    dy = points_xy[:, 1] - laser_xy[1]
    rho = np.hypot(dx, dy)
    bearing = np.mod(np.arctan2(dy, dx) - first_angle + np.pi, 2.0 * np.pi) - np.pi
    centre = bearing / increment
    half = np.arcsin(np.minimum(1.0, margin / np.maximum(rho, margin))) / increment
    low = np.floor(centre - half).astype(np.int64)
    high = np.ceil(centre + half).astype(np.int64)
    beams = beam_reach.shape[0]
    free = np.zeros(points_xy.shape[0], dtype=bool)
    inside = np.flatnonzero((low >= 0) & (high < beams) & (rho > margin))
    if not inside.size:
        return free
    # The least reach over each point's beams [low, high], all points at once.
    lengths = high[inside] - low[inside] + 1
    starts = np.concatenate(([0], np.cumsum(lengths)[:-1]))
    beams_of = (np.arange(lengths.sum()) - np.repeat(starts - low[inside], lengths))
    least = np.minimum.reduceat(beam_reach[beams_of], starts)
    free[inside] = least >= rho[inside] + margin
    return free


class NumpyMotionTracks:
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
        self._claimed = np.zeros(0, dtype=bool)
        self._last_stamp = -math.inf

    def update(self, stamp, laser_xy, hits_x, hits_y, hit_beams, beam_count, moving,
               segment_gap, first_angle=None, increment=None, beam_reach=None, surface=None):
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
            How far each beam saw free space [m] (``seen_free_points``); without it no
            segment is seen to move by the place it left.
        surface : (K,) ndarray of bool, optional
            Hits on known surfaces: a segment with at least half its hits on them is not
            compact for the tracks (continues nothing, left no place, is not remembered).

        Returns
        -------
        followed : (K,) ndarray of bool
            Hits of free-standing compact segments that continue a track (none of them in
            ``moving``).

        """
        count = hits_x.shape[0]
        followed = np.zeros(count, dtype=bool)
        if stamp < self._last_stamp:
            self.reset()                        # time went back: a restarted simulation
        self._last_stamp = stamp
        self.hit_ids = np.full(count, -1, dtype=np.int64)
        self.hit_long = np.zeros(count, dtype=bool)
        self.hit_object = np.zeros(count, dtype=bool)
        if self.config.confirm_within == 0.0:
            return followed
        self._drop_dead(stamp)
        self._claimed = np.zeros(self.positions.shape[0], dtype=bool)
        if count == 0:
            return followed
        segment, arc = scan_segments(hits_x, hits_y, hit_beams, segment_gap,
                                     self.config.bridge_beams)
        centroid_x, centroid_y, extent, open_sides = segment_summary(
            laser_xy, hits_x, hits_y, hit_beams, beam_count, segment, arc)
        small = extent <= self.config.compact_size
        segments = centroid_x.shape[0]
        # Segment ids are sorted: segment s holds hits first[s]:stop[s].
        first = np.searchsorted(segment, np.arange(segments))
        stop = np.append(first[1:], count)
        # Segments with motion evidence: the centroid of their moving hits.
        moving_count = np.bincount(segment[moving], minlength=segments)
        evidence = moving_count > 0
        # Segments of fewer than min_hits hits are not followed (TrackConfig.min_hits).
        enough = stop - first >= self.config.min_hits
        if evidence.any():
            mx = np.bincount(segment[moving], weights=hits_x[moving], minlength=segments)
            my = np.bincount(segment[moving], weights=hits_y[moving], minlength=segments)
            for s in np.flatnonzero(evidence & (enough | (open_sides != 2))):
                track = self._continue(np.array([mx[s], my[s]]) / moving_count[s], stamp,
                                       confirmed=True)
                own = slice(first[s], stop[s])
                self.hit_ids[own][moving[own]] = self.ids[track]
        on_surface = np.zeros(segments, dtype=bool)
        if surface is not None and surface.shape[0] == count:
            on_surface = 2 * np.bincount(segment[surface], minlength=segments) >= stop - first
        compact = small & (open_sides == 2) & enough & ~on_surface
        still = self._still(stamp, centroid_x, centroid_y, small & ~evidence)
        self.hit_long = ~small[segment]
        self.hit_object = (small & (stop - first >= OBJECT_MIN_HITS))[segment]
        vacated = np.zeros(segments, dtype=bool)
        if self.config.vacated and beam_reach is not None:
            vacated = self._vacated(stamp, centroid_x, centroid_y, compact & ~evidence & ~still,
                                    laser_xy, first_angle, increment, beam_reach)
        candidates = compact & ~evidence
        if not self.positions.shape[0]:
            candidates &= vacated               # nothing to continue: only new tracks
        for s in np.flatnonzero(candidates):
            position = np.array([centroid_x[s], centroid_y[s]])
            track = self._continue(position, stamp, confirmed=bool(vacated[s]),
                                   still=bool(still[s]))
            if track >= 0:
                followed[first[s]:stop[s]] = True
                self.hit_ids[first[s]:stop[s]] = self.ids[track]
        if self.config.half_open_gate > 0.0 and self.positions.shape[0]:
            for s in np.flatnonzero(small & (open_sides == 1) & ~evidence & ~on_surface):
                position = np.array([centroid_x[s], centroid_y[s]])
                track = self._continue(position, stamp, confirmed=False,
                                       gate=self.config.half_open_gate, still=bool(still[s]))
                if track >= 0:
                    followed[first[s]:stop[s]] = True
                    self.hit_ids[first[s]:stop[s]] = self.ids[track]
        keep = stamp - self._history_stamp <= self.config.history
        self._history_xy = np.vstack((self._history_xy[keep],
                                      np.column_stack((centroid_x[compact],
                                                       centroid_y[compact]))))
        self._history_stamp = np.concatenate((self._history_stamp[keep],
                                              np.full(int(compact.sum()), stamp)))
        return followed

    def _vacated(self, stamp, centroid_x, centroid_y, candidates, laser_xy, first_angle,
                 increment, beam_reach):
        """Segments near which a compact segment stood a moment ago, where now is empty."""
        vacated = np.zeros(candidates.shape[0], dtype=bool)
        age = stamp - self._history_stamp
        old = (age >= self.config.min_age) & (age <= self.config.history)
        if not old.any() or not candidates.any():
            return vacated
        old_xy = self._history_xy[old]
        free = seen_free_points(old_xy, laser_xy, first_angle, increment, beam_reach,
                                self.config.free_margin)
        if not free.any():
            return vacated
        old_xy = old_xy[free]
        for s in np.flatnonzero(candidates):
            distance = np.hypot(old_xy[:, 0] - centroid_x[s], old_xy[:, 1] - centroid_y[s])
            vacated[s] = bool((distance <= self.config.reach).any())
        return vacated

    def _still(self, stamp, centroid_x, centroid_y, segments):
        """Segments whose centroid is within ``still_distance`` of one ``still_age`` ago."""
        still = np.zeros(segments.shape[0], dtype=bool)
        if self.config.still_distance == 0.0:
            return still
        age = stamp - self._history_stamp
        old_xy = self._history_xy[(age >= self.config.still_age) & (age <= self.config.history)]
        for s in np.flatnonzero(segments):
            distance = np.hypot(old_xy[:, 0] - centroid_x[s], old_xy[:, 1] - centroid_y[s])
            still[s] = bool((distance <= self.config.still_distance).any())
        return still

    def _continue(self, position, stamp, confirmed, gate=None, still=False):
        """
        Move the nearest track within the gate to ``position``; return its index, or -1.

        With ``confirmed``, a new track starts when none is near. A ``still`` segment does not
        continue a track that has not moved; with ``exclusive``, no segment continues a track
        another segment of the scan continued.
        """
        exclusive = self.config.exclusive
        if self.positions.shape[0]:
            distance = np.hypot(*(self.positions - position).T)
            nearest = int(np.argmin(distance))
            if (distance[nearest] <= (self.config.gate if gate is None else gate)
                    and not (exclusive and self._claimed[nearest])):
                if still and not self.moved[nearest]:
                    return -1
                self._claimed[nearest] = exclusive
                self.positions[nearest] = position
                if confirmed and (np.hypot(*(position - self.origins[nearest]))
                                  >= self.config.move_distance):
                    self.moved[nearest] = True
                self.last_seen[nearest] = stamp
                if confirmed:
                    self.last_confirmed[nearest] = stamp
                return nearest
        if not confirmed:
            return -1
        self.positions = np.vstack((self.positions, position))
        self.origins = np.vstack((self.origins, position))
        self.moved = np.append(self.moved, False)
        self._claimed = np.append(self._claimed, exclusive)
        self.ids = np.append(self.ids, self._next_id)
        self._next_id += 1
        self.last_seen = np.append(self.last_seen, stamp)
        self.last_confirmed = np.append(self.last_confirmed, stamp)
        return self.positions.shape[0] - 1

    def _drop_dead(self, stamp):
        """Drop tracks lost or unconfirmed for too long."""
        alive = ((stamp - self.last_seen <= self.config.lost_after)
                 & (stamp - self.last_confirmed <= self.config.confirm_within))
        self.positions = self.positions[alive]
        self.ids = self.ids[alive]
        self.last_seen = self.last_seen[alive]
        self.last_confirmed = self.last_confirmed[alive]
        self.origins = self.origins[alive]
        self.moved = self.moved[alive]
