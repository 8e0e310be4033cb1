"""
The literal oracle of ``ChangeTracker``: the cells whose label changed, found by comparing.

A ``ChangeTracker`` promises a box that holds every cell changed since its last ``take``; this
twin keeps a copy of the labels and finds those cells by comparing every cell, so a test can
check the promise without trusting the tracker's own bookkeeping.

"""

import numpy as np


class ChangedCells:
    """A copy of a grid's labels; `take` returns the cells changed since the last call."""

    def __init__(self, labels):
        self._labels = labels
        self._copy = labels.copy()

    def take(self):
        """Return the changed cells as ``(rr, cc)`` arrays and copy the labels again."""
        rr, cc = np.nonzero(self._labels != self._copy)
        self._copy = self._labels.copy()
        return rr, cc


def assert_box_holds(box, changed):
    """
    Assert that a tracker's ``take()`` holds every changed cell.

    Parameters
    ----------
    box : (slice, slice, bool)
        ``ChangeTracker.take``'s answer.
    changed : (ndarray, ndarray)
        ``ChangedCells.take``'s answer, taken after the same update.

    """
    rows, cols, _ = box
    rr, cc = changed
    inside = ((rr >= rows.start) & (rr < rows.stop) & (cc >= cols.start) & (cc < cols.stop))
    assert inside.all(), (f'{np.count_nonzero(~inside)} changed cells outside the box '
                          f'{rows}, {cols}: first at {(rr[~inside][0], cc[~inside][0])}')
