"""
A grid grown by whole blocks of cells: how many cells each side needs, and per-cell state moved.

A map of a fixed size placed by its origin fits a robot whose start is known; a robot that
starts at the corner of its map, or drives out of it, needs the grid to grow (issue 29). The
grid grows on a side by whole blocks of ``step`` cells, and its origin moves by whole cells, so
every cell keeps its place in the map frame: the cell ``(i, j)`` of the old grid is the cell
``(i + below, j + left)`` of the new one. `GridGrowth` says how many rows and columns are
added on each side and moves per-cell arrays (`GridGrowth.embed`) and flat cell indices
(`GridGrowth.remap`) into the grown grid; the owners of per-cell state (``LabelGrid`` and its
memories, the navigator's masks and memories) call them in their ``grow``.

"""

from dataclasses import dataclass
import functools
import math

import numpy as np

from ..grid_geometry import GridGeometry

#: Most cells a map may grow to (2048 x 2048, the ``dpn`` node's limit at start): A*'s arrays
#: stay in memory and one plan takes seconds at most.
MAX_MAP_CELLS = 2048 * 2048
#: A sub-grid's offset must be this close to a whole number of its cells to be kept.
WHOLE_CELL_TOLERANCE = 1e-6


@dataclass(frozen=True)
class GridGrowth:
    """
    Rows and columns added on each side of a grid.

    Attributes
    ----------
    below, above : int
        Rows added before row 0 (toward -y) and after the last row (toward +y), >= 0.
    left, right : int
        Columns added before column 0 (toward -x) and after the last one (toward +x), >= 0.

    """

    below: int = 0
    above: int = 0
    left: int = 0
    right: int = 0

    def __post_init__(self):
        for name in ('below', 'above', 'left', 'right'):
            value = getattr(self, name)
            if int(value) != value or value < 0:
                raise ValueError(f'{name} must be a whole number of cells >= 0, got {value!r}')
            object.__setattr__(self, name, int(value))

    def __bool__(self):
        """Return whether any cell is added."""
        return bool(self.below or self.above or self.left or self.right)

    def geometry(self, geometry):
        """
        Return the grown grid's geometry: the old cells at the same map-frame places.

        Parameters
        ----------
        geometry : GridGeometry
            The grid before growing.

        Returns
        -------
        GridGeometry
            ``rows + below + above`` by ``cols + left + right`` cells of the same resolution,
            the origin moved by ``left`` and ``below`` whole cells.

        """
        res = geometry.resolution
        x0, y0 = geometry.origin
        return GridGeometry(geometry.width + (self.left + self.right) * res,
                            geometry.height + (self.below + self.above) * res, res,
                            (x0 - self.left * res, y0 - self.below * res))

    def embed(self, array, shape, fill):
        """
        Return ``array`` placed in a new array of ``shape``, the added cells set to ``fill``.

        Parameters
        ----------
        array : (rows, cols) ndarray
            Per-cell values of the old grid.
        shape : (int, int)
            The grown grid's shape.
        fill : scalar
            The value of the added cells (what a new grid starts with).

        Returns
        -------
        (shape) ndarray of ``array``'s dtype

        """
        return embed_at(array, shape, self.below, self.left, fill)

    def remap(self, flat, old_cols, new_cols):
        """
        Return flat cell indices of the old grid as flat indices of the grown one.

        Parameters
        ----------
        flat : (N,) ndarray of int64
            ``row * old_cols + col`` of old cells.
        old_cols, new_cols : int
            The column counts before and after.

        Returns
        -------
        (N,) ndarray of int64

        """
        flat = np.asarray(flat, dtype=np.int64)
        rows, cols = np.divmod(flat, old_cols)
        return (rows + self.below) * new_cols + (cols + self.left)

    def shift_window(self, rows, cols):
        """Return the slices of an old window as slices of the grown grid."""
        return (slice(rows.start + self.below, rows.stop + self.below),
                slice(cols.start + self.left, cols.stop + self.left))


def embed_at(array, shape, row0, col0, fill):
    """
    Return ``array`` copied into a new array of ``shape`` at ``(row0, col0)``, else ``fill``.

    Parameters
    ----------
    array : (rows, cols) ndarray
        The old values.
    shape : (int, int)
        At least ``(row0 + rows, col0 + cols)``.
    row0, col0 : int
        Where the old cell ``(0, 0)`` goes.
    fill : scalar
        The value of the other cells.

    Returns
    -------
    (shape) ndarray of ``array``'s dtype

    """
    rows, cols = array.shape
    if row0 < 0 or col0 < 0 or row0 + rows > shape[0] or col0 + cols > shape[1]:
        raise ValueError(f'a {rows} x {cols} grid does not fit into {shape} at '
                         f'({row0}, {col0})')
    grown = np.full(shape, fill, dtype=array.dtype)
    grown[row0:row0 + rows, col0:col0 + cols] = array
    return grown


