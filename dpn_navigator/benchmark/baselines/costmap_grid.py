"""
A Nav2-style costmap: ObstacleLayer marking and ray-trace clearing, InflationLayer, as labels.

The reference a ROS user would run instead of dpn, built to the semantics of Nav2 Jazzy's
``nav2_costmap_2d`` (``docs/benchmark.md`` cites each behaviour):

- **Points** are the scan projected as ``laser_geometry`` does: returns with
  ``range_min <= range < range_max``; with ``inf_is_valid`` a ``+inf`` return becomes a point at
  ``range_max - 1e-4`` first (``ObstacleLayer::laserScanValidInfCallback``). NaN and ``-inf``
  give no point.
- **Clearing** first: from the sensor's cell, Bresenham's line to each point's cell (the point
  clipped to the map as ``ObstacleLayer::raytraceFreespace`` does) sets every cell it passes,
  the end cell included, to free; the line stops after ``ceil(raytrace_max_range / res)``
  cells scaled along the dominant axis (``Costmap2D::raytraceLine`` and ``bresenham2D``).
- **Marking** after: each point closer than ``obstacle_max_range`` to the sensor (and not
  closer than ``obstacle_min_range``) makes its cell lethal (``ObstacleLayer::updateBounds``).
- Nothing else changes a cell: no time decay, no moving/steady distinction. An obstacle that
  left is cleared only when a later ray passes through its cell, so one that left where no ray
  passes (behind another obstacle, beyond ``raytrace_max_range``) stays: the Nav2 ghost.
- **Inflation** to the robot's circumscribed radius: a planning cell whose centre lies within
  the inflation radius of a lethal cell's centre is blocked (``InflationLayer``'s inscribed
  cost and above, which NavFn treats as an obstacle).
- The layer has its own resolution, finer than the planning grid (Nav2's costmaps are
  usually 0.05 to 0.1 m): at the planning grid's 0.5 m, a lethal cell's centre can lie 0.35 m
  from its hit and inflation would close passages a real costmap leaves open.
- **Unknown is free for planning** (NavFn's ``allow_unknown``).

The grid publishes through the same four labels as ``LabelGrid`` so that the navigator, its
planner and the benchmark's map measures read it alike: blocked (inflated lethal) cells are
``STEADY_OBSTACLE``, cells a ray cleared are ``EXPLORED``, the rest ``NON_EXPLORED``. It never
labels ``MOBILE_OBSTACLE``.

"""

from dataclasses import dataclass
import math

import numpy as np

from ...core._kernels import costmap as costmap_kernels
from ...core.cell_label import blocked_mask, CellLabel, LABEL_DTYPE, ScanInput
from ...core.grid_geometry import GridGeometry
from ...core.mapping.label_grid import check_update, PlanningMap

#: Nav2 Jazzy's ``obstacle_max_range`` and ``raytrace_max_range`` in ``nav2_params.yaml`` [m].
NAV2_OBSTACLE_MAX_RANGE = 2.5
NAV2_RAYTRACE_MAX_RANGE = 3.0
#: ``range_max`` of the laser those defaults were set for, the TurtleBot3's LDS-01 [m].
NAV2_DEFAULT_LASER_RANGE = 3.5
#: What ``inf_is_valid`` puts in place of ``+inf``: ``range_max`` less this [m].
INF_RETURN_EPSILON = 1e-4

_EMPTY_WINDOW = (slice(0, 0), slice(0, 0), np.zeros((0, 0), dtype=LABEL_DTYPE))


