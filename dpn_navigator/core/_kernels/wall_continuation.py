"""
Walls that go on past a laser's grazing cut-off: the points of their continuations.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core. The rules are those
of ``mapping.wall_continuation``.

"""

import math

import numpy as np

from .jit import kernel


@kernel
def continued_walls(ranges, angle_min, angle_increment, range_min, range_max, min_incidence,
                    reach, fit_hits, max_gap, point_step):
    """
    Return the continuation points ``(N, 2)`` [m] in the laser frame, side by side, run by run.

    ``mapping.wall_continuation.continued_walls`` with its module constants as arguments:
    ``fit_hits`` hits give the line, ``max_gap`` [m] between two of them at most, a point
    every ``point_step`` [m].
    """
    count = ranges.shape[0]
    hit = np.zeros(count, dtype=np.bool_)
    none = np.zeros(count, dtype=np.bool_)
    x = np.zeros(count)
    y = np.zeros(count)
    for i in range(count):
        r = ranges[i]
        angle = angle_min + angle_increment * i
        if math.isfinite(r) and range_min <= r < range_max:
            hit[i] = True
            x[i] = r * math.cos(angle)
            y[i] = r * math.sin(angle)
        elif r >= range_max:                          # +inf too; NaN compares False
            none[i] = True
    # Runs of beams with no return: [first, last].
    firsts = np.zeros(count, dtype=np.int64)
    lasts = np.zeros(count, dtype=np.int64)
    runs = 0
    i = 0
    while i < count:
        if not none[i]:
            i += 1
            continue
        firsts[runs] = i
        while i < count and none[i]:
            i += 1
        lasts[runs] = i - 1
        runs += 1
    cos_limit = math.cos(min_incidence)
    # Continuations: the nearest hit, the line's direction and the length.
    found = 0
    starts_x = np.zeros(2 * runs)
    starts_y = np.zeros(2 * runs)
    dirs_x = np.zeros(2 * runs)
    dirs_y = np.zeros(2 * runs)
    lengths = np.zeros(2 * runs, dtype=np.int64)
    total = 0
    for side in (-1, 1):
        for k in range(runs):
            nearest = firsts[k] - 1 if side == -1 else lasts[k] + 1
            farthest = nearest + side * (fit_hits - 1)
            if min(nearest, farthest) < 0 or max(nearest, farthest) >= count:
                continue
            fits = True
            for j in range(fit_hits):
                b = nearest + side * j
                if not hit[b]:
                    fits = False
                    break
                if j > 0:
                    a = b - side
                    if math.hypot(x[b] - x[a], y[b] - y[a]) > max_gap:
                        fits = False
                        break
            if not fits:
                continue
            px, py = x[nearest], y[nearest]
            ux, uy = px - x[farthest], py - y[farthest]
            norm = math.hypot(ux, uy)
            if norm == 0.0:
                continue
            ux /= norm
            uy /= norm
            beam = angle_min + angle_increment * nearest
            if abs(-uy * math.cos(beam) + ux * math.sin(beam)) >= cos_limit:
                continue                               # seen squarely enough
            end = 0.0
            for j in range(lasts[k] - firsts[k] + 1):
                m = firsts[k] + j if side == -1 else lasts[k] - j
                angle = angle_min + angle_increment * m
                vx, vy = math.cos(angle), math.sin(angle)
                det = -vx * uy + vy * ux
                if det == 0.0:
                    break
                t = (-px * uy + py * ux) / det
                s = (vx * py - vy * px) / det
                if not (t > 0.0 and s > 0.0 and t < range_max and s <= reach):
                    break
                end = max(end, s)
            steps = int(math.floor(end / point_step + 1e-9))
            if steps > 0:
                starts_x[found] = px
                starts_y[found] = py
                dirs_x[found] = ux
                dirs_y[found] = uy
                lengths[found] = steps
                total += steps
                found += 1
    points = np.zeros((total, 2))
    n = 0
    for c in range(found):
        for j in range(1, lengths[c] + 1):
            points[n, 0] = starts_x[c] + j * point_step * dirs_x[c]
            points[n, 1] = starts_y[c] + j * point_step * dirs_y[c]
            n += 1
    return points
