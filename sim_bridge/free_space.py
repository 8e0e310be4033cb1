"""
Where a round robot fits: free space shrunk by a clearance, on a coarse grid, with components.

A robot of radius ``r`` placed anywhere inside a *clear* cell of a `ClearanceGrid` built with
``clearance >= r`` touches no cell of the map that is not known free. Moving in a straight line
between the centres of two 8-adjacent clear cells only crosses those two cells (and, on a
diagonal, their shared corner), so a path of clear cells, as `dpn_navigator.core.astar` returns
on ``~clear``, is safe to follow centre to centre. Both the wanderers (planning their walks)
and the task sampler (placing the Husky) use it.

The coarse cells are a whole number of map cells, about ``cell_size`` on a side, so that A*
and the component labelling stay cheap on large, fine maps.

"""

from collections import deque
from dataclasses import dataclass
import math

from dpn_navigator.core import GridGeometry
import numpy as np

#: Default side of a coarse cell [m]; the map's own cells are used when they are larger.
DEFAULT_CELL_SIZE = 0.2


def near_cells(mask, clearance):
    """
    Find the cells that come closer than a clearance to a marked cell.

    Cells are unit squares; the distance between two cells is the least distance between their
    points, ``hypot(max(|dr| - 1, 0), max(|dc| - 1, 0))`` for cells ``dr`` rows and ``dc``
    columns apart (0 for the cell itself and its 8 neighbours).

    Parameters
    ----------
    mask : (rows, cols) array_like of bool
        The marked cells.
    clearance : float
        The clearance [cells], non-negative.

    Returns
    -------
    near : (rows, cols) ndarray of bool
        True where some marked cell is less than ``clearance`` away, and on marked cells
        themselves. Cells outside the grid count as unmarked.

    """
    mask = np.asarray(mask, dtype=bool)
    if mask.ndim != 2:
        raise ValueError(f'mask must be 2-D, got shape {mask.shape}')
    if not (math.isfinite(clearance) and clearance >= 0.0):
        raise ValueError(f'clearance must be finite and non-negative, got {clearance!r}')
    # Row offset dr -> largest column offset of a cell closer than the clearance.
    spans = {0: 0}
    for dr in range(int(math.ceil(clearance)) + 1):
        gap = max(dr - 1, 0)
        if gap < clearance:
            half = 1  # the columns at offsets -1, 0, 1 add no gap
            while math.hypot(gap, half) < clearance:
                half += 1
            spans[dr] = spans[-dr] = half
    rows, cols = mask.shape
    reach = max(spans)
    wide = max(spans.values())
    # A row's sums over column windows come from one cumulative sum along the rows.
    padded = np.zeros((rows + 2 * reach, cols + 2 * wide), dtype=np.int32)
    padded[reach:reach + rows, wide:wide + cols] = mask
    csum = np.zeros((rows + 2 * reach, cols + 2 * wide + 1), dtype=np.int32)
    np.cumsum(padded, axis=1, out=csum[:, 1:])
    near = np.zeros((rows, cols), dtype=bool)
    windows = {}
    for dr, half in spans.items():
        if half not in windows:
            windows[half] = (csum[:, wide + half + 1:wide + half + 1 + cols]
                             > csum[:, wide - half:wide - half + cols])
        near |= windows[half][reach + dr:reach + dr + rows]
    return near


def label_components(mask):
    """
    Label the 4-connected components of a mask.

    Parameters
    ----------
    mask : (rows, cols) array_like of bool
        The cells to label.

    Returns
    -------
    labels : (rows, cols) ndarray of int32
        0 outside ``mask``; 1, 2, ... for the components, numbered in row-major order of their
        first cell.
    count : int
        Number of components.

    """
    mask = np.asarray(mask, dtype=bool)
    rows, cols = mask.shape
    flat = np.zeros(rows * cols, dtype=np.int32)
    inside = mask.ravel().tolist()
    count = 0
    for seed in np.flatnonzero(mask).tolist():
        if flat[seed]:
            continue
        count += 1
        flat[seed] = count
        queue = deque([seed])
        while queue:
            cell = queue.popleft()
            col = cell % cols
            for nxt, ok in ((cell - cols, cell >= cols), (cell + cols, cell + cols < rows * cols),
                            (cell - 1, col > 0), (cell + 1, col < cols - 1)):
                if ok and inside[nxt] and not flat[nxt]:
                    flat[nxt] = count
                    queue.append(nxt)
    return flat.reshape(rows, cols), count


