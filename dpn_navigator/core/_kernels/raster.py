"""
Shared raster kernels: discs, boxes and edge bands marked on a window of cells, the scan polygon filled.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import math

import numpy as np

from .codes import SCAN_INSIDE
from .jit import kernel


#: Slack of the rows searched around a disc or an edge band [m]: far above the rounding of
#: ``dy`` for coordinates up to ``MAX_POSE_COORDINATE`` plus a laser's range.
_BOX_SLACK = 1e-6


#: Discs of a radius up to this many cells are marked from a box of cells around them
#: (`mark_small_disc`), larger ones by `disc_spans`.
_ROW_BY_ROW_CELLS = 3.0


#: How far [m] below the radius a point's distance from an edge's end may lie and still fail
#: the disc test of the radius: far above the rounding of the test.
_COVER_SLACK = 1e-6


@kernel
def count_below(first, count, origin, resolution, value):
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
def box_first(first, count, origin, resolution, value):
    """
    Return a first index in ``[0, count]`` whose centre may lie at or above ``value``.

    The centres are ``origin + (first + k + 0.5) * resolution``; the index has a cell to
    spare for rounding.
    """
    estimate = np.floor((value - origin) / resolution - 0.5) - first
    return int(min(max(estimate, 0.0), float(count)))


@kernel
def box_end(first, count, origin, resolution, value):
    """One past the last index in ``[0, count]`` whose centre may lie at or below ``value``."""
    estimate = np.floor((value - origin) / resolution - 0.5) + 2.0 - first
    return int(min(max(estimate, 0.0), float(count)))


@kernel
def disc_span(first_col, end_col, col0, x0, resolution, px, dy2, bound):
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
def disc_rows(py, radius, row0, n_rows, y0, resolution):
    """Window rows ``[first, end)`` whose centres may lie within ``radius`` of ``py``."""
    reach = radius + _BOX_SLACK * (1.0 + 1e-6 * abs(py))
    return (count_below(row0, n_rows, y0, resolution, py - reach),
            count_below(row0, n_rows, y0, resolution, py + reach))


@kernel
def disc_row_span(px, dy2, bound, col0, n_cols, x0, resolution):
    """
    Return the half-open window columns ``(first, end)`` of a disc's run in one row.

    ``dy2`` is the row's ``dy * dy``: the columns whose centre passes ``dx*dx + dy2 <= bound``
    (maybe none).
    """
    if dy2 > bound:
        return 0, 0
    half = math.sqrt(bound - dy2)
    return disc_span(box_first(col0, n_cols, x0, resolution, px - half),
                     box_end(col0, n_cols, x0, resolution, px + half),
                     col0, x0, resolution, px, dy2, bound)


@kernel
def disc_spans(px, py, radius, bound, row0, n_rows, col0, n_cols, x0, y0, resolution, spans):
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
    first_row, end_row = disc_rows(py, radius, row0, n_rows, y0, resolution)
    split = min(max(count_below(row0, n_rows, y0, resolution, py), first_row), end_row)
    for step in (1, -1):
        first = 0
        end = -1                                    # -1: no run found on this side yet
        i = split if step == 1 else split - 1
        while first_row <= i < end_row:
            dy = (y0 + (float(row0 + i) + 0.5) * resolution) - py
            dy2 = dy * dy
            if end < 0:
                first, end = disc_row_span(px, dy2, bound, col0, n_cols, x0, resolution)
            else:
                first, end = disc_span(first, end, col0, x0, resolution, px, dy2, bound)
            spans[i - first_row, 0] = first
            spans[i - first_row, 1] = end
            i += step
    return first_row, end_row


@kernel
def disc_box(px, py, row0, n_rows, col0, n_cols, x0, y0, resolution, reach):
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
def small_disc_reach(radius, resolution):
    """Return `disc_box`'s ``reach`` for discs of ``radius`` [m] (0 for large ones)."""
    if radius <= _ROW_BY_ROW_CELLS * resolution:
        return int(math.ceil(radius / resolution)) + 1
    return 0


