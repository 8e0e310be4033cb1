"""
What A* plans on: the blocked cells and the extra cost of cells beside obstacles, kept up to date.

The navigator plans on ``blocked = labels >= STEADY_OBSTACLE`` with the robot's footprint
cleared, and, with an obstacle proximity cost, on ``cost * touches_blocked(blocked)``. Both are
kept here as state: ``blocked`` is refreshed inside the box of cells the grid changed since the
last plan (a ``ChangeTracker``) by a compiled pass that also lists the cells whose ``blocked``
flipped, and the cost only on those and their neighbours (a cost depends on its cell's 8
neighbours alone). The footprint is cleared in place for one search and restored after
it. A plan therefore costs a pass over the changed cells and the search, not the grid.

"""

import numpy as np

from .astar_search import astar_checked
from .._kernels import planning_masks as mask_kernels
from ..cell_label import CellLabel, LABEL_DTYPE


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


def refresh_blocked(labels, blocked, rows, cols):
    """
    Bring ``blocked[rows, cols]`` up to ``blocked_mask(labels[rows, cols])``, in place.

    Parameters
    ----------
    labels : (H, W) ndarray of uint8
        Cell labels.
    blocked : (H, W) ndarray of bool, C-contiguous
        The mask to refresh.
    rows, cols : slice
        The window to refresh, inside the grid (may be empty).

    Returns
    -------
    flipped : (N,) ndarray of int64
        Flat indices (``row * W + col``) of the cells whose ``blocked`` flipped, row by row.

    Raises
    ------
    ValueError
        When ``labels`` and ``blocked`` differ in shape, or ``blocked`` is not a C-contiguous
        bool array.

    """
    labels = np.asarray(labels)
    if labels.shape != blocked.shape:
        raise ValueError(f'labels of shape {labels.shape} for a mask of {blocked.shape}')
    if blocked.dtype != np.bool_ or not blocked.flags.c_contiguous:
        raise ValueError('blocked must be a C-contiguous ndarray of bool')
    labels = np.ascontiguousarray(labels, dtype=LABEL_DTYPE)
    row_lo, row_hi, _ = rows.indices(labels.shape[0])
    col_lo, col_hi, _ = cols.indices(labels.shape[1])
    if row_hi <= row_lo or col_hi <= col_lo:
        return np.zeros(0, dtype=np.int64)
    flipped, count = mask_kernels.refresh_blocked(labels, blocked, row_lo, row_hi, col_lo, col_hi,
                                                  LABEL_DTYPE(CellLabel.STEADY_OBSTACLE),
                                                  np.empty(256, dtype=np.int64))
    return flipped[:count]


def recost_around(blocked, cost, cells, proximity_cost):
    """
    Recompute the proximity cost on ``cells`` and their 8 neighbours, in place.

    Parameters
    ----------
    blocked : (H, W) ndarray of bool
        Cells A* may not enter.
    cost : (H, W) ndarray of float64
        ``proximity_cost * touches_blocked(blocked)`` except around ``cells``; all of it after.
    cells : (N,) array_like of int
        Flat indices of the cells whose ``blocked`` changed.
    proximity_cost : float
        Cost of a free cell with a blocked neighbour, > 0.

    Returns
    -------
    change : int
        How many more cells of ``cost`` are nonzero than before.

    Raises
    ------
    ValueError
        When the arrays differ in shape or dtype from the above, or a cell is off the grid.

    """
    if blocked.shape != cost.shape or blocked.dtype != np.bool_ or cost.dtype != np.float64:
        raise ValueError('blocked (bool) and cost (float64) must be arrays of one shape')
    cells = np.ascontiguousarray(cells, dtype=np.int64)
    if cells.size and not (0 <= cells.min() and cells.max() < blocked.size):
        raise ValueError(f'cells must be flat indices into a grid of {blocked.shape}')
    return int(mask_kernels.recost_around(blocked, cost, cells, float(proximity_cost)))


def warm_up_planning_masks():
    """Compile (or load) the kernels with a tiny call."""
    blocked = np.zeros((2, 2), dtype=bool)
    flipped = refresh_blocked(np.full((2, 2), CellLabel.STEADY_OBSTACLE, dtype=LABEL_DTYPE),
                              blocked, slice(0, 1), slice(0, 2))
    recost_around(blocked, np.zeros((2, 2)), flipped, 1.0)


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

    def grow(self, growth):
        """
        Follow the grid as it grew (``map_growth.GridGrowth``): the added cells free, no cost.

        The grid's ``grow`` made this tracker hold the whole grid, so the next `refresh`
        brings the masks up to date everywhere.
        """
        shape = self._grid.geometry.shape
        self.blocked = growth.embed(self.blocked, shape, False)
        if self.cost is not None:
            self.cost = growth.embed(self.cost, shape, 0.0)

    @property
    def nbytes(self):
        """Bytes held by the masks."""
        return self.blocked.nbytes + (0 if self.cost is None else self.cost.nbytes)

    def refresh(self):
        """Bring the masks up to date with the grid's labels, inside the changed box only."""
        rows, cols, _ = self._changes.take()
        flipped = refresh_blocked(self._grid.labels, self.blocked, rows, cols)
        if self.cost is not None and flipped.size:
            self._costly += recost_around(self.blocked, self.cost, flipped,
                                          self._proximity_cost)

    def _recost(self, rows, cols):
        """Recompute ``cost[rows, cols]`` from ``blocked``."""
        window = self.cost[rows, cols]
        self._costly -= int(np.count_nonzero(window))
        touching = touches_blocked_in(self.blocked, rows, cols)
        window[...] = np.where(touching, self._proximity_cost, 0.0)
        self._costly += int(np.count_nonzero(touching))

    def plan(self, start, goal, footprint, cut_corners, extra_cost=None, opened=None):
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
        extra_cost : (rows, cols) ndarray of float64, optional
            Extra cost of entering each cell for this search only [cells], finite and >= 0,
            added to the proximity cost (the navigator's exploration and wait costs).
        opened : (rows, cols) ndarray of bool, optional
            Cells planned through for this search only although blocked (far mobile cells).

        Returns
        -------
        path : list of (int, int) or None
            As from ``astar``; None also when the goal cell is blocked.

        """
        if opened is None:
            return self._plan(start, goal, footprint, cut_corners, extra_cost)
        saved = self.blocked.copy()
        self.blocked &= ~opened
        try:
            return self._plan(start, goal, footprint, cut_corners, extra_cost)
        finally:
            self.blocked[...] = saved

    def _plan(self, start, goal, footprint, cut_corners, extra_cost):
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
        cost, max_cost = self.cost, self._proximity_cost if self._costly else 0.0
        if extra_cost is not None:
            cost = extra_cost if cost is None else cost + extra_cost
            max_cost = float(cost.max(initial=0.0))
        try:
            return astar_checked(self.blocked, start, goal, cost, max_cost, cut_corners)
        finally:
            self.blocked[rows, cols] = saved_blocked
            if self.cost is not None:
                self.cost[cost_rows, cost_cols] = saved_cost
                self._costly = saved_costly
