"""
Object memory: steady obstacles that only small objects explain are forgotten out of view.

A wanderer first seen where nothing was known, or where space was never *surely* seen free, is
labelled a steady obstacle, and stays one until it is seen to move (``motion_tracks``) or the
laser sees its cells empty. One that walks out of view before either leaves a steady *ghost*
for good, and so does one that stood still while the robot passed.

So the grid tells two kinds of steady cell apart, by the scan segments
(``moving_objects.scan_segments``) whose hits have been within the safety radius of it:

- **anchored**: a hit of a *long* segment (its extent along the hits more than
  ``compact_size``, 1 m: a wall, or an object standing by one) was once within the safety
  radius of it. It is kept, as the paper keeps every steady cell;
- **provisional**: a hit of a small-object segment (at most ``compact_size`` long, with at
  least ``OBJECT_MIN_HITS`` hits: a wanderer, free-standing or partly hidden, a pillar, a short
  piece of wall seen between nearer things) was within the safety radius of it, and no hit of
  a long one ever was. Hits of segments of one or two hits neither anchor nor list a cell: a
  wall seen at grazing incidence breaks into such segments, metres apart, and stays steady
  until a closer look anchors it. A provisional cell is forgotten
  once no hit has been within the safety radius for ``memory`` seconds, the latest scan does
  not see it (f1 = f2 = 0) and it lies more than twice the safety radius from the laser (the
  robot may turn in place beside it before it sees it): it goes back to explored when it was
  once surely seen free, else to non-explored.

A pillar is provisional too: out of view for that long it is forgotten, and found again as
soon as a scan sees it (a path through it turns the robot towards it first, and the laser looks
ahead). That is the price of forgetting a wanderer that was never seen to move.

"""

import numpy as np

from .cell_label import CellLabel, ScanInput
from .scan_features import hit_runs

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


class ObjectMemory:
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
