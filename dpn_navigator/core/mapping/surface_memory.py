"""
Intermittent surfaces: places the laser has hit for a while are surfaces, not motion.

A real laser's surfaces flicker: a dark or far object, or a wall seen at grazing incidence,
returns in some scans and not in others (no echo), and the scans that miss it see the space it
stands in empty. The next hit there looks like motion (the place was surely seen free) although
nothing moved. A walker, though, stands on one place only briefly: a leg's stance at walking
pace lasts about 0.6 s.

So each place (a square cell of side ``margin``, the laser's range noise) keeps a leaky bucket
of *hit time*: every scan that hits the place adds the time since the scan before (at most
`MAX_SCAN_PERIOD`), except with the hits of an object followed and seen to move (a moving
body's side slides over a place longer than a leg stands), and the bucket drains by
``surface_time`` every ``memory`` seconds, holding at most twice ``surface_time``. A place
whose bucket holds at least ``surface_time`` is a **known surface**; a hit on a place within
one cell of a known surface (within about the range noise of it) shows no motion and
continues no motion track.

Two compiled kernels per scan (``_kernels.surface_memory``); only additions, subtractions
and products, so the literal twin of the tests (``test/reference/real_sensor_rules.py``)
computes the same floats one hit at a time.

"""

import numpy as np

from .map_growth import embed_at, subgrid_offset
from .._kernels import surface_memory as surface_kernels
from ..grid_geometry import GridGeometry

#: Largest time one scan adds to a place's bucket [s] (a gap in the scans is no hit time).
MAX_SCAN_PERIOD = 0.5

#: Largest side of the memory, in cells (as the fine evidence's).
MAX_CELLS = 8192


class SurfaceMemory:
    """
    Leaky buckets of hit time over the label grid's extent, and the hits on known surfaces.

    Parameters
    ----------
    geometry : GridGeometry
        The label grid's placement; the memory covers the same rectangle.
    margin : float
        Side of a place [m] (about the laser's range noise), > 0.
    surface_time : float
        Hit time that makes a place a known surface [s], > 0.
    memory : float
        The bucket drains ``surface_time`` in this long [s], > 0.

    """

    def __init__(self, geometry, margin, surface_time, memory):
        for name, value in (('margin', margin), ('surface_time', surface_time),
                            ('memory', memory)):
            if not float(value) > 0.0:
                raise ValueError(f'{name} must be > 0, got {value!r}')
        self.geometry = GridGeometry(geometry.width, geometry.height, float(margin),
                                     origin=tuple(geometry.origin))
        if max(self.geometry.shape) > MAX_CELLS:
            raise ValueError(f'the surface memory would have {self.geometry.rows} x '
                             f'{self.geometry.cols} cells of {margin} m (at most {MAX_CELLS} '
                             'a side): raise noise_margin or use a smaller map')
        self.surface_time = float(surface_time)
        self.drain = self.surface_time / float(memory)      # [s of hit time per s]
        self.capacity = 2.0 * self.surface_time
        self.hit_time = np.zeros(self.geometry.shape)        # [s], at `stamp`
        self.filled = np.full(self.geometry.shape, -np.inf)  # when last filled [s]
        self._last_scan = None

    def grow(self, geometry):
        """
        Cover the grown label grid's ``geometry``; places keep their hit time.

        When the label grid's origin moved by a fraction of a place, the memory starts again
        empty.

        Raises
        ------
        ValueError
            When the grown memory would exceed ``MAX_CELLS`` a side (``Navigator`` checks
            first, with `cells_for`).

        """
        new = GridGeometry(geometry.width, geometry.height, self.geometry.resolution,
                           origin=tuple(geometry.origin))
        if max(new.shape) > MAX_CELLS:
            raise ValueError(f'the surface memory would have {new.rows} x {new.cols} cells '
                             f'(at most {MAX_CELLS} a side)')
        offset = subgrid_offset(self.geometry, new)
        if offset is None:
            self.hit_time = np.zeros(new.shape)
            self.filled = np.full(new.shape, -np.inf)
        else:
            self.hit_time = embed_at(self.hit_time, new.shape, *offset, 0.0)
            self.filled = embed_at(self.filled, new.shape, *offset, -np.inf)
        self.geometry = new

    def cells_for(self, geometry):
        """Return the ``(rows, cols)`` this memory would have over ``geometry``."""
        return GridGeometry(geometry.width, geometry.height, self.geometry.resolution,
                            origin=tuple(geometry.origin)).shape

    @property
    def nbytes(self):
        """Bytes held by the per-place arrays."""
        return self.hit_time.nbytes + self.filled.nbytes

    def on_surface(self, hits_x, hits_y, stamp):
        """
        Tell which hits of a scan lie on known surfaces.

        A hit is on a known surface when a place within one row and column of its own holds
        at least ``surface_time`` of hit time at ``stamp``.

        Parameters
        ----------
        hits_x, hits_y : (K,) ndarray of float64
            The scan's hit points [m].
        stamp : float
            Its time [s].

        Returns
        -------
        (K,) ndarray of bool

        """
        x0, y0 = self.geometry.origin
        return surface_kernels.surface_known(
            self.hit_time, self.filled, np.ascontiguousarray(hits_x, dtype=np.float64),
            np.ascontiguousarray(hits_y, dtype=np.float64), float(x0), float(y0),
            self.geometry.resolution, float(stamp), self.drain, self.surface_time)

    def fill(self, hits_x, hits_y, stamp, fill=None):
        """
        Fill the places a scan hit, once per place.

        Each place hit (by a hit marked in ``fill``) gains the time since the scan before (at
        most `MAX_SCAN_PERIOD`; nothing for the first scan or one no newer), up to twice
        ``surface_time``.

        Parameters
        ----------
        hits_x, hits_y : (K,) ndarray of float64
            The scan's hit points [m].
        stamp : float
            Its time [s].
        fill : (K,) ndarray of bool, optional
            The hits that fill their place; default all.

        """
        period = 0.0 if self._last_scan is None else min(max(stamp - self._last_scan, 0.0),
                                                         MAX_SCAN_PERIOD)
        self._last_scan = stamp
        x0, y0 = self.geometry.origin
        hits_x = np.ascontiguousarray(hits_x, dtype=np.float64)
        fill = (np.ones(hits_x.shape[0], dtype=bool) if fill is None
                else np.ascontiguousarray(fill, dtype=bool))
        surface_kernels.surface_fill(
            self.hit_time, self.filled, hits_x, np.ascontiguousarray(hits_y, dtype=np.float64),
            fill, float(x0), float(y0), self.geometry.resolution, float(stamp), self.drain,
            self.capacity, period)

    def reset(self):
        """Forget every surface."""
        self.hit_time.fill(0.0)
        self.filled.fill(-np.inf)
        self._last_scan = None