@dataclass(frozen=True, eq=False)
class ClearanceGrid:
    """
    Coarse cells in which a disc of radius ``clearance`` fits anywhere.

    Attributes
    ----------
    clear : (rows, cols) ndarray of bool
        True where every point of the cell is at least ``clearance`` from every map cell that
        is not known free (cells beyond the map's edge count as not free).
    labels : (rows, cols) ndarray of int32
        4-connected components of ``clear``, numbered from 1; 0 elsewhere.
    geometry : GridGeometry
        The coarse grid: same origin as the map, cells of ``factor`` map cells.
    clearance : float
        The clearance [m].
    factor : int
        Map cells per coarse cell side.

    """

    clear: np.ndarray
    labels: np.ndarray
    geometry: GridGeometry
    clearance: float
    factor: int

    def cell_of(self, x, y):
        """Return the coarse cell ``(row, col)`` holding map-frame ``(x, y)`` [m], or None."""
        rr, cc = self.geometry.world_to_cell(x, y)
        if not self.geometry.contains_cell(rr, cc):
            return None
        return int(rr), int(cc)

    def is_clear(self, x, y):
        """Return True when map-frame point ``(x, y)`` [m] lies in a clear cell."""
        cell = self.cell_of(x, y)
        return cell is not None and bool(self.clear[cell])

    def centre(self, row, col):
        """Return the map-frame centre ``(x, y)`` [m] of coarse cell ``(row, col)``."""
        x, y = self.geometry.cell_to_world(row, col)
        return float(x), float(y)


def clearance_grid(free, geometry, clearance, cell_size=DEFAULT_CELL_SIZE):
    """
    Build the `ClearanceGrid` of a map.

    Parameters
    ----------
    free : (rows, cols) array_like of bool
        Known-free cells of the map, row 0 at the bottom.
    geometry : GridGeometry
        The map's grid.
    clearance : float
        Radius of the disc that must fit [m], non-negative.
    cell_size : float
        Wanted side of a coarse cell [m]; rounded down to a whole number (at least 1) of map
        cells.

    Returns
    -------
    ClearanceGrid

    """
    free = np.asarray(free, dtype=bool)
    if free.shape != geometry.shape:
        raise ValueError(f'free has shape {free.shape}, the geometry {geometry.shape}')
    if not (math.isfinite(clearance) and clearance >= 0.0):
        raise ValueError(f'clearance must be finite and non-negative, got {clearance!r} m')
    res = geometry.resolution
    # Every point of a clear cell keeps `clearance` from every point of a cell not known free;
    # beyond the map's edge nothing is known.
    pad = int(math.ceil(clearance / res)) + 1
    blocked = np.pad(~free, pad, constant_values=True)
    near = near_cells(blocked, clearance / res)[pad:pad + free.shape[0], pad:pad + free.shape[1]]
    factor = max(1, int(math.floor(cell_size / res + 1e-9)))
    rows = -(-free.shape[0] // factor)
    cols = -(-free.shape[1] // factor)
    fine = np.zeros((rows * factor, cols * factor), dtype=bool)
    fine[:free.shape[0], :free.shape[1]] = ~near
    clear = fine.reshape(rows, factor, cols, factor).all(axis=(1, 3))
    labels, _ = label_components(clear)
    coarse = GridGeometry(cols * factor * res, rows * factor * res, factor * res,
                          geometry.origin)
    if coarse.shape != clear.shape:
        raise RuntimeError(f'coarse grid {coarse.shape} does not match {clear.shape}')
    return ClearanceGrid(clear, labels, coarse, float(clearance), factor)
