"""
The numpy label update that the compiled kernel replaced, kept as a reference.

``NumpyLabelGrid`` is ``LabelGrid`` with the update of commit 83e3dc1: vectorised numpy over
the scan's window (``scan_features``, ``free_evidence``, ``moving_objects``), and a ghost
expiry that sweeps the whole grid every scan; with the motion tracks and trails as the numpy
update of 57d0f72 ran them (the tracks told the object rule's moving hits, the trail marks
stamped from f1's runs). Tests check the kernel against it on long scan
sequences; the core benchmark times the two side by side. ``NumpyExtrasLabelGrid`` is the grid
of commit 1d9ead7, the compiled label kernel with the tracks, trails and object memory in
numpy around it: the oracle of their compiled versions.

"""


from dpn_navigator.core.cell_label import blocked_mask, CellLabel, LABEL_DTYPE, ScanInput
from dpn_navigator.core.cell_label import TRANSITION
from dpn_navigator.core.mapping.fine_evidence import FineEvidence
from dpn_navigator.core.mapping.label_grid import LabelGrid, LabelRule
from dpn_navigator.core.scan_polygon import scan_points
from free_evidence import surely_free
from moving_objects import moving_object_hits
import numpy as np
from numpy_motion_tracks import NumpyMotionTracks
from numpy_object_memory import NumpyObjectMemory
from scan_features import hit_runs, run_cover, scan_input

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


class NumpyFineEvidence(FineEvidence):
    """
    ``FineEvidence`` as commit 9c3e0ae kept it: a whole ``NumpyLabelGrid`` of the fine cells.

    The grid has only the conservative free space on and is updated with safety radius
    ``radius``; its ``seen_free`` is the evidence, and its moving hits are found in numpy.
    The oracle of ``label_update.surely_free_update`` and of the kernels
    ``_kernels.fine_evidence.fine_moving_hits`` and ``fine_hit_evidence``.
    """

    def __init__(self, geometry, resolution, radius, max_range):
        super().__init__(geometry, resolution, radius, max_range)
        self.grid = NumpyLabelGrid(geometry.width, geometry.height, resolution,
                                   origin=tuple(geometry.origin),
                                   rule=LabelRule(free_evidence_radius=self.radius))

    @property
    def seen_free(self):
        """Return the fine grid's ``seen_free``."""
        return self.grid.seen_free

    def evidence(self, hits_x, hits_y):
        """Look each hit's fine cell up in numpy (the oracle of ``fine_hit_evidence``)."""
        rows, cols = self.geometry.world_to_cell(hits_x, hits_y)
        inside = self.geometry.contains_cell(rows, cols)
        evidence = np.zeros(np.shape(hits_x), dtype=bool)
        evidence[inside] = self.seen_free[rows[inside], cols[inside]]
        return evidence

    def moving_hits(self, points, rule):
        """`evidence` looked up in numpy, then ``moving_objects.moving_object_hits``."""
        vertices_x, vertices_y, hits_x, hits_y, hit_beams = points[:5]
        evidence = self.evidence(hits_x, hits_y)
        if not evidence.any():
            return evidence
        return moving_object_hits(hits_x, hits_y, hit_beams, evidence, rule.segment_gap,
                                  rule.moving_object_size, rule.object_min_hits,
                                  (vertices_x[0], vertices_y[0]), vertices_x.shape[0] - 2,
                                  rule.segment_bridge_beams)

    def update(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
               stamp=0.0, hits=None):
        """Update the whole fine grid, labels and all (no burn-in: ``stamp``, ``hits`` unread)."""
        self.grid.update(pose, ranges, angle_min, angle_increment, range_min,
                         self.capped_range_max(range_min, range_max), self.radius)

    def reset(self):
        """Forget all evidence."""
        self.grid.reset()


