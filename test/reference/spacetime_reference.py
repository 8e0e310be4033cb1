"""
Brute-force twins of the space-time oracle's search (``baselines.spacetime_search``).

`reference_time_to_goal` relaxes every move until nothing changes (Bellman-Ford) instead of
Dijkstra's heap. `reference_best_cost` walks the time-expanded graph layer by layer, every
state reachable at each step from the start, with no heuristic, no heap and no closed set, and
returns the least cost of a plan (the arrival time at the goal, or the horizon's end plus the
static time left); `plan_cost` checks a plan move by move against the rules and prices it.
The rules, as the search's docstring states them: a wait lasts one step, a move to an
orthogonal (diagonal) neighbour ``straight`` (``diagonal``) steps; no diagonal past a wall; a
wait or a move from step ``k`` to ``k + d`` needs both its cells free from ``k - margin`` to
``k + d + margin`` (clipped to ``0 .. T``); the start cell is free at step 0, and a move out
of it at step 0 needs only its destination free.

"""

import math

MOVES = [(dr, dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if (dr, dc) != (0, 0)]


def _legal_moves(walls, r, c, straight, diagonal):
    rows, cols = len(walls), len(walls[0])
    for dr, dc in MOVES:
        nr, nc = r + dr, c + dc
        if not (0 <= nr < rows and 0 <= nc < cols) or walls[nr][nc]:
            continue
        if dr and dc and (walls[r + dr][c] or walls[r][c + dc]):
            continue
        yield nr, nc, (diagonal if dr and dc else straight)


def reference_time_to_goal(walls, goal, straight, diagonal):
    """Return each cell's least time to ``goal`` [steps] as nested lists, ``inf`` if none."""
    rows, cols = len(walls), len(walls[0])
    to_go = [[math.inf] * cols for _ in range(rows)]
    if walls[goal[0]][goal[1]]:
        return to_go
    to_go[goal[0]][goal[1]] = 0
    changed = True
    while changed:
        changed = False
        for r in range(rows):
            for c in range(cols):
                if walls[r][c]:
                    continue
                for nr, nc, d in _legal_moves(walls, r, c, straight, diagonal):
                    if to_go[nr][nc] + d < to_go[r][c]:
                        to_go[r][c] = to_go[nr][nc] + d
                        changed = True
    return to_go


def _free(walls, blocked, start, r, c, k):
    if walls[r][c]:
        return False
    if k == 0 and (r, c) == tuple(start):
        return True
    return not blocked[k][r][c]


def _free_during(walls, blocked, start, r, c, first, last, margin):
    horizon = len(blocked) - 1
    return all(_free(walls, blocked, start, r, c, k)
               for k in range(max(first - margin, 0), min(last + margin, horizon) + 1))


def reference_best_cost(walls, blocked, start, goal, straight, diagonal, margin):
    """Return the least cost of a plan by exhaustive layered search; ``inf`` if none."""
    horizon = len(blocked) - 1
    to_go = reference_time_to_goal(walls, goal, straight, diagonal)
    if math.isinf(to_go[start[0]][start[1]]):
        return math.inf
    best = math.inf
    layers = [set() for _ in range(horizon + 1)]
    layers[0].add(tuple(start))
    for k in range(horizon):
        for r, c in layers[k]:
            if (r, c) == tuple(goal):
                best = min(best, k)
                continue
            options = [(r, c, 1)] + list(_legal_moves(walls, r, c, straight, diagonal))
            for nr, nc, d in options:
                nk = min(k + d, horizon)
                leaving = k == 0 and (r, c) == tuple(start) and (nr, nc) != (r, c)
                if not ((leaving or _free_during(walls, blocked, start, r, c, k, nk, margin))
                        and _free_during(walls, blocked, start, nr, nc, k, nk, margin)):
                    continue
                if (nr, nc) == tuple(goal) or nk == horizon:
                    best = min(best, k + d + to_go[nr][nc])
                else:
                    layers[nk].add((nr, nc))
    if tuple(goal) in layers[horizon]:
        best = min(best, horizon)
    if tuple(start) == tuple(goal):
        best = 0
    return best


def plan_cost(walls, blocked, plan, start, goal, straight, diagonal, margin):
    """Check a plan ``[(row, col, step), ...]`` against the rules and return its cost."""
    horizon = len(blocked) - 1
    to_go = reference_time_to_goal(walls, goal, straight, diagonal)
    assert tuple(plan[0]) == (start[0], start[1], 0), 'a plan starts at the start, step 0'
    arrival = 0
    for (r, c, k), (nr, nc, nk) in zip(plan, plan[1:]):
        assert (r, c) != tuple(goal) and k < horizon, 'a plan ends at the goal or the horizon'
        if (nr, nc) == (r, c):
            d = 1
        else:
            moves = {(mr, mc): md for mr, mc, md in _legal_moves(walls, r, c, straight,
                                                                 diagonal)}
            assert (nr, nc) in moves, f'illegal move {(r, c)} -> {(nr, nc)}'
            d = moves[(nr, nc)]
        assert nk == min(k + d, horizon), 'a move lasts its duration'
        if not (k == 0 and (r, c) == tuple(start) and (nr, nc) != (r, c)):
            assert _free_during(walls, blocked, start, r, c, k, nk, margin)
        assert _free_during(walls, blocked, start, nr, nc, k, nk, margin)
        arrival = k + d
    r, c, k = plan[-1]
    if (r, c) == tuple(goal):
        return arrival if len(plan) > 1 else 0
    assert k == horizon, 'a plan that misses the goal runs to the horizon'
    return arrival + to_go[r][c]
