"""
Wall shapes of the generated maps, and their rasterization into a map_server image.

A map design paints shapes onto a grid of 0.1 m pixels in order: a `Rect`, `Segment` or `Disc`
turns the pixels whose **centre** lies strictly inside it into wall, and a shape wrapped in
`Free` turns them back into free space (to carve a tunnel out of solid rock, say). Only
`Rect` gives axis-aligned faces exactly on pixel edges; the others are staircases, and every
pixel row they cross becomes at least one pybullet box (see `sim_bridge.walls.merge_cells`).
Boxes in the laser's view cost simulation time, so designs use them sparingly, or coarsen
them with `Blocky` into staircases of larger steps, whose rows merge into one box per step.

"""

from dataclasses import dataclass
import math

from dpn_navigator.core import GridGeometry
import numpy as np

# Pixel values as map_saver writes them.
FREE_PIXEL = 254
OCCUPIED_PIXEL = 0


@dataclass(frozen=True)
class Rect:
    """
    An axis-aligned rectangle ``(x_min, y_min, x_max, y_max)`` in the map frame [m].

    A pixel belongs to it when its centre lies strictly inside.
    """

    x_min: float
    y_min: float
    x_max: float
    y_max: float

    def bounds(self):
        """Return the bounding box ``(x_min, y_min, x_max, y_max)`` [m]."""
        return (self.x_min, self.y_min, self.x_max, self.y_max)

    def contains(self, xs, ys):
        """Return a mask of the points ``(xs, ys)`` [m] strictly inside the rectangle."""
        return (xs > self.x_min) & (xs < self.x_max) & (ys > self.y_min) & (ys < self.y_max)


@dataclass(frozen=True)
class Segment:
    """
    A straight wall of a given thickness between two points, with round ends (a capsule).

    Attributes
    ----------
    x0, y0, x1, y1 : float
        The end points of its centre line in the map frame [m].
    thickness : float
        The wall's thickness [m]: points closer than half of it to the centre line are inside.

    """

    x0: float
    y0: float
    x1: float
    y1: float
    thickness: float

    def bounds(self):
        """Return the bounding box ``(x_min, y_min, x_max, y_max)`` [m]."""
        half = 0.5 * self.thickness
        return (min(self.x0, self.x1) - half, min(self.y0, self.y1) - half,
                max(self.x0, self.x1) + half, max(self.y0, self.y1) + half)

    def contains(self, xs, ys):
        """Return a mask of the points ``(xs, ys)`` [m] closer than half the thickness."""
        dx, dy = self.x1 - self.x0, self.y1 - self.y0
        length2 = dx * dx + dy * dy
        if length2 == 0.0:
            along = np.zeros_like(xs)
        else:
            along = np.clip(((xs - self.x0) * dx + (ys - self.y0) * dy) / length2, 0.0, 1.0)
        return np.hypot(xs - self.x0 - along * dx, ys - self.y0 - along * dy) < \
            0.5 * self.thickness


@dataclass(frozen=True)
class Disc:
    """
    A disc, or with ``inner > 0`` a ring, centred at ``(x, y)`` [m].

    Attributes
    ----------
    x, y : float
        The centre in the map frame [m].
    radius : float
        Points closer than it to the centre are inside [m].
    inner : float
        Points closer than it to the centre are outside [m]; 0 for a full disc.

    """

    x: float
    y: float
    radius: float
    inner: float = 0.0

    def bounds(self):
        """Return the bounding box ``(x_min, y_min, x_max, y_max)`` [m]."""
        return (self.x - self.radius, self.y - self.radius,
                self.x + self.radius, self.y + self.radius)

    def contains(self, xs, ys):
        """Return a mask of the points ``(xs, ys)`` [m] inside the disc or ring."""
        distance = np.hypot(xs - self.x, ys - self.y)
        return (distance < self.radius) & (distance >= self.inner)


@dataclass(frozen=True)
class Blocky:
    """
    A shape coarsened to square blocks: a pixel is inside when any pixel of its block is.

    Blocks are ``step`` on a side and aligned on multiples of it from the origin. A slanted or
    round wall so becomes a staircase whose pixel rows repeat ``step / resolution`` times, and
    so far fewer pybullet boxes; it stays closed, and grows by up to a block on either side.

    Attributes
    ----------
    shape : Rect, Segment or Disc
        The shape to coarsen.
    step : float
        Block side [m], a whole number of pixels.
    resolution : float
        Pixel side [m].

    """

    shape: object
    step: float
    resolution: float

    def bounds(self):
        """Return the bounding box of the blocks the shape touches [m]."""
        x_min, y_min, x_max, y_max = self.shape.bounds()
        step = self.step
        return (math.floor(x_min / step) * step, math.floor(y_min / step) * step,
                math.ceil(x_max / step) * step, math.ceil(y_max / step) * step)

    def contains(self, xs, ys):
        """Return a mask of the pixel centres ``(xs, ys)`` [m] whose block meets the shape."""
        step, res = self.step, self.resolution
        x0 = np.floor(xs / step) * step
        y0 = np.floor(ys / step) * step
        inside = np.zeros(np.broadcast(xs, ys).shape, dtype=bool)
        for i in range(int(round(step / res))):
            for j in range(int(round(step / res))):
                inside |= self.shape.contains(x0 + (i + 0.5) * res, y0 + (j + 0.5) * res)
        return inside


@dataclass(frozen=True)
class Free:
    """
    A shape whose pixels are made free again, painted in turn with the walls.

    Attributes
    ----------
    shape : Rect, Segment, Disc or Blocky
        The region to clear.

    """

    shape: object

    def bounds(self):
        """Return the wrapped shape's bounding box [m]."""
        return self.shape.bounds()

    def contains(self, xs, ys):
        """Return the wrapped shape's mask of the points ``(xs, ys)`` [m]."""
        return self.shape.contains(xs, ys)


def rasterize(shapes, size, resolution):
    """
    Paint shapes, in order, into a map_server image.

    Parameters
    ----------
    shapes : sequence of Rect, Segment, Disc, Blocky or Free
        Walls (`Free` ones clear their pixels instead) in the map frame [m].
    size : (float, float)
        Map width and height [m]; the origin is ``(0, 0)``.
    resolution : float
        Pixel side [m].

    Returns
    -------
    image : (rows, cols) ndarray of uint8
        254 for free and 0 for wall pixels; row 0 is the top of the map, as in a PGM.

    """
    geometry = GridGeometry(size[0], size[1], resolution)
    wall = np.zeros(geometry.shape, dtype=bool)
    for shape in shapes:
        x_min, y_min, x_max, y_max = shape.bounds()
        if not (math.isfinite(x_min + y_min + x_max + y_max) and x_min <= x_max and
                y_min <= y_max):
            raise ValueError(f'shape {shape!r} has no finite extent')
        rows, cols = geometry.cell_window(x_min, x_max, y_min, y_max)
        xs, ys = np.meshgrid(*geometry.window_centres(rows, cols))
        wall[rows, cols] = np.where(shape.contains(xs, ys), not isinstance(shape, Free),
                                    wall[rows, cols])
    image = np.where(wall, OCCUPIED_PIXEL, FREE_PIXEL).astype(np.uint8)
    return image[::-1]
