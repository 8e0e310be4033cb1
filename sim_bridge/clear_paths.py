"""
Paths through a coarse clearance grid: windowed A*, temporary obstacles and turning points.

The wanderers plan with these on ``~ClearanceGrid.clear`` (see `sim_bridge.free_space`). A* is
`dpn_navigator.core.astar`; it runs first on a window around start and goal, which is all a
walk of a few metres needs, and on the whole grid only when the window holds no path.

"""

from dpn_navigator.core import astar
import numpy as np

#: Margin of the A* window around start and goal [m].
WINDOW_MARGIN = 5.0


def plan_path(geometry, blocked, start, goal, window_margin=WINDOW_MARGIN):
    """
    Plan an 8-connected least-cost path, first within a window around start and goal.

    Parameters
    ----------
    geometry : GridGeometry
        The grid.
    blocked : (rows, cols) ndarray of bool
        Cells that cannot be entered.
    start, goal : (int, int)
        Cells ``(row, col)``.
    window_margin : float
        Margin of the window around the box spanned by start and goal [m].

    Returns
    -------
    path : list of (int, int) or None
        Cells from ``start`` to ``goal`` as `astar` returns them (optimal within the window
        when one is found there), or None when the whole grid has no path.

    """
    (sx, gx), (sy, gy) = geometry.cell_to_world((start[0], goal[0]), (start[1], goal[1]))
    margin = int(round(window_margin / geometry.resolution))
    rows, cols = geometry.cell_window(min(sx, gx), max(sx, gx), min(sy, gy), max(sy, gy),
                                      margin=margin)
    window = blocked[rows, cols]
    path = astar(window, (start[0] - rows.start, start[1] - cols.start),
                 (goal[0] - rows.start, goal[1] - cols.start))
    if path is not None:
        return [(r + rows.start, c + cols.start) for r, c in path]
    if window.shape == blocked.shape:
        return None
    return astar(blocked, start, goal)


def block_disc(blocked, geometry, cx, cy, radius):
    """
    Mark, in place, the cells whose centre lies within a disc.

    Parameters
    ----------
    blocked : (rows, cols) ndarray of bool
        Updated in place.
    geometry : GridGeometry
        The grid.
    cx, cy : float
        Centre of the disc in the map frame [m].
    radius : float
        Its radius [m].

    """
    rows, cols = geometry.cell_window(cx - radius, cx + radius, cy - radius, cy + radius)
    xs, ys = geometry.window_centres(rows, cols)
    blocked[rows, cols] |= np.hypot(xs[np.newaxis, :] - cx, ys[:, np.newaxis] - cy) < radius


def turning_points(path):
    """
    Keep the first, the last and every cell of a path where the direction changes.

    Parameters
    ----------
    path : list of (int, int)
        Cells, each an 8-neighbour of the one before.

    Returns
    -------
    list of (int, int)
        The same polyline with the cells inside straight runs left out.

    """
    if len(path) <= 2:
        return list(path)
    points = [path[0]]
    for prev, cell, nxt in zip(path, path[1:], path[2:]):
        if (cell[0] - prev[0], cell[1] - prev[1]) != (nxt[0] - cell[0], nxt[1] - cell[1]):
            points.append(cell)
    points.append(path[-1])
    return points
