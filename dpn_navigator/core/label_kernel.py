"""
The compiled label update: one scan folded into a window of the grid, in place.

`scan_update` does, for the window the scan can reach, everything ``LabelGrid.update`` does
per cell: f2 by even-odd crossings along each row, f1 as the cells within the safety radius of
each hit, the FSM, and the dpn ``LabelRule`` (conservative free space, object-level
relabelling, the hit clock of the ghost expiry). `expire_listed` is the ghost expiry itself,
visiting only the cells listed as mobile, not the whole grid.

Every test is the floating-point expression of the literal twin in the tests
(``test/literal_reference.py``), evaluated in the same order, so the result equals it cell for
cell:

- f1 and every disc: ``dx * dx + dy * dy <= bound`` with ``bound`` from
  ``scan_features.squared_radius_bound`` (the same answers as ``sqrt(...) <= r``);
- f2: edge ``(a, b)`` crosses the ray from centre ``(x, y)`` along +x when
  ``(y_a > y) != (y_b > y)`` and ``x < x_a + (x_b - x_a) * (y - y_a) / (y_b - y_a)``;
- an edge band as in ``free_evidence``: ``0 <= dot <= length2`` and
  ``abs(cross) / sqrt(length2) <= radius``.

The work grows with the beams and the window's cells, never with the grid.

"""

import functools
import math

import numpy as np

from .cell_label import CellLabel, ScanInput, TRANSITION
from .jit import kernel
from .scan_features import squared_radius_bound

# TRANSITION flattened for one lookup with index (label << 2) | scan_input.
_TRANSITION_BY_CODE = np.zeros(4 * len(CellLabel), dtype=np.uint8)
for _label in CellLabel:
    for _scan_input in ScanInput:
        _TRANSITION_BY_CODE[(_label << 2) | _scan_input] = TRANSITION[_label, _scan_input]

# The update writes f2 cells as explored and leaves cells without input alone, under every
# rule, without looking the table up: the paper's FSM says so for every label.
if not ((TRANSITION[:, ScanInput.INSIDE] == CellLabel.EXPLORED).all()
        and (TRANSITION[:, ScanInput.NONE] == np.arange(len(CellLabel))).all()):
    raise ImportError('label_kernel expects f2 cells to become explored and cells without '
                      'input to keep their label (cell_label.TRANSITION)')

_NON_EXPLORED = int(CellLabel.NON_EXPLORED)
_EXPLORED = int(CellLabel.EXPLORED)
_STEADY = int(CellLabel.STEADY_OBSTACLE)
_MOBILE = int(CellLabel.MOBILE_OBSTACLE)
_NONE = int(ScanInput.NONE)
_INSIDE = int(ScanInput.INSIDE)
_HIT = int(ScanInput.HIT)
#: `scan_update` without extra moving hits.
_NO_HITS = np.zeros(0, dtype=bool)


@functools.lru_cache(maxsize=64)
def squared_bound(radius):
    """Return ``squared_radius_bound(radius)``, remembered: a grid's radii never change."""
    return squared_radius_bound(radius)


#: Slack of the rows searched around a disc or an edge band [m]: far above the rounding of
#: ``dy`` for coordinates up to ``MAX_POSE_COORDINATE`` plus a laser's range.
_BOX_SLACK = 1e-6


@kernel
def _count_below(first, count, origin, resolution, value):
    """
    Count the centres ``origin + (first + k + 0.5) * resolution``, k < count, below ``value``.

    numpy's ``searchsorted(centres, value, 'left')``: an estimate from the division, settled
    with the exact comparisons.
    """
    estimate = np.floor((value - origin) / resolution - 0.5) + 1.0 - first
    k = int(min(max(estimate, 0.0), float(count)))
    while k > 0 and origin + (float(first + k - 1) + 0.5) * resolution >= value:
        k -= 1
    while k < count and origin + (float(first + k) + 0.5) * resolution < value:
        k += 1
    return k


@kernel
def _box_first(first, count, origin, resolution, value):
    """
    Return a first index in ``[0, count]`` whose centre may lie at or above ``value``.

    The centres are ``origin + (first + k + 0.5) * resolution``; the index has a cell to
    spare for rounding.
    """
    estimate = np.floor((value - origin) / resolution - 0.5) - first
    return int(min(max(estimate, 0.0), float(count)))


@kernel
def _box_end(first, count, origin, resolution, value):
    """One past the last index in ``[0, count]`` whose centre may lie at or below ``value``."""
    estimate = np.floor((value - origin) / resolution - 0.5) + 2.0 - first
    return int(min(max(estimate, 0.0), float(count)))


@kernel
def _disc_span(first_col, end_col, col0, x0, resolution, px, dy2, bound):
    """
    Shrink ``[first_col, end_col)`` to the columns whose centre passes ``dx*dx + dy2 <= bound``.

    Those columns are contiguous (every step of the expression is monotone in ``|dx|``), and
    the given range must hold them all; returns the half-open ``(first, end)``, maybe empty.
    """
    while first_col < end_col:
        dx = (x0 + (float(col0 + first_col) + 0.5) * resolution) - px
        if dx * dx + dy2 <= bound:
            break
        first_col += 1
    while end_col > first_col:
        dx = (x0 + (float(col0 + end_col - 1) + 0.5) * resolution) - px
        if dx * dx + dy2 <= bound:
            break
        end_col -= 1
    return first_col, end_col


@kernel
def _disc_rows(py, radius, row0, n_rows, y0, resolution):
    """Window rows ``[first, end)`` whose centres may lie within ``radius`` of ``py``."""
    reach = radius + _BOX_SLACK * (1.0 + 1e-6 * abs(py))
    return (_count_below(row0, n_rows, y0, resolution, py - reach),
            _count_below(row0, n_rows, y0, resolution, py + reach))


@kernel
def _disc_row_span(px, dy2, bound, col0, n_cols, x0, resolution):
    """
    Return the half-open window columns ``(first, end)`` of a disc's run in one row.

    ``dy2`` is the row's ``dy * dy``: the columns whose centre passes ``dx*dx + dy2 <= bound``
    (maybe none).
    """
    if dy2 > bound:
        return 0, 0
    half = math.sqrt(bound - dy2)
    return _disc_span(_box_first(col0, n_cols, x0, resolution, px - half),
                      _box_end(col0, n_cols, x0, resolution, px + half),
                      col0, x0, resolution, px, dy2, bound)


