"""
Walls: occupied grid cells merged into a few rectangles, built as static pybullet boxes.

Each row's runs of occupied cells are found with numpy, and a run that repeats exactly in the
next row extends the rectangle above it. A straight wall of any length thus becomes one box,
and a rectangular block one box, while every occupied cell is covered exactly once.

"""

import numpy as np
import pybullet

#: RGBA of walls in the GUI.
WALL_COLOUR = (0.55, 0.55, 0.6, 1.0)


def merge_cells(occupied):
    """
    Cover the occupied cells of a grid with disjoint rectangles.

    Parameters
    ----------
    occupied : (rows, cols) array_like of bool
        True for wall cells.

    Returns
    -------
    rects : (K, 4) ndarray of int64
        One rectangle per row ``(row, col, n_rows, n_cols)``: its lower-left cell and size in
        cells. Together they cover exactly the occupied cells, without overlap.

    """
    occupied = np.asarray(occupied, dtype=bool)
    if occupied.ndim != 2:
        raise ValueError(f'occupied must be a 2-D grid, got shape {occupied.shape}')
    rows, cols = occupied.shape
    padded = np.zeros((rows, cols + 2), dtype=np.int8)
    padded[:, 1:-1] = occupied
    edges = np.diff(padded, axis=1)
    starts_r, starts_c = np.nonzero(edges == 1)
    _, ends_c = np.nonzero(edges == -1)  # same row-major order as the starts
    row_runs = [[] for _ in range(rows)]
    for r, c0, c1 in zip(starts_r.tolist(), starts_c.tolist(), ends_c.tolist()):
        row_runs[r].append((c0, c1))
    rects = []
    open_rects = {}  # (c0, c1) -> first row of a rectangle still growing upwards
    for r in range(rows + 1):
        runs = set(row_runs[r]) if r < rows else set()
        for key in [key for key in open_rects if key not in runs]:
            r0 = open_rects.pop(key)
            rects.append((r0, key[0], r - r0, key[1] - key[0]))
        for key in runs:
            open_rects.setdefault(key, r)
    rects.sort()
    return np.asarray(rects, dtype=np.int64).reshape(-1, 4)


def wall_boxes(rects, geometry, height):
    """
    Return the boxes of wall rectangles, standing on the ground.

    Parameters
    ----------
    rects : (K, 4) array_like of int
        Rectangles ``(row, col, n_rows, n_cols)`` from `merge_cells`.
    geometry : GridGeometry
        The grid the rectangles index.
    height : float
        Wall height [m].

    Returns
    -------
    centres, half_extents : (K, 3) ndarray of float64
        Centre and half size of each box [m].

    """
    rects = np.asarray(rects, dtype=np.int64).reshape(-1, 4)
    res = geometry.resolution
    x_lo, y_lo = geometry.cell_to_world(rects[:, 0], rects[:, 1])
    x_hi, y_hi = geometry.cell_to_world(rects[:, 0] + rects[:, 2] - 1,
                                        rects[:, 1] + rects[:, 3] - 1)
    centres = np.column_stack([0.5 * (x_lo + x_hi), 0.5 * (y_lo + y_hi),
                               np.full(len(rects), 0.5 * height)])
    half_extents = np.column_stack([0.5 * res * rects[:, 3], 0.5 * res * rects[:, 2],
                                    np.full(len(rects), 0.5 * height)])
    return centres, half_extents


def build_walls(client, rects, geometry, height, group, mask, visual=False):
    """
    Create one static box body per rectangle.

    Collision shapes are shared between boxes of the same size.

    Parameters
    ----------
    client : int
        The pybullet physics client.
    rects : (K, 4) array_like of int
        Rectangles ``(row, col, n_rows, n_cols)`` from `merge_cells`.
    geometry : GridGeometry
        The grid the rectangles index.
    height : float
        Wall height [m]; the boxes stand on the ground (z = 0).
    group, mask : int
        Collision filter group and mask of the walls.
    visual : bool
        Give the boxes visual shapes (for the GUI).

    Returns
    -------
    bodies : list of int
        The body ids, one per rectangle.

    """
    shapes = {}
    bodies = []
    centres, half_extents = wall_boxes(rects, geometry, height)
    for centre, half in zip(centres.tolist(), half_extents.tolist()):
        if tuple(half) not in shapes:
            collision = pybullet.createCollisionShape(
                pybullet.GEOM_BOX, halfExtents=half, physicsClientId=client)
            look = pybullet.createVisualShape(
                pybullet.GEOM_BOX, halfExtents=half, rgbaColor=WALL_COLOUR,
                physicsClientId=client) if visual else -1
            shapes[tuple(half)] = (collision, look)
        collision, look = shapes[tuple(half)]
        body = pybullet.createMultiBody(
            baseMass=0.0, baseCollisionShapeIndex=collision, baseVisualShapeIndex=look,
            basePosition=centre, physicsClientId=client)
        pybullet.setCollisionFilterGroupMask(body, -1, group, mask, physicsClientId=client)
        bodies.append(body)
    return bodies