@dataclass(frozen=True)
class CostmapConfig:
    """
    The ObstacleLayer's observation-source parameters.

    Attributes
    ----------
    obstacle_max_range, obstacle_min_range : float
        A point marks its cell when ``obstacle_min_range <= distance < obstacle_max_range``
        from the sensor [m].
    raytrace_max_range : float
        Clearing rays stop after this distance, rounded up to whole cells [m].
    inf_is_valid : bool
        Take ``+inf`` returns as points at ``range_max`` (they clear, and mark if in range).

    """

    obstacle_max_range: float = NAV2_OBSTACLE_MAX_RANGE
    obstacle_min_range: float = 0.0
    raytrace_max_range: float = NAV2_RAYTRACE_MAX_RANGE
    inf_is_valid: bool = True

    def __post_init__(self):
        for name in ('obstacle_max_range', 'obstacle_min_range', 'raytrace_max_range'):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be a finite number >= 0, got {value!r} m')
        if self.obstacle_min_range > self.obstacle_max_range:
            raise ValueError(f'obstacle_min_range {self.obstacle_min_range} m is above '
                             f'obstacle_max_range {self.obstacle_max_range} m')

    @classmethod
    def scaled_to_laser(cls, range_max, inf_is_valid=True):
        """
        Return Nav2 Jazzy's default ranges scaled from the LDS-01's 3.5 m to ``range_max``.

        ``obstacle_max_range = 2.5 / 3.5 * range_max`` and ``raytrace_max_range = 3.0 / 3.5 *
        range_max``: the same share of the sensor's reach as in Nav2's defaults.

        Raises
        ------
        ValueError
            If ``range_max`` is not a positive finite number.

        """
        if not (math.isfinite(range_max) and range_max > 0.0):
            raise ValueError(f'range_max must be positive and finite, got {range_max!r} m')
        scale = range_max / NAV2_DEFAULT_LASER_RANGE
        return cls(obstacle_max_range=NAV2_OBSTACLE_MAX_RANGE * scale,
                   raytrace_max_range=NAV2_RAYTRACE_MAX_RANGE * scale,
                   inf_is_valid=inf_is_valid)