@kernel
def _disc_spans(px, py, radius, bound, row0, n_rows, col0, n_cols, x0, y0, resolution, spans):
    """
    Find the window cells within ``radius`` of ``(px, py)``, one run of columns per row.

    ``spans[i - first_row]`` becomes the half-open columns ``(first, end)`` of window row
    ``i`` whose centre passes ``dx * dx + dy * dy <= bound`` (maybe empty); returns
    ``(first_row, end_row)``. ``spans`` needs ``n_rows`` rows.

    The rows at and above ``py`` have ``dy >= 0`` growing row by row, those below ``dy < 0``
    shrinking, and the expression is monotone in ``dy * dy`` (rounding included): so a row's
    run lies within that of its neighbour nearer to ``py``, and is found by shrinking that one.
    Only the row nearest ``py`` on each side is searched from the square root.
    """
    first_row, end_row = _disc_rows(py, radius, row0, n_rows, y0, resolution)
    split = min(max(_count_below(row0, n_rows, y0, resolution, py), first_row), end_row)
    for step in (1, -1):
        first = 0
        end = -1                                    # -1: no run found on this side yet
        i = split if step == 1 else split - 1
        while first_row <= i < end_row:
            dy = (y0 + (float(row0 + i) + 0.5) * resolution) - py
            dy2 = dy * dy
            if end < 0:
                first, end = _disc_row_span(px, dy2, bound, col0, n_cols, x0, resolution)
            else:
                first, end = _disc_span(first, end, col0, x0, resolution, px, dy2, bound)
            spans[i - first_row, 0] = first
            spans[i - first_row, 1] = end
            i += step
    return first_row, end_row


#: Discs of a radius up to this many cells are marked from a box of cells around them
#: (`_mark_small_disc`), larger ones by `_disc_spans`.
_ROW_BY_ROW_CELLS = 3.0


@kernel
def _disc_box(px, py, row0, n_rows, col0, n_cols, x0, y0, resolution, reach):
    """
    Return the window cells ``(first_row, end_row, first_col, end_col)`` a disc may hold.

    Those within ``reach`` cells of the cell holding ``(px, py)``, clipped to the window's
    ``n_rows`` x ``n_cols``: ``reach = ceil(radius / resolution) + 1`` holds every cell whose
    centre lies within ``radius`` (the + 1 for the rounding of that cell's index).
    """
    centre_col = int(math.floor((px - x0) / resolution)) - col0
    centre_row = int(math.floor((py - y0) / resolution)) - row0
    return (max(centre_row - reach, 0), min(centre_row + reach + 1, n_rows),
            max(centre_col - reach, 0), min(centre_col + reach + 1, n_cols))


@kernel
def _small_disc_reach(radius, resolution):
    """Return `_disc_box`'s ``reach`` for discs of ``radius`` [m] (0 for large ones)."""
    if radius <= _ROW_BY_ROW_CELLS * resolution:
        return int(math.ceil(radius / resolution)) + 1
    return 0


@kernel
def _mark_small_disc(mark, value, px, py, row0, col0, x0, y0, resolution, bound, reach,
                     extent, dx2):
    """
    Set ``mark`` to ``value`` on the window cells whose centre passes ``dx*dx + dy*dy <= bound``.

    The cells tested are those of `_disc_box`. Each row's run is shrunk from the box's
    ends with the exact test, ``dx * dx`` taken once per column (``dx2``, at least
    ``2 * reach + 1`` long). ``extent`` as in `_mark_discs`.
    """
    n_rows, n_cols = mark.shape
    first_row, end_row, first_col, end_col = _disc_box(
        px, py, row0, n_rows, col0, n_cols, x0, y0, resolution, reach)
    if first_col >= end_col or first_row >= end_row:
        return
    for j in range(first_col, end_col):
        dx = (x0 + (float(col0 + j) + 0.5) * resolution) - px
        dx2[j - first_col] = dx * dx
    for i in range(first_row, end_row):
        dy = (y0 + (float(row0 + i) + 0.5) * resolution) - py
        dy2 = dy * dy
        if dy2 > bound:
            continue
        first = first_col
        end = end_col
        while first < end and dx2[first - first_col] + dy2 > bound:
            first += 1
        while end > first and dx2[end - 1 - first_col] + dy2 > bound:
            end -= 1
        if first >= end:
            continue
        for j in range(first, end):
            mark[i, j] = value
        if extent.shape[0]:
            extent[i, 0] = min(extent[i, 0], first)
            extent[i, 1] = max(extent[i, 1], end)


@kernel
def _mark_discs(mark, value, xs, ys, count, selected, row0, col0, x0, y0, resolution, radius,
                bound, extent):
    """
    Set ``mark`` to ``value`` on the window cells within ``radius`` of the selected points.

    ``mark`` is the window's ``(n_rows, n_cols)`` array, its cell ``(0, 0)`` the grid's
    ``(row0, col0)``; the first ``count`` points count where ``selected`` is True (all when
    it is empty). Each disc is marked as one run of cells per row. When ``extent`` has rows,
    ``extent[i]`` is widened to hold the columns marked in row ``i``.
    """
    n_rows, n_cols = mark.shape
    reach = _small_disc_reach(radius, resolution)
    dx2 = np.empty(2 * reach + 1)
    spans = np.empty((0 if reach else n_rows, 2), dtype=np.int64)
    for k in range(count):
        if selected.shape[0] and not selected[k]:
            continue
        px = xs[k]
        py = ys[k]
        if reach:
            _mark_small_disc(mark, value, px, py, row0, col0, x0, y0, resolution, bound, reach,
                             extent, dx2)
            continue
        first_row, end_row = _disc_spans(px, py, radius, bound, row0, n_rows, col0, n_cols,
                                         x0, y0, resolution, spans)
        for i in range(first_row, end_row):
            first = spans[i - first_row, 0]
            end = spans[i - first_row, 1]
            if first >= end:
                continue
            mark[i, first:end] = value
            if extent.shape[0]:
                extent[i, 0] = min(extent[i, 0], first)
                extent[i, 1] = max(extent[i, 1], end)


@kernel
def _fill_inside(cell_input, row0, col0, x0, y0, resolution, vertices_x, vertices_y, extent):
    """
    Set ``cell_input`` (all 0) to 1 (f2) on window centres inside the polygon.

    Each edge toggles the parity of the centres left of where it crosses a row; sorted, a
    row's crossings bound its runs of inside centres, which are filled whole. ``extent[i]``
    becomes the columns ``[first, end)`` filled in row ``i``.
    """
    n_rows, n_cols = cell_input.shape
    edges = vertices_x.shape[0] - 1
    # Rows with min(ya, yb) <= y < max(ya, yb): exactly (ya > y) != (yb > y).
    first_rows = np.empty(edges, dtype=np.int64)
    end_rows = np.empty(edges, dtype=np.int64)
    starts = np.zeros(n_rows + 1, dtype=np.int64)
    for a in range(edges):
        ya = vertices_y[a]
        yb = vertices_y[a + 1]
        first_rows[a] = _count_below(row0, n_rows, y0, resolution, min(ya, yb))
        end_rows[a] = _count_below(row0, n_rows, y0, resolution, max(ya, yb))
        for i in range(first_rows[a], end_rows[a]):
            starts[i + 1] += 1
    for i in range(n_rows):
        starts[i + 1] += starts[i]
    filled = starts[:n_rows].copy()
    crossings = np.empty(starts[n_rows], dtype=np.int64)
    for a in range(edges):
        xa = vertices_x[a]
        ya = vertices_y[a]
        xb = vertices_x[a + 1]
        yb = vertices_y[a + 1]
        for i in range(first_rows[a], end_rows[a]):
            y = y0 + (float(row0 + i) + 0.5) * resolution
            x_cross = xa + (xb - xa) * (y - ya) / (yb - ya)
            # The centres left of the crossing (x < x_cross) see it on their ray.
            crossings[filled[i]] = _count_below(col0, n_cols, x0, resolution, x_cross)
            filled[i] += 1
    for i in range(n_rows):
        row_crossings = crossings[starts[i]:starts[i + 1]]
        for k in range(1, row_crossings.shape[0]):          # insertion sort: rows hold few
            value = row_crossings[k]
            m = k - 1
            while m >= 0 and row_crossings[m] > value:
                row_crossings[m + 1] = row_crossings[m]
                m -= 1
            row_crossings[m + 1] = value
        # An even number per row: inside between the 1st and 2nd, the 3rd and 4th, ...
        for k in range(0, row_crossings.shape[0] - 1, 2):
            first = row_crossings[k]
            end = row_crossings[k + 1]
            if first < end:
                cell_input[i, first:end] = _INSIDE
                extent[i, 0] = min(extent[i, 0], first)
                extent[i, 1] = max(extent[i, 1], end)


