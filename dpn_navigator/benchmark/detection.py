"""
The map as a detector: per scan, how well the labels tell wanderers from walls.

A `DetectionMeter` is fed, after every navigator step, the labels, the scan's window and FSM
input (``LabelGrid.last_window``), the wanderers' true positions and the scan's hits on
wanderers, and counts (definitions in ``docs/detection.md``):

- **precision** of ``MOBILE_OBSTACLE`` among visible cells (``cell_input != NONE``): visible
  mobile cells whose centre lies within ``R + r`` of a wanderer, over visible mobile cells;
  and over **every** mobile cell of the grid (``mobile_precision_all``: ghosts out of view
  and wall cells labelled mobile count against it), which cannot be raised by not looking;
- **recall on wanderer hits**: cells within ``r`` of a hit on a wanderer and off every wall's
  f1 belt that are labelled mobile after the update, over those cells; the same on the cells
  within a wall's belt, reported apart (``wanderer_hit_recall_near_wall``: a wanderer beside
  a wall, where corridors are blocked);
- **wall cells ever mobile**: belt cells that some scan saw and left labelled mobile with no
  wanderer within ``R + r``, over belt cells ever seen;
- **ghosts**: mobile and steady obstacle cells that neither a wall's belt nor a wanderer within
  ``R + r`` explains, over the whole grid, per scan and at the end;
- **replans by cause**: the grid's flag raised by a wall or by a wanderer, no-path retries and
  the rest.

Precision and recall are pooled: counts are summed over the scans (and over episodes in the
summary), then divided once. The work per scan is bounded by the scan window, except the ghost
count, which reads the whole grid once (a few vectorised passes over ``H * W`` bytes; its share
of episode time is measured in the ``detection_wall_time`` column).

"""

from dataclasses import asdict, dataclass
import math

import numpy as np

from .ground_truth import near_any
from ..core.cell_label import CellLabel, ScanInput
from ..core.grid_geometry import squared_radius_bound
from ..core.navigator import ReplanCause

#: Replan classes, in column order.
REPLAN_CLASSES = ('wall', 'wanderer', 'no_path_retry', 'other')


@dataclass(frozen=True)
class DetectionResult:
    """
    One episode's detection measures (see ``docs/detection.md``).

    A ratio is None when its denominator is 0 (undefined; an empty CSV field).

    Attributes
    ----------
    scans : int
        Scans measured.
    mobile_visible, mobile_visible_true : int
        Visible mobile cells summed over scans, and those near a wanderer.
    mobile_precision : float or None
        ``mobile_visible_true / mobile_visible``.
    wanderer_hit_cells, wanderer_hit_cells_mobile : int
        Wanderers' f1 cells off the wall belts summed over scans, and those labelled mobile.
    wanderer_hit_recall : float or None
        ``wanderer_hit_cells_mobile / wanderer_hit_cells``.
    wall_cells_seen, wall_cells_ever_mobile : int
        Belt cells ever visible, and those ever left mobile with no wanderer near [cells].
    wall_mobile_share : float or None
        ``wall_cells_ever_mobile / wall_cells_seen``.
    mobile_ghosts_mean, steady_ghosts_mean : float or None
        Ghost cells per scan, mean over scans.
    mobile_ghost_scan_share, steady_ghost_scan_share : float or None
        Share of scans with at least one ghost cell of the label.
    mobile_ghosts_end, steady_ghosts_end : int
        Ghost cells after the last scan.
    replans_wall, replans_wanderer, replans_no_path_retry, replans_other : int
        Paths planned, by cause.
    mobile_all, mobile_all_true : int
        Every mobile cell of the grid summed over scans, in view or not, and those near a
        wanderer.
    mobile_precision_all : float or None
        ``mobile_all_true / mobile_all``.
    wanderer_hit_cells_near_wall, wanderer_hit_cells_near_wall_mobile : int
        Wanderers' f1 cells on a wall's belt summed over scans, and those labelled mobile.
    wanderer_hit_recall_near_wall : float or None
        ``wanderer_hit_cells_near_wall_mobile / wanderer_hit_cells_near_wall``.

    """

    scans: int
    mobile_visible: int
    mobile_visible_true: int
    mobile_precision: object
    wanderer_hit_cells: int
    wanderer_hit_cells_mobile: int
    wanderer_hit_recall: object
    wall_cells_seen: int
    wall_cells_ever_mobile: int
    wall_mobile_share: object
    mobile_ghosts_mean: object
    mobile_ghost_scan_share: object
    steady_ghosts_mean: object
    steady_ghost_scan_share: object
    mobile_ghosts_end: int
    steady_ghosts_end: int
    replans_wall: int
    replans_wanderer: int
    replans_no_path_retry: int
    replans_other: int
    mobile_all: int = 0
    mobile_all_true: int = 0
    mobile_precision_all: object = None
    wanderer_hit_cells_near_wall: int = 0
    wanderer_hit_cells_near_wall_mobile: int = 0
    wanderer_hit_recall_near_wall: object = None

    def as_row(self):
        """Return the measures as a flat dict, ratios rounded to 4 decimals."""
        row = asdict(self)
        for name, value in row.items():
            if isinstance(value, float):
                row[name] = round(value, 4)
        return row