def bresenham_cells(start_rr, start_cc, end_rr, end_cc, max_cells):
    """
    Return the cells of Nav2's ``raytraceLine`` from one start cell to many end cells.

    Step ``i`` of a line moves one cell along its dominant axis and, by Bresenham's integer
    error (started at half the dominant length), ``floor((d_a // 2 + i * d_b) / d_a)`` cells
    along the other in all. The line visits steps ``0 .. end`` with ``end = min(d_a,
    floor(scale * d_a))`` and ``scale = min(1, max_cells / hypot(d_r, d_c))``: the end cell is
    included unless the line is cut short.

    Parameters
    ----------
    start_rr, start_cc : int
        The sensor's cell.
    end_rr, end_cc : (N,) ndarray of int64
        End cells of the lines.
    max_cells : int
        ``cellDistance(raytrace_max_range)``: the line's length limit [cells].

    Returns
    -------
    rr, cc : (M,) ndarray of int64
        Every cell visited by a line (with repeats across lines).

    """
    d_rr = np.asarray(end_rr, dtype=np.int64) - start_rr
    d_cc = np.asarray(end_cc, dtype=np.int64) - start_cc
    abs_rr = np.abs(d_rr)
    abs_cc = np.abs(d_cc)
    col_dominant = abs_cc >= abs_rr                   # Nav2's "x is dominant" (x is the column)
    abs_a = np.where(col_dominant, abs_cc, abs_rr)
    abs_b = np.where(col_dominant, abs_rr, abs_cc)
    distance = np.hypot(d_rr, d_cc)
    scale = np.minimum(1.0, max_cells / np.where(distance == 0.0, 1.0, distance))
    end = np.minimum((scale * abs_a).astype(np.int64), abs_a)
    if not end.shape[0]:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    steps = np.arange(int(end.max()) + 1, dtype=np.int64)[None, :]
    visited = steps <= end[:, None]
    along_b = (abs_a[:, None] // 2 + steps * abs_b[:, None]) // np.maximum(abs_a, 1)[:, None]
    sign_rr = np.where(d_rr > 0, 1, -1)[:, None]
    sign_cc = np.where(d_cc > 0, 1, -1)[:, None]
    step_rr = np.where(col_dominant[:, None], along_b, steps)
    step_cc = np.where(col_dominant[:, None], steps, along_b)
    return (start_rr + sign_rr * step_rr)[visited], (start_cc + sign_cc * step_cc)[visited]


def inflate(lethal, layer_geometry, geometry, radius):
    """
    Mark the cells of ``geometry`` whose centre lies within ``radius`` of a lethal cell's centre.

    Parameters
    ----------
    lethal : (h, w) ndarray of bool
        Lethal cells on ``layer_geometry``.
    layer_geometry : GridGeometry
        The costmap layer's grid.
    geometry : GridGeometry
        The grid to inflate onto (the planning grid; may be the same).
    radius : float
        Inflation radius [m], finite and >= 0.

    Returns
    -------
    inflated : (H, W) ndarray of bool
        On ``geometry``.

    Raises
    ------
    ValueError
        If ``lethal`` does not have the layer's shape or ``radius`` is not finite and >= 0.

    """
    lethal = np.ascontiguousarray(lethal, dtype=bool)
    if lethal.shape != layer_geometry.shape:
        raise ValueError(f'lethal has shape {lethal.shape}, the layer {layer_geometry.shape}')
    radius = float(radius)
    if not (math.isfinite(radius) and radius >= 0.0):
        raise ValueError(f'radius must be finite and >= 0, got {radius!r} m')
    inflated = np.zeros(geometry.shape, dtype=bool)
    costmap_kernels.inflate(
        lethal, float(layer_geometry.origin[0]), float(layer_geometry.origin[1]),
        float(layer_geometry.resolution), float(geometry.origin[0]), float(geometry.origin[1]),
        float(geometry.resolution), radius, inflated)
    return inflated


def any_in_blocks(layer_mask, factor):
    """
    Reduce a fine mask to a coarse grid: True where any of a coarse cell's fine cells is.

    Parameters
    ----------
    layer_mask : (h, w) ndarray of bool
        On the fine grid; ``h`` and ``w`` are whole multiples of ``factor``.
    factor : int
        Fine cells per coarse cell side, >= 1.

    Returns
    -------
    cells : (h // factor, w // factor) ndarray of bool
        ``layer_mask.reshape(h // factor, factor, w // factor, factor).any(axis=(1, 3))``,
        computed in one compiled pass (numpy's reduction over two strided axes took about
        1 ms per update of a 200 m x 200 m layer of 0.1 m cells).

    Raises
    ------
    ValueError
        If the mask is not 2-D or its sides are not whole multiples of ``factor``.

    """
    layer_mask = np.ascontiguousarray(layer_mask, dtype=bool)
    factor = int(factor)
    if layer_mask.ndim != 2 or factor < 1 or any(side % factor for side in layer_mask.shape):
        raise ValueError(f'a mask of shape {layer_mask.shape} does not split into blocks of '
                         f'{factor} x {factor} cells')
    cells = np.zeros((layer_mask.shape[0] // factor, layer_mask.shape[1] // factor), dtype=bool)
    costmap_kernels.any_in_blocks(layer_mask, factor, cells)
    return cells


def warm_up_costmap():
    """Compile (or load from the cache) the costmap's kernels with a tiny call."""
    layer = np.zeros((2, 2), dtype=bool)
    layer[0, 0] = True
    costmap_kernels.inflate(layer, 0.0, 0.0, 0.5, 0.0, 0.0, 0.5, 0.6, np.zeros((2, 2), dtype=bool))
    one = np.zeros(1, dtype=np.int64)
    costmap_kernels.clear_rays(0, 0, one, one + 1, 1, 1, layer, layer.copy(), layer.copy())
    costmap_kernels.any_in_blocks(layer, 1, np.zeros((2, 2), dtype=bool))


def layer_geometry_for(geometry, layer_resolution):
    """
    Return the costmap layer's grid: ``geometry`` cut into cells ``n`` times finer.

    Raises
    ------
    ValueError
        Unless ``geometry.resolution`` is a whole multiple ``n >= 1`` of ``layer_resolution``.

    """
    if not (math.isfinite(layer_resolution) and layer_resolution > 0.0):
        raise ValueError(f'layer_resolution must be positive, got {layer_resolution!r} m')
    factor = round(geometry.resolution / layer_resolution)
    if factor < 1 or abs(factor * layer_resolution - geometry.resolution) > 1e-9:
        raise ValueError(f'the grid resolution {geometry.resolution} m must be a whole multiple '
                         f'of layer_resolution {layer_resolution} m')
    return GridGeometry(geometry.cols * geometry.resolution, geometry.rows * geometry.resolution,
                        geometry.resolution / factor, geometry.origin), factor


class CostmapGrid(PlanningMap):
    """
    The costmap as a drop-in for ``LabelGrid`` in the ``Navigator``.

    The obstacle layer (marking and clearing) runs on its own grid, ``layer_resolution``
    cells, as Nav2's does (Nav2's default is 0.05 m); the inflation is sampled at the centres
    of the navigator's planning cells, which the labels are on.

    Parameters
    ----------
    width, height : float
        Size of the environment [m].
    resolution : float
        Planning cell side [m].
    origin : (float, float)
        Map-frame position of the lower-left corner [m].
    config : CostmapConfig
    layer_resolution : float, optional
        The obstacle layer's cell side [m]; ``resolution`` must be a whole multiple of it.
        Default: ``resolution``.

    Attributes
    ----------
    geometry : GridGeometry
        The planning grid.
    layer_geometry : GridGeometry
        The obstacle layer's grid, covering the planning grid exactly.
    config : CostmapConfig
    lethal : (h, w) ndarray of bool
        The obstacle layer's ``LETHAL_OBSTACLE`` cells, on ``layer_geometry``.
    known_free : (h, w) ndarray of bool
        Layer cells a ray has cleared and no point marked since (``FREE_SPACE``); the rest of
        the non-lethal cells are ``NO_INFORMATION``. Change these two only through `update`
        and `reset`: they keep the planning-cell views that ``labels`` is built from.
    labels : (H, W) ndarray of uint8
        On ``geometry``: ``STEADY_OBSTACLE`` where the centre is within the inflation radius of
        a lethal cell's centre, else ``EXPLORED`` where a layer cell is known free, else
        ``NON_EXPLORED``; rebuilt by every update.
    last_window : (slice, slice, ndarray of uint8)
        The latest update's window on ``geometry`` and what it did there as ``ScanInput``:
        ``HIT`` for cells holding a layer cell this scan marked, ``INSIDE`` for cells holding
        one its rays cleared, ``NONE`` elsewhere.

    """

    def __init__(self, width, height, resolution=0.5, origin=(0.0, 0.0), config=None,
                 layer_resolution=None):
        self.geometry = GridGeometry(width, height, resolution, tuple(origin))
        self.layer_geometry, self._factor = layer_geometry_for(
            self.geometry, resolution if layer_resolution is None else layer_resolution)
        self.config = CostmapConfig() if config is None else config
        self.lethal = np.zeros(self.layer_geometry.shape, dtype=bool)
        self.known_free = np.zeros(self.layer_geometry.shape, dtype=bool)
        self.labels = np.full(self.geometry.shape, CellLabel.NON_EXPLORED, dtype=LABEL_DTYPE)
        self._lethal_cells = np.zeros(self.geometry.shape, dtype=bool)
        self._free_cells = np.zeros(self.geometry.shape, dtype=bool)
        self.last_window = _EMPTY_WINDOW
        self._trackers = []

    def labels_changed(self):
        """Note that ``labels`` changed, anywhere: every change tracker holds the whole map."""
        self._widen_trackers_all()

    def update(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
               safety_radius, path=None, angle_max=None, stamp=None):
        """
        Clear along the scan's rays, mark its points, inflate; say whether the path is hit.

        Parameters
        ----------
        pose : (float, float, float)
            The laser's ``(x, y, yaw)`` in the map frame [m, m, rad].
        ranges, angle_min, angle_increment, range_min, range_max, angle_max
            The scan, as for ``LabelGrid.update``.
        safety_radius : float
            Inflation radius [m]: the robot's circumscribed radius.
        path : (N, 2) array_like of int, optional
            The planned path as ``(row, col)`` cells of ``geometry``.
        stamp : float, optional
            Unused: the costmap has no time decay.

        Returns
        -------
        replan : bool
            True when a cell of ``path`` became blocked in this update.

        Raises
        ------
        ValueError
            For a malformed pose, scan, radius or path; the costmap is then unchanged.

        """
        self.labels_changed()
        pose, ranges, safety_radius, path = check_update(
            self.geometry.shape, pose, ranges, angle_min, angle_increment, range_min, range_max,
            safety_radius, path, angle_max)
        points_x, points_y, distance = self._points(pose, ranges, angle_min, angle_increment,
                                                    range_min, range_max)
        cleared = self._raytrace(pose, points_x, points_y)
        marking = (distance >= self.config.obstacle_min_range) & (
            distance < self.config.obstacle_max_range)
        layer = self.layer_geometry
        marked_rr, marked_cc = layer.world_to_cell(points_x[marking], points_y[marking])
        on_grid = layer.contains_cell(marked_rr, marked_cc)
        marked_rr, marked_cc = marked_rr[on_grid], marked_cc[on_grid]
        self.lethal[marked_rr, marked_cc] = True
        self.known_free[marked_rr, marked_cc] = False
        self._reduce_to_cells(pose, points_x, points_y)
        before = self.labels
        blocked = inflate(self.lethal, layer, self.geometry, safety_radius)
        self.labels = np.where(blocked, CellLabel.STEADY_OBSTACLE, np.where(
            self._free_cells, CellLabel.EXPLORED, CellLabel.NON_EXPLORED)).astype(LABEL_DTYPE)
        self._record_window(pose, points_x, points_y, cleared, marked_rr, marked_cc,
                            safety_radius)
        if path is None or not path.shape[0]:
            return False
        return bool((~blocked_mask(before[path[:, 0], path[:, 1]])
                     & blocked[path[:, 0], path[:, 1]]).any())

    def _reduce_to_cells(self, pose, points_x, points_y):
        """
        Bring the planning-cell views of ``lethal`` and ``known_free`` up to date.

        An update changes layer cells only on its rays and at its points, all inside the box
        of the sensor and the points, so only the planning cells of that box are reduced again.
        """
        rows, cols = self.geometry.cell_window(
            min(pose[0], float(points_x.min(initial=pose[0]))),
            max(pose[0], float(points_x.max(initial=pose[0]))),
            min(pose[1], float(points_y.min(initial=pose[1]))),
            max(pose[1], float(points_y.max(initial=pose[1]))))
        factor = self._factor
        layer_rows = slice(rows.start * factor, rows.stop * factor)
        layer_cols = slice(cols.start * factor, cols.stop * factor)
        self._lethal_cells[rows, cols] = any_in_blocks(self.lethal[layer_rows, layer_cols],
                                                       factor)
        self._free_cells[rows, cols] = any_in_blocks(self.known_free[layer_rows, layer_cols],
                                                     factor)

    def _points(self, pose, ranges, angle_min, angle_increment, range_min, range_max):
        """Project the scan as ``laser_geometry`` does; return x, y [m] and distance [m]."""
        ranges = ranges.astype(np.float64)
        if self.config.inf_is_valid:
            ranges = np.where(np.isposinf(ranges), range_max - INF_RETURN_EPSILON, ranges)
        with np.errstate(invalid='ignore'):
            valid = (ranges >= range_min) & (ranges < range_max)
        beams = np.flatnonzero(valid)
        x, y, yaw = pose
        theta = yaw + (angle_min + beams * angle_increment)
        distance = ranges[beams]
        return x + distance * np.cos(theta), y + distance * np.sin(theta), distance

    def _raytrace(self, pose, points_x, points_y):
        """
        Clear the layer cells the rays pass, end cells included (Nav2's raytraceFreespace).

        Returns
        -------
        cleared : (H, W) ndarray of bool
            Planning cells holding a layer cell a ray passed.

        """
        layer = self.layer_geometry
        cleared = np.zeros(self.geometry.shape, dtype=bool)
        start_rr, start_cc = (int(v) for v in layer.world_to_cell(pose[0], pose[1]))
        if not layer.contains_cell(start_rr, start_cc) or not points_x.shape[0]:
            return cleared
        end_x, end_y = clip_to_map(pose[0], pose[1], points_x, points_y, layer)
        end_rr, end_cc = layer.world_to_cell(end_x, end_y)
        legal = layer.contains_cell(end_rr, end_cc)
        max_cells = max(0, math.ceil(self.config.raytrace_max_range / layer.resolution))
        costmap_kernels.clear_rays(start_rr, start_cc, np.ascontiguousarray(end_rr[legal]),
                                   np.ascontiguousarray(
                                       end_cc[legal]), max_cells, self._factor, self.lethal,
                                   self.known_free, cleared)
        return cleared

    def _record_window(self, pose, points_x, points_y, cleared, marked_rr, marked_cc,
                       safety_radius):
        """Store the update's window with its ``ScanInput`` for the benchmark's meters."""
        xs = np.append(points_x, pose[0])
        ys = np.append(points_y, pose[1])
        rows, cols = self.geometry.cell_window(float(xs.min()) - safety_radius,
                                               float(xs.max()) + safety_radius,
                                               float(ys.min()) - safety_radius,
                                               float(ys.max()) + safety_radius)
        if rows.start == rows.stop or cols.start == cols.stop:
            self.last_window = _EMPTY_WINDOW
            return
        shape = (rows.stop - rows.start, cols.stop - cols.start)
        factor = self._factor
        marked = np.zeros(shape, dtype=bool)
        marked[marked_rr // factor - rows.start, marked_cc // factor - cols.start] = True
        cell_input = np.where(marked, ScanInput.HIT, np.where(
            cleared[rows, cols], ScanInput.INSIDE, ScanInput.NONE)).astype(LABEL_DTYPE)
        self.last_window = (rows, cols, cell_input)

    def lethal_labels(self):
        """
        Return the costmap before inflation as labels, for the benchmark's map measures.

        Returns
        -------
        labels : (H, W) ndarray of uint8
            On ``geometry``: ``STEADY_OBSTACLE`` where a layer cell is lethal, else
            ``EXPLORED`` where one is known free, else ``NON_EXPLORED``.

        """
        return np.where(self._lethal_cells, CellLabel.STEADY_OBSTACLE, np.where(
            self._free_cells, CellLabel.EXPLORED, CellLabel.NON_EXPLORED)).astype(LABEL_DTYPE)

    def reset(self):
        """Forget everything (Nav2's ``ClearEntireCostmap``)."""
        self.lethal.fill(False)
        self.known_free.fill(False)
        self._lethal_cells.fill(False)
        self._free_cells.fill(False)
        self.labels.fill(CellLabel.NON_EXPLORED)
        self.last_window = _EMPTY_WINDOW
        self.labels_changed()


def clip_to_map(origin_x, origin_y, points_x, points_y, geometry):
    """
    Clip ray end points to the map as ``ObstacleLayer::raytraceFreespace`` does.

    A point below the map's lower edge moves along its ray onto the edge; one past the upper
    edge onto the edge less 1 mm, so that its cell lies on the map.

    Parameters
    ----------
    origin_x, origin_y : float
        The sensor [m], on the map.
    points_x, points_y : (N,) ndarray of float64
        Ray ends [m].
    geometry : GridGeometry
        The map.

    Returns
    -------
    end_x, end_y : (N,) ndarray of float64

    """
    x0, y0 = geometry.origin
    x1 = x0 + geometry.cols * geometry.resolution
    y1 = y0 + geometry.rows * geometry.resolution
    wx = points_x.copy()
    wy = points_y.copy()
    a = points_x - origin_x
    b = points_y - origin_y
    with np.errstate(divide='ignore', invalid='ignore'):
        low = wx < x0
        wy = np.where(low, origin_y + b * (x0 - origin_x) / a, wy)
        wx = np.where(low, x0, wx)
        low = wy < y0
        wx = np.where(low, origin_x + a * (y0 - origin_y) / b, wx)
        wy = np.where(low, y0, wy)
        high = wx > x1
        wy = np.where(high, origin_y + b * (x1 - origin_x) / a, wy)
        wx = np.where(high, x1 - 0.001, wx)
        high = wy > y1
        wx = np.where(high, origin_x + a * (y1 - origin_y) / b, wx)
        wy = np.where(high, y1 - 0.001, wy)
    return wx, wy
