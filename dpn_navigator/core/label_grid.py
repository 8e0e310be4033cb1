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

from dataclasses import dataclass
import math

import numpy as np

from .cell_label import blocked_mask, CellLabel, LABEL_DTYPE, ScanInput, TRANSITION
from .free_evidence import surely_free
from .grid_geometry import GridGeometry
from .motion_tracks import MotionTracks, TrackConfig
from .moving_objects import moving_object_hits
from .scan_features import hit_runs, run_cover, scan_input
from .scan_polygon import check_pose, check_scan, scan_points

# TRANSITION flattened for one-step lookup with index (label << 2) | scan_input.
_TRANSITION_BY_CODE = np.zeros(4 * len(CellLabel), dtype=LABEL_DTYPE)
for _label in CellLabel:
    for _scan_input in ScanInput:
        _TRANSITION_BY_CODE[(_label << 2) | _scan_input] = TRANSITION[_label, _scan_input]
_TRANSITION_BY_CODE.setflags(write=False)

_EMPTY_WINDOW = (slice(0, 0), slice(0, 0), np.zeros((0, 0), dtype=LABEL_DTYPE))


def _runs_touching(runs, cells, hit_count):
    """
    Tell for each hit whether one of its runs holds a True cell.

    ``runs`` is ``hit_runs(..., return_hits=True)`` over the window of ``cells`` (bool).
    """
    starts, ends, hit_index = runs
    before = np.concatenate(([0], np.cumsum(cells.ravel())))
    touching = np.zeros(hit_count, dtype=bool)
    touching[hit_index[before[ends] > before[starts]]] = True
    return touching


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
    trail_distance : float
        Trails [m]: a mobile cell last labelled by a followed object goes back to explored
        while out of view (f1 = f2 = 0) once the scan sees that object at least this far from
        the cell: the object has moved on, what it left is a trail. 0 turns it off. Needs
        ``track_confirm_time`` > 0.

    """

    free_evidence_radius: float = 0.0
    moving_object_size: float = 0.0
    evidence_margin: float = 0.15
    segment_gap: float = 0.3
    mobile_expiry: float = 0.0
    track_confirm_time: float = 0.0
    trail_distance: float = 0.0

    def __post_init__(self):
        for name in ('free_evidence_radius', 'moving_object_size', 'evidence_margin',
                     'mobile_expiry', 'track_confirm_time', 'trail_distance'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if not (math.isfinite(self.segment_gap) and self.segment_gap > 0.0):
            raise ValueError(f'segment_gap must be positive, got {self.segment_gap!r} m')
        if self.trail_distance > 0.0 and self.track_confirm_time == 0.0:
            raise ValueError('trail_distance needs track_confirm_time > 0: a trail is left by '
                             'a followed object')
        if self.track_confirm_time > 0.0 and self.moving_object_size == 0.0:
            raise ValueError('track_confirm_time needs moving_object_size > 0: tracks follow '
                             'moving objects')
        if self.moving_object_size > 0.0 and self.free_evidence_radius == 0.0:
            raise ValueError('moving_object_size needs free_evidence_radius > 0: motion is '
                             'shown by hits in space surely seen free')


#: The paper's rule: f1, f2 and the FSM table, nothing else.
PAPER_RULE = LabelRule()


class LabelGrid:
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
        Cells once surely seen free; None unless ``rule.free_evidence_radius`` > 0.
    last_hit : (rows, cols) ndarray of float64, or None
        Stamp of the last scan with f1 = 1 on each cell [s], ``-inf`` before any; None unless
        ``rule.mobile_expiry`` > 0.
    tracks : MotionTracks
        The moving objects followed (none unless ``rule.track_confirm_time`` > 0).
    cell_track : (rows, cols) ndarray of int64, or None
        The track (``MotionTracks.ids``) whose hits last labelled each cell mobile, -1 for
        none; None unless ``rule.trail_distance`` > 0.
    last_window : (slice, slice, (n_rows, n_cols) ndarray of uint8)
        The latest update's window and its FSM input (``ScanInput``); empty slices when the
        scan missed the grid. Cells outside the window had input ``NONE``.

    """

    def __init__(self, width, height, resolution=0.5, origin=(0.0, 0.0), rule=PAPER_RULE):
        self.geometry = GridGeometry(width, height, resolution, tuple(origin))
        self.rule = rule
        self.labels = np.full(self.geometry.shape, CellLabel.NON_EXPLORED, dtype=LABEL_DTYPE)
        self.seen_free = (np.zeros(self.geometry.shape, dtype=bool)
                          if rule.free_evidence_radius > 0.0 else None)
        self.last_hit = (np.full(self.geometry.shape, -math.inf)
                         if rule.mobile_expiry > 0.0 else None)
        self._last_stamp = -math.inf
        self.last_window = _EMPTY_WINDOW
        self.tracks = MotionTracks(TrackConfig(confirm_within=rule.track_confirm_time))
        self.cell_track = (np.full(self.geometry.shape, -1, dtype=np.int64)
                           if rule.trail_distance > 0.0 else None)
        self._marked = np.zeros(0, dtype=np.int64)   # flat cells that may hold a track
        self._scan_fan = (0.0, 1.0)         # map-frame bearing of beam 0, beam step [rad]

    def update(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
               safety_radius, path=None, angle_max=None, stamp=None):
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
        pose = check_pose(pose)
        ranges = check_scan(ranges, angle_min, angle_increment, range_min, range_max, angle_max)
        safety_radius = float(safety_radius)
        if not (math.isfinite(safety_radius) and safety_radius >= 0.0):
            raise ValueError(f'safety_radius must be finite and >= 0, got {safety_radius!r} m')
        path = check_path(path, self.geometry.shape)
        expiring = self.rule.mobile_expiry > 0.0
        if expiring or self.rule.track_confirm_time > 0.0:
            if stamp is None or not math.isfinite(stamp):
                raise ValueError('the label rule (mobile_expiry, track_confirm_time) needs a '
                                 f'finite scan stamp, got {stamp!r}')
            self._restart_clocks_if_time_went_back(float(stamp))
        points = scan_points(pose, ranges, angle_min, angle_increment, range_min, range_max)
        self._scan_fan = (pose[2] + angle_min, angle_increment)
        # Every cell within r of a hit (f1), or within the evidence radius of one.
        reach = max(safety_radius, self.rule.free_evidence_radius)
        rows, cols = self.geometry.cell_window(
            float(points.vertices_x.min()) - reach, float(points.vertices_x.max()) + reach,
            float(points.vertices_y.min()) - reach, float(points.vertices_y.max()) + reach)
        if rows.start == rows.stop or cols.start == cols.stop:
            self.last_window = _EMPTY_WINDOW
            if expiring:
                self._expire_mobile(float(stamp))
            return False
        runs = None
        if self.rule.moving_object_size > 0.0:
            # f1's runs, with the hit of each, serve the objects' rule too.
            runs = hit_runs(self.geometry, rows, cols, self.geometry.window_centres(rows, cols),
                            points.hits_x, points.hits_y, safety_radius, return_hits=True)
        cell_input = scan_input(self.geometry, rows, cols, points, safety_radius, runs)
        self.last_window = (rows, cols, cell_input)
        window = self.labels[rows, cols]
        before = window.copy()
        # np.take is about twice as fast as fancy indexing for this lookup.
        window[...] = np.take(_TRANSITION_BY_CODE, (before << 2) | cell_input)
        if self.rule.free_evidence_radius > 0.0:
            self._apply_free_evidence(rows, cols, points, safety_radius, before, cell_input,
                                      window, runs, stamp)
        if expiring:
            self.last_hit[rows, cols][cell_input == ScanInput.HIT] = stamp
            self._expire_mobile(float(stamp))
        if self.cell_track is not None:
            self._expire_trails(float(stamp))
        if path is None or not path.shape[0]:
            return False
        on_window = ((path[:, 0] >= rows.start) & (path[:, 0] < rows.stop)
                     & (path[:, 1] >= cols.start) & (path[:, 1] < cols.stop))
        path_rr = path[on_window, 0] - rows.start
        path_cc = path[on_window, 1] - cols.start
        new_obstacle = (~blocked_mask(before[path_rr, path_cc])
                        & blocked_mask(window[path_rr, path_cc]))
        return bool(new_obstacle.any())

    def _apply_free_evidence(self, rows, cols, points, safety_radius, before, cell_input,
                             window, runs, stamp=None):
        """
        Conservative free space and object-level relabelling over the window, in place.

        ``before`` holds the window's labels before this scan, ``window`` (a view into
        ``labels``) those after the paper's FSM; ``runs`` are f1's runs with their hits
        (``hit_runs(..., return_hits=True)``) when the objects' rule is on.
        """
        seen_free = self.seen_free[rows, cols]
        hit = cell_input == ScanInput.HIT
        window[(before == CellLabel.EXPLORED) & hit & ~seen_free] = CellLabel.STEADY_OBSTACLE
        if self.rule.moving_object_size > 0.0:
            near_moving = self._near_moving_objects(rows, cols, points, safety_radius,
                                                    seen_free, runs, stamp)
            window[hit] = np.where(near_moving[hit], CellLabel.MOBILE_OBSTACLE,
                                   CellLabel.STEADY_OBSTACLE)
        seen_free |= surely_free(self.geometry, rows, cols, points,
                                 self.rule.free_evidence_radius, cell_input, safety_radius)

    def _near_moving_objects(self, rows, cols, points, safety_radius, seen_free, runs,
                             stamp):
        """
        Find the window cells within the safety radius of a hit on an object seen to move.

        A hit shows motion when a cell within ``free_evidence_radius - evidence_margin`` of it
        was once surely seen free (``seen_free``, before this scan): never so for a hit on a
        steady wall, which would then have been inside that scan's polygon.
        """
        centres = self.geometry.window_centres(rows, cols)
        evidence_radius = max(self.rule.free_evidence_radius - self.rule.evidence_margin, 0.0)
        hit_count = points.hits_x.shape[0]
        evidence = _runs_touching(runs, seen_free, hit_count)
        if evidence_radius > safety_radius:
            evidence = _runs_touching(
                hit_runs(self.geometry, rows, cols, centres, points.hits_x, points.hits_y,
                         evidence_radius, return_hits=True), seen_free, hit_count)
        elif evidence_radius < safety_radius and evidence.any():
            # Only hits with a surely-free cell within r can have one within the smaller
            # evidence radius; most hits (walls) have none.
            candidates = np.flatnonzero(evidence)
            evidence = np.zeros(hit_count, dtype=bool)
            evidence[candidates] = _runs_touching(
                hit_runs(self.geometry, rows, cols, centres, points.hits_x[candidates],
                         points.hits_y[candidates], evidence_radius, return_hits=True),
                seen_free, candidates.shape[0])
        moving = moving_object_hits(points.hits_x, points.hits_y, points.hit_beams, evidence,
                                    self.rule.segment_gap, self.rule.moving_object_size)
        if self.rule.track_confirm_time > 0.0:
            moving |= self.tracks.update(
                float(stamp), (points.vertices_x[0], points.vertices_y[0]), points.hits_x,
                points.hits_y, points.hit_beams, points.vertices_x.shape[0] - 2, moving,
                self.rule.segment_gap, *self._scan_fan,
                np.hypot(points.vertices_x[1:-1] - points.vertices_x[0],
                         points.vertices_y[1:-1] - points.vertices_y[0]))
        starts, ends, hit_index = runs
        if self.cell_track is not None:
            self._stamp_tracks(rows, cols, runs)
        return run_cover(starts[moving[hit_index]], ends[moving[hit_index]], seen_free.shape)

    def _stamp_tracks(self, rows, cols, runs):
        """Note in ``cell_track`` which track's hits are within the safety radius of a cell."""
        starts, ends, hit_index = runs
        run_ids = self.tracks.hit_ids[hit_index]
        window = self.cell_track[rows, cols]
        window[self.last_window[2] == ScanInput.HIT] = -1    # marks are of the last hit
        for track in np.unique(run_ids[run_ids >= 0]):
            own = run_ids == track
            cover = run_cover(starts[own], ends[own], window.shape)
            window[cover] = track
            local_rr, local_cc = np.nonzero(cover)
            self._marked = np.concatenate((
                self._marked,
                (local_rr + rows.start) * self.geometry.cols + local_cc + cols.start))
        if self._marked.shape[0] > 4096:
            self._marked = np.unique(self._marked)

    def _expire_trails(self, stamp):
        """Set out-of-view mobile cells whose object the scan sees far from them to explored."""
        tracks = self.tracks
        seen = tracks.last_seen == stamp
        if not seen.any() or not self._marked.size:
            return
        marked = np.unique(self._marked)
        rr, cc = np.divmod(marked, self.geometry.cols)
        marks = self.cell_track[rr, cc]
        kept = (marks >= 0) & (self.labels[rr, cc] == CellLabel.MOBILE_OBSTACLE)
        self.cell_track[rr[~kept], cc[~kept]] = -1
        rr, cc, marks = rr[kept], cc[kept], marks[kept]
        order = np.argsort(tracks.ids[seen])
        seen_ids = tracks.ids[seen][order]
        seen_xy = tracks.positions[seen][order]
        which = np.minimum(np.searchsorted(seen_ids, marks), seen_ids.shape[0] - 1)
        found = seen_ids[which] == marks
        rr, cc, which = rr[found], cc[found], which[found]
        rows, cols, cell_input = self.last_window
        out_of_view = np.ones(rr.shape[0], dtype=bool)
        if cell_input.size:
            inside = ((rr >= rows.start) & (rr < rows.stop) & (cc >= cols.start)
                      & (cc < cols.stop))
            out_of_view[inside] = (cell_input[rr[inside] - rows.start, cc[inside] - cols.start]
                                   == ScanInput.NONE)
        centre_x, centre_y = self.geometry.cell_to_world(rr, cc)
        far = (np.hypot(centre_x - seen_xy[which, 0], centre_y - seen_xy[which, 1])
               >= self.rule.trail_distance)
        trail = out_of_view & far
        self.labels[rr[trail], cc[trail]] = CellLabel.EXPLORED
        self.cell_track[rr[trail], cc[trail]] = -1
        cleared = np.zeros(found.shape[0], dtype=bool)
        cleared[np.flatnonzero(found)[trail]] = True
        self._marked = marked[kept][~cleared]

    def _restart_clocks_if_time_went_back(self, stamp):
        """After a jump back in time (a restarted simulation), no hit is newer than now."""
        if stamp < self._last_stamp and self.last_hit is not None:
            np.minimum(self.last_hit, stamp, out=self.last_hit)
        self._last_stamp = stamp

    def _expire_mobile(self, stamp):
        """Set mobile cells out of view and unconfirmed for ``mobile_expiry`` to explored."""
        rows, cols, cell_input = self.last_window
        stale = ((self.labels == CellLabel.MOBILE_OBSTACLE)
                 & (stamp - self.last_hit >= self.rule.mobile_expiry))
        stale[rows, cols] &= cell_input == ScanInput.NONE
        self.labels[stale] = CellLabel.EXPLORED

    def blocked(self):
        """
        Cells that planning treats as blocked: steady and mobile obstacles.

        Returns
        -------
        blocked : (rows, cols) ndarray of bool

        """
        return blocked_mask(self.labels)

    def reset(self):
        """Forget everything: every cell back to ``NON_EXPLORED``, no evidence kept."""
        self.labels.fill(CellLabel.NON_EXPLORED)
        if self.seen_free is not None:
            self.seen_free.fill(False)
        if self.last_hit is not None:
            self.last_hit.fill(-math.inf)
        self._last_stamp = -math.inf
        self.last_window = _EMPTY_WINDOW
        self.tracks.reset()
        if self.cell_track is not None:
            self.cell_track.fill(-1)
        self._marked = np.zeros(0, dtype=np.int64)
