"""
Builders of the benchmark maps' recurring layouts.

Bands and wall polylines, solid rock, mazes, square spirals and scattered posts.

Each returns a list of `sim_bridge.scenarios.shapes` shapes in the map frame [m]; the map
designs (the ``sim_bridge.scenarios.maps_*`` modules) combine them with hand-placed walls.

"""

import math

from .design import random_stream, RESOLUTION, WALL
from .shapes import Blocky, Disc, rasterize, Rect, Segment
from ..walls import merge_cells


def band(points, width):
    """
    Return a band of a given width along a polyline: a wall, or with `Free` a passage.

    An axis-aligned piece becomes a `Rect` that runs past its end points by half the width,
    so that corners close squarely; a slanted piece becomes a `Segment`, whose round ends
    close the joints.

    Parameters
    ----------
    points : sequence of (float, float)
        The band's centre line [m].
    width : float
        Its width [m].

    Returns
    -------
    shapes : list of Rect or Segment

    """
    half = 0.5 * width
    shapes = []
    for (xa, ya), (xb, yb) in zip(points[:-1], points[1:]):
        if xa == xb or ya == yb:
            shapes.append(Rect(_r(min(xa, xb) - half), _r(min(ya, yb) - half),
                               _r(max(xa, xb) + half), _r(max(ya, yb) + half)))
        else:
            shapes.append(Segment(xa, ya, xb, yb, width))
    return shapes


def polyline_walls(points, thickness=WALL):
    """Return a wall of a given thickness [m] along a polyline [m] (see `band`)."""
    return band(points, thickness)


def rock(size, keep_free, step=0.5):
    """
    Fill with rectangles every block of a map that keeps clear of some shapes.

    Used to make the ground beyond a slanted or round wall solid, so that no unreachable
    pocket is left for the wanderers to spawn in, with a few large boxes rather than one per
    pixel row.

    Parameters
    ----------
    size : (float, float)
        Map width and height [m].
    keep_free : sequence of shapes
        Regions that must stay free; a block is filled when none of its pixels lies in one.
    step : float
        Side of a block [m], a whole number of pixels.

    Returns
    -------
    walls : list of Rect
        Blocks merged into rectangles: runs along x, stacked along y when they repeat.

    """
    image = rasterize(keep_free, size, RESOLUTION)[::-1] == 0
    factor = int(round(step / RESOLUTION))
    rows, cols = image.shape[0] // factor, image.shape[1] // factor
    touched = image[:rows * factor, :cols * factor].reshape(rows, factor, cols, factor)
    rects = merge_cells(~touched.any(axis=(1, 3)))
    return [Rect(c * step, r * step, (c + n_c) * step, (r + n_r) * step)
            for r, c, n_r, n_c in rects.tolist()]


def maze(origin, cells, corridor, seed, rooms=(), loops=0, thickness=WALL):
    """
    Return the walls of a maze on a grid of square cells, closed all round.

    A perfect maze is carved by a depth-first search whose choices come from
    `design.random_stream`; ``loops`` extra walls are then removed to give it cycles, and the
    cells of each room are joined into one open area.

    Parameters
    ----------
    origin : (float, float)
        Lower-left corner of the maze's outer wall [m].
    cells : (int, int)
        Columns and rows of cells.
    corridor : float
        Free width of a cell between wall faces [m]; the cell pitch is
        ``corridor + thickness``.
    seed : int
        Seed of the carving.
    rooms : sequence of (int, int, int, int)
        Open areas ``(col, row, n_cols, n_rows)`` of cells.
    loops : int
        Extra walls removed.
    thickness : float
        Wall thickness [m].

    Returns
    -------
    walls : list of Rect

    """
    n_cols, n_rows = cells
    rand = random_stream(seed)
    passages = set()
    seen = {(0, 0)}
    stack = [(0, 0)]
    while stack:
        c, r = stack[-1]
        nexts = [(c + dc, r + dr) for dc, dr in ((1, 0), (0, 1), (-1, 0), (0, -1))
                 if 0 <= c + dc < n_cols and 0 <= r + dr < n_rows and
                 (c + dc, r + dr) not in seen]
        if not nexts:
            stack.pop()
            continue
        cell = nexts[int(next(rand) * len(nexts))]
        passages.add(frozenset(((c, r), cell)))
        seen.add(cell)
        stack.append(cell)
    inner = sorted(
        [((c, r), (c + 1, r)) for c in range(n_cols - 1) for r in range(n_rows)] +
        [((c, r), (c, r + 1)) for c in range(n_cols) for r in range(n_rows - 1)])
    closed = [pair for pair in inner if frozenset(pair) not in passages]
    for _ in range(loops):
        passages.add(frozenset(closed.pop(int(next(rand) * len(closed)))))
    for c0, r0, n_c, n_r in rooms:
        for a, b in inner:
            if all(c0 <= c < c0 + n_c and r0 <= r < r0 + n_r for c, r in (a, b)):
                passages.add(frozenset((a, b)))
    pitch = corridor + thickness
    x0, y0 = origin

    def is_open(a, b):
        inside = all(0 <= c < n_cols and 0 <= r < n_rows for c, r in (a, b))
        return inside and frozenset((a, b)) in passages

    walls = []
    for k in range(n_rows + 1):  # horizontal lines, below row k
        pieces = runs_of([not is_open((c, k - 1), (c, k)) for c in range(n_cols)])
        walls += [Rect(_r(x0 + a * pitch), _r(y0 + k * pitch), _r(x0 + b * pitch + thickness),
                       _r(y0 + k * pitch + thickness)) for a, b in pieces]
    for k in range(n_cols + 1):  # vertical lines, left of column k
        pieces = runs_of([not is_open((k - 1, r), (k, r)) for r in range(n_rows)])
        walls += [Rect(_r(x0 + k * pitch), _r(y0 + a * pitch), _r(x0 + k * pitch + thickness),
                       _r(y0 + b * pitch + thickness)) for a, b in pieces]
    return walls


