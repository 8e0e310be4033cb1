"""
The ``OccupancyGrid`` values of a label grid, kept in step with it box by box.

A published map holds one int8 value per cell (``OCCUPANCY_VALUE`` of its label). Converting a
scan's whole window and comparing it with the values sent before costs about 1.5 ns per cell
(1.2 ms for the 700,000 cells of a 0.05 m window), though a scan changes a few hundred labels at
most. `MapValues` keeps, beside the values, the labels they were made from: a window is first
compared label against label, a row at a time (a comparison the compiler turns into vector
instructions), and only the rows that differ are converted, written and taken into the box of
changed values.

"""

import numpy as np

from .._kernels import map_values as map_value_kernels
from ..cell_label import CellLabel, LABEL_DTYPE


class MapValues:
    """
    Map values of ``labels`` under ``table``, refreshed inside boxes; the changed box reported.

    Parameters
    ----------
    values : (H, W) ndarray of int8
        The values, written in place (e.g. a view of a message's ``array('b')``); set here to
        ``table[CellLabel.NON_EXPLORED]``, the value of a grid no scan has reached.
    table : (n,) ndarray of int8
        The value of each label (``OCCUPANCY_VALUE`` or a copy with another mobile value).

    Raises
    ------
    ValueError
        When ``values`` is not a 2-D int8 array or ``table`` not a 1-D int8 one holding
        ``CellLabel.NON_EXPLORED``.

    """

    def __init__(self, values, table):
        if not (isinstance(values, np.ndarray) and values.ndim == 2
                and values.dtype == np.int8):
            raise ValueError('values must be a 2-D ndarray of int8')
        table = np.ascontiguousarray(table)
        if table.ndim != 1 or table.dtype != np.int8 or table.shape[0] <= CellLabel.NON_EXPLORED:
            raise ValueError('table must be a 1-D int8 array with a value per label')
        self.values = values
        # A private, writable copy: numba compiles a kernel per array flag, so a read-only
        # table (a constant such as ``OCCUPANCY_VALUE``) would load a second specialisation
        # at the node's first map, after `warm_up_map_values`, with its native memory.
        self.table = table.copy()
        self._made_from = np.full(values.shape, CellLabel.NON_EXPLORED, dtype=LABEL_DTYPE)
        values[...] = table[CellLabel.NON_EXPLORED]

    def refresh(self, labels, rows, cols):
        """
        Rewrite the values of ``labels[rows, cols]``; return the box of values that changed.

        Parameters
        ----------
        labels : (H, W) ndarray of uint8
            The labels, of the values' shape.
        rows, cols : slice
            The box to refresh, inside the grid (may be empty); cells outside it keep their
            values whatever their labels.

        Returns
        -------
        rows, cols : slice
            The smallest box holding every value that changed (empty slices when none did).

        Raises
        ------
        ValueError
            When ``labels`` has another shape, or a label has no value in ``table`` (the
            values before it in the box are refreshed then).

        """
        labels = np.asarray(labels)
        if labels.shape != self.values.shape:
            raise ValueError(f'labels of shape {labels.shape} for a buffer of '
                             f'{self.values.shape}')
        labels = np.ascontiguousarray(labels, dtype=LABEL_DTYPE)
        row_lo, row_hi, _ = rows.indices(labels.shape[0])
        col_lo, col_hi, _ = cols.indices(labels.shape[1])
        if row_hi <= row_lo or col_hi <= col_lo:
            return slice(0, 0), slice(0, 0)
        box = map_value_kernels.refresh_values(labels, self._made_from, self.values, self.table,
                                               row_lo, row_hi, col_lo, col_hi)
        if box[0] < 0:
            raise ValueError(f'label {box[1]} has no map value (labels are 0..'
                             f'{self.table.shape[0] - 1})')
        if box[1] <= box[0]:
            return slice(0, 0), slice(0, 0)
        return slice(box[0], box[1]), slice(box[2], box[3])


def warm_up_map_values():
    """Compile (or load) the kernel with a tiny call."""
    values = np.full((2, 2), -1, dtype=np.int8)
    map_values = MapValues(values, np.array([-1, 0, 100, 99], dtype=np.int8))
    map_values.refresh(np.ones((2, 2), dtype=LABEL_DTYPE), slice(0, 2), slice(0, 2))