@kernel
def _mark_band_rows(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2, length,
                    radius, first_row, end_row, box_first_col, box_end_col, narrow):
    """
    Mark the band cells of edge ``a + t e`` in window rows and columns of a box.

    Sets ``mark`` on the cells of rows ``[first_row, end_row)`` and columns
    ``[box_first_col, box_end_col)`` whose centre lies in the band. With ``narrow``, each
    row's columns are first narrowed to those near the band (worth it when the box is wide).
    """
    n_cols = mark.shape[1]
    # Half a cell more than the rounding of the band's ends below can move them.
    slack = 0.5 * resolution
    for i in range(first_row, end_row):
        cy = y0 + (float(row0 + i) + 0.5) * resolution
        first_col = box_first_col
        end_col = box_end_col
        if narrow:
            # The band's columns in this row, solved for cx - xa from 0 <= dot <= length2 and
            # |cross| <= radius * length (when the edge's direction has a component along x,
            # resp. y; otherwise that condition does not depend on cx).
            low = -math.inf
            high = math.inf
            along = (cy - ya) * ey
            if ex != 0.0:
                u_1 = -along / ex
                u_2 = (length2 - along) / ex
                low = max(low, min(u_1, u_2))
                high = min(high, max(u_1, u_2))
            if ey != 0.0:
                across = (cy - ya) * ex
                v_1 = (across - radius * length) / ey
                v_2 = (across + radius * length) / ey
                low = max(low, min(v_1, v_2))
                high = min(high, max(v_1, v_2))
            if high + slack < low - slack:
                continue
            first_col = max(first_col,
                            _box_first(col0, n_cols, x0, resolution, xa + low - slack))
            end_col = min(end_col, _box_end(col0, n_cols, x0, resolution, xa + high + slack))
        # The band's cells in a row are contiguous (dot and cross are monotone along the
        # row): shrink the candidates to them from both ends, then mark them all.
        while first_col < end_col and not _in_band(
                x0 + (float(col0 + first_col) + 0.5) * resolution, cy, xa, ya, ex, ey,
                length2, length, radius):
            first_col += 1
        while end_col > first_col and not _in_band(
                x0 + (float(col0 + end_col - 1) + 0.5) * resolution, cy, xa, ya, ex, ey,
                length2, length, radius):
            end_col -= 1
        mark[i, first_col:end_col] = True


@kernel
def _mark_edge_band(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2, length,
                    radius):
    """Set ``mark`` on the window's cells within ``radius`` of edge ``a + t e``."""
    n_rows, n_cols = mark.shape
    reach = radius + _BOX_SLACK * (1.0 + 1e-6 * abs(ya))
    # Rows with centres in [y_low - reach, y_high + reach] (the + 1: one equal to it).
    first_row = _count_below(row0, n_rows, y0, resolution, min(ya, ya + ey) - reach)
    end_row = min(_count_below(row0, n_rows, y0, resolution, max(ya, ya + ey) + reach) + 1,
                  n_rows)
    first_col = _box_first(col0, n_cols, x0, resolution, min(xa, xa + ex) - reach)
    end_col = _box_end(col0, n_cols, x0, resolution, max(xa, xa + ex) + reach)
    _mark_band_rows(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2, length,
                    radius, first_row, end_row, first_col, end_col, end_col - first_col > 8)


@kernel
def _mark_edge_bands(mark, row0, col0, x0, y0, resolution, vertices_x, vertices_y, radius):
    """Set ``mark`` on the window's cells within ``radius`` of some polygon edge."""
    for a in range(vertices_x.shape[0] - 1):
        xa = vertices_x[a]
        ya = vertices_y[a]
        ex = vertices_x[a + 1] - xa
        ey = vertices_y[a + 1] - ya
        length2 = ex * ex + ey * ey
        if length2 > 0.0:
            _mark_edge_band(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2,
                            math.sqrt(length2), radius)


#: How far [m] below the radius a point's distance from an edge's end may lie and still fail
#: the disc test of the radius: far above the rounding of the test.
_COVER_SLACK = 1e-6


@kernel
def _mark_uncovered_edge_bands(mark, row0, col0, x0, y0, resolution, vertices_x, vertices_y,
                               radius):
    """
    Mark the band cells of `_mark_edge_bands` that are not within ``radius`` of an edge's end.

    Sets ``mark`` on every such cell and on no cell outside the bands (some band cells near
    the ends may be marked too). For the update's free evidence, where every vertex's disc of
    ``radius`` is marked (or, around a hit, made f1) besides: a band cell within it needs no
    mark of its own. A point of the band of an edge of length ``L`` that is farther than
    ``radius`` from both ends is at least ``sqrt(radius**2 - L**2 / 4)`` from the edge's
    line; for an edge no longer than ``radius`` these points lie in two thin strips along
    the edge, and only the cells whose centre lies in a strip's box are tested. (The boxes
    hold the strips with ``_COVER_SLACK`` to spare, so a centre on a box's side is no band
    cell beyond the ends.)
    """
    n_rows, n_cols = mark.shape
    # Reciprocals for the boxes only, whose slack is far above their rounding.
    per_cell = 1.0 / resolution
    for a in range(vertices_x.shape[0] - 1):
        xa = vertices_x[a]
        ya = vertices_y[a]
        ex = vertices_x[a + 1] - xa
        ey = vertices_y[a + 1] - ya
        length2 = ex * ex + ey * ey
        if not length2 > 0.0:
            continue
        length = math.sqrt(length2)
        if length > radius:
            _mark_edge_band(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2,
                            length, radius)
            continue
        slack = _COVER_SLACK * (1.0 + 1e-6 * (abs(xa) + abs(ya)))
        inner = radius - slack
        offset_low = math.sqrt(max(inner * inner - 0.25 * length2, 0.0)) - slack
        offset_high = radius + slack
        # Unit vectors along the edge and across it.
        per_length = 1.0 / length
        ux = ex * per_length
        uy = ey * per_length
        for side in (1.0, -1.0):
            x_low = y_low = math.inf
            x_high = y_high = -math.inf
            for t in (-slack, length + slack):
                for offset in (offset_low, offset_high):
                    px = xa + t * ux - side * offset * uy
                    py = ya + t * uy + side * offset * ux
                    x_low = min(x_low, px)
                    x_high = max(x_high, px)
                    y_low = min(y_low, py)
                    y_high = max(y_high, py)
            # The cells whose centre lies in the strip's box (often none: a strip is thin; a
            # box clear of every row's or every column's centre by far more than rounding is
            # passed over).
            if (_clear_of_centres(y_low, y_high, y0, per_cell)
                    or _clear_of_centres(x_low, x_high, x0, per_cell)):
                continue
            first_row = _count_below(row0, n_rows, y0, resolution, y_low)
            end_row = _count_below(row0, n_rows, y0, resolution, y_high)
            if first_row == end_row:
                continue
            first_col = _count_below(col0, n_cols, x0, resolution, x_low)
            end_col = _count_below(col0, n_cols, x0, resolution, x_high)
            if first_col < end_col:
                _mark_band_rows(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2,
                                length, radius, first_row, end_row, first_col, end_col, False)


