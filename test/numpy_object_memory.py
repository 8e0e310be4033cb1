"""
The numpy object memory that the compiled one replaced, kept as the oracle of the tests.

``NumpyObjectMemory`` is ``object_memory.ObjectMemory`` of commit 1d9ead7: the cells near the
hits as f1's runs (``scan_features.hit_runs``) expanded into flat indices, the list and the
forgetting as array operations (``numpy_label_grid.NumpyExtrasLabelGrid`` runs it).

"""

from dpn_navigator.core.cell_label import CellLabel, ScanInput
from dpn_navigator.core.scan_features import hit_runs
import numpy as np

#: Entries of the list of provisional cells at first; it doubles when full.
_INITIAL_LIST = 256


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


class NumpyObjectMemory:
    """
    Which steady cells only small objects explain, and when to forget them.

    Parameters
    ----------
    geometry : GridGeometry
        The grid's geometry.
    memory : float
        How long a provisional cell is kept without a hit, out of view [s], > 0.

    Attributes
    ----------
    anchored : (rows, cols) ndarray of bool
        Cells a hit of a long segment was once within the safety radius of.
    forgotten : int
        Cells forgotten since the last ``reset``.

    """

    def __init__(self, geometry, memory):
        if not memory > 0.0:
            raise ValueError(f'memory must be positive, got {memory!r} s')
        self.geometry = geometry
        self.memory = float(memory)
        self.anchored = np.zeros(geometry.shape, dtype=bool)
        self._listed = np.zeros(geometry.shape, dtype=bool)
        self.reset()

    def reset(self):
        """Forget every anchor and every listed cell."""
        self.anchored.fill(False)
        self._listed.fill(False)
        self._cells = np.empty(_INITIAL_LIST, dtype=np.int64)
        self._count = 0
        self.forgotten = 0

    @property
    def provisional(self):
        """(N,) ndarray of int64: flat indices of the listed cells (some may be stale)."""
        return self._cells[:self._count].copy()

    def update(self, labels, seen_free, last_hit, window, hits_x, hits_y, long, small_object,
               laser_xy, safety_radius, stamp):
        """
        Take one scan's hits into account, then forget the provisional cells due.

        Parameters
        ----------
        labels : (rows, cols) ndarray of uint8
            The grid's labels after the scan's update; forgotten cells are written here.
        seen_free : (rows, cols) ndarray of bool
            Cells once surely seen free.
        last_hit : (rows, cols) ndarray of float64
            Stamp of the last scan with f1 = 1 on each cell [s].
        window : (slice, slice, (n_rows, n_cols) ndarray of uint8)
            The update's window and its FSM input (``LabelGrid.last_window``).
        hits_x, hits_y : (K,) ndarray of float64
            The scan's hit points [m], map frame.
        long : (K,) ndarray of bool
            Hits of segments longer than ``compact_size`` (``MotionTracks.hit_long``).
        small_object : (K,) ndarray of bool
            Hits of small-object segments (``MotionTracks.hit_object``).
        laser_xy : (float, float)
            Laser position [m].
        safety_radius : float
            f1's ``r`` [m].
        stamp : float
            Time of the scan [s].

        Returns
        -------
        changed : (slice, slice) or None
            The box of the cells forgotten, None when none was.

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
