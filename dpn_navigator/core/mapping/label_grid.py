"""
The labelled occupancy grid: per scan, f1 and f2 drive each cell's finite state machine.

Only the cells a scan can reach are touched: the window around the scan polygon widened by the
safety radius. Cells elsewhere see ``(f1, f2) = (0, 0)``, which keeps every state.

A ``LabelRule`` adds evidence to the paper's FSM; its defaults (``PAPER_RULE``) are the paper's
rule exactly. With ``free_evidence_radius`` an explored cell hit by the laser becomes a mobile
obstacle only if it was once surely seen free (``free_evidence``), and a steady obstacle
otherwise; with ``moving_object_size`` the cells a scan hits are labelled by object, mobile
near an object seen to move and steady elsewhere (``moving_objects``); with ``mobile_expiry`` a
mobile cell that no hit has confirmed for that long goes back to explored while out of view.

"""

from dataclasses import dataclass, fields, replace
import math

import numpy as np

from .fine_evidence import FineEvidence
from .label_update import (expire_listed, mark_free_window, scan_hits, scan_update,
                           squared_bound, surely_free_update)
from .laser_standing import LaserStanding
from .motion_tracks import MotionTracks, TrackConfig
from .object_memory import ObjectMemory
from .scan_reading import (edge_pixels, no_return_as_reading, read_no_echo,
                           shorten_no_returns, veiling_points)
from .second_look import hold_back, scan_window
from .surface_memory import SurfaceMemory
from .trail_marks import update_trails
from .travel_generations import TravelGenerations
from .._kernels import motion_evidence
from ..cell_label import blocked_mask, CellLabel, LABEL_DTYPE
from ..grid_geometry import GridGeometry
from ..scan_polygon import check_pose, check_scan

_EMPTY_WINDOW = (slice(0, 0), slice(0, 0), np.zeros((0, 0), dtype=LABEL_DTYPE))

# Stand-ins for the state arrays of the parts of a rule that are off: the kernel takes the
# same types whatever the rule, so it is compiled once.
_NO_BOOL = np.zeros((1, 1), dtype=bool)
_NO_TIME = np.zeros((1, 1), dtype=np.float64)
_NO_PATH = np.zeros((0, 2), dtype=np.int64)

#: Entries of the list of mobile cells at first; it doubles when full.
_INITIAL_MOBILE_LIST = 256


def check_path(path, shape):
    """
    Validate a path of grid cells.

    Parameters
    ----------
    path : (N, 2) array_like of int, or None
        ``(row, col)`` cells.
    shape : (int, int)
        Grid shape ``(rows, cols)``.

    Returns
    -------
    path : (N, 2) ndarray of int64, or None

    Raises
    ------
    ValueError
        For a wrong shape, non-integer entries or cells off the grid.

    """
    if path is None:
        return None
    cells = np.asarray(path)
    if cells.size == 0:
        return np.zeros((0, 2), dtype=np.int64)
    if cells.ndim != 2 or cells.shape[1] != 2:
        raise ValueError(f'path must be an (N, 2) array of (row, col) cells, got {cells.shape}')
    if not np.issubdtype(cells.dtype, np.integer):
        raise ValueError(f'path cells must be integers, got dtype {cells.dtype}')
    cells = cells.astype(np.int64, copy=False)
    rows, cols = shape
    off = (cells[:, 0] < 0) | (cells[:, 0] >= rows) | (cells[:, 1] < 0) | (cells[:, 1] >= cols)
    if np.any(off):
        raise ValueError(
            f'path cell {tuple(cells[np.argmax(off)].tolist())} is off the {rows}x{cols} grid')
    return cells


def check_update(shape, pose, ranges, angle_min, angle_increment, range_min, range_max,
                 safety_radius, path, angle_max=None):
    """
    Validate the arguments every map's ``update`` takes (``LabelGrid.update``).

    Parameters
    ----------
    shape : (int, int)
        The map's ``(rows, cols)``.
    pose : (float, float, float)
        The laser's ``(x, y, yaw)`` [m, m, rad].
    ranges, angle_min, angle_increment, range_min, range_max, angle_max
        The scan, as in ``LabelGrid.update``.
    safety_radius : float
        f1's ``r`` [m].
    path : (N, 2) array_like of int, or None
        Path cells ``(row, col)``.

    Returns
    -------
    pose : (float, float, float)
    ranges : (L,) ndarray of float64
    safety_radius : float
    path : (N, 2) ndarray of int64, or None

    Raises
    ------
    ValueError
        Naming what is wrong.

    """
    pose = check_pose(pose)
    ranges = check_scan(ranges, angle_min, angle_increment, range_min, range_max, angle_max)
    safety_radius = float(safety_radius)
    if not (math.isfinite(safety_radius) and safety_radius >= 0.0):
        raise ValueError(f'safety_radius must be finite and >= 0, got {safety_radius!r} m')
    return pose, ranges, safety_radius, check_path(path, shape)


