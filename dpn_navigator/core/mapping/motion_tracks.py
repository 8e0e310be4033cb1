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

One compiled kernel per scan (``_kernels.motion_tracks.track_update``) follows the objects.
The bearings of the places seen a moment ago are numpy's (``arctan2``, ``arcsin``: on this
AVX-512 machine numpy's SIMD routines, which differ from the C library's in the last bits),
computed before the call, so that the kernel decides exactly as the numpy implementation it
replaced, the oracle of the tests (``test/reference/numpy_motion_tracks.py``).

"""

from dataclasses import dataclass
import math

import numpy as np

from .._kernels import motion_tracks as track_kernels


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
    bridge_beams : int
        Segments go on across up to this many beams without a hit between hits within the
        segment gap (``LabelRule.segment_bridge_beams``); 0: every such beam ends one.

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
    bridge_beams: int = 0

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
        if isinstance(self.bridge_beams, bool) \
                or not isinstance(self.bridge_beams, (int, np.integer)) or self.bridge_beams < 0:
            raise ValueError(f'bridge_beams must be an integer >= 0, got {self.bridge_beams!r}')


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
            How far each beam saw free space [m]: its range, ``range_max`` for no return, 0
            for an invalid beam; without it no segment is seen to move by the place it left.
        surface : (K,) ndarray of bool, optional
            Hits on known surfaces (``surface_memory``): a segment with at least half its
            hits on them continues no track, is not seen to move by a place left empty and
            is not remembered as a place an object stood.

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
         self._history_xy, self._history_stamp) = track_kernels.track_update(
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
            bool(config.exclusive), np.ascontiguousarray(beam_reach, np.float64),
            np.zeros(0, dtype=bool) if surface is None
            else np.ascontiguousarray(surface, dtype=bool), int(config.bridge_beams))
        return followed


def _place_bearings(points_xy, laser_xy, first_angle, increment, margin):
    """
    Return the beams ``[low, high]`` passing within ``margin`` of each point, and its range.

    numpy's ``arctan2`` and ``arcsin``, as the numpy implementation used them (the kernel's
    would differ in the last bits); the kernel's ``seen_free_between`` decides with them.

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