#: The measures' names, in `DetectionResult` (and CSV) order.
DETECTION_FIELDS = tuple(DetectionResult.__dataclass_fields__)


def ratio(numerator, denominator):
    """Return ``numerator / denominator``, or None (undefined) when the denominator is 0."""
    return numerator / denominator if denominator else None


class DetectionMeter:
    """
    Accumulate one episode's detection measures, scan by scan.

    Parameters
    ----------
    geometry : GridGeometry
        The navigator's grid.
    wall_belt : (H, W) ndarray of bool
        Cells a wall explains (``ground_truth.wall_belt``).
    wanderer_radius : float
        The wanderers' circumscribed radius ``R`` [m].
    safety_radius : float
        The navigator's f1 radius ``r`` [m].

    """

    def __init__(self, geometry, wall_belt, wanderer_radius, safety_radius):
        wall_belt = np.asarray(wall_belt, dtype=bool)
        if wall_belt.shape != geometry.shape:
            raise ValueError(f'wall_belt has shape {wall_belt.shape}, the grid '
                             f'{geometry.shape}')
        self.geometry = geometry
        self.wall_belt = wall_belt
        self.safety_radius = float(safety_radius)
        self.reach = float(wanderer_radius) + self.safety_radius
        self._wall_seen = np.zeros(geometry.shape, dtype=bool)
        self._wall_mobile = np.zeros(geometry.shape, dtype=bool)
        self._counts = dict.fromkeys(
            ('scans', 'mobile_visible', 'mobile_visible_true', 'wanderer_hit_cells',
             'wanderer_hit_cells_mobile', 'mobile_ghosts', 'steady_ghosts',
             'mobile_ghost_scans', 'steady_ghost_scans', 'mobile_all', 'mobile_all_true',
             'wanderer_hit_cells_near_wall', 'wanderer_hit_cells_near_wall_mobile'), 0)
        self._replans = dict.fromkeys(REPLAN_CLASSES, 0)
        self._ghosts_now = (0, 0)
        self._off_belt_flat = ~wall_belt.ravel()
        all_x, all_y = geometry.cell_to_world(np.arange(geometry.rows)[:, None],
                                              np.arange(geometry.cols)[None, :])
        self._centre_x = np.broadcast_to(all_x, geometry.shape).ravel()
        self._centre_y = np.broadcast_to(all_y, geometry.shape).ravel()
        # f1's test of eq. 2, and the cell offsets around a hit's cell that can pass it: a
        # centre d cells away lies more than (d - 1/2) cells from the hit.
        self._f1_bound = squared_radius_bound(self.safety_radius)
        reach = math.floor(self.safety_radius / geometry.resolution + 0.5 + 1e-9)
        offsets = np.arange(-reach, reach + 1)
        self._f1_dr = np.repeat(offsets, offsets.shape[0])[None, :]
        self._f1_dc = np.tile(offsets, offsets.shape[0])[None, :]

    def record_scan(self, labels, window, wanderer_xy, wanderer_hits_xy):
        """
        Measure the labels after one scan's update.

        Parameters
        ----------
        labels : (H, W) ndarray of uint8
            The labels after the update.
        window : (slice, slice, (n_rows, n_cols) ndarray of uint8)
            ``LabelGrid.last_window``: the window and its ``ScanInput`` values.
        wanderer_xy : (K, 2) array_like of float
            True wanderer positions at the scan [m].
        wanderer_hits_xy : ((M,) ndarray, (M,) ndarray)
            Hit points of the beams that hit a wanderer [m]
            (``ground_truth.wanderer_hit_points``).

        """
        counts = self._counts
        counts['scans'] += 1
        rows, cols, cell_input = window
        if cell_input.size:
            self._record_window(labels[rows, cols], rows, cols, cell_input, wanderer_xy)
        if len(wanderer_hits_xy[0]):
            hit_rr, hit_cc = self.f1_cells(*wanderer_hits_xy)
            off_walls = ~self.wall_belt[hit_rr, hit_cc]
            hit_mobile = labels[hit_rr, hit_cc] == CellLabel.MOBILE_OBSTACLE
            counts['wanderer_hit_cells'] += int(np.count_nonzero(off_walls))
            counts['wanderer_hit_cells_mobile'] += int(np.count_nonzero(off_walls & hit_mobile))
            counts['wanderer_hit_cells_near_wall'] += int(np.count_nonzero(~off_walls))
            counts['wanderer_hit_cells_near_wall_mobile'] += int(np.count_nonzero(
                ~off_walls & hit_mobile))
        mobile, steady = self._ghosts_now = self.ghosts(labels, wanderer_xy)
        every_mobile = np.flatnonzero(np.ascontiguousarray(labels).ravel()
                                      == CellLabel.MOBILE_OBSTACLE)
        counts['mobile_all'] += int(every_mobile.shape[0])
        counts['mobile_all_true'] += int(np.count_nonzero(near_any(
            self._centre_x[every_mobile], self._centre_y[every_mobile], wanderer_xy,
            self.reach)))
        counts['mobile_ghosts'] += mobile
        counts['steady_ghosts'] += steady
        counts['mobile_ghost_scans'] += mobile > 0
        counts['steady_ghost_scans'] += steady > 0

    def _record_window(self, window_labels, rows, cols, cell_input, wanderer_xy):
        """Count precision and wall cells in one scan's window."""
        counts = self._counts
        visible = cell_input != ScanInput.NONE
        belt = self.wall_belt[rows, cols]
        self._wall_seen[rows, cols] |= visible & belt
        # Only the visible mobile cells need a distance to the wanderers.
        mobile_rr, mobile_cc = np.nonzero(visible & (window_labels == CellLabel.MOBILE_OBSTACLE))
        centre_x, centre_y = self.geometry.cell_to_world(mobile_rr + rows.start,
                                                         mobile_cc + cols.start)
        true = near_any(centre_x, centre_y, wanderer_xy, self.reach)
        counts['mobile_visible'] += int(mobile_rr.shape[0])
        counts['mobile_visible_true'] += int(np.count_nonzero(true))
        false_on_wall = ~true & belt[mobile_rr, mobile_cc]
        self._wall_mobile[mobile_rr[false_on_wall] + rows.start,
                          mobile_cc[false_on_wall] + cols.start] = True

    def f1_cells(self, hits_x, hits_y):
        """
        Return the cells f1 marks for some hit points: centre within ``r`` of one of them.

        The test is eq. 2's, in the core's floating-point form (``scan_features.hit_runs``),
        evaluated only on the few cells around each hit.

        Parameters
        ----------
        hits_x, hits_y : (M,) array_like of float
            Hit points [m].

        Returns
        -------
        rr, cc : (C,) ndarray of int64
            The cells on the grid, each once.

        """
        hits_x = np.asarray(hits_x, dtype=np.float64).reshape(-1, 1)
        hits_y = np.asarray(hits_y, dtype=np.float64).reshape(-1, 1)
        home_rr, home_cc = self.geometry.world_to_cell(hits_x, hits_y)
        rr = home_rr + self._f1_dr
        cc = home_cc + self._f1_dc
        centre_x, centre_y = self.geometry.cell_to_world(rr, cc)
        dx = centre_x - hits_x
        dy = centre_y - hits_y
        within = (dx * dx + dy * dy <= self._f1_bound) & self.geometry.contains_cell(rr, cc)
        flat = np.unique(rr[within] * self.geometry.cols + cc[within])
        return flat // self.geometry.cols, flat % self.geometry.cols

    def ghosts(self, labels, wanderer_xy):
        """
        Count the obstacle cells that no wall's belt and no wanderer explains.

        Parameters
        ----------
        labels : (H, W) ndarray of uint8
            The navigator's labels.
        wanderer_xy : (K, 2) array_like of float
            True wanderer positions [m].

        Returns
        -------
        mobile, steady : int
            Ghost cells labelled mobile and steady obstacle.

        """
        flat_labels = np.ascontiguousarray(labels).ravel()
        flat = np.flatnonzero((flat_labels >= CellLabel.STEADY_OBSTACLE) & self._off_belt_flat)
        ghost = ~near_any(self._centre_x[flat], self._centre_y[flat], wanderer_xy, self.reach)
        mobile = int(np.count_nonzero(ghost & (flat_labels[flat] == CellLabel.MOBILE_OBSTACLE)))
        return mobile, int(np.count_nonzero(ghost)) - mobile

    def record_replan(self, cause, path, path_labels_before, labels, wanderer_xy):
        """
        Count one planning step by its cause.

        A ``FLAG`` replan is put down to a wanderer when a path cell that turned obstacle in
        this step (not blocked before, blocked after) has its centre within ``R + r`` of a
        wanderer, else to a wall.

        Parameters
        ----------
        cause : ReplanCause
            ``NavigatorOutput.replan_cause``; ``NONE`` counts nothing.
        path : (N, 2) ndarray of int, or None
            The path the scan was checked against (before the step).
        path_labels_before : (N,) ndarray of uint8, or None
            Labels of its cells before the step.
        labels : (H, W) ndarray of uint8
            The labels after the step.
        wanderer_xy : (K, 2) array_like of float
            True wanderer positions [m].

        """
        if cause is ReplanCause.NONE:
            return
        if cause is ReplanCause.NO_PATH_RETRY:
            self._replans['no_path_retry'] += 1
        elif cause is ReplanCause.OTHER:
            self._replans['other'] += 1
        else:
            after = labels[path[:, 0], path[:, 1]]
            turned = ((path_labels_before < CellLabel.STEADY_OBSTACLE)
                      & (after >= CellLabel.STEADY_OBSTACLE))
            centre_x, centre_y = self.geometry.cell_to_world(path[turned, 0], path[turned, 1])
            by_wanderer = near_any(centre_x, centre_y, wanderer_xy, self.reach).any()
            self._replans['wanderer' if by_wanderer else 'wall'] += 1

    def result(self):
        """Return the measures so far as a `DetectionResult`."""
        counts = self._counts
        scans = counts['scans']
        seen = int(np.count_nonzero(self._wall_seen))
        ever_mobile = int(np.count_nonzero(self._wall_mobile))
        return DetectionResult(
            scans=scans, mobile_visible=counts['mobile_visible'],
            mobile_visible_true=counts['mobile_visible_true'],
            mobile_precision=ratio(counts['mobile_visible_true'], counts['mobile_visible']),
            wanderer_hit_cells=counts['wanderer_hit_cells'],
            wanderer_hit_cells_mobile=counts['wanderer_hit_cells_mobile'],
            wanderer_hit_recall=ratio(counts['wanderer_hit_cells_mobile'],
                                      counts['wanderer_hit_cells']),
            wall_cells_seen=seen, wall_cells_ever_mobile=ever_mobile,
            wall_mobile_share=ratio(ever_mobile, seen),
            mobile_ghosts_mean=ratio(counts['mobile_ghosts'], scans),
            mobile_ghost_scan_share=ratio(counts['mobile_ghost_scans'], scans),
            steady_ghosts_mean=ratio(counts['steady_ghosts'], scans),
            steady_ghost_scan_share=ratio(counts['steady_ghost_scans'], scans),
            mobile_ghosts_end=self._ghosts_now[0], steady_ghosts_end=self._ghosts_now[1],
            replans_wall=self._replans['wall'], replans_wanderer=self._replans['wanderer'],
            replans_no_path_retry=self._replans['no_path_retry'],
            replans_other=self._replans['other'], mobile_all=counts['mobile_all'],
            mobile_all_true=counts['mobile_all_true'],
            mobile_precision_all=ratio(counts['mobile_all_true'], counts['mobile_all']),
            wanderer_hit_cells_near_wall=counts['wanderer_hit_cells_near_wall'],
            wanderer_hit_cells_near_wall_mobile=counts['wanderer_hit_cells_near_wall_mobile'],
            wanderer_hit_recall_near_wall=ratio(counts['wanderer_hit_cells_near_wall_mobile'],
                                                counts['wanderer_hit_cells_near_wall']))