@kernel
def _clear_of_centres(low, high, origin, per_cell):
    """
    Tell whether no centre ``origin + (k + 0.5) / per_cell`` lies near ``[low, high]``.

    ``per_cell`` is ``1 / resolution``; near: within a millionth of a cell, far above the
    rounding of these products.
    """
    return (math.floor((high - origin) * per_cell - 0.5 + 1e-6)
            < math.ceil((low - origin) * per_cell - 0.5 - 1e-6))


@kernel
def _in_band(cx, cy, xa, ya, ex, ey, length2, length, radius):
    """Tell whether ``(cx, cy)`` projects onto edge ``a + t e`` within ``radius`` of it."""
    dot = (cx - xa) * ex + (cy - ya) * ey
    cross = (cx - xa) * ey - (cy - ya) * ex
    return 0.0 <= dot <= length2 and abs(cross) / length <= radius


@kernel
def _moving_hits(hits_x, hits_y, hit_beams, evidence, segment_gap, object_size, min_hits,
                 laser_x, laser_y, beam_count):
    """``moving_objects.moving_object_hits`` as a loop, with the same arithmetic."""
    count = hits_x.shape[0]
    moving = np.zeros(count, dtype=np.bool_)
    segment = np.zeros(count, dtype=np.int64)
    arc = np.zeros(count, dtype=np.float64)
    for k in range(1, count):
        dx = hits_x[k] - hits_x[k - 1]
        dy = hits_y[k] - hits_y[k - 1]
        step = math.sqrt(dx * dx + dy * dy)
        cut = step > segment_gap or hit_beams[k] - hit_beams[k - 1] != 1
        segment[k] = segment[k - 1] + (1 if cut else 0)
        arc[k] = arc[k - 1] + step
    # Evidence counts for nothing in a free-standing segment of fewer than min_hits hits.
    if min_hits > 1 and count > 0:
        evidence = evidence.copy()
        start = 0
        for k in range(1, count + 1):
            if k == count or segment[k] != segment[k - 1]:
                if k - start < min_hits and _free_standing(
                        hits_x, hits_y, hit_beams, start, k, laser_x, laser_y, beam_count):
                    evidence[start:k] = False
                start = k
    # The nearest hit with evidence at or before each hit, then at or after it.
    last = -1
    for k in range(count):
        if evidence[k]:
            last = k
        if last >= 0 and segment[last] == segment[k] and arc[k] - arc[last] <= object_size:
            moving[k] = True
    last = -1
    for k in range(count - 1, -1, -1):
        if evidence[k]:
            last = k
        if last >= 0 and segment[last] == segment[k] and arc[last] - arc[k] <= object_size:
            moving[k] = True
    return moving


@kernel
def _free_standing(hits_x, hits_y, hit_beams, start, stop, laser_x, laser_y, beam_count):
    """
    Tell whether the segment of hits ``start:stop`` stands free: both its ends are open.

    An end is open when the beam just outside it exists and returns nothing, or a hit farther
    from the laser than the end (``motion_tracks``' open sides, the same arithmetic).
    """
    count = hits_x.shape[0]
    distance_first = math.hypot(hits_x[start] - laser_x, hits_y[start] - laser_y)
    distance_last = math.hypot(hits_x[stop - 1] - laser_x, hits_y[stop - 1] - laser_y)
    if start > 0 and hit_beams[start - 1] == hit_beams[start] - 1:
        open_before = math.hypot(hits_x[start - 1] - laser_x,
                                 hits_y[start - 1] - laser_y) > distance_first
    else:
        open_before = hit_beams[start] > 0
    if stop < count and hit_beams[stop] == hit_beams[stop - 1] + 1:
        open_after = math.hypot(hits_x[stop] - laser_x,
                                hits_y[stop] - laser_y) > distance_last
    else:
        open_after = hit_beams[stop - 1] < beam_count - 1
    return open_before and open_after


@kernel
def _hit_evidence(seen_free, hits_x, hits_y, x0, y0, resolution, radius, bound):
    """Tell for each hit whether a cell once surely seen free lies within ``radius``."""
    rows, cols = seen_free.shape
    count = hits_x.shape[0]
    evidence = np.zeros(count, dtype=np.bool_)
    # Every disc searched in its box, small or not: a box row is read whole, without branches.
    reach = int(math.ceil(radius / resolution)) + 1
    dx2 = np.empty(2 * reach + 1)
    for k in range(count):
        evidence[k] = _disc_holds(seen_free, hits_x[k], hits_y[k], x0, y0, resolution, bound,
                                  reach, dx2)
    return evidence


@kernel
def _disc_holds(cells, px, py, x0, y0, resolution, bound, reach, dx2):
    """
    Tell whether a True cell of ``cells`` passes ``dx*dx + dy*dy <= bound`` around a point.

    The cells searched are those of `_disc_box` with ``reach``, a row at a time: each row's
    test is or-ed over the whole row of the box, which runs on vectors. ``dx2`` holds at
    least ``2 * reach + 1`` values.
    """
    first_row, end_row, first_col, end_col = _disc_box(
        px, py, 0, cells.shape[0], 0, cells.shape[1], x0, y0, resolution, reach)
    for j in range(first_col, end_col):
        dx = (x0 + (float(j) + 0.5) * resolution) - px
        dx2[j - first_col] = dx * dx
    for i in range(first_row, end_row):
        dy = (y0 + (float(i) + 0.5) * resolution) - py
        dy2 = dy * dy
        if dy2 > bound:
            continue
        found = False
        for j in range(first_col, end_col):
            found |= cells[i, j] & (dx2[j - first_col] + dy2 <= bound)
        if found:
            return True
    return False