def runs_of(flags):
    """Return the ``(start, end)`` index ranges of the runs of True in a list."""
    found = []
    start = None
    for k, flag in enumerate(list(flags) + [False]):
        if flag and start is None:
            start = k
        elif not flag and start is not None:
            found.append((start, k))
            start = None
    return found


def _r(value):
    """Round a coordinate to 1 um, dropping floating-point noise such as 4.3999999999."""
    return round(value, 6)


def spiral_points(centre, pitch, n_pieces, heading=0, first=1):
    """
    Return the corners of a square spiral, wound outwards anticlockwise from its centre.

    Its pieces are ``first`` pitches long, twice, then one pitch longer every second piece,
    so that successive turns lie ``pitch`` apart.

    Parameters
    ----------
    centre : (float, float)
        The first point [m].
    pitch : float
        Growth of the piece length every second piece [m].
    n_pieces : int
        Number of pieces.
    heading : int
        Direction of the first piece, in quarter turns from +x.
    first : int
        Length of the first two pieces, in pitches.

    Returns
    -------
    points : list of (float, float)

    """
    x, y = centre
    points = [(_r(x), _r(y))]
    for k in range(n_pieces):
        length = (first + k // 2) * pitch
        angle = 0.5 * math.pi * (heading + k)
        x += round(math.cos(angle)) * length
        y += round(math.sin(angle)) * length
        points.append((_r(x), _r(y)))
    return points


def scatter(area, count, sizes, seed, gap=2.6, round_share=0.0, round_step=None, keep_out=(),
            attempts=None):
    """
    Return posts thrown at random into an area, squares and discs, at least ``gap`` apart.

    Dart throwing: a candidate post is kept when its circumscribed circle keeps ``gap`` from
    every kept post's and from the area's edges, and stays out of the ``keep_out`` discs;
    candidates come from `design.random_stream`. Centres and sizes are rounded to the pixel.

    Parameters
    ----------
    area : (float, float, float, float)
        ``(x_min, y_min, x_max, y_max)``, the free space inside the walls [m].
    count : int
        How many posts at most.
    sizes : (float, float)
        Smallest and largest side (or diameter) of a post [m].
    seed : int
        Seed of the throw.
    gap : float
        Least free gap between two posts [m].
    round_share : float
        Share of the posts that are discs, 0 to 1.
    round_step : float, optional
        Draw the discs as `Blocky` staircases of this step [m] (far fewer pybullet boxes than
        a disc drawn pixel by pixel); pixel by pixel by default.
    keep_out : sequence of (float, float, float)
        Discs ``(x, y, radius)`` [m] no post may reach into (task positions, doors).
    attempts : int, optional
        Candidates to try; ``50 * count`` by default.

    Returns
    -------
    walls : list of Rect, Disc or Blocky

    """
    x_min, y_min, x_max, y_max = area
    rand = random_stream(seed)
    kept = []  # (x, y, circumscribed radius)
    posts = []
    for _ in range(50 * count if attempts is None else attempts):
        if len(posts) == count:
            break
        u, v, w, kind = (next(rand) for _ in range(4))
        side = round(sizes[0] + w * (sizes[1] - sizes[0]), 1)
        is_round = kind < round_share
        # Circumscribed radius, with what a staircase disc may grow by.
        if is_round:
            radius = 0.5 * side + (0.0 if round_step is None else round_step)
        else:
            radius = 0.5 * side * math.sqrt(2.0)
        margin = radius + gap
        x = round(x_min + margin + u * (x_max - x_min - 2.0 * margin), 1)
        y = round(y_min + margin + v * (y_max - y_min - 2.0 * margin), 1)
        if any(math.hypot(x - kx, y - ky) < kr + radius + gap for kx, ky, kr in kept) or \
                any(math.hypot(x - kx, y - ky) < kr + radius for kx, ky, kr in keep_out):
            continue
        kept.append((x, y, radius))
        if is_round:
            disc = Disc(x, y, 0.5 * side)
            posts.append(disc if round_step is None else Blocky(disc, round_step, RESOLUTION))
        else:
            posts.append(Rect(_r(x - 0.5 * side), _r(y - 0.5 * side),
                              _r(x + 0.5 * side), _r(y + 0.5 * side)))
    return posts
