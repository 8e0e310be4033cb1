"""
Obstacle cells no hit has confirmed for a while, dropped when they alone close the route.

A steady or mobile cell stays an obstacle out of view for as long as no scan sees it free. One
that nothing explains any more (a wanderer seen once and gone, a speck of a wall seen through a
gap) can close the only way out for good: the laser never looks there again because the plan
never leads there. `ObstacleConfirmations` keeps, per cell, when a hit last confirmed it, so
that the navigator can tell which obstacles are *stale* (not confirmed for a given time) and,
when there is no path but one would exist without the stale ones, drop the stale cells on that
path: the robot then drives to see them, and a wall there is hit and marked again.

"""

import math

import numpy as np

from ..cell_label import blocked_mask, CellLabel, ScanInput

#: ``ObstacleConfirmations.hits`` stops counting here.
MAX_HITS = 1000


class ObstacleConfirmations:
    """
    When a laser hit last confirmed each cell, kept from the grid's latest update window.

    Parameters
    ----------
    shape : (int, int)
        The grid's ``(rows, cols)``.

    Attributes
    ----------
    confirmed : (rows, cols) ndarray of float64
        Stamp of the last scan with f1 = 1 on each cell [s], ``-inf`` before any.
    hits : (rows, cols) ndarray of uint16
        How many scans had f1 = 1 on each cell (at most `MAX_HITS`): a wall is hit by many,
        a glimpse of a wanderer by few.
    dropped : int
        How many cells `drop` has dropped since `reset`.

    """

    def __init__(self, shape):
        self.confirmed = np.full(shape, -math.inf)
        self.hits = np.zeros(shape, dtype=np.uint16)
        self.dropped = 0
        self._last_stamp = -math.inf

    def grow(self, growth, shape):
        """Follow the grid as it grows (``map_growth.GridGrowth``) to ``shape``."""
        self.confirmed = growth.embed(self.confirmed, shape, -math.inf)
        self.hits = growth.embed(self.hits, shape, 0)

    @property
    def nbytes(self):
        """Bytes held by the per-cell arrays."""
        return self.confirmed.nbytes + self.hits.nbytes

    def reset(self):
        """Forget every confirmation (a new goal keeps them: they describe the map)."""
        self.confirmed.fill(-math.inf)
        self.hits.fill(0)
        self.dropped = 0
        self._last_stamp = -math.inf

    def observe(self, window, stamp):
        """
        Record the hits of one update.

        Parameters
        ----------
        window : (slice, slice, (n_rows, n_cols) ndarray of uint8)
            The update's window and its FSM input (``LabelGrid.last_window``).
        stamp : float
            Time of the scan [s]. Time going backwards (a restarted simulator) moves every
            confirmation to ``stamp``: their ages are unknown, none is stale yet.

        """
        if stamp < self._last_stamp:
            finite = np.isfinite(self.confirmed)
            self.confirmed[finite] = stamp
        self._last_stamp = stamp
        rows, cols, inputs = window
        if inputs.size:
            hit = inputs == ScanInput.HIT
            self.confirmed[rows, cols][hit] = stamp
            counts = self.hits[rows, cols]
            counts[hit & (counts < MAX_HITS)] += 1

    def stale(self, labels, stamp, age):
        """
        Return the obstacle cells no hit has confirmed for ``age`` seconds or more.

        Parameters
        ----------
        labels : (rows, cols) ndarray of uint8
            The grid's labels.
        stamp : float
            Now [s].
        age : float
            Least time since the last confirming hit [s], > 0.

        Returns
        -------
        stale : (rows, cols) ndarray of bool

        """
        return blocked_mask(labels) & (stamp - self.confirmed >= age)

    def drop(self, grid, cells):
        """
        Drop obstacle cells: explored when once surely seen free, else non-explored.

        Parameters
        ----------
        grid : PlanningMap
            The map; its ``labels`` are written and ``labels_changed`` is called.
        cells : (N, 2) ndarray of int
            ``(row, col)`` cells to drop; those that are not obstacles are left as they are.

        Returns
        -------
        count : int
            How many cells were dropped.

        """
        cells = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
        if not cells.shape[0]:
            return 0
        rows, cols = cells[:, 0], cells[:, 1]
        obstacle = blocked_mask(grid.labels[rows, cols])
        rows, cols = rows[obstacle], cols[obstacle]
        if not rows.shape[0]:
            return 0
        seen_free = getattr(grid, 'seen_free', None)
        back = np.full(rows.shape[0], CellLabel.NON_EXPLORED, dtype=grid.labels.dtype)
        if seen_free is not None:
            back[seen_free[rows, cols]] = CellLabel.EXPLORED
        grid.labels[rows, cols] = back
        grid.labels_changed()
        self.dropped += int(rows.shape[0])
        return int(rows.shape[0])