@kernel
def _scan_points(ranges, x, y, yaw, angle_min, angle_increment, range_min, range_max):
    """
    ``scan_polygon.scan_points`` as a loop: the closed polygon and the hits of a scan.

    Beam ``i`` points along ``yaw + (angle_min + i * angle_increment)``; ``math.cos`` and
    ``math.sin`` are the C library's, as in the literal twin.
    """
    beams = ranges.shape[0]
    vertices_x = np.empty(beams + 2)
    vertices_y = np.empty(beams + 2)
    vertices_x[0] = vertices_x[beams + 1] = x
    vertices_y[0] = vertices_y[beams + 1] = y
    hit_beams = np.empty(beams, dtype=np.int64)
    hit_count = 0
    for i in range(beams):
        reading = ranges[i]
        theta = yaw + (angle_min + float(i) * angle_increment)
        if reading >= range_min and reading < range_max:     # False for NaN
            reach = reading
            hit_beams[hit_count] = i
            hit_count += 1
        elif reading >= range_max:                           # True for +inf
            reach = range_max
        else:
            reach = 0.0
        vertices_x[i + 1] = x + reach * math.cos(theta)
        vertices_y[i + 1] = y + reach * math.sin(theta)
    hit_beams = hit_beams[:hit_count].copy()
    hits_x = np.empty(hit_count)
    hits_y = np.empty(hit_count)
    for k in range(hit_count):
        hits_x[k] = vertices_x[hit_beams[k] + 1]
        hits_y[k] = vertices_y[hit_beams[k] + 1]
    return vertices_x, vertices_y, hits_x, hits_y, hit_beams


@kernel
def _window_bound(low, origin, resolution, margin, count):
    """``GridGeometry.cell_window``'s bound of one axis (``margin`` negative for the low end)."""
    index = np.floor((low - origin) / resolution) + margin
    return int(min(max(index, 0.0), float(count)))


@kernel
def _scan_window(shape, vertices_x, vertices_y, reach, x0, y0, resolution):
    """
    ``GridGeometry.cell_window`` of the polygon's box widened by ``reach`` [m], margin 1.

    Returns the half-open ``(row0, row_end, col0, col_end)`` on a grid of ``shape``.
    """
    rows, cols = shape
    row0 = _window_bound(vertices_y.min() - reach, y0, resolution, -1.0, rows)
    row_end = max(row0, _window_bound(vertices_y.max() + reach, y0, resolution, 2.0, rows))
    col0 = _window_bound(vertices_x.min() - reach, x0, resolution, -1.0, cols)
    col_end = max(col0, _window_bound(vertices_x.max() + reach, x0, resolution, 2.0, cols))
    return row0, row_end, col0, col_end


@kernel
def _not_surely_free(n_rows, n_cols, row0, col0, x0, y0, resolution, vertices_x, vertices_y,
                     hit_beams, safety_radius, free_radius, free_bound):
    """
    Mark the window cells that a scan cannot show surely free: near a vertex or an edge.

    Returns the window's ``(n_rows, n_cols)`` marks: every vertex's disc of ``free_radius``
    and every edge band beyond the ends' discs (`_mark_uncovered_edge_bands`). Within the
    safety radius a hit's disc holds only f1 cells, which are never marked free, so then only
    the vertices that are not hits need theirs.
    """
    not_free = np.zeros((n_rows, n_cols), dtype=np.bool_)
    # Every vertex but the closing repeat of the first.
    not_hit = np.zeros(0, dtype=np.bool_)
    if free_radius <= safety_radius:
        not_hit = np.ones(vertices_x.shape[0], dtype=np.bool_)
        for k in range(hit_beams.shape[0]):
            not_hit[hit_beams[k] + 1] = False
    _mark_discs(not_free, True, vertices_x, vertices_y, vertices_x.shape[0] - 1, not_hit,
                row0, col0, x0, y0, resolution, free_radius, free_bound,
                np.zeros((0, 2), dtype=np.int64))
    # Every vertex's disc of free_radius is marked or f1: the bands need only the rest.
    _mark_uncovered_edge_bands(not_free, row0, col0, x0, y0, resolution, vertices_x,
                               vertices_y, free_radius)
    return not_free


@kernel
def _mark_free_row(row_free, row_input, row_not_free):
    """Set ``row_free`` on the f2 cells of a row run not in ``row_not_free``; no branches."""
    for j in range(row_free.shape[0]):
        row_free[j] = row_free[j] | ((row_input[j] == _INSIDE) & (not row_not_free[j]))


@kernel
def _mark_free_window(seen_free, row0, col0, cell_input, extent, x0, y0, resolution,
                      vertices_x, vertices_y, hit_beams, safety_radius, free_radius,
                      free_bound):
    """
    Mark the surely-free cells of a scan whose update left them (``defer_free``).

    The arguments are those of that `_update_window` call, its ``cell_input`` and ``extent``
    as it filled them; ``seen_free`` becomes what the call would have made it.
    """
    n_rows, n_cols = cell_input.shape
    not_free = _not_surely_free(n_rows, n_cols, row0, col0, x0, y0, resolution, vertices_x,
                                vertices_y, hit_beams, safety_radius, free_radius, free_bound)
    _mark_free_rows(seen_free, row0, col0, cell_input, extent, not_free)


@kernel
def _mark_free_rows(seen_free, row0, col0, cell_input, extent, not_free):
    """`_mark_free_row` over each window row's f2 columns ``[extent[i, 0], extent[i, 1])``."""
    for i in range(cell_input.shape[0]):
        first = extent[i, 0]
        end = extent[i, 1]
        if first < end:
            _mark_free_row(seen_free[row0 + i, col0 + first:col0 + end],
                           cell_input[i, first:end], not_free[i, first:end])


