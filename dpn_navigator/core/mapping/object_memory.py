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
  a long one ever was. Hits of segments of one or two hits neither anchor nor list a cell
  (a wall seen at grazing incidence breaks into such segments, metres apart, and stays steady
  until a closer look anchors it), unless the caller passes them as small objects too
  (``LabelRule.object_memory_short_segments``: a wanderer glimpsed far off through a gap
  leaves only such segments). A provisional cell is forgotten
  once no hit has been within the safety radius for ``memory`` seconds, the latest scan does
  not see it (f1 = f2 = 0) and it lies more than twice the safety radius from the laser (the
  robot may turn in place beside it before it sees it): it goes back to explored when it was
  once surely seen free, else to non-explored.

A pillar is provisional too: out of view for that long it is forgotten, and found again as
soon as a scan sees it (a path through it turns the robot towards it first, and the laser looks
ahead). That is the price of forgetting a wanderer that was never seen to move.

Two compiled kernels per scan (``mark_near_hits``, ``forget_due`` of ``_kernels.object_memory``)
do it all, over the scan's window and the listed cells only; the numpy implementation it
replaced is the oracle of the tests (``test/reference/numpy_object_memory.py``), equal array
for array and list for list.

"""

import numpy as np

from .._kernels import object_memory as memory_kernels
from ..cell_label import CellLabel, ScanInput
from ..grid_geometry import squared_bound

#: Entries of the list of provisional cells at first; it doubles when full.
_INITIAL_LIST = 256

_EXPLORED = int(CellLabel.EXPLORED)
_NON_EXPLORED = int(CellLabel.NON_EXPLORED)
_STEADY = int(CellLabel.STEADY_OBSTACLE)
_NONE = int(ScanInput.NONE)


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
        self._deferred_marks = None
        self.anchored.fill(False)
        self._listed.fill(False)
        self._cells = np.empty(_INITIAL_LIST, dtype=np.int64)
        self._count = 0
        self.forgotten = 0

    def grow(self, growth, geometry):
        """
        Follow the label grid as it grows (``LabelGrid.grow``, after its ``settle``).

        Parameters
        ----------
        growth : map_growth.GridGrowth
            The rows and columns added on each side.
        geometry : GridGeometry
            The grown grid's.

        """
        self.settle()
        old_cols = self.geometry.cols
        self.anchored = growth.embed(self.anchored, geometry.shape, False)
        self._listed = growth.embed(self._listed, geometry.shape, False)
        self._cells[:self._count] = growth.remap(self._cells[:self._count], old_cols,
                                                 geometry.cols)
        self.geometry = geometry

    @property
    def nbytes(self):
        """Bytes held by the per-cell arrays."""
        return self.anchored.nbytes + self._listed.nbytes

    @property
    def provisional(self):
        """(N,) ndarray of int64: flat indices of the listed cells (some may be stale)."""
        return self._cells[:self._count].copy()

    def update(self, labels, seen_free, last_hit, window, hits_x, hits_y, long, small_object,
               laser_xy, safety_radius, stamp, defer_marks=False):
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
        defer_marks : bool
            Forget now, and leave the anchoring and listing by this scan's hits for `settle`
            (or the next update, which settles first); ``labels`` must not change in between.
            The labels are the same: the cells this scan anchors or lists lie within the
            safety radius of its hits, in view, and are not forgotten now either way. A listed
            cell this scan anchors is dropped from the list at the next update instead of this
            one (``provisional`` may hold it until then).

        Returns
        -------
        changed : (slice, slice) or None
            The box of the cells forgotten, None when none was.

        """
        self.settle()
        rows, cols, cell_input = window
        x0, y0 = self.geometry.origin
        safety_radius = float(safety_radius)
        # Copies: they may be read at `settle`.
        marks = (labels, rows.start, cols.start, cell_input.shape[0], cell_input.shape[1],
                 np.array(hits_x, dtype=np.float64), np.array(hits_y, dtype=np.float64),
                 np.array(long, dtype=bool), np.array(small_object, dtype=bool), safety_radius,
                 squared_bound(safety_radius))
        if defer_marks:
            self._deferred_marks = marks
        else:
            self._mark(marks)
        self._count, forgotten, row_lo, row_hi, col_lo, col_hi = memory_kernels.forget_due(
            labels, seen_free, last_hit, self.anchored, self._listed, self._cells, self._count,
            rows.start, cols.start, cell_input, x0, y0, self.geometry.resolution,
            float(laser_xy[0]), float(laser_xy[1]), 2.0 * safety_radius, float(stamp),
            self.memory)
        if not forgotten:
            return None
        self.forgotten += int(forgotten)
        return slice(row_lo, row_hi), slice(col_lo, col_hi)

    def settle(self):
        """Anchor and list by the hits of an update with ``defer_marks``; nothing when none."""
        if self._deferred_marks is not None:
            marks = self._deferred_marks
            self._deferred_marks = None
            self._mark(marks)

    def _mark(self, marks):
        """Anchor the cells near the long segments' hits, then list those near small objects."""
        x0, y0 = self.geometry.origin
        (labels, row0, col0, n_rows, n_cols, hits_x, hits_y, long, small_object, safety_radius,
         safety_bound) = marks
        self._cells, self._count = memory_kernels.mark_near_hits(
            labels, self.anchored, self._listed, self._cells, self._count, row0, col0, n_rows,
            n_cols, x0, y0, self.geometry.resolution, hits_x, hits_y, long, small_object,
            safety_radius, safety_bound)
