"""
Where two robots can pass each other: corridor widths across a path, and passing places.

Two pieces of grid geometry for the head-on yield state (``head_on_yield``), on the labelled
grid alone: how wide the free space is across a path, wall to wall, as f1's belt of steady
cells shows it (`corridor_widths`), and the free cell nearest to the robot, by a route over
free cells, among the cells that would let another robot pass (`passing_place`).

"""

import heapq
import math

import numpy as np


def corridor_widths(steady, cells, resolution, safety_radius, limit):
    """
    Estimate the wall-to-wall width of the free space across a path at each of its cells.

    Across the path (both ways along the normal to its local direction, in half-cell steps
    from one cell out) the free run ends at the first wall cell or the grid's edge, whose
    centre lies ``t`` cells across the path from the path cell's. f1 labels every cell within
    ``r`` of a hit, so the wall itself lies about ``r - res / 2`` beyond the centre of its
    first cell: the width is ``(t_left + t_right) * res + 2 r - res``, true to within one cell
    (where the f1 belt ends depends on where the wall falls between cell centres).

    Parameters
    ----------
    steady : (H, W) ndarray of bool
        Wall cells (steady obstacles); mobile and non-explored cells are not walls.
    cells : (N, 2) ndarray of int
        The path as ``(row, col)`` cells, ``N >= 1``, on the grid.
    resolution : float
        Cell side [m].
    safety_radius : float
        f1's ``r`` [m].
    limit : float
        Widths are not measured beyond this [m]: wider is reported as ``limit``.

    Returns
    -------
    widths : (N,) ndarray of float64
        [m], at most ``limit``.

    Raises
    ------
    ValueError
        When ``steady`` is not 2-D or ``cells`` is not a non-empty (N, 2) array.

    """
    steady = np.asarray(steady, dtype=bool)
    cells = np.asarray(cells, dtype=np.int64)
    if steady.ndim != 2:
        raise ValueError(f'steady must be a 2-D mask, got shape {steady.shape}')
    if cells.ndim != 2 or cells.shape[1] != 2 or cells.shape[0] == 0:
        raise ValueError(f'cells must be a non-empty (N, 2) array, got shape {cells.shape}')
    count = cells.shape[0]
    index = np.arange(count)
    direction = (cells[np.minimum(index + 1, count - 1)]
                 - cells[np.maximum(index - 1, 0)]).astype(np.float64)
    norm = np.hypot(direction[:, 0], direction[:, 1])
    direction[norm == 0.0] = (0.0, 1.0)              # a one-cell path: measure across rows
    norm[norm == 0.0] = 1.0
    across = np.column_stack((direction[:, 1], -direction[:, 0])) / norm[:, None]
    extra = 2.0 * safety_radius - resolution
    steps = max(1, math.ceil(2.0 * max(limit - extra, 0.0) / resolution))
    t = 1.0 + 0.5 * np.arange(steps)                 # [cells]
    reach = np.empty((2, count))
    rows, cols = steady.shape
    for side, sign in enumerate((1.0, -1.0)):
        rr = np.floor(cells[:, 0, None] + sign * t * across[:, 0, None] + 0.5).astype(np.int64)
        cc = np.floor(cells[:, 1, None] + sign * t * across[:, 1, None] + 0.5).astype(np.int64)
        inside = (rr >= 0) & (rr < rows) & (cc >= 0) & (cc < cols)
        wall = ~inside
        wall[inside] = steady[rr[inside], cc[inside]]
        first = np.argmax(wall, axis=1)
        # How far across the path the first wall cell's centre lies [cells].
        offset = np.abs((rr[index, first] - cells[:, 0]) * across[:, 0]
                        + (cc[index, first] - cells[:, 1]) * across[:, 1])
        reach[side] = np.where(wall.any(axis=1), offset, t[-1] + 0.5)
    return np.minimum((reach[0] + reach[1]) * resolution + extra, limit)


def passing_place(passable, candidate, start, resolution, search_distance):
    """
    Find the candidate cell nearest to ``start`` by a route over passable cells.

    Dijkstra over the 8-connected grid: steps of ``res`` and ``sqrt(2) res``, a diagonal step
    only between two passable cells (no corner cutting, as the navigator plans).

    Parameters
    ----------
    passable : (H, W) ndarray of bool
        Cells the robot may drive through (known free).
    candidate : (H, W) ndarray of bool
        Cells that are passing places.
    start : (int, int)
        The robot's cell; it is passable whatever ``passable`` says.
    resolution : float
        Cell side [m].
    search_distance : float
        Longest route [m].

    Returns
    -------
    route : (K, 2) ndarray of int64 or None
        Cells from ``start`` to the passing place, or None when none is in reach.

    """
    rows, cols = passable.shape
    start = (int(start[0]), int(start[1]))
    if not (0 <= start[0] < rows and 0 <= start[1] < cols):
        return None
    diagonal = math.sqrt(2.0) * resolution
    best = {start: 0.0}
    parent = {start: None}
    heap = [(0.0, start)]
    while heap:
        cost, cell = heapq.heappop(heap)
        if cost > best[cell]:
            continue
        if candidate[cell]:
            route = []
            while cell is not None:
                route.append(cell)
                cell = parent[cell]
            return np.array(route[::-1], dtype=np.int64)
        r, c = cell
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                nr, nc = r + dr, c + dc
                if (dr == 0 and dc == 0) or not (0 <= nr < rows and 0 <= nc < cols):
                    continue
                if not passable[nr, nc]:
                    continue
                if dr and dc and not (passable[r, nc] and passable[nr, c]):
                    continue
                step = diagonal if dr and dc else resolution
                new = cost + step
                if new <= search_distance and new < best.get((nr, nc), math.inf):
                    best[(nr, nc)] = new
                    parent[(nr, nc)] = cell
                    heapq.heappush(heap, (new, (nr, nc)))
    return None


def nearest_points(x, y, points_xy):
    """
    Distance from each point ``(x, y)`` to the nearest of ``points_xy``, and its index.

    Parameters
    ----------
    x, y : (P,) ndarray of float64
        Points [m].
    points_xy : (M, 2) ndarray of float64
        ``M >= 1`` points [m].

    Returns
    -------
    distance : (P,) ndarray of float64
        [m]
    index : (P,) ndarray of int64

    """
    distance = np.hypot(x[:, None] - points_xy[None, :, 0], y[:, None] - points_xy[None, :, 1])
    index = np.argmin(distance, axis=1)
    return distance[np.arange(x.shape[0]), index], index