@kernel
def _update_window(labels, seen_free, last_hit, listed, row0, col0, cell_input, x0, y0,
                   resolution, vertices_x, vertices_y, hits_x, hits_y, hit_beams,
                   safety_radius, safety_bound, free_on, free_radius, free_bound, objects_on,
                   evidence_radius, evidence_bound, segment_gap, object_size, min_hits,
                   expiry_on, stamp, path, new_mobile, extra_moving, moving_known, defer_free,
                   extent):
    """
    Fold one scan into the window ``labels[row0:row0 + n_rows, col0:col0 + n_cols]``.

    Parameters
    ----------
    labels : (rows, cols) ndarray of uint8
        The grid's labels, updated in place.
    seen_free : (rows, cols) ndarray of bool
        Cells once surely seen free, updated in place; read only with ``free_on``.
    last_hit : (rows, cols) ndarray of float64
        Stamp of each cell's last hit, updated in place; only with ``expiry_on``.
    listed : (rows, cols) ndarray of bool
        Cells in the grid's list of mobile cells; set here for the cells this scan makes
        mobile (with ``expiry_on``), which are also written to ``new_mobile``.
    row0, col0 : int
        The window's first row and column.
    cell_input : (n_rows, n_cols) ndarray of uint8
        Filled with the window's FSM input (``ScanInput``).
    x0, y0, resolution : float
        The grid's origin and cell side [m].
    vertices_x, vertices_y : (L + 2,) ndarray of float64
        The closed scan polygon [m].
    hits_x, hits_y : (K,) ndarray of float64
        Hit points [m].
    hit_beams : (K,) ndarray of int64
        Their beams.
    safety_radius, safety_bound : float
        f1's ``r`` [m] and its ``squared_radius_bound``.
    free_on, objects_on, expiry_on : bool
        Which parts of the ``LabelRule`` are on.
    free_radius, free_bound, evidence_radius, evidence_bound : float
        The free-evidence and motion-evidence radii [m] and their squared bounds.
    segment_gap, object_size : float
        As in ``LabelRule`` [m].
    min_hits : int
        ``LabelRule.object_min_hits``: evidence counts for nothing in a free-standing segment
        of fewer hits.
    stamp : float
        The scan's time [s]; read with ``expiry_on``.
    path : (N, 2) ndarray of int64
        The planned path's cells (may be empty).
    new_mobile : (n_rows * n_cols,) ndarray of int64
        Receives the flat grid indices of the cells newly listed.
    extra_moving : (K,) ndarray of bool
        Hits to count as moving besides those the object rule finds (empty: none).
    moving_known : bool
        ``extra_moving`` holds every moving hit, the object rule's included (as `scan_hits`
        finds them): the rule's evidence is not looked for again.
    defer_free : bool
        Leave ``seen_free`` alone (with ``free_on``): `_mark_free_window` marks this scan's
        surely-free cells later. No label of this scan depends on them.
    extent : (n_rows, 2) ndarray of int64
        Receives the columns ``[first, end)`` of each window row that f2 filled.

    Returns
    -------
    replan : bool
        A path cell went from free to an obstacle.
    new_count : int
        How many entries of ``new_mobile`` were written.

    """
    n_rows, n_cols = cell_input.shape
    grid_cols = labels.shape[1]
    # extent[i]: the columns [first, end) of row i that f2 filled; hit_extent[i] those of
    # its f1 cells (which may lie within the first).
    extent[:, 0] = n_cols
    extent[:, 1] = 0
    hit_extent = extent.copy()
    cell_input[...] = _NONE
    _fill_inside(cell_input, row0, col0, x0, y0, resolution, vertices_x, vertices_y, extent)
    no_selection = np.zeros(0, dtype=np.bool_)
    no_extent = np.zeros((0, 2), dtype=np.int64)
    _mark_discs(cell_input, _HIT, hits_x, hits_y, hits_x.shape[0], no_selection, row0, col0,
                x0, y0, resolution, safety_radius, safety_bound, hit_extent)
    near_moving = np.zeros((0, 0), dtype=np.bool_)      # read only with objects_on
    if objects_on:
        if moving_known:
            moving = extra_moving
        else:
            evidence = _hit_evidence(seen_free, hits_x, hits_y, x0, y0, resolution,
                                     evidence_radius, evidence_bound)
            moving = _moving_hits(hits_x, hits_y, hit_beams, evidence, segment_gap,
                                  object_size, min_hits, vertices_x[0], vertices_y[0],
                                  vertices_x.shape[0] - 2)
        if not moving_known and extra_moving.shape[0] == moving.shape[0]:
            for k in range(moving.shape[0]):
                if extra_moving[k]:
                    moving[k] = True
        near_moving = np.zeros((n_rows, n_cols), dtype=np.bool_)
        _mark_discs(near_moving, True, hits_x, hits_y, hits_x.shape[0], moving, row0, col0,
                    x0, y0, resolution, safety_radius, safety_bound, no_extent)
    mark_free = free_on and not defer_free
    not_free = np.zeros((0, 0), dtype=np.bool_)         # read only with mark_free
    if mark_free:
        not_free = _not_surely_free(n_rows, n_cols, row0, col0, x0, y0, resolution,
                                    vertices_x, vertices_y, hit_beams, safety_radius,
                                    free_radius, free_bound)
    # The path's labels before the update, for the replan flag.
    path_before = np.empty(path.shape[0], dtype=np.uint8)
    for k in range(path.shape[0]):
        path_before[k] = labels[path[k, 0], path[k, 1]]
    new_count = 0
    for i in range(n_rows):
        row = row0 + i
        # f2 (INSIDE) cells: explored under every rule; surely seen free when the rule keeps
        # that and no edge band or vertex disc marked them. Written without branches, so that
        # the loop runs on vectors; f1 (HIT) and no-input cells are written back unchanged.
        first = extent[i, 0]
        end = extent[i, 1]
        if first < end:
            row_labels = labels[row, col0 + first:col0 + end]
            row_input = cell_input[i, first:end]
            for j in range(end - first):
                row_labels[j] = _EXPLORED if row_input[j] == _INSIDE else row_labels[j]
            if mark_free:
                _mark_free_row(seen_free[row, col0 + first:col0 + end], row_input,
                               not_free[i, first:end])
        # f1 (HIT) cells, which no cell above changed.
        if not (free_on or expiry_on):
            # The paper's rule: the FSM table alone.
            for j in range(hit_extent[i, 0], hit_extent[i, 1]):
                if cell_input[i, j] == _HIT:
                    col = col0 + j
                    labels[row, col] = _TRANSITION_BY_CODE[(labels[row, col] << 2) | _HIT]
            continue
        for j in range(hit_extent[i, 0], hit_extent[i, 1]):
            if cell_input[i, j] != _HIT:
                continue
            col = col0 + j
            old = labels[row, col]
            if old == _NON_EXPLORED:
                new = _STEADY
            elif old == _EXPLORED:
                new = _MOBILE
            else:
                new = old
            if objects_on:
                new = _MOBILE if near_moving[i, j] else _STEADY
            elif free_on and old == _EXPLORED and not seen_free[row, col]:
                new = _STEADY
            if expiry_on:
                last_hit[row, col] = stamp
                if new == _MOBILE and not listed[row, col]:
                    listed[row, col] = True
                    new_mobile[new_count] = row * grid_cols + col
                    new_count += 1
            labels[row, col] = new
    replan = False
    for k in range(path.shape[0]):
        before = path_before[k]
        if before == _NON_EXPLORED or before == _EXPLORED:
            if labels[path[k, 0], path[k, 1]] >= _STEADY:
                replan = True
    return replan, new_count


@kernel
def _expire_listed(labels, last_hit, listed, cells, count, stamp, mobile_expiry, row0, col0,
                   cell_input):
    """
    Expire the listed mobile cells that are stale and out of view; drop non-mobile ones.

    Returns the count of cells kept (compacted to the front of ``cells``), the earliest
    ``last_hit`` among them (``inf`` when none), and the half-open box ``(row_lo, row_hi,
    col_lo, col_hi)`` of the cells expired (empty when none).
    """
    grid_rows, grid_cols = labels.shape
    n_rows, n_cols = cell_input.shape
    kept = 0
    earliest = math.inf
    row_lo = grid_rows
    row_hi = 0
    col_lo = grid_cols
    col_hi = 0
    for k in range(count):
        flat = cells[k]
        row = flat // grid_cols
        col = flat - row * grid_cols
        if labels[row, col] != _MOBILE:
            listed[row, col] = False
            continue
        i = row - row0
        j = col - col0
        in_view = 0 <= i < n_rows and 0 <= j < n_cols and cell_input[i, j] != _NONE
        if not in_view and stamp - last_hit[row, col] >= mobile_expiry:
            labels[row, col] = _EXPLORED
            listed[row, col] = False
            row_lo = min(row_lo, row)
            row_hi = max(row_hi, row + 1)
            col_lo = min(col_lo, col)
            col_hi = max(col_hi, col + 1)
            continue
        cells[kept] = flat
        kept += 1
        earliest = min(earliest, last_hit[row, col])
    return kept, earliest, row_lo, row_hi, col_lo, col_hi


