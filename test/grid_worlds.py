"""
Planning grids for A* tests and the core benchmark: random obstacles and perfect mazes.

Grids are (rows, cols) bool arrays, True = blocked, with the corners (0, 0) and
(rows - 1, cols - 1) free so that corner-to-corner queries make sense.

"""

import numpy as np


def random_grid(rows, cols, density, rng):
    """
    Make a grid whose cells are blocked independently with probability ``density``.

    Parameters
    ----------
    rows, cols : int
        Grid shape.
    density : float
        Probability that a cell is blocked, in [0, 1].
    rng : numpy.random.Generator
        Source of randomness.

    Returns
    -------
    blocked : (rows, cols) ndarray of bool

    """
    blocked = rng.random((rows, cols)) < density
    blocked[0, 0] = blocked[-1, -1] = False
    return blocked


def maze_grid(rows, cols, rng):
    """
    Make a perfect maze (recursive backtracker) with 1-cell walls and 1-cell corridors.

    The maze's nodes sit on even rows and columns; a grid with an even side gets a last row or
    column of wall with the corner cell opened onto the maze.

    Parameters
    ----------
    rows, cols : int
        Grid shape, at least 2 x 2.
    rng : numpy.random.Generator
        Source of randomness.

    Returns
    -------
    blocked : (rows, cols) ndarray of bool

    """
    node_rows, node_cols = (rows + 1) // 2, (cols + 1) // 2
    blocked = np.ones((rows, cols), dtype=bool)
    seen = np.zeros((node_rows, node_cols), dtype=bool)
    stack = [(0, 0)]
    seen[0, 0] = True
    blocked[0, 0] = False
    steps = ((0, 1), (1, 0), (0, -1), (-1, 0))
    while stack:
        r, c = stack[-1]
        options = [(r + dr, c + dc) for dr, dc in steps
                   if 0 <= r + dr < node_rows and 0 <= c + dc < node_cols
                   and not seen[r + dr, c + dc]]
        if not options:
            stack.pop()
            continue
        nr, nc = options[rng.integers(len(options))]
        seen[nr, nc] = True
        blocked[nr + r, nc + c] = False
        blocked[2 * nr, 2 * nc] = False
        stack.append((nr, nc))
    # Open the far corner onto the nearest maze node when the side is even.
    last_r, last_c = rows - 1, cols - 1
    blocked[last_r, last_c] = False
    blocked[last_r - (last_r % 2), last_c - (last_c % 2)] = False
    if last_r % 2:
        blocked[last_r, last_c - (last_c % 2)] = False
    if last_c % 2:
        blocked[last_r - (last_r % 2), last_c] = False
    return blocked
