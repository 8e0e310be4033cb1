"""
The numpy object memory that the compiled one replaced, kept as the oracle of the tests.

``NumpyObjectMemory`` is ``object_memory.ObjectMemory`` of commit 1d9ead7: the cells near the
hits as f1's runs (``scan_features.hit_runs``) expanded into flat indices, the list and the
forgetting as array operations (``numpy_label_grid.NumpyExtrasLabelGrid`` runs it).

"""

from dpn_navigator.core.cell_label import CellLabel, ScanInput
from dpn_navigator.core.mapping.object_memory import ObjectMemory
import numpy as np
from scan_features import hit_runs


def run_cells(starts, ends):
    """
    Expand half-open runs into the positions they cover.

    Parameters
    ----------
    starts, ends : (R,) ndarray of int64
        Runs ``[start, end)``, ``end >= start``.

    Returns
    -------
    positions : (sum(ends - starts),) ndarray of int64
        Every position of every run, run after run (overlapping runs repeat positions).

    """
    lengths = ends - starts
    total = int(lengths.sum())
    offsets = np.cumsum(lengths) - lengths
    return np.arange(total, dtype=np.int64) + np.repeat(starts - offsets, lengths)


class NumpyObjectMemory(ObjectMemory):
    """
    ``ObjectMemory`` with the per-scan work of commit 1d9ead7, in numpy.

    The state (anchors, the list of provisional cells, the counter) and its reset are the
    compiled class's; ``update`` (same arguments and result) and its steps are the old array
    operations, so that the tests compare the two algorithms on the same state.
    """

    def update(self, labels, seen_free, last_hit, window, hits_x, hits_y, long, small_object,
               laser_xy, safety_radius, stamp, defer_marks=False):
        """
        Take one scan's hits into account, then forget the provisional cells due.

        ``defer_marks`` is taken and ignored: nothing was deferred then.
        """
        rows, cols, cell_input = window
        if cell_input.size and hits_x.shape[0]:
            self._anchor(rows, cols, hits_x[long], hits_y[long], safety_radius)
            self._list(labels, rows, cols, hits_x[small_object], hits_y[small_object],
                       safety_radius)
        return self._forget(labels, seen_free, last_hit, window, laser_xy,
                            2.0 * safety_radius, stamp)

    def _window_cells(self, rows, cols, hits_x, hits_y, safety_radius):
        """Flat grid indices of the window cells within the safety radius of the hits."""
        if not hits_x.shape[0]:
            return np.zeros(0, dtype=np.int64)
        starts, ends = hit_runs(self.geometry, rows, cols,
                                self.geometry.window_centres(rows, cols), hits_x, hits_y,
                                safety_radius)
        local = run_cells(starts, ends)
        n_cols = cols.stop - cols.start
        return ((local // n_cols + rows.start) * self.geometry.cols + local % n_cols
                + cols.start)

    def _anchor(self, rows, cols, hits_x, hits_y, safety_radius):
        """Anchor the cells near hits of long segments."""
        self.anchored.ravel()[self._window_cells(rows, cols, hits_x, hits_y,
                                                 safety_radius)] = True

    def _list(self, labels, rows, cols, hits_x, hits_y, safety_radius):
        """List the steady, unanchored cells near hits of small objects."""
        cells = np.unique(self._window_cells(rows, cols, hits_x, hits_y, safety_radius))
        cells = cells[(labels.ravel()[cells] == CellLabel.STEADY_OBSTACLE)
                      & ~self.anchored.ravel()[cells] & ~self._listed.ravel()[cells]]
        if not cells.shape[0]:
            return
        needed = self._count + cells.shape[0]
        if needed > self._cells.shape[0]:
            grown = np.empty(max(needed, 2 * self._cells.shape[0]), dtype=np.int64)
            grown[:self._count] = self._cells[:self._count]
            self._cells = grown
        self._cells[self._count:needed] = cells
        self._count = needed
        self._listed.ravel()[cells] = True

    def _forget(self, labels, seen_free, last_hit, window, laser_xy, keep_within, stamp):
        """Forget the listed cells that are due; drop those no longer provisional."""
        if not self._count:
            return None
        cells = self._cells[:self._count]
        flat_labels = labels.ravel()
        still = ((flat_labels[cells] == CellLabel.STEADY_OBSTACLE)
                 & ~self.anchored.ravel()[cells])
        rr, cc = np.divmod(cells, self.geometry.cols)
        rows, cols, cell_input = window
        out_of_view = np.ones(cells.shape[0], dtype=bool)
        inside = ((rr >= rows.start) & (rr < rows.stop) & (cc >= cols.start)
                  & (cc < cols.stop))
        out_of_view[inside] = (cell_input[rr[inside] - rows.start, cc[inside] - cols.start]
                               == ScanInput.NONE)
        centre_x, centre_y = self.geometry.cell_to_world(rr, cc)
        far = np.hypot(centre_x - laser_xy[0], centre_y - laser_xy[1]) > keep_within
        due = (still & out_of_view & far
               & (stamp - last_hit.ravel()[cells] >= self.memory))
        changed = None
        if due.any():
            gone = cells[due]
            flat_labels[gone] = np.where(seen_free.ravel()[gone], CellLabel.EXPLORED,
                                         CellLabel.NON_EXPLORED)
            self.forgotten += int(gone.shape[0])
            changed = (slice(int(rr[due].min()), int(rr[due].max()) + 1),
                       slice(int(cc[due].min()), int(cc[due].max()) + 1))
        keep = still & ~due
        self._listed.ravel()[cells[~keep]] = False
        kept = cells[keep]
        self._cells[:kept.shape[0]] = kept
        self._count = kept.shape[0]
        return changed