def subgrid_offset(old, new):
    """
    Return where a sub-grid's old cell ``(0, 0)`` lies in its grown version, or None.

    A finer grid laid over the label grid (the fine free evidence, the surface memory) grows
    with it; its cells keep their places only when the origin moved by whole cells of its own.

    Parameters
    ----------
    old, new : GridGeometry
        The sub-grid before and after, of the same resolution.

    Returns
    -------
    (int, int) or None
        ``(row0, col0)``, or None when the origin moved by a fraction of a cell.

    """
    res = old.resolution
    offsets = []
    for before, after in zip(old.origin, new.origin):
        cells = (before - after) / res
        whole = round(cells)
        if abs(cells - whole) > WHOLE_CELL_TOLERANCE or whole < 0:
            return None
        offsets.append(whole)
    col0, row0 = offsets
    if row0 + old.rows > new.rows or col0 + old.cols > new.cols:
        return None
    return row0, col0


def growth_to_cover(geometry, x_min, x_max, y_min, y_max, step):
    """
    Return the growth that makes a grid cover a map-frame box, in whole blocks of cells.

    Parameters
    ----------
    geometry : GridGeometry
        The grid now.
    x_min, x_max, y_min, y_max : float
        The box to cover [m], finite.
    step : int
        Cells added on a side at a time, >= 1: a side that must grow grows by the fewest whole
        blocks that reach the box.

    Returns
    -------
    GridGrowth
        Empty (false) when the grid already covers the box.

    """
    if step < 1:
        raise ValueError(f'step must be >= 1 cell, got {step!r}')
    res = geometry.resolution
    x0, y0 = geometry.origin
    x1 = x0 + geometry.cols * res
    y1 = y0 + geometry.rows * res

    def blocks(short):
        return 0 if short <= 0.0 else step * math.ceil(short / (step * res) - 1e-9)

    return GridGrowth(below=blocks(y0 - y_min), above=blocks(y_max - y1),
                      left=blocks(x0 - x_min), right=blocks(x_max - x1))


def scan_hit_box(laser_pose, ranges, angle_min, angle_increment, range_min, range_max):
    """
    Return the map-frame box ``(x_min, x_max, y_min, y_max)`` of a scan's hits, or None.

    Only valid returns (``range_min <= r < range_max``) count: a beam with no return shows
    where nothing is, not a surface the map must hold.

    Parameters
    ----------
    laser_pose : (float, float, float)
        The laser's ``(x, y, yaw)`` in the map frame [m, m, rad].
    ranges : (L,) array_like of float
        Ranges [m].
    angle_min, angle_increment, range_min, range_max : float
        The scan's fields [rad, rad, m, m].

    Returns
    -------
    (float, float, float, float) or None
        None when no beam hit (or the fields do not make finite points). The box holds the
        laser's position too.

    """
    ranges = np.asarray(ranges, dtype=np.float64).ravel()
    valid = (ranges >= range_min) & (ranges < range_max)
    if not valid.any():
        return None
    cos_a, sin_a = beam_directions(ranges.shape[0], float(angle_min), float(angle_increment))
    # An invalid beam reaches 0 m: its point is the laser's, which the box may hold.
    reach = np.where(valid, ranges, 0.0)
    cos_y, sin_y = math.cos(laser_pose[2]), math.sin(laser_pose[2])
    along = reach * cos_a
    across = reach * sin_a
    x = cos_y * along - sin_y * across
    y = sin_y * along + cos_y * across
    box = (laser_pose[0] + float(x.min()), laser_pose[0] + float(x.max()),
           laser_pose[1] + float(y.min()), laser_pose[1] + float(y.max()))
    return box if all(math.isfinite(v) for v in box) else None


def scan_reach(ranges, range_min, range_max):
    """
    Return the longest valid range of a scan [m] (0 when none): its hits lie within it.

    Parameters
    ----------
    ranges : (L,) array_like of float
        Ranges [m].
    range_min, range_max : float
        The valid interval ``[range_min, range_max)`` [m].

    Returns
    -------
    float

    """
    ranges = np.asarray(ranges, dtype=np.float64)
    valid = (ranges >= range_min) & (ranges < range_max)
    return float(np.max(ranges, where=valid, initial=0.0))


@functools.lru_cache(maxsize=4)
def beam_directions(beams, angle_min, angle_increment):
    """Return the cosines and sines of a layout's beam angles in the laser frame (cached)."""
    angles = angle_min + np.arange(beams) * angle_increment
    cos_a, sin_a = np.cos(angles), np.sin(angles)
    cos_a.flags.writeable = sin_a.flags.writeable = False
    return cos_a, sin_a
