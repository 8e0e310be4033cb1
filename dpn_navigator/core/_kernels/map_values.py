"""
The map's kernel: the OccupancyGrid values of the changed box refreshed.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import numpy as np

from .jit import kernel


@kernel
def refresh_values(labels, made_from, values, table, row_lo, row_hi, col_lo, col_hi):
    """
    Bring ``values[rows, cols]`` up to ``table[labels]``; return the box of changed values.

    ``made_from`` holds the label each value was made from (``values == table[made_from]``
    everywhere), so a cell whose label equals it keeps its value. Returns the box
    ``(first row, last row + 1, first col, last col + 1)`` of the values that changed, empty
    (``row_hi <= row_lo``) when none did, or ``(-1, label, 0, 0)`` at a label outside
    ``table`` (cells before it are refreshed already).
    """
    n_values = table.shape[0]
    box_row_lo, box_row_hi = row_hi, row_lo
    box_col_lo, box_col_hi = col_hi, col_lo
    for r in range(row_lo, row_hi):
        label_row = labels[r, col_lo:col_hi]
        made_row = made_from[r, col_lo:col_hi]
        differ = np.uint8(0)
        for c in range(label_row.shape[0]):
            differ |= label_row[c] ^ made_row[c]
        if differ == 0:
            continue
        value_row = values[r, col_lo:col_hi]
        for c in range(label_row.shape[0]):
            label = label_row[c]
            if label == made_row[c]:
                continue
            if label >= n_values:
                return -1, np.int64(label), 0, 0
            made_row[c] = label
            value = table[label]
            if value == value_row[c]:
                continue                 # another label of the same value (mobile_value 100)
            value_row[c] = value
            box_row_lo = min(box_row_lo, r)
            box_row_hi = max(box_row_hi, r + 1)
            box_col_lo = min(box_col_lo, col_lo + c)
            box_col_hi = max(box_col_hi, col_lo + c + 1)
    return box_row_lo, box_row_hi, box_col_lo, box_col_hi