@kernel
def _scan_update(labels, seen_free, last_hit, listed, ranges, x, y, yaw, angle_min,
                 angle_increment, range_min, range_max, x0, y0, resolution, reach,
                 safety_radius, safety_bound, free_on, free_radius, free_bound, objects_on,
                 evidence_radius, evidence_bound, segment_gap, object_size, min_hits, expiry_on,
                 stamp, path, extra_moving):
    """
    Find the scan's points, then run `_points_update` with them (nothing deferred).

    Returns ``(replan, row0, row_end, col0, col_end, cell_input, new_mobile)``.
    """
    vertices_x, vertices_y, hits_x, hits_y, hit_beams = _scan_points(
        ranges, x, y, yaw, angle_min, angle_increment, range_min, range_max)
    replan, row0, row_end, col0, col_end, cell_input, new_mobile, _ = _points_update(
        labels, seen_free, last_hit, listed, vertices_x, vertices_y, hits_x, hits_y,
        hit_beams, x0, y0, resolution, reach, safety_radius, safety_bound, free_on,
        free_radius, free_bound, objects_on, evidence_radius, evidence_bound, segment_gap,
        object_size, min_hits, expiry_on, stamp, path, extra_moving, False, False)
    return replan, row0, row_end, col0, col_end, cell_input, new_mobile


@kernel
def _points_update(labels, seen_free, last_hit, listed, vertices_x, vertices_y, hits_x,
                   hits_y, hit_beams, x0, y0, resolution, reach, safety_radius, safety_bound,
                   free_on, free_radius, free_bound, objects_on, evidence_radius,
                   evidence_bound, segment_gap, object_size, min_hits, expiry_on, stamp, path,
                   extra_moving, moving_known, defer_free):
    """
    Find the scan's window from its points, then run `_update_window` over it.

    Returns ``(replan, row0, row_end, col0, col_end, cell_input, new_mobile, extent)``, the
    last f2's columns per window row (for `_mark_free_window` after ``defer_free``); an empty
    window (the scan misses the grid) changes nothing.
    """
    row0, row_end, col0, col_end = _scan_window(labels.shape, vertices_x, vertices_y, reach,
                                                x0, y0, resolution)
    n_rows = row_end - row0
    n_cols = col_end - col0
    if n_rows == 0 or n_cols == 0:
        return (False, 0, 0, 0, 0, np.zeros((0, 0), dtype=np.uint8),
                np.zeros(0, dtype=np.int64), np.zeros((0, 2), dtype=np.int64))
    cell_input = np.empty((n_rows, n_cols), dtype=np.uint8)
    new_mobile = np.empty(n_rows * n_cols if expiry_on else 0, dtype=np.int64)
    extent = np.empty((n_rows, 2), dtype=np.int64)
    replan, new_count = _update_window(
        labels, seen_free, last_hit, listed, row0, col0, cell_input, x0, y0, resolution,
        vertices_x, vertices_y, hits_x, hits_y, hit_beams, safety_radius, safety_bound,
        free_on, free_radius, free_bound, objects_on, evidence_radius, evidence_bound,
        segment_gap, object_size, min_hits, expiry_on, stamp, path, new_mobile, extra_moving,
        moving_known, defer_free, extent)
    return (replan, row0, row_end, col0, col_end, cell_input, new_mobile[:new_count].copy(),
            extent)


@kernel
def _surely_free_update(seen_free, ranges, x, y, yaw, angle_min, angle_increment, range_min,
                        range_max, x0, y0, resolution, radius, bound):
    """
    Mark the cells whose disc of ``radius`` lies inside the scan's polygon as surely free.

    Exactly the ``seen_free`` of `_update_window` under a rule with only the conservative free
    space on and a safety radius equal to ``radius``: f2 cells that no vertex's disc and no
    edge band reaches (a hit's f1 disc is its vertex's disc). Nothing else is computed.
    """
    vertices_x, vertices_y, _, _, _ = _scan_points(
        ranges, x, y, yaw, angle_min, angle_increment, range_min, range_max)
    # The window of `_points_update` with reach = radius.
    row0, row_end, col0, col_end = _scan_window(seen_free.shape, vertices_x, vertices_y, radius,
                                                x0, y0, resolution)
    n_rows = row_end - row0
    n_cols = col_end - col0
    if n_rows == 0 or n_cols == 0:
        return
    cell_input = np.zeros((n_rows, n_cols), dtype=np.uint8)
    extent = np.empty((n_rows, 2), dtype=np.int64)
    extent[:, 0] = n_cols
    extent[:, 1] = 0
    _fill_inside(cell_input, row0, col0, x0, y0, resolution, vertices_x, vertices_y, extent)
    # Every vertex's disc, hits included (their f1 discs): a safety radius of 0 selects them
    # all.
    not_free = _not_surely_free(n_rows, n_cols, row0, col0, x0, y0, resolution, vertices_x,
                                vertices_y, np.zeros(0, dtype=np.int64), 0.0, radius, bound)
    _mark_free_rows(seen_free, row0, col0, cell_input, extent, not_free)


def surely_free_update(seen_free, geometry, pose, ranges, angle_min, angle_increment,
                       range_min, range_max, radius):
    """
    Fold one checked scan into ``seen_free`` alone: the conservative free space of a grid.

    The same cells ``scan_update`` marks in ``seen_free`` under a ``LabelRule`` with only
    ``free_evidence_radius = radius`` on and a safety radius of ``radius``, without the labels.

    Parameters
    ----------
    seen_free : (rows, cols) ndarray of bool
        Cells once surely seen free, updated in place.
    geometry : GridGeometry
        The grid's placement.
    pose, ranges, angle_min, angle_increment, range_min, range_max
        As in `scan_update`, checked.
    radius : float
        A cell is surely free when its disc of this radius lies inside the polygon [m], > 0.

    """
    x0, y0 = geometry.origin
    _surely_free_update(seen_free, np.ascontiguousarray(ranges), pose[0], pose[1], pose[2],
                        float(angle_min), float(angle_increment), float(range_min),
                        float(range_max), x0, y0, geometry.resolution, float(radius),
                        squared_bound(float(radius)))


