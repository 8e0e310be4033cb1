"""
The labelled occupancy grid: per scan, f1 and f2 drive each cell's finite state machine.

Only the cells a scan can reach are touched: the window around the scan polygon widened by the
safety radius. Cells elsewhere see ``(f1, f2) = (0, 0)``, which keeps every state.

"""

import math

import numpy as np

from .cell_label import blocked_mask, CellLabel, LABEL_DTYPE, ScanInput, TRANSITION
from .grid_geometry import GridGeometry
from .scan_features import scan_input
from .scan_polygon import check_pose, check_scan, scan_points

# TRANSITION flattened for one-step lookup with index (label << 2) | scan_input.
_TRANSITION_BY_CODE = np.zeros(4 * len(CellLabel), dtype=LABEL_DTYPE)
for _label in CellLabel:
    for _scan_input in ScanInput:
        _TRANSITION_BY_CODE[(_label << 2) | _scan_input] = TRANSITION[_label, _scan_input]
_TRANSITION_BY_CODE.setflags(write=False)

# ``LabelGrid.last_window`` of an update whose window missed the grid.
_EMPTY_WINDOW = (slice(0, 0), slice(0, 0), np.zeros((0, 0), dtype=LABEL_DTYPE))


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

    Attributes
    ----------
    geometry : GridGeometry
        Size and placement; owns every world <-> cell conversion.
    labels : (rows, cols) ndarray of uint8
        Current labels, row ``i`` along y; all ``NON_EXPLORED`` at start. Updated in place.
    last_window : (slice, slice, (n_rows, n_cols) ndarray of uint8)
        The latest update's window ``(rows, cols, cell_input)``: the cells it could touch and
        their ``ScanInput`` (f1/f2); ``(slice(0, 0), slice(0, 0), empty)`` when the window was
        empty (or before the first update). For measuring the map, not for planning.

    """

    def __init__(self, width, height, resolution=0.5, origin=(0.0, 0.0)):
        self.geometry = GridGeometry(width, height, resolution, tuple(origin))
        self.labels = np.full(self.geometry.shape, CellLabel.NON_EXPLORED, dtype=LABEL_DTYPE)
        self.last_window = _EMPTY_WINDOW

    def update(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
               safety_radius, path=None, angle_max=None):
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

        Returns
        -------
        replan : bool
            True when a cell of ``path`` went non-explored -> steady obstacle or explored ->
            mobile obstacle in this update.

        Raises
        ------
        ValueError
            For a non-finite pose, malformed scan fields, a negative or non-finite safety
            radius or a malformed path; the labels are then unchanged.

        """
        pose = check_pose(pose)
        ranges = check_scan(ranges, angle_min, angle_increment, range_min, range_max, angle_max)
        safety_radius = float(safety_radius)
        if not (math.isfinite(safety_radius) and safety_radius >= 0.0):
            raise ValueError(f'safety_radius must be finite and >= 0, got {safety_radius!r} m')
        path = check_path(path, self.geometry.shape)
        points = scan_points(pose, ranges, angle_min, angle_increment, range_min, range_max)
        rows, cols = self.geometry.cell_window(
            float(points.vertices_x.min()) - safety_radius,
            float(points.vertices_x.max()) + safety_radius,
            float(points.vertices_y.min()) - safety_radius,
            float(points.vertices_y.max()) + safety_radius)
        if rows.start == rows.stop or cols.start == cols.stop:
            self.last_window = _EMPTY_WINDOW
            return False
        cell_input = scan_input(self.geometry, rows, cols, points, safety_radius)
        self.last_window = (rows, cols, cell_input)
        window = self.labels[rows, cols]
        if path is not None and path.shape[0]:
            on_window = ((path[:, 0] >= rows.start) & (path[:, 0] < rows.stop)
                         & (path[:, 1] >= cols.start) & (path[:, 1] < cols.stop))
            path_rr = path[on_window, 0] - rows.start
            path_cc = path[on_window, 1] - cols.start
            before = window[path_rr, path_cc]
        # np.take is about twice as fast as fancy indexing for this lookup.
        window[...] = np.take(_TRANSITION_BY_CODE, (window << 2) | cell_input)
        if path is None or not path.shape[0]:
            return False
        after = window[path_rr, path_cc]
        new_obstacle = (((before == CellLabel.NON_EXPLORED) & (after == CellLabel.STEADY_OBSTACLE))
                        | ((before == CellLabel.EXPLORED) & (after == CellLabel.MOBILE_OBSTACLE)))
        return bool(new_obstacle.any())

    def blocked(self):
        """
        Cells that planning treats as blocked: steady and mobile obstacles.

        Returns
        -------
        blocked : (rows, cols) ndarray of bool

        """
        return blocked_mask(self.labels)

    def reset(self):
        """Forget everything: every cell back to ``NON_EXPLORED``."""
        self.labels.fill(CellLabel.NON_EXPLORED)