class NumpyExtrasLabelGrid(LabelGrid):
    """
    ``LabelGrid`` of commit 1d9ead7: the compiled label kernel, the rest numpy.

    The motion tracks (``NumpyMotionTracks``), the trail marks and the object memory
    (``NumpyObjectMemory``) as they ran in numpy around the kernel before they were compiled.
    """

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.tracks = NumpyMotionTracks(self.tracks.config)
        if self.object_memory is not None:
            self.object_memory = NumpyObjectMemory(self.geometry, self.rule.object_memory)
        if self.fine_evidence is not None:
            # The fine evidence kept by the numpy update below.
            self.fine_evidence = NumpyFineEvidence(self.geometry,
                                                   self.rule.fine_evidence_resolution,
                                                   self.rule.fine_evidence_radius,
                                                   self.rule.fine_evidence_range)

    def _follow(self, *args):
        """
        Follow the objects; the label kernel then finds the scan's points itself again.

        Not with the rules for real lasers (``no_return_reach`` below 1, ``surface_time``),
        which change the points and their evidence; their twin is the literal one
        (``real_sensor_rules.py``).
        """
        followed, points = super()._follow(*args)
        if self.surface_memory is not None or self.rule.no_return_reach < 1.0:
            return followed, points
        return followed, None

    def _trails(self, safety_radius, stamp):
        """Stamp the marks from f1's runs, then expire the trails, in numpy."""
        self._stamp_tracks(safety_radius)
        self._expire_trails(stamp)

    def _stamp_tracks(self, safety_radius):
        """Note in ``cell_track`` which track's hits are within the safety radius of a cell."""
        rows, cols, cell_input = self.last_window
        window = self.cell_track[rows, cols]
        window[cell_input == ScanInput.HIT] = -1     # marks are of the last hit
        ids = self.tracks.hit_ids
        tracked = ids >= 0
        if not tracked.any():
            return
        hits_x, hits_y = self._followed_hits
        starts, ends, hit_index = hit_runs(
            self.geometry, rows, cols, self.geometry.window_centres(rows, cols),
            hits_x[tracked], hits_y[tracked], safety_radius, return_hits=True)
        self._mark_runs(rows, cols, starts, ends, ids[tracked][hit_index])

    def _mark_runs(self, rows, cols, starts, ends, run_ids):
        """
        Mark the cells of each f1 run with its hit's track in ``cell_track``, and list them.

        ``starts``, ``ends`` are window runs (``hit_runs``), ``run_ids`` the track of each run
        (-1: none).
        """
        window = self.cell_track[rows, cols]
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
        inside = ((rr >= rows.start) & (rr < rows.stop) & (cc >= cols.start)
                  & (cc < cols.stop))
        out_of_view[inside] = (cell_input[rr[inside] - rows.start, cc[inside] - cols.start]
                               == ScanInput.NONE)
        centre_x, centre_y = self.geometry.cell_to_world(rr, cc)
        far = (np.hypot(centre_x - seen_xy[which, 0], centre_y - seen_xy[which, 1])
               >= self.rule.trail_distance)
        trail = out_of_view & far
        if trail.any():
            self.labels[rr[trail], cc[trail]] = CellLabel.EXPLORED
            self.cell_track[rr[trail], cc[trail]] = -1
            # The ghost expiry's list drops cells no longer mobile when it next visits them.
            self._widen_trackers(slice(int(rr[trail].min()), int(rr[trail].max()) + 1),
                                 slice(int(cc[trail].min()), int(cc[trail].max()) + 1))
        cleared = np.zeros(found.shape[0], dtype=bool)
        cleared[np.flatnonzero(found)[trail]] = True
        self._marked = marked[kept][~cleared]


