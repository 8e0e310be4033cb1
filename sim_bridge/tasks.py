"""
Navigation tasks: a start pose and a goal, given in an index or drawn from a map's free space.

Drawn tasks are reproducible: the same map, seed and parameters give the same tasks.

"""

from dataclasses import dataclass
import math

import numpy as np

from .free_space import clearance_grid

#: Free radius around drawn start and goal positions [m]: the Husky's circumscribed radius
#: (0.6 m, which is also the navigator's safety radius) plus 0.1 m.
DEFAULT_TASK_CLEARANCE = 0.7
#: Least straight-line distance between a drawn start and goal [m].
DEFAULT_MIN_TASK_DISTANCE = 5.0


@dataclass(frozen=True)
class Task:
    """
    One navigation task.

    Attributes
    ----------
    start : (float, float, float)
        The Husky's start pose ``(x, y, yaw)`` in the map frame [m, m, rad].
    goal : (float, float)
        The goal position ``(x, y)`` in the map frame [m].

    """

    start: tuple
    goal: tuple


def draw_tasks(free, geometry, n_tasks, seed, clearance=DEFAULT_TASK_CLEARANCE,
               min_distance=DEFAULT_MIN_TASK_DISTANCE):
    """
    Draw navigation tasks from a map's free space, reproducibly.

    Start and goal are centres of coarse cells (see `free_space.clearance_grid`) that keep
    ``clearance`` from every cell that is not known free, lie in the same 4-connected component
    of such cells, and are at least ``min_distance`` apart. The start yaw is uniform in
    ``[-pi, pi)``, rounded to 1 mrad.

    Parameters
    ----------
    free : (rows, cols) array_like of bool
        Known-free cells, row 0 at the bottom.
    geometry : GridGeometry
        The map's grid.
    n_tasks : int
        How many tasks, non-negative.
    seed : int
        Seed of the draw: the same seed gives the same tasks.
    clearance : float
        Free radius around start and goal [m].
    min_distance : float
        Least straight-line start-goal distance [m].

    Returns
    -------
    tasks : tuple of Task

    Raises
    ------
    ValueError
        If no start-goal pair satisfies the constraints.

    """
    if isinstance(n_tasks, bool) or not isinstance(n_tasks, int) or n_tasks < 0:
        raise ValueError(f'n_tasks must be a non-negative integer, got {n_tasks!r}')
    if n_tasks == 0:
        return ()
    grid = clearance_grid(free, geometry, clearance)
    rr, cc = np.nonzero(grid.clear)
    if len(rr) == 0:
        raise ValueError(f'the map has no free cell with {clearance} m clearance for a task')
    xs, ys = grid.geometry.cell_to_world(rr, cc)
    labels = grid.labels[rr, cc]
    rng = np.random.default_rng(seed)
    tasks = []
    for _ in range(200 * n_tasks):
        if len(tasks) == n_tasks:
            break
        k = int(rng.integers(len(rr)))
        far = np.flatnonzero((labels == labels[k])
                             & (np.hypot(xs - xs[k], ys - ys[k]) >= min_distance))
        if len(far) == 0:
            continue
        g = int(far[rng.integers(len(far))])
        yaw = round(float(rng.uniform(-math.pi, math.pi)), 3)
        # Cell centres, rounded to um to drop floating-point noise such as 12.700000000000001.
        start = (round(float(xs[k]), 6), round(float(ys[k]), 6), yaw)
        tasks.append(Task(start, (round(float(xs[g]), 6), round(float(ys[g]), 6))))
    if len(tasks) < n_tasks:
        raise ValueError(
            f'could not draw {n_tasks} tasks: no start and goal {min_distance} m apart in one '
            f'connected region with {clearance} m clearance')
    return tuple(tasks)
