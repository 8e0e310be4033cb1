"""
A map design as data: its number, name, family, size, wall shapes and tasks.

The designs of the benchmark set (the ``sim_bridge.scenarios.maps_*`` modules) are built from
these pieces and the family builders (`sim_bridge.scenarios.families`), and listed in
`sim_bridge.scenarios.catalogue`; the generator (`sim_bridge.scenarios.generate`) rasterizes
them into map_server files and writes the index.

Conventions shared by every design: the map's lower-left corner is the origin, pixels are
``RESOLUTION`` on a side, the outer walls and most inner walls are ``WALL`` thick and lie on
pixel edges, and no passage the Husky must take is narrower than ``MIN_PASSAGE`` between wall
faces.

"""

from dataclasses import dataclass
import math

from .shapes import Rect

#: Pixel side of every generated map [m].
RESOLUTION = 0.1
#: Thickness of ordinary walls [m].
WALL = 0.2
#: Narrowest passage between wall faces [m]: the Husky's half width (0.35 m) plus the
#: navigator's safety radius (0.6 m) on either side of its centre, rounded up. The narrow-route
#: maps use exactly this width in their narrow parts.
MIN_PASSAGE = 2.0
#: Start headings [rad], rounded as the index writes them.
EAST = 0.0
NORTH = round(0.5 * math.pi, 4)
WEST = round(math.pi, 4)
SOUTH = round(-0.5 * math.pi, 4)


@dataclass(frozen=True)
class TaskSpec:
    """
    One task of a design: the Husky's start pose, the goal and what the task tests.

    Attributes
    ----------
    start : (float, float, float)
        Start pose ``(x, y, yaw)`` in the map frame [m, m, rad].
    goal : (float, float)
        Goal position ``(x, y)`` [m].
    note : str
        A short comment for the index.

    """

    start: tuple
    goal: tuple
    note: str = ''


@dataclass(frozen=True)
class MapDesign:
    """
    One map of the benchmark set.

    Attributes
    ----------
    number : int
        Its number in the set, 1 to 34.
    name : str
        Unique snake_case name; also the stem of its files.
    family : str
        Layout class (``corridors``, ``maze``, ``trap``, ``dense``, ``rooms``, ...).
    size : (float, float)
        Width and height [m].
    walls : tuple of shapes
        `sim_bridge.scenarios.shapes` shapes, painted in order.
    tasks : tuple of TaskSpec
        Three tasks.
    passage : float
        Narrowest passage every task's route must take, between wall faces [m];
        ``MIN_PASSAGE`` for the narrow-route maps.
    note : str
        A one-line description for the index.

    """

    number: int
    name: str
    family: str
    size: tuple
    walls: tuple
    tasks: tuple
    passage: float
    note: str


def task(start, goal, note=''):
    """
    Return a `TaskSpec` with its numbers rounded for the index.

    Parameters
    ----------
    start : (float, float, float)
        Start pose ``(x, y, yaw)`` [m, m, rad].
    goal : (float, float)
        Goal ``(x, y)`` [m].
    note : str
        A short comment.

    Returns
    -------
    TaskSpec

    """
    return TaskSpec(tuple(round(float(v), 4) for v in start),
                    tuple(round(float(v), 4) for v in goal), note)


def outer_walls(width, height, thickness=WALL):
    """
    Return the four walls that close a map: bottom, top, left, right.

    Parameters
    ----------
    width, height : float
        Map size [m].
    thickness : float
        Wall thickness [m], inside the map.

    Returns
    -------
    walls : list of Rect

    """
    return [Rect(0.0, 0.0, width, thickness), Rect(0.0, height - thickness, width, height),
            Rect(0.0, 0.0, thickness, height), Rect(width - thickness, 0.0, width, height)]


def hwall(x0, x1, y, gaps=(), thickness=WALL):
    """
    Return a horizontal wall from ``x0`` to ``x1`` with its lower face at ``y``, with gaps.

    Parameters
    ----------
    x0, x1 : float
        Its extent along x [m].
    y : float
        Its lower face [m]; the wall covers ``[y, y + thickness]``.
    gaps : sequence of (float, float)
        Openings ``(x_start, x_end)`` [m] cut out of it (doors).
    thickness : float
        Wall thickness [m].

    Returns
    -------
    walls : list of Rect

    """
    return [Rect(a, y, b, y + thickness) for a, b in _pieces(x0, x1, gaps)]


def vwall(x, y0, y1, gaps=(), thickness=WALL):
    """
    Return a vertical wall from ``y0`` to ``y1`` with its left face at ``x``, with gaps.

    Parameters
    ----------
    x : float
        Its left face [m]; the wall covers ``[x, x + thickness]``.
    y0, y1 : float
        Its extent along y [m].
    gaps : sequence of (float, float)
        Openings ``(y_start, y_end)`` [m] cut out of it (doors).
    thickness : float
        Wall thickness [m].

    Returns
    -------
    walls : list of Rect

    """
    return [Rect(x, a, x + thickness, b) for a, b in _pieces(y0, y1, gaps)]


def _pieces(lo, hi, gaps):
    """Return the intervals of ``[lo, hi]`` left between sorted, disjoint gaps."""
    pieces = []
    for gap_lo, gap_hi in sorted(gaps):
        if gap_lo > lo:
            pieces.append((lo, gap_lo))
        lo = max(lo, gap_hi)
    if hi > lo:
        pieces.append((lo, hi))
    return pieces


def random_stream(seed=0):
    """
    Yield a reproducible stream of numbers in ``[0, 1)`` (SplitMix64).

    The designs that scatter obstacles or carve mazes draw from it rather than from numpy or
    `random`, whose streams may change between versions: the generated files must stay
    byte-identical. Nearby seeds give unrelated streams.

    Parameters
    ----------
    seed : int
        Seed; the same seed gives the same numbers.

    Yields
    ------
    value : float
        A multiple of ``2**-53``.

    """
    mask = 2 ** 64 - 1
    state = seed & mask
    while True:
        state = (state + 0x9E3779B97F4A7C15) & mask
        mixed = ((state ^ (state >> 30)) * 0xBF58476D1CE4E5B9) & mask
        mixed = ((mixed ^ (mixed >> 27)) * 0x94D049BB133111EB) & mask
        mixed ^= mixed >> 31
        yield (mixed >> 11) / 2 ** 53
