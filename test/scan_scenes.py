"""
Synthetic worlds and laser scans for tests and the core benchmark, without a simulator.

Scans are ray-marched on a fine ground-truth grid, so neighbouring beams see the same walls as a
real laser would; a scan of independent random ranges is kept as the worst case.

"""

import math

import numpy as np

LASER_BEAMS = 640
ANGLE_MIN = -math.pi / 2
ANGLE_INCREMENT = math.pi / (LASER_BEAMS - 1)
RANGE_MIN = 0.1
RANGE_MAX = 30.0


def hall(size, boxes, rng, truth_resolution=0.05):
    """
    Make a square hall with walls and random axis-aligned boxes.

    Parameters
    ----------
    size : float
        Side of the hall [m].
    boxes : int
        Number of boxes, each 0.5 to 3 m on a side.
    rng : numpy.random.Generator
        Source of randomness.
    truth_resolution : float
        Cell side of the ground-truth grid [m].

    Returns
    -------
    occupied : (n, n) ndarray of bool
        Ground truth, row along y, origin at (0, 0).

    """
    n = int(round(size / truth_resolution))
    occupied = np.zeros((n, n), dtype=bool)
    wall = max(1, int(round(0.3 / truth_resolution)))
    occupied[:wall, :] = occupied[-wall:, :] = True
    occupied[:, :wall] = occupied[:, -wall:] = True
    for _ in range(boxes):
        w, h = rng.uniform(0.5, 3.0, 2) / truth_resolution
        c, r = rng.uniform(0, n - max(w, h), 2)
        occupied[int(r):int(r + h), int(c):int(c + w)] = True
    return occupied


def free_pose(occupied, rng, truth_resolution=0.05, clearance=1.0):
    """Draw a pose ``(x, y, yaw)`` [m, m, rad] at least ``clearance`` m from any occupied cell."""
    n = occupied.shape[0]
    pad = int(math.ceil(clearance / truth_resolution))
    while True:
        r, c = rng.integers(pad, n - pad, 2)
        if not occupied[r - pad:r + pad + 1, c - pad:c + pad + 1].any():
            return ((c + 0.5) * truth_resolution, (r + 0.5) * truth_resolution,
                    rng.uniform(-math.pi, math.pi))


def ray_cast(occupied, pose, truth_resolution=0.05, range_max=RANGE_MAX):
    """
    Ranges of a 640-beam, 180-degree laser at ``pose``, REP 117 (``inf`` for no return).

    Parameters
    ----------
    occupied : (n, m) ndarray of bool
        Ground truth, origin (0, 0), cell side ``truth_resolution`` [m].
    pose : (float, float, float)
        The laser's ``(x, y, yaw)`` [m, m, rad].
    truth_resolution : float
        Cell side of ``occupied`` [m].
    range_max : float
        Maximum range [m]; beams that hit nothing closer return ``inf``.

    Returns
    -------
    ranges : (640,) ndarray of float64 [m]

    """
    x, y, yaw = pose
    angles = yaw + ANGLE_MIN + np.arange(LASER_BEAMS) * ANGLE_INCREMENT
    step = truth_resolution / 2
    distances = np.arange(RANGE_MIN, range_max, step)
    px = x + np.cos(angles)[:, None] * distances
    py = y + np.sin(angles)[:, None] * distances
    cc = np.floor(px / truth_resolution).astype(np.int64)
    rr = np.floor(py / truth_resolution).astype(np.int64)
    inside = (rr >= 0) & (rr < occupied.shape[0]) & (cc >= 0) & (cc < occupied.shape[1])
    hit = np.zeros(px.shape, dtype=bool)
    hit[inside] = occupied[rr[inside], cc[inside]]
    first = np.argmax(hit, axis=1)
    return np.where(hit.any(axis=1), distances[first], np.inf)


def moving_box_world(static, step, rng_seed, boxes=3, truth_resolution=0.05):
    """
    Return ``static`` with ``boxes`` 0.6 m boxes, each moving along a fixed heading.

    Box ``k`` starts at a random cell and moves up to 6 truth cells along each axis per step,
    stopping at the hall's border: at step ``step`` it stands where that walk puts it.
    """
    occupied = static.copy()
    rng = np.random.default_rng(rng_seed)
    n = static.shape[0]
    side = int(round(0.6 / truth_resolution))
    for _ in range(boxes):
        r0, c0 = rng.integers(side, n - 2 * side, 2)
        dr, dc = rng.integers(-6, 7, 2)
        r = int(np.clip(r0 + dr * step, 0, n - side))
        c = int(np.clip(c0 + dc * step, 0, n - side))
        occupied[r:r + side, c:c + side] = True
    return occupied


def random_ranges(rng):
    """Worst case: independent ranges, 2 to 35 m, so every edge of the polygon is a spike."""
    return rng.uniform(2.0, 35.0, LASER_BEAMS)
