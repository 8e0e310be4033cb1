"""
What A* plans on: the blocked cells and the extra cost of cells beside obstacles, kept up to date.

The navigator plans on ``blocked = labels >= STEADY_OBSTACLE`` with the robot's footprint
cleared, and, with an obstacle proximity cost, on ``cost * touches_blocked(blocked)``. Both are
kept here as state and refreshed only inside the box of cells the grid changed since the last
plan (a ``ChangeTracker``), widened by one cell for the cost. The footprint is cleared in place
for one search and restored after it. A plan therefore costs the changed cells and the search,
not the grid.

"""

import numpy as np

from .astar_search import astar_checked
from .cell_label import blocked_mask


def touches_blocked(blocked):
    """
    Mark the free cells that have a blocked cell among their 8 neighbours.

    Parameters
    ----------
    blocked : (H, W) ndarray of bool
        Cells A* may not enter.

    Returns
    -------
    touching : (H, W) ndarray of bool
        False on blocked cells themselves.

    """
    rows, cols = blocked.shape
    return touches_blocked_in(blocked, slice(0, rows), slice(0, cols))


def touches_blocked_in(blocked, rows, cols):
    """
    `touches_blocked` over the window ``blocked[rows, cols]`` only, neighbours outside included.

    Parameters
    ----------
    blocked : (H, W) ndarray of bool
        Cells A* may not enter.
    rows, cols : slice
        The window, inside the grid.

    Returns
    -------
    touching : (n_rows, n_cols) ndarray of bool

    """
    grid_rows, grid_cols = blocked.shape
    n_rows = rows.stop - rows.start
    n_cols = cols.stop - cols.start
    # The window and a ring of neighbours around it, False beyond the grid's edge.
    padded = np.zeros((n_rows + 2, n_cols + 2), dtype=bool)
    row_lo, row_hi = max(rows.start - 1, 0), min(rows.stop + 1, grid_rows)
    col_lo, col_hi = max(cols.start - 1, 0), min(cols.stop + 1, grid_cols)
    padded[row_lo - rows.start + 1:row_hi - rows.start + 1,
           col_lo - cols.start + 1:col_hi - cols.start + 1] = blocked[row_lo:row_hi,
                                                                      col_lo:col_hi]
    near = np.zeros((n_rows, n_cols), dtype=bool)
    for dr in (0, 1, 2):
        for dc in (0, 1, 2):
            if dr != 1 or dc != 1:
                near |= padded[dr:dr + n_rows, dc:dc + n_cols]
    return near & ~padded[1:-1, 1:-1]


def _grown(rows, cols, shape):
    """Widen the window ``(rows, cols)`` by one cell on every side, clipped to ``shape``."""
    return (slice(max(rows.start - 1, 0), min(rows.stop + 1, shape[0])),
            slice(max(cols.start - 1, 0), min(cols.stop + 1, shape[1])))


class PlanningMasks:
    """
    The blocked and cost masks of a ``LabelGrid`` for A*, refreshed where the grid changed.

    Parameters
    ----------
    grid : LabelGrid
        The grid to follow (a ``ChangeTracker`` of it is taken here).
    proximity_cost : float
        Extra cost of entering a free cell next to a blocked one [cells]; 0: no cost mask.

    Attributes
    ----------
    blocked : (rows, cols) ndarray of bool
        ``blocked_mask(grid.labels)`` as of the last `refresh`.
    cost : (rows, cols) ndarray of float64, or None
        ``proximity_cost`` on the cells that touch ``blocked``, else 0; None without a cost.

    """

    def __init__(self, grid, proximity_cost):
        self._grid = grid
        self._changes = grid.change_tracker()
        self._proximity_cost = float(proximity_cost)
        self.blocked = np.zeros(grid.geometry.shape, dtype=bool)
        self.cost = (np.zeros(grid.geometry.shape, dtype=np.float64)
                     if self._proximity_cost > 0.0 else None)
        # How many cells of cost are nonzero: the largest cost, which sets A*'s fixed point,
        # is proximity_cost when there is one, else 0.
        self._costly = 0

    def refresh(self):
        """Bring the masks up to date with the grid's labels, inside the changed box only."""
        rows, cols, whole = self._changes.take()
        if rows.start == rows.stop or cols.start == cols.stop:
            return
        self.blocked[rows, cols] = blocked_mask(self._grid.labels[rows, cols])
        if self.cost is not None:
            self._recost(*_grown(rows, cols, self.blocked.shape))

    def _recost(self, rows, cols):
        """Recompute ``cost[rows, cols]`` from ``blocked``."""
        window = self.cost[rows, cols]
        self._costly -= int(np.count_nonzero(window))
        touching = touches_blocked_in(self.blocked, rows, cols)
        window[...] = np.where(touching, self._proximity_cost, 0.0)
        self._costly += int(np.count_nonzero(touching))

    def plan(self, start, goal, footprint, cut_corners):
        """
        Plan with A* on the masks with ``footprint`` cells (and ``start``) free, then restore.

        Parameters
        ----------
        start, goal : (int, int)
            Cells on the grid.
        footprint : (slice, slice, (n_rows, n_cols) ndarray of bool)
            A window and the cells of it the robot stands on.
        cut_corners : bool
            As for ``astar``.

        Returns
        -------
        path : list of (int, int) or None
            As from ``astar``; None also when the goal cell is blocked.

        """
        if self.blocked[goal]:
            return None
        rows, cols, near = footprint
        saved_blocked = self.blocked[rows, cols].copy()
        self.blocked[rows, cols] &= ~near
        self.blocked[start] = False                 # the robot's own cell, always
        cost_rows, cost_cols = _grown(rows, cols, self.blocked.shape)
        if self.cost is not None:
            saved_cost = self.cost[cost_rows, cost_cols].copy()
            saved_costly = self._costly
            self._recost(cost_rows, cost_cols)
        try:
            return astar_checked(
                self.blocked, start, goal, self.cost,
                self._proximity_cost if self._costly else 0.0, cut_corners)
        finally:
            self.blocked[rows, cols] = saved_blocked
            if self.cost is not None:
                self.cost[cost_rows, cost_cols] = saved_cost
                self._costly = saved_costly
