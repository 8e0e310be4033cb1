"""
The slow, obvious twin of ``mapping.wall_continuation.continued_walls``.

One run, one side and one beam at a time, in plain Python; the meeting point of a beam and a
wall's line from the line's normal form (distance along the beam = the line's distance from the
laser over the cosine of the beam to the normal, then projected on the line), not from the
kernel's 2x2 solve, so that an error in either's arithmetic shows.
"""

import math


def reference_continued_walls(ranges, angle_min, angle_increment, range_min, range_max,
                              min_incidence, reach, fit_hits=4, max_gap=0.3, step=0.1):
    """Return the continuation points as a list of ``(x, y)`` [m], in the laser frame."""
    n = len(ranges)
    angle = [angle_min + angle_increment * i for i in range(n)]

    def is_hit(i):
        r = ranges[i]
        return math.isfinite(r) and range_min <= r < range_max

    def no_return(i):
        return not math.isnan(ranges[i]) and ranges[i] >= range_max

    def point(i):
        return ranges[i] * math.cos(angle[i]), ranges[i] * math.sin(angle[i])

    runs, i = [], 0
    while i < n:
        if not no_return(i):
            i += 1
            continue
        first = i
        while i < n and no_return(i):
            i += 1
        runs.append((first, i - 1))
    out = []
    for side in (-1, 1):
        for first, last in runs:
            nearest = first - 1 if side == -1 else last + 1
            fit = [nearest + side * k for k in range(fit_hits)]
            if min(fit) < 0 or max(fit) >= n or not all(is_hit(k) for k in fit):
                continue
            points = [point(k) for k in fit]
            if any(math.dist(a, b) > max_gap for a, b in zip(points, points[1:])):
                continue
            (px, py), (fx, fy) = points[0], points[-1]
            length = math.hypot(px - fx, py - fy)
            if length == 0.0:
                continue
            ux, uy = (px - fx) / length, (py - fy) / length
            # The wall's line in normal form: n . q = c, n its unit normal.
            nx, ny = -uy, ux
            c = nx * px + ny * py
            # Grazing: the nearest hit's beam lies more than min_incidence from the normal.
            incidence = math.acos(min(1.0, abs(nx * math.cos(angle[nearest])
                                               + ny * math.sin(angle[nearest]))))
            if incidence <= min_incidence:
                continue                                   # seen squarely enough
            order = range(first, last + 1) if side == -1 else range(last, first - 1, -1)
            end = 0.0
            for m in order:
                vx, vy = math.cos(angle[m]), math.sin(angle[m])
                facing = nx * vx + ny * vy                 # cosine of the beam to the normal
                if facing == 0.0:
                    break                                  # parallel: never meets the line
                distance = c / facing                      # along the beam, to the line
                meet_x, meet_y = distance * vx, distance * vy
                along = (meet_x - px) * ux + (meet_y - py) * uy   # past the nearest hit
                if not (distance > 0.0 and along > 0.0 and distance < range_max
                        and along <= reach):
                    break
                end = max(end, along)
            k = 1
            while k * step <= end + 1e-9 * step:
                out.append((px + k * step * ux, py + k * step * uy))
                k += 1
    return out