class NumpyLabelGrid(NumpyExtrasLabelGrid):
    """``LabelGrid`` with the numpy update of commit 83e3dc1 (see the module docstring)."""

    def update(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
               safety_radius, path=None, angle_max=None, stamp=None):
        """Fold one scan into the labels as 83e3dc1 did; as ``LabelGrid.update``."""
        pose, ranges, safety_radius, path, stamp = self._checked_scan(
            pose, ranges, angle_min, angle_increment, range_min, range_max, safety_radius, path,
            angle_max, stamp)
        expiring = self.rule.mobile_expiry > 0.0
        if expiring:
            self._restart_clocks_if_time_went_back(stamp)
        points = scan_points(pose, ranges, angle_min, angle_increment, range_min, range_max)
        self._scan_fan = (pose[2] + angle_min, angle_increment)
        self._stamp = stamp
        self._fine_moving = None
        if self.fine_evidence is not None:
            # Read before this scan goes into the fine evidence.
            self._fine_moving = self.fine_evidence.moving_hits(
                (points.vertices_x, points.vertices_y, points.hits_x, points.hits_y,
                 points.hit_beams), self.rule)
            self.fine_evidence.update(pose, ranges, angle_min, angle_increment, range_min,
                                      range_max)
        # Every cell within r of a hit (f1), or within the evidence radius of one.
        reach = max(safety_radius, self.rule.free_evidence_radius)
        rows, cols = self.geometry.cell_window(
            float(points.vertices_x.min()) - reach, float(points.vertices_x.max()) + reach,
            float(points.vertices_y.min()) - reach, float(points.vertices_y.max()) + reach)
        if rows.start == rows.stop or cols.start == cols.stop:
            self.last_window = _EMPTY_WINDOW
            if expiring:
                self._expire_mobile(float(stamp))
            self._forget_objects_of(points, safety_radius, stamp)
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
                                      window, runs)
        if expiring:
            self.last_hit[rows, cols][cell_input == ScanInput.HIT] = stamp
            self._expire_mobile(float(stamp))
        if self.cell_track is not None:
            self._expire_trails(float(stamp))
        self._forget_objects_of(points, safety_radius, stamp)
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
                             window, runs):
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
                                                    seen_free, runs)
            window[hit] = np.where(near_moving[hit], CellLabel.MOBILE_OBSTACLE,
                                   CellLabel.STEADY_OBSTACLE)
        seen_free |= surely_free(self.geometry, rows, cols, points,
                                 self.rule.free_evidence_radius, cell_input, safety_radius)

    def _near_moving_objects(self, rows, cols, points, safety_radius, seen_free, runs):
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
                                    self.rule.segment_gap, self.rule.moving_object_size,
                                    self.rule.object_min_hits,
                                    (points.vertices_x[0], points.vertices_y[0]),
                                    points.vertices_x.shape[0] - 2,
                                    self.rule.segment_bridge_beams)
        if self._fine_moving is not None:
            moving |= self._fine_moving
        if self.rule.track_confirm_time > 0.0:
            moving |= self.tracks.update(
                float(self._stamp), (points.vertices_x[0], points.vertices_y[0]),
                points.hits_x, points.hits_y, points.hit_beams, points.vertices_x.shape[0] - 2,
                moving, self.rule.segment_gap, *self._scan_fan,
                np.hypot(points.vertices_x[1:-1] - points.vertices_x[0],
                         points.vertices_y[1:-1] - points.vertices_y[0]))
        starts, ends, hit_index = runs
        if self.cell_track is not None:
            self._stamp_runs(rows, cols, runs)
        return run_cover(starts[moving[hit_index]], ends[moving[hit_index]], seen_free.shape)

    def _forget_objects_of(self, points, safety_radius, stamp):
        """Run the object memory after the update, as ``LabelGrid.update`` does."""
        if self.object_memory is not None:
            self._followed_hits = (points.hits_x, points.hits_y)
            self._laser_xy = (points.vertices_x[0], points.vertices_y[0])
            self._forget_objects(safety_radius, float(stamp))

    def _stamp_runs(self, rows, cols, runs):
        """Note in ``cell_track`` which track's hits are within the safety radius of a cell."""
        starts, ends, hit_index = runs
        self.cell_track[rows, cols][self.last_window[2] == ScanInput.HIT] = -1
        self._mark_runs(rows, cols, starts, ends, self.tracks.hit_ids[hit_index])

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

    def labels_changed(self):
        """Nothing to do: the whole-grid expiry needs no list of mobile cells."""