@dataclass(frozen=True)
class LabelRule:
    """
    What the grid adds to the paper's FSM; the defaults switch everything off (the paper).

    Attributes
    ----------
    free_evidence_radius : float
        Conservative free space [m]. A cell is surely seen free when its disc of this radius
        lies inside one scan's polygon (``free_evidence.surely_free``); explored -> mobile
        obstacle then happens only to such cells, and a hit in any other explored cell makes
        it a steady obstacle. 0 turns it off: every explored cell counts as seen free.
    moving_object_size : float
        Object-level relabelling [m]. A hit shows motion when a cell within
        ``free_evidence_radius - evidence_margin`` of it was once surely seen free; the hits
        of its scan segment within this distance of it are one moving object
        (``moving_objects``). Every cell the scan hits (f1 = 1) is then labelled by object: a
        mobile obstacle when within the safety radius of a moving object's hit, else a steady
        obstacle, whatever its label was (so the steady cells of an object seen to move
        become mobile, and mobile cells that only objects not seen to move hit, such as a
        wall a wanderer stood by, become steady).
        0 turns it off. Needs ``free_evidence_radius`` > 0.
    evidence_margin : float
        How much closer than ``free_evidence_radius`` a hit must be to a surely-free cell to
        show motion [m]. The scan polygon's edge between two beams cuts a little into a
        convex corner facing the laser (up to about half the beam spacing there), so a
        surely-free disc may reach that far into a wall.
    segment_gap : float
        Consecutive hits farther apart than this start a new scan segment [m].
    segment_bridge_beams : int
        Lost returns inside a surface [beams]: a scan segment goes on across up to this many
        consecutive beams without a hit (no return, an invalid reading, one the edge-pixel
        rules drop) when the hits on both sides lie within ``segment_gap`` of each other.
        0: every beam without a hit ends a segment (before issue 28). A real laser loses a
        return now and then (0.5-2 % of the beams), which cut a wall into short pieces that
        stand free (both ends next to a beam with no return): such a piece next to a walker
        could continue its motion track, or be taken whole for a moving object.
    object_min_hits : int
        Thin things [hits]: a free-standing scan segment (both ends open: the beams just
        outside it return farther or nothing) of fewer hits than this is no object that can
        be seen to move. Its hits show no motion (``moving_object_hits``), and the motion
        tracks neither start nor continue a track with it nor remember where it stood
        (``TrackConfig.min_hits``). A partly hidden segment is not concerned: its hits say
        nothing of its width. A thing narrower than about two beam spacings at its range (a
        post or a speck of a wall 20 m away, where the beams are 0.1 m apart) is hit in one
        scan and slips between the beams in the next, so the space it stands in is seen
        empty and its next hit looks like motion. 0 or 1 turns it off. Does nothing without
        ``moving_object_size``.
    fine_evidence_resolution : float
        Fine free evidence [m] (``fine_evidence``): the side of the cells of a second, finer
        grid of surely-free space. A hit also shows motion (besides within
        ``free_evidence_radius - evidence_margin`` of a surely-free label cell) when its fine
        cell was once surely seen free with ``fine_evidence_radius``: it lies at least that
        radius less half the fine cell's diagonal inside space one scan saw empty. 0 turns it
        off. Needs ``fine_evidence_radius`` > 0 and ``moving_object_size`` > 0.
    fine_evidence_radius : float
        A fine cell is surely free when its disc of this radius lay inside one scan's polygon
        [m]; 0 with ``fine_evidence_resolution`` 0.
    fine_evidence_range : float
        Fine cells are marked surely free only within this distance of the laser [m] (beyond
        it the beams are too far apart for the fine cells: a thin thing hides between them).
        Read with the fine free evidence on; > 0.
    free_evidence_renewal : float
        Free evidence (``seen_free`` and the fine evidence) that the laser's own travel has
        made unsafe is dropped [m of travel]: the evidence is kept in two generations, a new
        one started each time the laser has travelled half this far, so that what is looked
        up was seen free within the last half to whole of this travel. A pose whose heading
        is off by a fixed angle (a localiser's error) places what was seen from two poses
        ``d`` metres apart that angle times ``d`` apart; older evidence under a wall seen
        again from farther on would show the wall moving. 0 keeps the evidence for good (as
        before 27 November). Read with the conservative free space on.
    mobile_expiry : float
        Ghost expiry [s]. A mobile obstacle cell that no hit has been within the safety radius
        of for this long, and that the latest scan does not see (f1 = f2 = 0), goes back to
        explored. 0 turns it off. Needs the scan's ``stamp``.
    track_confirm_time : float
        Motion tracks [s] (``motion_tracks``): an object seen to move is followed from scan to
        scan, and a compact, free-standing segment that continues it is a moving object (its
        hits count as moving hits above) even without evidence of its own; a compact
        free-standing segment next to where one stood a moment ago, now seen empty, is seen to
        move. A track nothing showed moving for this long is dropped. 0 turns it off. Needs
        ``moving_object_size`` > 0 and the scan's ``stamp``.
    track_still_distance : float
        Still objects [m]: a compact segment whose centroid lies within this distance of where
        a compact free-standing segment stood 0.8-1.5 s ago stood still: the places left empty
        near it (by a wanderer passing a post) do not show it moving, and it does not continue
        a track that never moved 0.3 m from where it started. 0 turns it off. Does nothing
        without ``track_confirm_time`` (a rule of the tracks; so that turning the tracks off
        is one parameter).
    track_exclusive : bool
        Exclusive tracks: at most one scan segment continues a track per scan; a segment whose
        nearest track another one took is not followed (with motion evidence of its own it
        starts a track). False: the segments share it. Does nothing without
        ``track_confirm_time``.
    trail_distance : float
        Trails [m]: a mobile cell last labelled by a followed object goes back to explored
        while out of view (f1 = f2 = 0) once the scan sees that object at least this far from
        the cell: the object has moved on, what it left is a trail. 0 turns it off. Needs
        ``track_confirm_time`` > 0.
    object_memory : float
        Object memory [s] (``object_memory``): a steady cell that a hit of a small object (a
        scan segment at most 1 m long with at least 3 hits) has been within the safety radius
        of, and no hit of a longer segment ever was (a wanderer never seen to move, or a
        pillar), is forgotten, back
        to explored if once surely seen free and to non-explored otherwise, once no hit has
        been within the safety radius of it for this long, the latest scan does not see it
        (f1 = f2 = 0) and it is more than twice the safety radius from the laser. 0 turns it
        off. Needs ``track_confirm_time`` > 0 and ``mobile_expiry`` > 0.
    object_memory_short_segments : bool
        Short segments in the object memory: the hits of scan segments of one or two hits
        (fewer than 3; a wanderer glimpsed far off through a gap, or a wall seen at grazing
        incidence) list the steady cells near them as the small objects' do, so that they
        are forgotten on the same terms unless a longer segment anchors them. Off, such hits
        neither anchor nor list. Read only with ``object_memory`` > 0.
    no_echo_below_range_min : bool
        No-echo codes: a finite reading ``0 <= range < range_min`` is read as no return
        (``+inf``) instead of invalid (REP 117). For drivers that write a beam with no echo
        as a tiny range (the old Hokuyo driver writes 0.000-0.019 m); False (REP 117) for
        drivers that write ``+inf``.
    no_return_reach : float
        How far a beam with no return (``+inf`` or ``range >= range_max``) shows space empty,
        as a share of ``range_max`` [1], in ``[0, 1]``: its polygon vertex lies at
        ``no_return_reach * range_max`` (no farther than the fine evidence's range), and at
        the laser when that is below ``range_min``. 1: out to ``range_max`` (the paper, REP
        117; Nav2's obstacle layer with ``inf_is_valid`` true and ``raytrace_max_range`` at
        the sensor's range); 0: a no-return beam clears nothing (``inf_is_valid`` false).
        Weak echoes (dark or far surfaces, grazing incidence) drop out long before
        ``range_max``, so a beam with no return does not show the last stretch empty.
    no_return_standing_distance : float
        Beams with no return clear only while the laser stands [m]
        (``laser_standing.LaserStanding``): with this > 0, ``no_return_reach`` applies while
        the laser has stayed within this distance of one place for
        ``no_return_standing_time``; while it moves such beams clear nothing (as with
        ``no_return_reach`` 0), and when it starts to move the free evidence (``seen_free``
        and the fine evidence) is dropped. A wall at grazing incidence returns nothing; from
        a moving laser it turns towards the beams, and its echo would land in space they
        showed empty. 0 turns it off (``no_return_reach`` always applies). Needs the scan's
        ``stamp``.
    no_return_standing_time : float
        How long the laser must stay within ``no_return_standing_distance`` of a place before
        it stands [s], >= 0.
    surface_time : float
        Intermittent surfaces [s] (``surface_memory.SurfaceMemory``): a place (a cell of
        ``noise_margin``) hit for this long in all, in the scans' time, is a known surface,
        and a hit within one such cell of a known surface shows no motion and continues no
        motion track: a flickering surface (no echo in some scans) is not a moving object.
        0 turns it off. Needs ``moving_object_size`` > 0.
    surface_memory : float
        A place's hit time drains by ``surface_time`` in this long [s] (it holds at most twice
        ``surface_time``); > 0.
    noise_margin : float
        Side of the places of the intermittent surfaces [m], about the laser's range noise: a
        hit within one place of a known surface is on it; > 0.
    mixed_pixel_angle : float
        Mixed pixels [rad] (``scan_reading.mixed_pixels``): a hit that lies between its two
        neighbours in depth, the segments to both within this angle of its beam, is read as
        invalid (no hit, no free space): the spot of a beam at a depth edge fell on both
        surfaces and its range lies between them, on nothing. 0 turns it off.
    spike_angle : float
        Spikes [rad] (``scan_reading.spikes``): a hit whose neighbours both lie nearer, or
        both farther, the segments to both within this angle of its beam, is read as invalid:
        a lone point in depth (two mixed pixels side by side at a depth edge, speckle, a thing
        one beam wide). With ``mixed_pixel_angle`` at the same angle, every hit that veils
        towards both sides is invalid. 0 turns it off.
    edge_pixel_flatness : float
        Flat walls at grazing incidence [m]: a hit within this distance, along its beam, of
        the line through its neighbours' points lies on a flat surface with them and is
        neither a mixed pixel
        nor a spike (a wall met more than ``pi / 2 - mixed_pixel_angle`` from its normal veils
        towards both neighbours too, and its range noise makes spikes). 0 turns it off. Read
        with ``mixed_pixel_angle`` or ``spike_angle`` > 0.
    veiling_angle : float
        Veiling hits [rad] (``scan_reading.veiling_points``, ROS ``laser_filters``' shadow
        filter): a hit whose segment to a neighbour lies within this angle of its beam (beside
        a depth edge, or on a surface seen at grazing incidence, where the polygon's edge runs
        along the beam and a spot's range is least sure) shows no motion of its own; it still
        marks its cells (f1), and a moving object's other hits still make it moving. 0 turns
        it off. Needs ``surface_time`` > 0 (its evidence is taken away with the surfaces').
    range_noise_margin : float
        Range noise [m]: a hit shows motion of its own only when the point
        ``range_noise_margin + range_noise_fraction * range`` farther along its beam shows it
        too (space once surely seen free, coarse or fine): a surface an earlier, longer reading
        showed empty behind its true place is hit again by a shorter one, which is noise, not
        motion. About three standard deviations of the laser's range noise. 0 (with
        ``range_noise_fraction`` 0) turns it off. Needs ``surface_time`` > 0 (its evidence is
        taken away with the surfaces').
    range_noise_fraction : float
        The part of that margin that grows with the range [1] (a laser whose noise is a share
        of the distance: 0.015 for an RPLIDAR A2's 0.5 %).
    free_burn_in : float
        Burn-in of the free evidence [s] (Dynablox's ``burn_in_period``): a fine cell is
        marked surely free only when no hit of an earlier scan has come within
        ``fine_evidence_radius`` of it in this long (``FineEvidence``), and a label cell only
        when none has come within the safety radius (its ``last_hit``, the ghost expiry's
        clock). A surface that returns an echo in some scans and none in others is seen empty
        between its hits, and its next hit would show motion. 0 turns it off. Needs the fine
        free evidence, ``mobile_expiry`` > 0 and a scan stamp.
    free_first_sight : float
        Free evidence needs a second look [s] (``second_look``): a cell, of the label grid's
        ``seen_free`` or of the fine evidence, counts as surely free only from a scan at least
        this long after the first scan that showed it empty. The first scan of a recording,
        or the first to show a place, takes for empty the place of a surface that returned no
        echo in that one scan, and its echo in the next scans would show motion; no hit came
        near it before, so the burn-in cannot hold it back. 0 turns it off. Needs the fine
        free evidence and a scan stamp.
    object_min_width : float
        Narrow things [m]: a scan segment whose first and last hits lie less than this apart
        shows no motion of its own: its evidence is taken away with that of the hits on known
        surfaces. A leg is 0.1-0.15 m wide; a thin or intermittent thing a few centimetres
        wide that returns in some scans only (a cable, a chair leg, one spot of a dark
        surface) is no object that can be seen to move, however many beams hit it, and a
        sliver of an object peeking past a nearer one shows too little of it. 0 turns it off.
        Needs ``surface_time`` > 0.

    """

    free_evidence_radius: float = 0.0
    moving_object_size: float = 0.0
    evidence_margin: float = 0.15
    segment_gap: float = 0.3
    segment_bridge_beams: int = 0
    object_min_hits: int = 0
    fine_evidence_resolution: float = 0.0
    fine_evidence_radius: float = 0.0
    fine_evidence_range: float = 20.0
    free_evidence_renewal: float = 0.0
    mobile_expiry: float = 0.0
    track_confirm_time: float = 0.0
    track_still_distance: float = 0.0
    track_exclusive: bool = False
    trail_distance: float = 0.0
    object_memory: float = 0.0
    object_memory_short_segments: bool = False
    no_echo_below_range_min: bool = False
    no_return_reach: float = 1.0
    no_return_standing_distance: float = 0.0
    no_return_standing_time: float = 0.5
    surface_time: float = 0.0
    surface_memory: float = 10.0
    noise_margin: float = 0.1
    mixed_pixel_angle: float = 0.0
    spike_angle: float = 0.0
    edge_pixel_flatness: float = 0.0
    veiling_angle: float = 0.0
    range_noise_margin: float = 0.0
    range_noise_fraction: float = 0.0
    free_burn_in: float = 0.0
    free_first_sight: float = 0.0
    object_min_width: float = 0.0

    def __post_init__(self):
        for name in ('free_evidence_radius', 'moving_object_size', 'evidence_margin',
                     'fine_evidence_resolution', 'fine_evidence_radius',
                     'fine_evidence_range', 'free_evidence_renewal', 'mobile_expiry',
                     'track_confirm_time', 'track_still_distance', 'trail_distance',
                     'object_memory'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if (isinstance(self.object_min_hits, bool)
                or not isinstance(self.object_min_hits, (int, np.integer))
                or self.object_min_hits < 0):
            raise ValueError('object_min_hits must be an integer >= 0, got '
                             f'{self.object_min_hits!r}')
        if not (math.isfinite(self.segment_gap) and self.segment_gap > 0.0):
            raise ValueError(f'segment_gap must be positive, got {self.segment_gap!r} m')
        if (isinstance(self.segment_bridge_beams, bool)
                or not isinstance(self.segment_bridge_beams, (int, np.integer))
                or self.segment_bridge_beams < 0):
            raise ValueError('segment_bridge_beams must be an integer >= 0, got '
                             f'{self.segment_bridge_beams!r}')
        if self.trail_distance > 0.0 and self.track_confirm_time == 0.0:
            raise ValueError('trail_distance needs track_confirm_time > 0: a trail is left by '
                             'a followed object')
        if self.object_memory > 0.0 and (self.track_confirm_time == 0.0
                                         or self.mobile_expiry == 0.0):
            raise ValueError('object_memory needs track_confirm_time > 0 (the scan segments) '
                             'and mobile_expiry > 0 (the hit clock)')
        if not isinstance(self.object_memory_short_segments, (bool, np.bool_)):
            raise ValueError('object_memory_short_segments must be a bool, got '
                             f'{self.object_memory_short_segments!r}')
        if self.track_confirm_time > 0.0 and self.moving_object_size == 0.0:
            raise ValueError('track_confirm_time needs moving_object_size > 0: tracks follow '
                             'moving objects')
        if (self.fine_evidence_resolution > 0.0) != (self.fine_evidence_radius > 0.0):
            raise ValueError('fine_evidence_resolution and fine_evidence_radius are both 0 '
                             f'(off) or both > 0, got {self.fine_evidence_resolution!r} and '
                             f'{self.fine_evidence_radius!r} m')
        if self.fine_evidence_radius > 0.0 and self.fine_evidence_range == 0.0:
            raise ValueError('fine_evidence_range must be > 0 with the fine free evidence on')
        if self.fine_evidence_radius > 0.0 and self.moving_object_size == 0.0:
            raise ValueError('fine_evidence_radius needs moving_object_size > 0: fine evidence '
                             'shows objects moving')
        if not isinstance(self.no_echo_below_range_min, (bool, np.bool_)):
            raise ValueError('no_echo_below_range_min must be a bool, got '
                             f'{self.no_echo_below_range_min!r}')
        if not (math.isfinite(self.no_return_reach) and 0.0 <= self.no_return_reach <= 1.0):
            raise ValueError('no_return_reach is a share of range_max in [0, 1], got '
                             f'{self.no_return_reach!r}')
        for name in ('surface_time', 'surface_memory', 'noise_margin'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if self.surface_time > 0.0:
            if self.moving_object_size == 0.0:
                raise ValueError('surface_time needs moving_object_size > 0: it takes away '
                                 'motion evidence')
            if self.surface_memory == 0.0 or self.noise_margin == 0.0:
                raise ValueError('surface_time needs surface_memory > 0 and noise_margin > 0')
        if self.moving_object_size > 0.0 and self.free_evidence_radius == 0.0:
            raise ValueError('moving_object_size needs free_evidence_radius > 0: motion is '
                             'shown by hits in space surely seen free')
        for name in ('mixed_pixel_angle', 'spike_angle', 'veiling_angle'):
            value = getattr(self, name)
            if not (math.isfinite(value) and 0.0 <= value <= 0.5 * math.pi):
                raise ValueError(f'{name} must lie in [0, pi / 2] rad, got {value!r}')
        for name in ('range_noise_margin', 'range_noise_fraction', 'edge_pixel_flatness'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if (self.range_noise_margin > 0.0 or self.range_noise_fraction > 0.0) and \
                self.surface_time == 0.0:
            raise ValueError('range_noise_margin and range_noise_fraction need surface_time > 0: '
                             'the hits lose their motion evidence with those on known surfaces')
        if self.veiling_angle > 0.0 and self.surface_time == 0.0:
            raise ValueError('veiling_angle needs surface_time > 0: the veiling hits lose their '
                             'motion evidence with those on known surfaces')
        for name in ('free_burn_in', 'free_first_sight', 'object_min_width',
                     'no_return_standing_distance', 'no_return_standing_time'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if self.free_burn_in > 0.0 and (self.fine_evidence_radius == 0.0
                                        or self.mobile_expiry == 0.0):
            raise ValueError('free_burn_in needs fine_evidence_radius > 0 and mobile_expiry > '
                             '0: it holds back the fine and the coarse free evidence by their '
                             'hit clocks')
        if self.free_first_sight > 0.0 and self.fine_evidence_radius == 0.0:
            raise ValueError('free_first_sight needs fine_evidence_radius > 0: it holds back '
                             'the coarse and the fine free evidence')
        if self.object_min_width > 0.0 and self.surface_time == 0.0:
            raise ValueError('object_min_width needs surface_time > 0: the narrow segments lose '
                             'their motion evidence with those on known surfaces')

    def kernel_arguments(self):
        """
        Return the rule as the label kernel takes it (``label_update.scan_update``).

        Returns
        -------
        tuple
            ``(free_on, free_radius, free_bound, objects_on, evidence_radius,
            evidence_bound, segment_gap, object_size, min_hits, bridge_beams, expiry_on)``, the
            bounds being ``squared_radius_bound`` of the radius before them.

        """
        evidence_radius = max(self.free_evidence_radius - self.evidence_margin, 0.0)
        return (self.free_evidence_radius > 0.0, self.free_evidence_radius,
                squared_bound(self.free_evidence_radius), self.moving_object_size > 0.0,
                evidence_radius, squared_bound(evidence_radius), self.segment_gap,
                self.moving_object_size, int(self.object_min_hits),
                int(self.segment_bridge_beams), self.mobile_expiry > 0.0)


#: The fields of a ``LabelRule`` a running grid may switch (``LabelGrid.switch_rule``): those read
#: scan by scan, which hold no state of their own.
SWITCHABLE_RULE_FIELDS = frozenset({
    'no_return_reach', 'mixed_pixel_angle', 'spike_angle', 'veiling_angle', 'edge_pixel_flatness',
    'range_noise_margin', 'range_noise_fraction', 'free_burn_in', 'object_min_width'})
#: The paper's rule: f1, f2 and the FSM table, nothing else.
PAPER_RULE = LabelRule()


def warm_up_label_update():
    """Compile (or load from the cache) the label kernels with one tiny scan, every rule part."""
    rule = LabelRule(free_evidence_radius=0.5, moving_object_size=0.5, mobile_expiry=1.0,
                     track_confirm_time=1.0, track_still_distance=0.1, track_exclusive=True,
                     trail_distance=1.0, object_memory=1.0, fine_evidence_resolution=0.25,
                     fine_evidence_radius=0.25, no_echo_below_range_min=True,
                     no_return_reach=0.8, surface_time=0.2)
    grid = LabelGrid(2.0, 2.0, 0.5, rule=rule)
    grid.labels[0, 0] = CellLabel.MOBILE_OBSTACLE          # to expire at the second scan
    grid.last_hit[0, 0] = 0.0
    grid.labels_changed()
    ranges = np.array([0.75, np.inf, 0.75])
    for stamp in (0.0, 2.0, 3.0):
        grid.update((1.0, 1.5, 0.0), ranges, -0.5, 0.5, 0.1, 1.5, 0.25, path=[[0, 0]],
                    stamp=stamp, defer_evidence=stamp > 2.5)
    grid.settle()
    # Without the tracks the kernel finds the scan's points itself; without the surface memory
    # the fine evidence finds the moving hits.
    without_surfaces = replace(rule, surface_time=0.0)
    for rule in (PAPER_RULE, LabelRule(free_evidence_radius=0.5), without_surfaces):
        LabelGrid(2.0, 2.0, 0.5, rule=rule).update(
            (1.0, 1.5, 0.0), ranges, -0.5, 0.5, 0.1, 1.5, 0.25, path=[[0, 0]], stamp=0.0,
            defer_evidence=True)


class ChangeTracker:
    """
    A box around the cells of a ``LabelGrid`` that changed since its owner last looked.

    Made by ``LabelGrid.change_tracker``; every update widens it by the scan's window and the
    cells the ghost expiry touched, `LabelGrid.labels_changed` and ``reset`` make it the whole
    grid. The owner (a planner's masks, a published map) refreshes what it derives from the
    labels inside `take` and nothing else.

    """

    def __init__(self, shape):
        self._shape = shape
        self._box = [0, shape[0], 0, shape[1]]            # all changed: nothing derived yet

    def widen(self, rows, cols):
        """Add the cells of ``labels[rows, cols]`` (slices, possibly empty)."""
        if rows.start >= rows.stop or cols.start >= cols.stop:
            return
        box = self._box
        if box[0] >= box[1]:
            self._box = [rows.start, rows.stop, cols.start, cols.stop]
            return
        box[0] = min(box[0], rows.start)
        box[1] = max(box[1], rows.stop)
        box[2] = min(box[2], cols.start)
        box[3] = max(box[3], cols.stop)

    def widen_all(self):
        """Mark every cell changed."""
        self._box = [0, self._shape[0], 0, self._shape[1]]

    def resize(self, shape):
        """Follow the grid to a new ``shape`` (it grew): every cell changed."""
        self._shape = tuple(shape)
        self.widen_all()

    def take(self):
        """
        Return the changed box and start a new one, empty.

        Returns
        -------
        rows, cols : slice
            A box holding every cell changed since the last call (empty slices when none).
        whole : bool
            True when the box is the whole grid.

        """
        row_lo, row_hi, col_lo, col_hi = self._box
        self._box = [0, 0, 0, 0]
        whole = (row_lo, row_hi, col_lo, col_hi) == (0, self._shape[0], 0, self._shape[1])
        return slice(row_lo, max(row_lo, row_hi)), slice(col_lo, max(col_lo, col_hi)), whole


class PlanningMap:
    """
    The map a ``Navigator`` plans on: the interface it relies on, and the change trackers.

    A subclass (``LabelGrid``; the benchmark's ``CostmapGrid`` and ``OracleGrid``) has
    ``geometry`` (``GridGeometry``) and ``labels`` ((rows, cols) ndarray of uint8, the
    ``CellLabel`` of each cell, written by its own methods only), sets ``self._trackers = []``
    and widens them where its labels change, and implements ``update(pose, ranges, angle_min,
    angle_increment, range_min, range_max, safety_radius, path=None, angle_max=None,
    stamp=None)``, which folds one scan in and returns the replan flag, and
    ``labels_changed()``. What the navigator needs besides has a default here: `settle`,
    `forget_obstacles` and `change_tracker`.
    """

    #: Whether ``update`` takes ``defer_evidence=True`` and `settle` finishes what it left.
    defers_evidence = False

    def settle(self):
        """Finish what an update with ``defer_evidence`` left; nothing for this map."""

    def forget_obstacles(self, centre, keep_radius, every_obstacle):
        """
        Forget obstacle cells: mobile ones back to explored, or every one to non-explored.

        Parameters
        ----------
        centre : (float, float)
            Map-frame point [m] around which cells are kept (the robot).
        keep_radius : float
            Cells whose centre is within this distance of ``centre`` are kept [m].
        every_obstacle : bool
            False: mobile obstacles go back to explored; True: every obstacle cell (steady
            too) goes back to non-explored.

        """
        labels = self.labels
        geometry = self.geometry
        rows, cols = geometry.cell_window(centre[0] - keep_radius, centre[0] + keep_radius,
                                          centre[1] - keep_radius, centre[1] + keep_radius)
        x_centres, y_centres = geometry.window_centres(rows, cols)
        near = np.hypot(x_centres[None, :] - centre[0],
                        y_centres[:, None] - centre[1]) <= keep_radius
        kept = labels[rows, cols].copy()
        if not every_obstacle:
            labels[labels == CellLabel.MOBILE_OBSTACLE] = CellLabel.EXPLORED
        else:
            labels[blocked_mask(labels)] = CellLabel.NON_EXPLORED
        labels[rows, cols] = np.where(near, kept, labels[rows, cols])
        self.labels_changed()

    def change_tracker(self):
        """
        Return a new `ChangeTracker` of this map, at first holding every cell.

        Returns
        -------
        ChangeTracker

        """
        tracker = ChangeTracker(self.geometry.shape)
        self._trackers.append(tracker)
        return tracker

    def _widen_trackers(self, rows, cols):
        for tracker in self._trackers:
            tracker.widen(rows, cols)

    def _widen_trackers_all(self):
        for tracker in self._trackers:
            tracker.widen_all()


class LabelGrid(PlanningMap):
    """
    Occupancy grid whose cells carry one of the four ``CellLabel`` values.

    Parameters
    ----------
    width, height : float
        Size of the environment along x and y [m].
    resolution : float
        Cell side [m]; the paper uses 0.5.
    origin : (float, float)
        Map-frame position of the lower-left corner [m].
    rule : LabelRule
        What to add to the paper's FSM; default ``PAPER_RULE``.

    Attributes
    ----------
    geometry : GridGeometry
        Size and placement; owns every world <-> cell conversion.
    labels : (rows, cols) ndarray of uint8
        Current labels, row ``i`` along y; all ``NON_EXPLORED`` at start. Updated in place.
    rule : LabelRule
    seen_free : (rows, cols) ndarray of bool, or None
        Cells once surely seen free; None unless ``rule.free_evidence_radius`` > 0. After an
        update with ``defer_evidence``, without that scan's cells until `settle`.
    last_hit : (rows, cols) ndarray of float64, or None
        Stamp of the last scan with f1 = 1 on each cell [s], ``-inf`` before any; None unless
        ``rule.mobile_expiry`` > 0.
    tracks : MotionTracks
        The moving objects followed (none unless ``rule.track_confirm_time`` > 0).
    cell_track : (rows, cols) ndarray of int64, or None
        The track (``MotionTracks.ids``) whose hits last labelled each cell mobile, -1 for
        none; None unless ``rule.trail_distance`` > 0.
    object_memory : ObjectMemory or None
        The steady cells only small free-standing objects explain (``object_memory``); None
        unless ``rule.object_memory`` > 0.
    last_window : (slice, slice, (n_rows, n_cols) ndarray of uint8)
        The latest update's window and its FSM input (``ScanInput``); empty slices when the
        scan missed the grid. Cells outside the window had input ``NONE``.

    Notes
    -----
    An update is one compiled kernel over the window the scan reaches
    (``label_update.scan_update``); nothing is done over the whole grid. The ghost expiry
    keeps a list of the cells it has seen become mobile and visits only those, and only when
    the earliest hit among them is ``mobile_expiry`` old. Code that writes ``labels`` or
    ``last_hit`` itself (tests, a forgetting navigator) calls `labels_changed` afterwards.

    """

    defers_evidence = True

    def __init__(self, width, height, resolution=0.5, origin=(0.0, 0.0), rule=PAPER_RULE):
        self.geometry = GridGeometry(width, height, resolution, tuple(origin))
        self.rule = rule
        self.labels = np.full(self.geometry.shape, CellLabel.NON_EXPLORED, dtype=LABEL_DTYPE)
        self.seen_free = (np.zeros(self.geometry.shape, dtype=bool)
                          if rule.free_evidence_radius > 0.0 else None)
        # The free evidence's renewal: the cells marked since the current generation began,
        # and the travel that ends it.
        renewing = self.seen_free is not None and rule.free_evidence_renewal > 0.0
        self._fresh_free = np.zeros(self.geometry.shape, dtype=bool) if renewing else None
        self._generations = (TravelGenerations(0.5 * rule.free_evidence_renewal) if renewing
                             else None)
        self.last_hit = (np.full(self.geometry.shape, -math.inf)
                         if rule.mobile_expiry > 0.0 else None)
        # A second look (`second_look`): per cell the first scan that showed it surely empty.
        self.first_free = (np.full(self.geometry.shape, math.inf)
                           if self.seen_free is not None and rule.free_first_sight > 0.0
                           else None)
        self._kernel_rule = rule.kernel_arguments()
        # The ghost expiry's list of mobile cells (flat indices, the first _mobile_count), the
        # grid of which cells it holds, and a lower bound of their last_hit.
        self._listed = (np.zeros(self.geometry.shape, dtype=bool)
                        if rule.mobile_expiry > 0.0 else None)
        self._mobile_cells = np.empty(_INITIAL_MOBILE_LIST, dtype=np.int64)
        self._mobile_count = 0
        self._earliest_hit = math.inf
        self._last_stamp = -math.inf
        self._trackers = []
        self.last_window = _EMPTY_WINDOW
        self.tracks = MotionTracks(TrackConfig(confirm_within=rule.track_confirm_time,
                                               still_distance=rule.track_still_distance,
                                               min_hits=int(rule.object_min_hits),
                                               exclusive=bool(rule.track_exclusive),
                                               bridge_beams=int(rule.segment_bridge_beams)))
        self.cell_track = (np.full(self.geometry.shape, -1, dtype=np.int64)
                           if rule.trail_distance > 0.0 else None)
        self._marked = np.zeros(0, dtype=np.int64)   # flat cells that may hold a track
        self._followed_hits = None                  # (hits_x, hits_y) of the latest scan
        self._laser_xy = (0.0, 0.0)
        self.object_memory = (ObjectMemory(self.geometry, rule.object_memory)
                              if rule.object_memory > 0.0 else None)
        self.fine_evidence = (FineEvidence(self.geometry, rule.fine_evidence_resolution,
                                           rule.fine_evidence_radius, rule.fine_evidence_range,
                                           rule.free_evidence_renewal, rule.free_burn_in,
                                           rule.free_first_sight)
                              if rule.fine_evidence_radius > 0.0 else None)
        # Free evidence an update left for `settle`: (free window, fine scan), or None.
        self._deferred = None
        self.surface_memory = (SurfaceMemory(self.geometry, rule.noise_margin,
                                             rule.surface_time, rule.surface_memory)
                               if rule.surface_time > 0.0 else None)
        self.laser_standing = (LaserStanding(rule.no_return_standing_distance,
                                             rule.no_return_standing_time)
                               if rule.no_return_standing_distance > 0.0 else None)

    def update(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
               safety_radius, path=None, angle_max=None, stamp=None, defer_evidence=False):
        """
        Fold one laser scan into the labels and say whether the path needs replanning.

        Parameters
        ----------
        pose : (float, float, float)
            The laser's ``(x, y, yaw)`` in the map frame [m, m, rad]; may lie off the grid.
        ranges : (L,) array_like of float
            Ranges [m], REP 117 (``+inf`` no return; NaN, ``-inf`` or short: invalid).
        angle_min, angle_increment : float
            Laser-frame angle of the first beam and the step between beams [rad].
        range_min, range_max : float
            Valid return interval ``[range_min, range_max)`` [m].
        safety_radius : float
            f1's ``r`` [m]: cells whose centre is within it of a hit become obstacles.
        path : (N, 2) array_like of int, optional
            The planned path as ``(row, col)`` cells.
        angle_max : float, optional
            Angle of the last beam [rad]; when given, the beam count is checked against it.
        stamp : float, optional
            Time of the scan [s], any clock; needed with ``rule.mobile_expiry`` > 0.
        defer_evidence : bool
            Leave the evidence this scan gives (``seen_free``, the fine evidence, the object
            memory's anchors and list) for `settle`, or for the next update, which settles
            first. The labels, the replan flag and the window are the same as without: the
            rule reads that evidence only for later scans. A node publishes the map in
            between. Code that writes ``labels`` itself calls `settle` first
            (``ObjectMemory.update``'s ``defer_marks`` says why, and what its list may hold).

        Returns
        -------
        replan : bool
            True when a cell of ``path`` went from free (non-explored or explored) to an
            obstacle in this update. Under the paper's rule these are exactly its two
            transitions, non-explored -> steady and explored -> mobile.

        Raises
        ------
        ValueError
            For a non-finite pose, malformed scan fields, a negative or non-finite safety
            radius, a malformed path or a missing stamp; the labels are then unchanged.

        """
        self.settle()
        pose, ranges, safety_radius, path, stamp = self._checked_scan(
            pose, ranges, angle_min, angle_increment, range_min, range_max, safety_radius, path,
            angle_max, stamp)
        expiring = self.rule.mobile_expiry > 0.0
        if expiring or self.first_free is not None:
            self._restart_clocks_if_time_went_back(stamp)
        reach = self._no_return_reach(pose, stamp)
        ranges = read_no_echo(ranges, range_min, self.rule.no_echo_below_range_min)
        if self.rule.mixed_pixel_angle > 0.0 or self.rule.spike_angle > 0.0:
            mixed = edge_pixels(ranges, angle_increment, range_min, range_max,
                                self.rule.mixed_pixel_angle, self.rule.spike_angle,
                                self.rule.edge_pixel_flatness)
            if mixed.any():
                ranges = ranges.copy()
                ranges[mixed] = math.nan
        if self._generations is not None and self._generations.step(pose):
            # A new generation: the one that ends is kept, the older ones are dropped.
            np.copyto(self.seen_free, self._fresh_free)
            self._fresh_free.fill(False)
        followed = points = None
        if (self.rule.track_confirm_time > 0.0 or self.fine_evidence is not None
                or self.surface_memory is not None or reach < 1.0):
            followed, points = self._follow(pose, ranges, angle_min, angle_increment,
                                            range_min, range_max, stamp, reach)
        fine_scan = None
        if self.fine_evidence is not None:
            # Read by the next scans only (`_follow` took this one's before).
            fine_ranges = no_return_as_reading(ranges, range_min, range_max, reach)
            fine_scan = (pose, fine_ranges.copy() if defer_evidence and fine_ranges is ranges
                         else fine_ranges, angle_min, angle_increment, range_min, range_max,
                         0.0 if stamp is None else stamp, (points[2], points[3]))
            if not defer_evidence:
                self.fine_evidence.update(*fine_scan)
                fine_scan = None
        look = None
        if self.first_free is not None:
            look = (scan_window(self.geometry, pose, range_max + max(
                safety_radius, self.rule.free_evidence_radius)), stamp)
            before = None if defer_evidence else self.seen_free[look[0]].copy()
        replan, self.last_window, new_mobile, free_scan = scan_update(
            self.labels, _NO_BOOL if self.seen_free is None else self.seen_free,
            _NO_TIME if self.last_hit is None else self.last_hit,
            _NO_BOOL if self._listed is None else self._listed, self.geometry, pose, ranges,
            angle_min, angle_increment, range_min, range_max, safety_radius, self._kernel_rule,
            stamp if expiring else 0.0, _NO_PATH if path is None else path, followed, points,
            defer_free=defer_evidence, free_fresh_after=self._free_fresh_after(stamp))
        if free_scan is not None or fine_scan is not None:
            self._deferred = (free_scan, fine_scan, look)
        elif look is not None:
            self._hold_back(self.seen_free, *look, before)
        if self._fresh_free is not None:
            # This generation's marks, at least as conservative as the kernel's (a safety
            # radius above the free one keeps more cells out): `seen_free` at the next renewal.
            burning_in = self.rule.free_burn_in > 0.0
            fresh_before = None if look is None else self._fresh_free[look[0]].copy()
            surely_free_update(self._fresh_free, self.geometry, pose, no_return_as_reading(
                ranges, range_min, range_max, reach), angle_min,
                angle_increment, range_min, range_max,
                max(self.rule.free_evidence_radius, safety_radius),
                self.last_hit if burning_in else None, self._free_fresh_after(stamp))
            if look is not None:
                self._hold_back(self._fresh_free, *look, fresh_before)
        self._widen_trackers(self.last_window[0], self.last_window[1])
        if expiring:
            self._list_mobile(new_mobile, stamp)
            self._expire_mobile(stamp)
        if self.cell_track is not None and self.last_window[2].size:
            self._trails(safety_radius, stamp)
        if self.object_memory is not None:
            self._forget_objects(safety_radius, stamp, defer_evidence)
        return replan

    def settle(self):
        """
        Mark the evidence an update with ``defer_evidence`` left; nothing when none.

        Until then ``seen_free`` and the fine evidence lack that scan's cells, and the object
        memory its anchors and listed cells. `update` and `reset` call it first themselves.
        """
        if self.object_memory is not None:
            self.object_memory.settle()
        if self._deferred is None:
            return
        free_scan, fine_scan, look = self._deferred
        self._deferred = None
        if free_scan is not None:
            before = None if look is None else self.seen_free[look[0]].copy()
            mark_free_window(self.seen_free, self.geometry, free_scan, self.last_hit)
            if look is not None:
                self._hold_back(self.seen_free, *look, before)
        if fine_scan is not None:
            self.fine_evidence.update(*fine_scan)

    def _hold_back(self, marks, window, stamp, before):
        """Take back a scan's coarse ``marks`` on cells first seen free too recently."""
        hold_back(marks, self.first_free, window, before, stamp, self.rule.free_first_sight)

    def _free_fresh_after(self, stamp):
        """
        Return the burn-in's bound for the scan at ``stamp`` [s]: ``-inf`` without it.

        A cell whose hit clock (``last_hit``: a hit within ``r``) is later is not marked
        surely free (``free_burn_in``).
        """
        if self.rule.free_burn_in > 0.0:
            return stamp - self.rule.free_burn_in
        return -math.inf

    def _no_return_reach(self, pose, stamp):
        """
        Return how far beams with no return clear in this scan, as a share of ``range_max``.

        ``no_return_reach``, or 0 while the laser moves (``no_return_standing_distance``);
        when the laser starts to move, drops the free evidence.
        """
        if self.laser_standing is None:
            return self.rule.no_return_reach
        if self.laser_standing.step(pose, stamp):
            self._drop_free_evidence()
        return self.rule.no_return_reach if self.laser_standing.standing else 0.0

    def switch_rule(self, rule):
        """
        Take ``rule`` from the next scan on, dropping the free evidence gathered so far.

        Only the rules that read each scan as it comes may change (`SWITCHABLE_RULE_FIELDS`:
        how beams with no return clear, the edge-pixel rules, the range noise, the burn-in,
        narrow things); the labels, the hit clocks, the tracks and the memories stay. The free
        evidence (``seen_free`` and the fine evidence) was gathered under the old rule (beams
        with no return that cleared through a wall, say) and is dropped (`_drop_free_evidence`).

        Parameters
        ----------
        rule : LabelRule
            The rule from the next scan on; a valid ``LabelRule`` (its constructor checks it).

        Raises
        ------
        ValueError
            When a field outside `SWITCHABLE_RULE_FIELDS` differs; the grid is then unchanged.

        """
        changed = {item.name for item in fields(LabelRule)
                   if getattr(rule, item.name) != getattr(self.rule, item.name)}
        fixed = sorted(changed - SWITCHABLE_RULE_FIELDS)
        if fixed:
            raise ValueError(f'a grid cannot switch {", ".join(fixed)} while it runs; only '
                             f'{", ".join(sorted(SWITCHABLE_RULE_FIELDS))}')
        if not changed:
            return
        self.settle()
        if self.fine_evidence is not None:
            self.fine_evidence.set_burn_in(rule.free_burn_in)
        self.rule = rule
        self._kernel_rule = rule.kernel_arguments()
        self._drop_free_evidence()

    def _drop_free_evidence(self):
        """
        Forget which space was surely seen free (coarse and fine, both generations).

        The labels and the hit clocks stay. Used when the laser starts to move after it
        stood: its beams with no return showed space empty that a wall at grazing incidence
        may fill from the next place.
        """
        if self.seen_free is not None:
            self.seen_free.fill(False)
        if self._fresh_free is not None:
            self._fresh_free.fill(False)
        if self.fine_evidence is not None:
            self.fine_evidence.drop_free()

    def _follow(self, pose, ranges, angle_min, angle_increment, range_min, range_max, stamp,
                reach):
        """
        Follow the moving objects through the scan.

        ``reach`` is how far beams with no return clear, a share of ``range_max``.

        Returns the hits of followed objects and those the fine evidence shows moving, and the
        scan's points and moving hits (`scan_hits`, with the fine evidence's) for the update.
        """
        points = scan_hits(
            _NO_BOOL if self.seen_free is None else self.seen_free, self.geometry, pose, ranges,
            angle_min, angle_increment, range_min, range_max, self._kernel_rule,
            find_moving=self.surface_memory is None)
        vertices_x, vertices_y, hits_x, hits_y, hit_beams, moving = points
        if reach < 1.0:
            shorten_no_returns(vertices_x, vertices_y, ranges, range_min, range_max, reach)
        if self.surface_memory is not None:
            return self._follow_off_surfaces(pose, ranges, angle_min, angle_increment,
                                             range_min, range_max, stamp, points)
        fine_moving = None
        if self.fine_evidence is not None:
            # From the fine evidence before this scan; the hits are moving for the label
            # update too (as extra moving hits, so that an update that finds the points
            # again agrees).
            fine_moving = self.fine_evidence.moving_hits(points, self.rule)
            moving = moving | fine_moving
            points = (vertices_x, vertices_y, hits_x, hits_y, hit_beams, moving)
        self._followed_hits = (hits_x, hits_y)
        self._laser_xy = (vertices_x[0], vertices_y[0])
        beam_reach = np.hypot(vertices_x[1:-1] - vertices_x[0],
                              vertices_y[1:-1] - vertices_y[0])
        if self.rule.track_confirm_time > 0.0:
            followed = self.tracks.update(
                stamp, (vertices_x[0], vertices_y[0]), hits_x, hits_y, hit_beams,
                ranges.shape[0], moving, self.rule.segment_gap, pose[2] + angle_min,
                angle_increment, beam_reach)
        else:
            followed = np.zeros(hits_x.shape[0], dtype=bool)
        if fine_moving is not None:
            followed = followed | fine_moving
        return followed, points

    def _follow_off_surfaces(self, pose, ranges, angle_min, angle_increment, range_min,
                             range_max, stamp, points):
        """
        `_follow` with the intermittent surfaces: no evidence nor track on known surfaces.

        The evidence of each hit (the coarse free space's and the fine's) is taken away on
        known surfaces (and from veiling hits, with ``veiling_angle``, and narrow segments,
        with ``object_min_width``) before the object rule
        spreads it along the segments; then the scan's
        hits fill the surface memory, but those of objects followed and seen to move.
        """
        vertices_x, vertices_y, hits_x, hits_y, hit_beams, _ = points
        rule = self.rule
        (_, _, _, _, evidence_radius, evidence_bound, segment_gap, object_size, min_hits,
         bridge_beams, _) = self._kernel_rule
        x0, y0 = self.geometry.origin
        evidence = motion_evidence.hit_evidence(self.seen_free, hits_x, hits_y, x0, y0,
                                                self.geometry.resolution, evidence_radius,
                                                evidence_bound)
        if self.fine_evidence is not None:
            evidence = evidence | self.fine_evidence.evidence(hits_x, hits_y)
        if rule.range_noise_margin > 0.0 or rule.range_noise_fraction > 0.0:
            shown = np.flatnonzero(evidence)
            if shown.size:
                evidence[shown] = self._evidence_beyond_noise(
                    hits_x[shown], hits_y[shown], vertices_x[0], vertices_y[0],
                    evidence_radius, evidence_bound)
        on_surface = self.surface_memory.on_surface(hits_x, hits_y, stamp)
        if rule.veiling_angle > 0.0:
            veiling = veiling_points(ranges, angle_increment, range_min, range_max,
                                     rule.veiling_angle)
            evidence = evidence & ~veiling[hit_beams]
        if rule.object_min_width > 0.0 and hits_x.shape[0]:
            evidence = evidence & ~motion_evidence.narrow_segments(
                hits_x, hits_y, hit_beams, segment_gap, rule.object_min_width, bridge_beams)
        moving = motion_evidence.moving_hits(hits_x, hits_y, hit_beams, evidence & ~on_surface,
                                             segment_gap, object_size, min_hits,
                                             vertices_x[0], vertices_y[0], ranges.shape[0],
                                             bridge_beams)
        points = (vertices_x, vertices_y, hits_x, hits_y, hit_beams, moving)
        self._followed_hits = (hits_x, hits_y)
        self._laser_xy = (vertices_x[0], vertices_y[0])
        if rule.track_confirm_time > 0.0:
            beam_reach = np.hypot(vertices_x[1:-1] - vertices_x[0],
                                  vertices_y[1:-1] - vertices_y[0])
            followed = self.tracks.update(
                stamp, (vertices_x[0], vertices_y[0]), hits_x, hits_y, hit_beams,
                ranges.shape[0], moving, segment_gap, pose[2] + angle_min, angle_increment,
                beam_reach, surface=on_surface)
            followed &= ~on_surface
            # The hits of objects followed and seen to move fill no place.
            fill = None
            for track in self.tracks.ids[self.tracks.moved]:      # a few tracks at most
                fill = self.tracks.hit_ids != track if fill is None else (
                    fill & (self.tracks.hit_ids != track))
        else:
            followed = np.zeros(hits_x.shape[0], dtype=bool)
            fill = None
        self.surface_memory.fill(hits_x, hits_y, stamp, fill)
        return followed, points

    def _evidence_beyond_noise(self, hits_x, hits_y, laser_x, laser_y, evidence_radius,
                               evidence_bound):
        """
        Tell for each hit whether the point the range noise margin beyond it shows motion.

        Parameters
        ----------
        hits_x, hits_y : (K,) ndarray of float64
            Hit points in the map frame [m].
        laser_x, laser_y : float
            The laser [m].
        evidence_radius, evidence_bound : float
            The coarse evidence's search reach and squared radius (the kernel rule's).

        Returns
        -------
        (K,) ndarray of bool

        """
        dx, dy = hits_x - laser_x, hits_y - laser_y
        reach = np.hypot(dx, dy)
        margin = self.rule.range_noise_margin + self.rule.range_noise_fraction * reach
        scale = margin / np.maximum(reach, 1e-9)
        far_x = np.ascontiguousarray(hits_x + dx * scale)
        far_y = np.ascontiguousarray(hits_y + dy * scale)
        x0, y0 = self.geometry.origin
        beyond = motion_evidence.hit_evidence(self.seen_free, far_x, far_y, x0, y0,
                                              self.geometry.resolution, evidence_radius,
                                              evidence_bound)
        if self.fine_evidence is not None:
            beyond |= self.fine_evidence.evidence(far_x, far_y)
        return beyond

    def _trails(self, safety_radius, stamp):
        """Mark the cells of the followed objects' hits; clear the trails they left."""
        hits_x, hits_y = self._followed_hits
        tracks = self.tracks
        self._marked, cleared = update_trails(
            self.cell_track, self.labels, self._marked, self.geometry, self.last_window,
            hits_x, hits_y, tracks.hit_ids, tracks.ids, tracks.positions, tracks.last_seen,
            stamp, safety_radius, self.rule.trail_distance)
        # The ghost expiry's list drops cells no longer mobile when it next visits them.
        self._widen_trackers(*cleared)

    def _forget_objects(self, safety_radius, stamp, defer_marks=False):
        """Forget the steady cells of small objects out of view and unconfirmed for long."""
        hits_x, hits_y = self._followed_hits
        # With short segments, every hit not of a long segment lists: the small objects' and
        # those of segments of fewer than 3 hits.
        listing = (~self.tracks.hit_long if self.rule.object_memory_short_segments
                   else self.tracks.hit_object)
        changed = self.object_memory.update(
            self.labels, self.seen_free, self.last_hit, self.last_window, hits_x, hits_y,
            self.tracks.hit_long, listing, self._laser_xy, safety_radius, stamp, defer_marks)
        if changed is not None:
            self._widen_trackers(*changed)

    def _checked_scan(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
                      safety_radius, path, angle_max, stamp):
        """Validate `update`'s arguments; return pose, ranges, radius, path and stamp."""
        pose, ranges, safety_radius, path = check_update(
            self.geometry.shape, pose, ranges, angle_min, angle_increment, range_min, range_max,
            safety_radius, path, angle_max)
        if (self.rule.mobile_expiry > 0.0 or self.rule.track_confirm_time > 0.0
                or self.rule.free_burn_in > 0.0 or self.rule.free_first_sight > 0.0
                or self.rule.no_return_standing_distance > 0.0):
            if stamp is None or not math.isfinite(stamp):
                raise ValueError('the label rule (mobile_expiry, track_confirm_time, '
                                 'free_burn_in, free_first_sight, no_return_standing_distance) '
                                 f'needs a finite scan stamp, got {stamp!r}')
            stamp = float(stamp)
        return pose, ranges, safety_radius, path, stamp

    def _list_mobile(self, cells, stamp):
        """Append cells just made mobile (their last hit is ``stamp``) to the list."""
        count = cells.shape[0]
        if not count:
            return
        needed = self._mobile_count + count
        if needed > self._mobile_cells.shape[0]:
            grown = np.empty(max(needed, 2 * self._mobile_cells.shape[0]), dtype=np.int64)
            grown[:self._mobile_count] = self._mobile_cells[:self._mobile_count]
            self._mobile_cells = grown
        self._mobile_cells[self._mobile_count:needed] = cells
        self._mobile_count = needed
        self._earliest_hit = min(self._earliest_hit, stamp)

    def _restart_clocks_if_time_went_back(self, stamp):
        """After a jump back in time (a restarted simulation), no clock is later than now."""
        if stamp < self._last_stamp:
            if self.last_hit is not None:
                np.minimum(self.last_hit, stamp, out=self.last_hit)
            if self.first_free is not None:
                np.minimum(self.first_free, stamp, out=self.first_free)
            self._earliest_hit = min(self._earliest_hit, stamp)
        self._last_stamp = stamp

    def _expire_mobile(self, stamp):
        """
        Set mobile cells out of view and unconfirmed for ``mobile_expiry`` to explored.

        Only the listed cells are visited, and only when the earliest last hit among them is
        old enough: ``stamp - last_hit`` is monotone in ``last_hit``, so no cell is stale
        while ``stamp - earliest < mobile_expiry``.
        """
        if not self._mobile_count or stamp - self._earliest_hit < self.rule.mobile_expiry:
            return
        self._mobile_count, self._earliest_hit, (rows, cols) = expire_listed(
            self.labels, self.last_hit, self._listed, self._mobile_cells, self._mobile_count,
            stamp, self.rule.mobile_expiry, self.last_window)
        self._widen_trackers(rows, cols)

    def labels_changed(self):
        """
        Relist the mobile cells after ``labels`` or ``last_hit`` were written from outside.

        Updates keep the ghost expiry's list of mobile cells themselves; a caller that sets
        cells mobile by hand, or changes ``last_hit``, calls this (a whole-grid pass) so that
        the expiry sees them, and so that every `ChangeTracker` holds the whole grid.

        """
        self._widen_trackers_all()
        if self._listed is None:
            return
        mobile = self.labels == CellLabel.MOBILE_OBSTACLE
        self._listed[...] = mobile
        cells = np.flatnonzero(mobile)
        self._mobile_cells = np.empty(max(_INITIAL_MOBILE_LIST, 2 * cells.shape[0]),
                                      dtype=np.int64)
        self._mobile_count = cells.shape[0]
        self._mobile_cells[:self._mobile_count] = cells
        self._earliest_hit = (float(self.last_hit.ravel()[cells].min()) if cells.shape[0]
                              else math.inf)

    def grow(self, growth):
        """
        Add cells on the grid's sides; every cell and what is known of it keeps its place.

        The labels, the free evidence, the hit times, the ghost expiry's list, the trails'
        cells, the object memory, the fine free evidence and the surface memory move with
        their cells (a finer grid whose origin would move by a fraction of its cell starts
        again empty); the added cells are as a new grid's. Every `ChangeTracker` then holds
        the whole grid.

        Parameters
        ----------
        growth : map_growth.GridGrowth
            The rows and columns added on each side.

        """
        if not growth:
            return
        self.settle()
        old = self.geometry
        new = growth.geometry(old)
        shape = new.shape
        self.labels = growth.embed(self.labels, shape, CellLabel.NON_EXPLORED)
        if self.seen_free is not None:
            self.seen_free = growth.embed(self.seen_free, shape, False)
        if self._fresh_free is not None:
            self._fresh_free = growth.embed(self._fresh_free, shape, False)
        if self.last_hit is not None:
            self.last_hit = growth.embed(self.last_hit, shape, -math.inf)
            self._listed = growth.embed(self._listed, shape, False)
        if self.first_free is not None:
            self.first_free = growth.embed(self.first_free, shape, math.inf)
        count = self._mobile_count
        self._mobile_cells[:count] = growth.remap(self._mobile_cells[:count], old.cols,
                                                  new.cols)
        if self.cell_track is not None:
            self.cell_track = growth.embed(self.cell_track, shape, -1)
        self._marked = growth.remap(self._marked, old.cols, new.cols)
        rows, cols, cell_input = self.last_window
        self.last_window = (*growth.shift_window(rows, cols), cell_input)
        self.geometry = new
        if self.object_memory is not None:
            self.object_memory.grow(growth, new)
        if self.fine_evidence is not None:
            self.fine_evidence.grow(new)
        if self.surface_memory is not None:
            self.surface_memory.grow(new)
        for tracker in self._trackers:
            tracker.resize(shape)

    @property
    def nbytes(self):
        """Bytes held by the per-cell arrays (the memories' finer grids too)."""
        arrays = [self.labels, self.seen_free, self.last_hit, self._listed, self.cell_track,
                  self._fresh_free, self.first_free]
        total = sum(array.nbytes for array in arrays if array is not None)
        for part in (self.object_memory, self.fine_evidence, self.surface_memory):
            if part is not None:
                total += part.nbytes
        return total

    def reset(self):
        """Forget everything: every cell back to ``NON_EXPLORED``, no evidence kept."""
        self._deferred = None
        self.labels.fill(CellLabel.NON_EXPLORED)
        if self.seen_free is not None:
            self.seen_free.fill(False)
        if self._fresh_free is not None:
            self._fresh_free.fill(False)
            self._generations.reset()
        if self.last_hit is not None:
            self.last_hit.fill(-math.inf)
            self._listed.fill(False)
        if self.first_free is not None:
            self.first_free.fill(math.inf)
        self._mobile_count = 0
        self._earliest_hit = math.inf
        self._last_stamp = -math.inf
        self.last_window = _EMPTY_WINDOW
        self._widen_trackers_all()
        self.tracks.reset()
        if self.cell_track is not None:
            self.cell_track.fill(-1)
        self._marked = np.zeros(0, dtype=np.int64)
        if self.object_memory is not None:
            self.object_memory.reset()
        if self.laser_standing is not None:
            self.laser_standing.reset()

        if self.fine_evidence is not None:
            self.fine_evidence.reset()
        if self.surface_memory is not None:
            self.surface_memory.reset()