def scan_update(labels, seen_free, last_hit, listed, geometry, pose, ranges, angle_min,
                angle_increment, range_min, range_max, safety_radius, rule_arguments, stamp,
                path, extra_moving=None, points=None, defer_free=False):
    """
    Fold one validated scan into the grid's state arrays in place.

    Parameters
    ----------
    labels : (rows, cols) ndarray of uint8
        The grid's labels.
    seen_free, listed : (rows, cols) ndarray of bool
        ``(1, 1)`` stand-ins when the rule keeps no such state.
    last_hit : (rows, cols) ndarray of float64
        Likewise.
    geometry : GridGeometry
        The grid's placement.
    pose : (float, float, float)
        The laser's ``(x, y, yaw)`` [m, m, rad], checked.
    ranges : (L,) ndarray of float64
        Checked ranges [m].
    angle_min, angle_increment, range_min, range_max : float
        The scan's fields, checked.
    safety_radius : float
        f1's ``r`` [m].
    rule_arguments : tuple
        ``LabelRule.kernel_arguments()``: ``(free_on, free_radius, free_bound, objects_on,
        evidence_radius, evidence_bound, segment_gap, object_size, min_hits, expiry_on)``.
    stamp : float
        The scan's time [s] (any float when the expiry is off).
    path : (N, 2) ndarray of int64
        The planned path's cells, on the grid.
    extra_moving : (K,) ndarray of bool, optional
        Hits (in the order of `scan_hits`) to count as hits on moving objects besides those
        the object rule finds, such as the followed objects of ``motion_tracks``; read only
        with the object rule on.
    points : tuple, optional
        ``(vertices_x, vertices_y, hits_x, hits_y, hit_beams, moving)`` of this scan from
        `scan_hits` on the same state, so that they are not found again; ``extra_moving`` is
        then added to ``moving``.
    defer_free : bool
        With the conservative free space on, leave ``seen_free`` as it is and return what
        `mark_free_window` needs to mark this scan's surely-free cells later. The labels, the
        replan flag and the window are the same either way: no label of this scan depends on
        the cells it shows surely free (they are f2 cells; the rule reads ``seen_free`` only
        at f1 cells and at the hits, before the update).

    Returns
    -------
    replan : bool
    window : (slice, slice, (n_rows, n_cols) ndarray of uint8)
        The window the scan reached and its FSM input (``ScanInput``).
    new_mobile : (M,) ndarray of int64
        Flat indices of the cells this scan made mobile and listed (with the expiry on).
    deferred : tuple or None
        For `mark_free_window`, with ``defer_free`` and the free space on; else None.

    """
    x0, y0 = geometry.origin
    free_on, free_radius, free_bound = rule_arguments[:3]
    reach = max(safety_radius, free_radius)
    defer_free = bool(defer_free and free_on)
    if points is None and not defer_free:
        replan, row0, row_end, col0, col_end, cell_input, new_mobile = _scan_update(
            labels, seen_free, last_hit, listed, np.ascontiguousarray(ranges), pose[0],
            pose[1], pose[2], float(angle_min), float(angle_increment), float(range_min),
            float(range_max), x0, y0, geometry.resolution, reach, safety_radius,
            squared_bound(safety_radius), *rule_arguments, float(stamp),
            np.ascontiguousarray(path),
            _NO_HITS if extra_moving is None else np.ascontiguousarray(extra_moving, dtype=bool))
        return (bool(replan), (slice(row0, row_end), slice(col0, col_end), cell_input),
                new_mobile, None)
    if points is None:
        # The kernel's object rule finds the moving hits itself (moving_known False).
        vertices_x, vertices_y, hits_x, hits_y, hit_beams = _scan_points(
            np.ascontiguousarray(ranges), pose[0], pose[1], pose[2], float(angle_min),
            float(angle_increment), float(range_min), float(range_max))
        moving = (_NO_HITS if extra_moving is None
                  else np.ascontiguousarray(extra_moving, dtype=bool))
        moving_known = False
    else:
        vertices_x, vertices_y, hits_x, hits_y, hit_beams, moving = points
        if extra_moving is not None:
            moving = moving | extra_moving
        moving_known = True
    replan, row0, row_end, col0, col_end, cell_input, new_mobile, extent = _points_update(
        labels, seen_free, last_hit, listed, vertices_x, vertices_y, hits_x, hits_y,
        hit_beams, x0, y0, geometry.resolution, reach, safety_radius,
        squared_bound(safety_radius), *rule_arguments, float(stamp),
        np.ascontiguousarray(path), moving, moving_known, defer_free)
    deferred = None
    if defer_free:
        deferred = (row0, col0, cell_input, extent, vertices_x, vertices_y, hit_beams,
                    float(safety_radius), float(free_radius), float(free_bound))
    return (bool(replan), (slice(row0, row_end), slice(col0, col_end), cell_input),
            new_mobile, deferred)


def mark_free_window(seen_free, geometry, deferred):
    """
    Mark the surely-free cells that a `scan_update` with ``defer_free`` left unmarked.

    Parameters
    ----------
    seen_free : (rows, cols) ndarray of bool
        The grid's cells once surely seen free, updated in place.
    geometry : GridGeometry
        The grid's placement.
    deferred : tuple
        What that `scan_update` returned last.

    """
    x0, y0 = geometry.origin
    (row0, col0, cell_input, extent, vertices_x, vertices_y, hit_beams, safety_radius,
     free_radius, free_bound) = deferred
    _mark_free_window(seen_free, row0, col0, cell_input, extent, x0, y0, geometry.resolution,
                      vertices_x, vertices_y, hit_beams, safety_radius, free_radius, free_bound)


def scan_hits(seen_free, geometry, pose, ranges, angle_min, angle_increment, range_min,
              range_max, rule_arguments):
    """
    Return the scan's polygon and hits, and the hits the object rule finds moving.

    The same points and the same evidence as `scan_update` finds in its kernel, from the
    grid's state before the update.

    Parameters
    ----------
    seen_free : (rows, cols) ndarray of bool
        Cells once surely seen free (a stand-in without the object rule).
    geometry, pose, ranges, angle_min, angle_increment, range_min, range_max, rule_arguments
        As in `scan_update`.

    Returns
    -------
    vertices_x, vertices_y : (L + 2,) ndarray of float64
        The closed scan polygon [m].
    hits_x, hits_y : (K,) ndarray of float64
        Hit points [m].
    hit_beams : (K,) ndarray of int64
        Their beams.
    moving : (K,) ndarray of bool
        Hits on objects seen to move (all False without the object rule).

    """
    vertices_x, vertices_y, hits_x, hits_y, hit_beams = _scan_points(
        np.ascontiguousarray(ranges), pose[0], pose[1], pose[2], float(angle_min),
        float(angle_increment), float(range_min), float(range_max))
    (_, _, _, objects_on, evidence_radius, evidence_bound, segment_gap, object_size,
     min_hits, _) = rule_arguments
    moving = np.zeros(hits_x.shape[0], dtype=bool)
    if objects_on:
        x0, y0 = geometry.origin
        evidence = _hit_evidence(seen_free, hits_x, hits_y, x0, y0, geometry.resolution,
                                 evidence_radius, evidence_bound)
        moving = _moving_hits(hits_x, hits_y, hit_beams, evidence, segment_gap, object_size,
                              min_hits, vertices_x[0], vertices_y[0], ranges.shape[0])
    return vertices_x, vertices_y, hits_x, hits_y, hit_beams, moving


def expire_listed(labels, last_hit, listed, cells, count, stamp, mobile_expiry, window):
    """
    Run `_expire_listed` over ``cells[:count]`` after the scan of ``window``.

    Returns
    -------
    kept : int
    earliest : float
        The earliest last hit of the cells kept [s], ``inf`` when none.
    expired : (slice, slice)
        Rows and columns of a box around the cells expired (empty when none).

    """
    rows, cols, cell_input = window
    kept, earliest, row_lo, row_hi, col_lo, col_hi = _expire_listed(
        labels, last_hit, listed, cells, count, float(stamp), float(mobile_expiry), rows.start,
        cols.start, cell_input)
    return (int(kept), float(earliest),
            (slice(row_lo, max(row_lo, row_hi)), slice(col_lo, max(col_lo, col_hi))))
