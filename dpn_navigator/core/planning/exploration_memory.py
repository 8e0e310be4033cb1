"""
Exploration with memory: the extra A* cost of unknown space and of obstacles once seen.

The paper plans through non-explored cells as if they were free. A robot that does so heads
into any unexplored corridor that looks shorter, and, once the walls of an explored dead end
have been forgotten (object memory, the forget recovery, a stale cell dropped), into the same
dead end again. NavFn, Nav2's default planner, plans through unknown space (``allow_unknown``)
at a cost of 253 against 50 for a free cell: unknown is passable but dear. `ExplorationMemory`
gives the same to A*: an extra cost for entering a non-explored cell, and a larger one for a
non-explored cell that was once an obstacle (a wall forgotten, not a wall never seen), or
that lies on the continuation of a wall the laser saw at grazing incidence
(``mapping.wall_continuation``: a real laser returns nothing from it there).

"""

import numpy as np

from ..cell_label import blocked_mask, CellLabel


class ExplorationMemory:
    """
    The cells once seen as obstacles, and the extra cost of unknown cells from them.

    Parameters
    ----------
    shape : (int, int)
        The grid's ``(rows, cols)``.
    unknown_cost : float
        Extra cost of entering a non-explored cell [cells], >= 0.
    forgotten_cost : float
        Extra cost of entering a non-explored cell that was once an obstacle [cells], >= 0
        (instead of ``unknown_cost``).
    continued_cost : float, optional
        Extra cost of entering a non-explored cell on a wall's continuation [cells], >= 0
        (instead of the others when larger); 0 (the default) keeps no such cells.

    Attributes
    ----------
    once_blocked : (rows, cols) ndarray of bool
        Cells that were an obstacle after some update.
    continued : (rows, cols) ndarray of bool, or None
        Cells on a wall's continuation while non-explored (None with ``continued_cost`` 0).

    """

    def __init__(self, shape, unknown_cost, forgotten_cost, continued_cost=0.0):
        for name, value in (('unknown_cost', unknown_cost), ('forgotten_cost', forgotten_cost),
                            ('continued_cost', continued_cost)):
            if not (np.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        self.once_blocked = np.zeros(shape, dtype=bool)
        self.unknown_cost = float(unknown_cost)
        self.forgotten_cost = float(forgotten_cost)
        self.continued_cost = float(continued_cost)
        self.continued = np.zeros(shape, dtype=bool) if continued_cost > 0.0 else None

    def grow(self, growth, shape):
        """Follow the grid as it grows (``map_growth.GridGrowth``) to ``shape``."""
        self.once_blocked = growth.embed(self.once_blocked, shape, False)
        if self.continued is not None:
            self.continued = growth.embed(self.continued, shape, False)

    @property
    def nbytes(self):
        """Bytes held by the per-cell arrays."""
        return self.once_blocked.nbytes + (0 if self.continued is None else
                                           self.continued.nbytes)

    def continue_walls(self, labels, rows, cols):
        """
        Mark the non-explored cells among ``(rows, cols)`` as on a wall's continuation.

        Parameters
        ----------
        labels : (rows, cols) ndarray of uint8
            The grid's labels.
        rows, cols : (N,) ndarray of int
            Cells inside the grid (``wall_continuation.continued_walls``' points, as cells).

        """
        if self.continued is None or rows.size == 0:
            return
        unknown = labels[rows, cols] == CellLabel.NON_EXPLORED
        self.continued[rows[unknown], cols[unknown]] = True

    def observe(self, labels, window):
        """
        Record the obstacles of one update's window.

        Parameters
        ----------
        labels : (rows, cols) ndarray of uint8
            The grid's labels after the update.
        window : (slice, slice, ndarray)
            The update's window (``LabelGrid.last_window``; only its slices are read).

        """
        rows, cols = window[0], window[1]
        self.once_blocked[rows, cols] |= blocked_mask(labels[rows, cols])

    @property
    def max_cost(self):
        """Return the largest extra cost a cell can get here [cells]."""
        return max(self.unknown_cost, self.forgotten_cost, self.continued_cost)

    def cost(self, labels):
        """
        Return the extra cost of entering each cell [cells].

        Parameters
        ----------
        labels : (rows, cols) ndarray of uint8
            The grid's labels.

        Returns
        -------
        cost : (rows, cols) ndarray of float64
            ``forgotten_cost`` on non-explored cells once blocked, ``unknown_cost`` on the
            other non-explored cells, at least ``continued_cost`` on non-explored cells on a
            wall's continuation, 0 elsewhere.

        """
        unknown = labels == CellLabel.NON_EXPLORED
        cost = np.where(unknown, self.unknown_cost, 0.0)
        cost[unknown & self.once_blocked] = self.forgotten_cost
        if self.continued is not None:
            on = unknown & self.continued
            cost[on] = np.maximum(cost[on], self.continued_cost)
        return cost
