"""
Time-expanded A* on a grid whose blocked cells change over time: the space-time oracle's search.

A state is a cell and a time step ``k`` (``k * step`` seconds from now). From ``(cell, k)`` the
robot waits one step (to ``(cell, k + 1)``) or moves to one of its eight neighbours, which takes
``straight_steps`` steps along a row or column and ``diagonal_steps`` along a diagonal (the
robot's top speed, rounded up to whole steps: never faster than it can drive). A move or a
wait from step ``k`` to ``k + d`` is allowed when both its cells are free at every step from
``k - margin`` to ``k + d + margin`` (``margin`` steps of slack for the robot's timing), but a
move out of the start cell at step 0 needs only its destination free (the robot stands there;
an agent within reach of it must not pin it down), and no diagonal cuts a corner (both side
cells free, walls only). ``blocked[k]`` holds the blocked cells at step ``k`` for
``k <= horizon``; the walls are blocked at every step.

The cost of a plan is its arrival time in steps. A plan that has not reached the goal by the
horizon ends there, at the cost ``horizon + to_go[cell]`` (``to_go``: the static shortest
time to the goal around the walls, a lower bound of what is left): the windowed planning of
cooperative A* (Silver 2005). Every path to a state ``(cell, k)`` costs ``k``, so a state is
closed when first expanded and the search is exact: it returns a plan of least cost (the
brute-force twin ``test/reference/spacetime_reference.py`` checks it on tiny grids).

"""

import heapq

import numpy as np

#: The eight neighbour moves, orthogonal first.
MOVES = ((0, 1), (1, 0), (0, -1), (-1, 0), (1, 1), (1, -1), (-1, 1), (-1, -1))


def moves_from(walls, r, c, straight_steps, diagonal_steps):
    """
    Yield the moves out of cell ``(r, c)`` as ``(row, col, duration [steps])``.

    Into the grid's free cells, 8-connected; no diagonal past a wall (no cut corner).
    """
    rows, cols = walls.shape
    for dr, dc in MOVES:
        nr, nc = r + dr, c + dc
        if not (0 <= nr < rows and 0 <= nc < cols) or walls[nr, nc]:
            continue
        if dr and dc:
            if walls[r + dr, c] or walls[r, c + dc]:
                continue
            yield nr, nc, diagonal_steps
        else:
            yield nr, nc, straight_steps


def static_time_to_goal(walls, goal, straight_steps, diagonal_steps):
    """
    Return every cell's least time to the goal around the walls [steps] (Dijkstra).

    Parameters
    ----------
    walls : (H, W) ndarray of bool
        Cells blocked at every time.
    goal : (int, int)
        The goal cell ``(row, col)``.
    straight_steps, diagonal_steps : int
        Duration of an orthogonal and a diagonal move [steps], positive.

    Returns
    -------
    to_go : (H, W) ndarray of float64
        ``inf`` where the goal cannot be reached (and on the walls).

    """
    walls = np.asarray(walls, dtype=bool)
    to_go = np.full(walls.shape, np.inf)
    if walls[goal]:
        return to_go
    to_go[goal] = 0.0
    heap = [(0, goal[0], goal[1])]
    while heap:
        cost, r, c = heapq.heappop(heap)
        if cost > to_go[r, c]:
            continue
        for nr, nc, duration in moves_from(walls, r, c, straight_steps, diagonal_steps):
            new = cost + duration
            if new < to_go[nr, nc]:
                to_go[nr, nc] = new
                heapq.heappush(heap, (new, nr, nc))
    return to_go


def spacetime_plan(walls, blocked, start, goal, to_go, straight_steps, diagonal_steps,
                   margin=0, max_expansions=200_000):
    """
    Plan a least-time path from ``start`` at step 0 to ``goal``, waiting where that pays.

    Parameters
    ----------
    walls : (H, W) ndarray of bool
        Cells blocked at every time (corners are cut past walls only).
    blocked : (T + 1, H, W) ndarray of bool
        Cells blocked at steps ``0 .. T`` (the horizon ``T``), walls included or not.
    start, goal : (int, int)
        Cells ``(row, col)``; the start cell counts as free at step 0 (the robot stands there),
        and a move out of it at step 0 needs only its destination free (an agent that comes
        within reach of the robot's cell does not keep the robot from leaving it).
    to_go : (H, W) ndarray of float
        ``static_time_to_goal`` of these walls and goal.
    straight_steps, diagonal_steps : int
        Durations of the moves [steps], positive.
    margin : int
        Steps of slack before and after a move or a wait in which its cells must be free.
    max_expansions : int
        Stop after expanding this many states and return the best plan closed so far (the
        horizon-ending state of least cost among them); None if none.

    Returns
    -------
    plan : list of (int, int, int), or None
        ``(row, col, step)`` from ``(start, 0)``: one entry per state, consecutive entries a
        wait or a move; it ends at the goal or at the horizon. None when every plan collides
        (or the goal cannot be reached around the walls).
    cost : float
        Its cost [steps]: the arrival time, or ``T + to_go`` at the horizon's end.

    """
    walls = np.asarray(walls, dtype=bool)
    blocked = np.asarray(blocked, dtype=bool)
    horizon = blocked.shape[0] - 1
    start = (int(start[0]), int(start[1]))
    goal = (int(goal[0]), int(goal[1]))
    if not np.isfinite(to_go[start]):
        return None, np.inf
    # Free over time, with the start cell free at step 0 and the walls at every step.
    free = ~(blocked | walls[None])
    free[0][start] = True

    def free_during(r, c, first, last):
        lo = max(first - margin, 0)
        hi = min(last + margin, horizon)
        return bool(free[lo:hi + 1, r, c].all()) if lo <= hi else True

    parents = {(start[0], start[1], 0): None}
    heap = [(float(to_go[start]), 0, start[0], start[1])]
    closed = set()
    best_end = None
    expansions = 0
    while heap:
        f, negk, r, c = heapq.heappop(heap)
        k = -negk
        state = (r, c, k)
        if state in closed:
            continue
        closed.add(state)
        if (r, c) == goal or k >= horizon:
            return _unwind(parents, state), f
        expansions += 1
        if expansions > max_expansions:
            break
        if best_end is None or f < best_end[0]:
            best_end = (f, state)
        # Wait one step.
        successors = [(r, c, 1), *moves_from(walls, r, c, straight_steps, diagonal_steps)]
        for nr, nc, duration in successors:
            nk = min(k + duration, horizon)
            nxt = (nr, nc, nk)
            if nxt in closed or not np.isfinite(to_go[nr, nc]):
                continue
            leaving = k == 0 and (r, c) == start and (nr, nc) != start
            if not ((leaving or free_during(r, c, k, nk)) and free_during(nr, nc, k, nk)):
                continue
            # Cost: the arrival time; a state at the horizon adds what is left at least.
            cost = float(k + duration + to_go[nr, nc])
            if nxt not in parents or cost < parents[nxt][1]:
                parents[nxt] = (state, cost)
                heapq.heappush(heap, (cost, -nk, nr, nc))
    if best_end is not None and expansions > max_expansions:
        return _unwind(parents, best_end[1]), best_end[0]
    return None, np.inf


def _unwind(parents, state):
    """Return the states from the start to ``state``."""
    plan = [state]
    while parents[plan[-1]] is not None:
        plan.append(parents[plan[-1]][0])
    plan.reverse()
    return plan
