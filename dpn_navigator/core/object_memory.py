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

Two compiled kernels per scan (`_mark_near_hits`, `_forget_due`) do it all, over the scan's
window and the listed cells only; the numpy implementation it replaced is the oracle of the tests
(``test/numpy_object_memory.py``), equal array for array and list for list.

"""

import math

import numpy as np

from .cell_label import CellLabel, ScanInput
from .jit import kernel
from .label_kernel import _box_end, _box_first, _disc_rows, _mark_discs, squared_bound

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
        self._count, forgotten, row_lo, row_hi, col_lo, col_hi = _forget_due(
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
        self._cells, self._count = _mark_near_hits(
            labels, self.anchored, self._listed, self._cells, self._count, row0, col0, n_rows,
            n_cols, x0, y0, self.geometry.resolution, hits_x, hits_y, long, small_object,
            safety_radius, safety_bound)


@kernel
def _mark_near_hits(labels, anchored, listed, cells, count, row0, col0, n_rows, n_cols, x0, y0,
                    resolution, hits_x, hits_y, long, small_object, safety_radius,
                    safety_bound):
    """
    Anchor the window cells near hits of long segments, then list the provisional ones.

    ``anchored`` and ``listed`` are updated in place; ``cells[:count]`` is the list of
    provisional cells (flat grid indices), grown into a new array when full. Returns
    ``(cells, count)``.
    """
    grid_cols = labels.shape[1]
    if n_rows * n_cols > 0 and hits_x.shape[0] > 0:
        hit_count = hits_x.shape[0]
        no_extent = np.zeros((0, 2), dtype=np.int64)
        _mark_discs(anchored[row0:row0 + n_rows, col0:col0 + n_cols], True, hits_x, hits_y,
                    hit_count, long, row0, col0, x0, y0, resolution, safety_radius,
                    safety_bound, no_extent)
        # List the steady, unanchored cells near hits of small objects, in grid order: the
        # columns [extent[i, 0], extent[i, 1]) of row i of the discs' box hold those of the
        # row. The box (window rows [box_row, box_row + box_rows), likewise columns) holds
        # every disc, with a cell to spare.
        box_row = n_rows
        box_row_end = 0
        box_col = n_cols
        box_col_end = 0
        for k in range(hit_count):
            if small_object[k]:
                first_row, end_row = _disc_rows(hits_y[k], safety_radius, row0, n_rows, y0,
                                                resolution)
                box_row = min(box_row, first_row)
                box_row_end = max(box_row_end, end_row)
                box_col = min(box_col, _box_first(col0, n_cols, x0, resolution,
                                                  hits_x[k] - safety_radius))
                box_col_end = max(box_col_end, _box_end(col0, n_cols, x0, resolution,
                                                        hits_x[k] + safety_radius))
        box_rows = max(box_row_end - box_row, 0)
        box_cols = max(box_col_end - box_col, 0)
        near = np.zeros((box_rows, box_cols), dtype=np.bool_)
        extent = np.empty((box_rows, 2), dtype=np.int64)
        extent[:, 0] = box_cols
        extent[:, 1] = 0
        if box_rows * box_cols > 0:
            _mark_discs(near, True, hits_x, hits_y, hit_count, small_object, row0 + box_row,
                        col0 + box_col, x0, y0, resolution, safety_radius, safety_bound,
                        extent)
        for i in range(box_rows):
            row = row0 + box_row + i
            for j in range(extent[i, 0], extent[i, 1]):
                col = col0 + box_col + j
                if (near[i, j] and labels[row, col] == _STEADY and not anchored[row, col]
                        and not listed[row, col]):
                    if count == cells.shape[0]:
                        grown = np.empty(2 * cells.shape[0], dtype=np.int64)
                        grown[:count] = cells[:count]
                        cells = grown
                    cells[count] = row * grid_cols + col
                    count += 1
                    listed[row, col] = True
    return cells, count


@kernel
def _forget_due(labels, seen_free, last_hit, anchored, listed, cells, count, row0, col0,
                cell_input, x0, y0, resolution, laser_x, laser_y, keep_within, stamp, memory):
    """
    Forget the listed cells that are due; drop those no longer provisional.

    ``labels`` and ``listed`` are updated in place, the kept cells compacted to the front of
    ``cells``. Returns ``(count, forgotten, row_lo, row_hi, col_lo, col_hi)``: the cells kept,
    how many this scan forgot and the half-open box around them.
    """
    n_rows, n_cols = cell_input.shape
    grid_cols = labels.shape[1]
    forgotten = 0
    row_lo = labels.shape[0]
    row_hi = 0
    col_lo = grid_cols
    col_hi = 0
    kept = 0
    for k in range(count):
        flat = cells[k]
        row = flat // grid_cols
        col = flat - row * grid_cols
        if labels[row, col] != _STEADY or anchored[row, col]:
            listed[row, col] = False
            continue
        i = row - row0
        j = col - col0
        # The conditions in the order of their cost; each is free of side effects.
        if (stamp - last_hit[row, col] >= memory
                and (not (0 <= i < n_rows and 0 <= j < n_cols) or cell_input[i, j] == _NONE)
                and math.hypot(x0 + (float(col) + 0.5) * resolution - laser_x,
                               y0 + (float(row) + 0.5) * resolution - laser_y) > keep_within):
            labels[row, col] = _EXPLORED if seen_free[row, col] else _NON_EXPLORED
            listed[row, col] = False
            forgotten += 1
            row_lo = min(row_lo, row)
            row_hi = max(row_hi, row + 1)
            col_lo = min(col_lo, col)
            col_hi = max(col_hi, col + 1)
            continue
        cells[kept] = flat
        kept += 1
    return kept, forgotten, row_lo, row_hi, col_lo, col_hi