@kernel
def mark_small_disc(mark, value, px, py, row0, col0, x0, y0, resolution, bound, reach,
                    extent, dx2):
    """
    Set ``mark`` to ``value`` on the window cells whose centre passes ``dx*dx + dy*dy <= bound``.

    The cells tested are those of `disc_box`. Each row's run is shrunk from the box's
    ends with the exact test, ``dx * dx`` taken once per column (``dx2``, at least
    ``2 * reach + 1`` long). ``extent`` as in `mark_discs`.
    """
    n_rows, n_cols = mark.shape
    first_row, end_row, first_col, end_col = disc_box(
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
def mark_discs(mark, value, xs, ys, count, selected, row0, col0, x0, y0, resolution, radius,
               bound, extent):
    """
    Set ``mark`` to ``value`` on the window cells within ``radius`` of the selected points.

    ``mark`` is the window's ``(n_rows, n_cols)`` array, its cell ``(0, 0)`` the grid's
    ``(row0, col0)``; the first ``count`` points count where ``selected`` is True (all when
    it is empty). Each disc is marked as one run of cells per row. When ``extent`` has rows,
    ``extent[i]`` is widened to hold the columns marked in row ``i``.
    """
    n_rows, n_cols = mark.shape
    reach = small_disc_reach(radius, resolution)
    dx2 = np.empty(2 * reach + 1)
    spans = np.empty((0 if reach else n_rows, 2), dtype=np.int64)
    for k in range(count):
        if selected.shape[0] and not selected[k]:
            continue
        px = xs[k]
        py = ys[k]
        if reach:
            mark_small_disc(mark, value, px, py, row0, col0, x0, y0, resolution, bound, reach,
                            extent, dx2)
            continue
        first_row, end_row = disc_spans(px, py, radius, bound, row0, n_rows, col0, n_cols,
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
def fill_inside(cell_input, row0, col0, x0, y0, resolution, vertices_x, vertices_y, extent):
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
        first_rows[a] = count_below(row0, n_rows, y0, resolution, min(ya, yb))
        end_rows[a] = count_below(row0, n_rows, y0, resolution, max(ya, yb))
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
            crossings[filled[i]] = count_below(col0, n_cols, x0, resolution, x_cross)
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
                cell_input[i, first:end] = SCAN_INSIDE
                extent[i, 0] = min(extent[i, 0], first)
                extent[i, 1] = max(extent[i, 1], end)


@kernel
def mark_band_rows(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2, length,
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
                            box_first(col0, n_cols, x0, resolution, xa + low - slack))
            end_col = min(end_col, box_end(col0, n_cols, x0, resolution, xa + high + slack))
        # The band's cells in a row are contiguous (dot and cross are monotone along the
        # row): shrink the candidates to them from both ends, then mark them all.
        while first_col < end_col and not in_band(
                x0 + (float(col0 + first_col) + 0.5) * resolution, cy, xa, ya, ex, ey,
                length2, length, radius):
            first_col += 1
        while end_col > first_col and not in_band(
                x0 + (float(col0 + end_col - 1) + 0.5) * resolution, cy, xa, ya, ex, ey,
                length2, length, radius):
            end_col -= 1
        mark[i, first_col:end_col] = True


@kernel
def mark_edge_band(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2, length,
                   radius):
    """Set ``mark`` on the window's cells within ``radius`` of edge ``a + t e``."""
    n_rows, n_cols = mark.shape
    reach = radius + _BOX_SLACK * (1.0 + 1e-6 * abs(ya))
    # Rows with centres in [y_low - reach, y_high + reach] (the + 1: one equal to it).
    first_row = count_below(row0, n_rows, y0, resolution, min(ya, ya + ey) - reach)
    end_row = min(count_below(row0, n_rows, y0, resolution, max(ya, ya + ey) + reach) + 1,
                  n_rows)
    first_col = box_first(col0, n_cols, x0, resolution, min(xa, xa + ex) - reach)
    end_col = box_end(col0, n_cols, x0, resolution, max(xa, xa + ex) + reach)
    mark_band_rows(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2, length,
                   radius, first_row, end_row, first_col, end_col, end_col - first_col > 8)


@kernel
def mark_edge_bands(mark, row0, col0, x0, y0, resolution, vertices_x, vertices_y, radius):
    """Set ``mark`` on the window's cells within ``radius`` of some polygon edge."""
    for a in range(vertices_x.shape[0] - 1):
        xa = vertices_x[a]
        ya = vertices_y[a]
        ex = vertices_x[a + 1] - xa
        ey = vertices_y[a + 1] - ya
        length2 = ex * ex + ey * ey
        if length2 > 0.0:
            mark_edge_band(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2,
                           math.sqrt(length2), radius)


@kernel
def mark_uncovered_edge_bands(mark, row0, col0, x0, y0, resolution, vertices_x, vertices_y,
                              radius):
    """
    Mark the band cells of `mark_edge_bands` that are not within ``radius`` of an edge's end.

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
            mark_edge_band(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2,
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
            if (clear_of_centres(y_low, y_high, y0, per_cell)
                    or clear_of_centres(x_low, x_high, x0, per_cell)):
                continue
            first_row = count_below(row0, n_rows, y0, resolution, y_low)
            end_row = count_below(row0, n_rows, y0, resolution, y_high)
            if first_row == end_row:
                continue
            first_col = count_below(col0, n_cols, x0, resolution, x_low)
            end_col = count_below(col0, n_cols, x0, resolution, x_high)
            if first_col < end_col:
                mark_band_rows(mark, row0, col0, x0, y0, resolution, xa, ya, ex, ey, length2,
                               length, radius, first_row, end_row, first_col, end_col, False)


@kernel
def clear_of_centres(low, high, origin, per_cell):
    """
    Tell whether no centre ``origin + (k + 0.5) / per_cell`` lies near ``[low, high]``.

    ``per_cell`` is ``1 / resolution``; near: within a millionth of a cell, far above the
    rounding of these products.
    """
    return (math.floor((high - origin) * per_cell - 0.5 + 1e-6)
            < math.ceil((low - origin) * per_cell - 0.5 - 1e-6))


@kernel
def in_band(cx, cy, xa, ya, ex, ey, length2, length, radius):
    """Tell whether ``(cx, cy)`` projects onto edge ``a + t e`` within ``radius`` of it."""
    dot = (cx - xa) * ex + (cy - ya) * ey
    cross = (cx - xa) * ey - (cy - ya) * ex
    return 0.0 <= dot <= length2 and abs(cross) / length <= radius
