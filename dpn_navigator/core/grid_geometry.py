"""
World <-> cell conversion for a regular 2-D grid: the one place that owns coordinates.

Cells are indexed ``(row, col) = (i, j)`` with rows running along +y and columns along +x,
row-major like ``nav_msgs/OccupancyGrid``. Cell ``(i, j)`` covers
``[x0 + j * res, x0 + (j + 1) * res) x [y0 + i * res, y0 + (i + 1) * res)`` in the map frame and
has its centre at ``(x0 + (j + 0.5) * res, y0 + (i + 0.5) * res)``.

"""

from dataclasses import dataclass, field
import functools
import math

import numpy as np


def _finite(value, name):
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f'{name} must be finite, got {value!r}')
    return value


@dataclass(frozen=True)
class GridGeometry:
    """
    Size, resolution and placement of a grid in the map frame.

    Parameters
    ----------
    width, height : float
        Extent of the covered area along x and y [m]; positive and finite.
    resolution : float
        Side of one square cell [m]; positive and finite.
    origin : (float, float)
        Map-frame position of the grid's lower-left corner ``(x0, y0)`` [m].

    Attributes
    ----------
    rows, cols : int
        ``ceil(height / resolution)`` and ``ceil(width / resolution)``.

    """

    width: float
    height: float
    resolution: float
    origin: tuple = (0.0, 0.0)
    rows: int = field(init=False)
    cols: int = field(init=False)

    def __post_init__(self):
        width = _finite(self.width, 'width')
        height = _finite(self.height, 'height')
        resolution = _finite(self.resolution, 'resolution')
        if width <= 0.0 or height <= 0.0:
            raise ValueError(f'width and height must be positive, got {width!r} x {height!r} m')
        if resolution <= 0.0:
            raise ValueError(f'resolution must be positive, got {resolution!r} m')
        if len(self.origin) != 2:
            raise ValueError(f'origin must be (x0, y0) in metres, got {self.origin!r}')
        origin = (_finite(self.origin[0], 'origin x'), _finite(self.origin[1], 'origin y'))
        object.__setattr__(self, 'width', width)
        object.__setattr__(self, 'height', height)
        object.__setattr__(self, 'resolution', resolution)
        object.__setattr__(self, 'origin', origin)
        # A tiny relative slack keeps 40.0 / 0.5 from becoming 81 cells through rounding.
        object.__setattr__(self, 'rows', max(1, math.ceil(height / resolution - 1e-9)))
        object.__setattr__(self, 'cols', max(1, math.ceil(width / resolution - 1e-9)))

    @property
    def shape(self):
        """Grid shape ``(rows, cols)``."""
        return (self.rows, self.cols)

    def world_to_cell(self, x, y):
        """
        Cell indices of map-frame points, without bounds checking.

        Parameters
        ----------
        x, y : float or ndarray of float
            Map-frame coordinates [m]; any shape, broadcast together; finite.

        Returns
        -------
        rr, cc : ndarray of int64
            Row and column of the cell containing each point (may lie outside the grid).

        """
        x0, y0 = self.origin
        cc = np.floor((np.asarray(x, dtype=np.float64) - x0) / self.resolution).astype(np.int64)
        rr = np.floor((np.asarray(y, dtype=np.float64) - y0) / self.resolution).astype(np.int64)
        return rr, cc

    def cell_to_world(self, rr, cc):
        """
        Map-frame centres of cells.

        Parameters
        ----------
        rr, cc : int or ndarray of int
            Row and column indices; any shape, broadcast together.

        Returns
        -------
        x, y : ndarray of float64
            Cell centres [m], ``x0 + (cc + 0.5) * res`` and ``y0 + (rr + 0.5) * res``.

        """
        x0, y0 = self.origin
        x = x0 + (np.asarray(cc, dtype=np.float64) + 0.5) * self.resolution
        y = y0 + (np.asarray(rr, dtype=np.float64) + 0.5) * self.resolution
        return x, y

    def contains_cell(self, rr, cc):
        """Boolean mask (broadcast shape of ``rr``, ``cc``): True where the cell is on the grid."""
        rr = np.asarray(rr)
        cc = np.asarray(cc)
        return (rr >= 0) & (rr < self.rows) & (cc >= 0) & (cc < self.cols)

    def cell_window(self, x_min, x_max, y_min, y_max, margin=1):
        """
        Slices of the rows and columns that hold every cell centre in a map-frame box.

        The window is widened by ``margin`` cells on every side, so that cells whose centre lies
        exactly on the box edge are never lost to rounding, and clipped to the grid.

        Parameters
        ----------
        x_min, x_max, y_min, y_max : float
            The box [m]; finite, ``x_min <= x_max`` and ``y_min <= y_max``.
        margin : int
            Extra cells on each side.

        Returns
        -------
        rows, cols : slice
            Row and column slices, possibly empty when the box misses the grid.

        """
        x0, y0 = self.origin
        res = self.resolution
        # math.floor gives Python ints, so a box far off the map cannot overflow here.
        c_lo = int(min(max(math.floor((x_min - x0) / res) - margin, 0), self.cols))
        c_hi = int(min(max(math.floor((x_max - x0) / res) + margin + 1, 0), self.cols))
        r_lo = int(min(max(math.floor((y_min - y0) / res) - margin, 0), self.rows))
        r_hi = int(min(max(math.floor((y_max - y0) / res) + margin + 1, 0), self.rows))
        return slice(r_lo, max(r_lo, r_hi)), slice(c_lo, max(c_lo, c_hi))

    def window_centres(self, rows, cols):
        """
        Centre coordinates of the cells in a window.

        Parameters
        ----------
        rows, cols : slice
            A window as returned by :meth:`cell_window`.

        Returns
        -------
        x_centres : (n_cols,) ndarray of float64
            Map-frame x of each column's centres [m].
        y_centres : (n_rows,) ndarray of float64
            Map-frame y of each row's centres [m].

        """
        x_centres, _ = self.cell_to_world(0, np.arange(cols.start, cols.stop))
        _, y_centres = self.cell_to_world(np.arange(rows.start, rows.stop), 0)
        return np.asarray(x_centres, dtype=np.float64), np.asarray(y_centres, dtype=np.float64)


def squared_radius_bound(radius):
    """
    Largest float ``t`` with ``sqrt(t) <= radius``, so that ``sqrt(s) <= radius`` iff ``s <= t``.

    ``sqrt`` is correctly rounded and hence monotone, so the floats that pass eq. 2's test form
    the interval ``[0, t]``; comparing squared distances with ``t`` gives the same answers
    without a square root per cell.

    """
    bound = radius * radius
    while math.sqrt(bound) > radius:
        bound = math.nextafter(bound, -math.inf)
    while math.sqrt(math.nextafter(bound, math.inf)) <= radius:
        bound = math.nextafter(bound, math.inf)
    return bound


@functools.lru_cache(maxsize=64)
def squared_bound(radius):
    """Return ``squared_radius_bound(radius)``, remembered: a grid's radii never change."""
    return squared_radius_bound(radius)
