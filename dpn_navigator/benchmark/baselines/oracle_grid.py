"""
The oracle's map: the true walls from the start and every wanderer's true footprint each scan.

A drop-in for ``LabelGrid`` in the ``Navigator`` that ignores the laser. The walls are the
cells of their f1 belt (centre within ``r`` of a wall, ``ground_truth.wall_belt``): what f1
would label around them. A wanderer blocks the cells whose centre lies within ``R + r`` of its
centre (``R`` its circumscribed radius): its footprint inflated by the same ``r``. Every other
cell is known free. With the same planner, follower and limits as dpn, the oracle's success is
what the map, the wanderers and the time limit allow.

"""

import numpy as np

from ..ground_truth import near_any
from ...core.cell_label import blocked_mask, CellLabel, LABEL_DTYPE
from ...core.grid_geometry import GridGeometry
from ...core.mapping.label_grid import check_path, PlanningMap

_EMPTY_WINDOW = (slice(0, 0), slice(0, 0), np.zeros((0, 0), dtype=LABEL_DTYPE))


class OracleGrid(PlanningMap):
    """
    Ground-truth labels: walls steady, wanderers mobile, the rest explored.

    Parameters
    ----------
    geometry : GridGeometry
        The navigator's grid.
    wall_belt : (H, W) ndarray of bool
        The walls' f1 belt on ``geometry`` (``ground_truth.wall_belt`` with the navigator's
        ``r``).
    wanderer_reach : float
        ``R + r`` [m]: cells whose centre is this close to a wanderer are blocked.

    Attributes
    ----------
    geometry : GridGeometry
    labels : (H, W) ndarray of uint8
        ``STEADY_OBSTACLE`` on the wall belt, ``MOBILE_OBSTACLE`` near a wanderer (as of the
        last `set_wanderers`), ``EXPLORED`` elsewhere.
    last_window : tuple
        Always empty: the oracle sees no scan.

    """

    def __init__(self, geometry, wall_belt, wanderer_reach):
        if not isinstance(geometry, GridGeometry):
            raise TypeError(f'geometry must be a GridGeometry, got {type(geometry).__name__}')
        wall_belt = np.asarray(wall_belt, dtype=bool)
        if wall_belt.shape != geometry.shape:
            raise ValueError(f'wall_belt has shape {wall_belt.shape}, the grid {geometry.shape}')
        if not (np.isfinite(wanderer_reach) and wanderer_reach >= 0.0):
            raise ValueError(f'wanderer_reach must be finite and >= 0, got {wanderer_reach!r}')
        self.geometry = geometry
        self._walls = np.where(wall_belt, CellLabel.STEADY_OBSTACLE,
                               CellLabel.EXPLORED).astype(LABEL_DTYPE)
        self._reach = float(wanderer_reach)
        self.labels = self._walls.copy()
        self._pending = self.labels
        self.last_window = _EMPTY_WINDOW
        self._trackers = []

    def labels_changed(self):
        """Note that ``labels`` changed, anywhere: every change tracker holds the whole map."""
        self._widen_trackers_all()

    def set_wanderers(self, wanderer_xy):
        """
        Place the wanderers for the next `update`.

        Parameters
        ----------
        wanderer_xy : (K, 2) array_like of float
            Their true positions [m]; ``K`` may be 0.

        """
        wanderer_xy = np.asarray(wanderer_xy, dtype=np.float64).reshape(-1, 2)
        labels = self._walls.copy()
        reach = self._reach
        for x, y in wanderer_xy:
            rows, cols = self.geometry.cell_window(x - reach, x + reach, y - reach, y + reach)
            if rows.start == rows.stop or cols.start == cols.stop:
                continue
            x_centres, y_centres = self.geometry.window_centres(rows, cols)
            xx, yy = np.meshgrid(x_centres, y_centres)
            near = near_any(xx.ravel(), yy.ravel(), [(x, y)], reach).reshape(xx.shape)
            window = labels[rows, cols]
            window[near & (window == CellLabel.EXPLORED)] = CellLabel.MOBILE_OBSTACLE
        self._pending = labels

    def update(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
               safety_radius, path=None, angle_max=None, stamp=None):
        """
        Take the wanderers of the last `set_wanderers` as the map; ignore the scan.

        The arguments are those of ``LabelGrid.update``; only ``path`` is read.

        Returns
        -------
        replan : bool
            True when a cell of ``path`` became blocked.

        """
        path = check_path(path, self.geometry.shape)
        before = self.labels
        self.labels = self._pending
        self.labels_changed()
        if path is None or not path.shape[0]:
            return False
        rr, cc = path[:, 0], path[:, 1]
        return bool((~blocked_mask(before[rr, cc]) & blocked_mask(self.labels[rr, cc])).any())
