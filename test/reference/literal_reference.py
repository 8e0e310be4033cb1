"""
Slow, obvious twins of the core, written straight from the paper's equations for comparison.

Nothing here is vectorised or clever: every cell is compared with every laser point in plain
Python loops. Tests compare the core with these cell for cell; the benchmark times them.

"""

import heapq
import math

import numpy as np
from real_sensor_rules import (literal_fine_ranges, literal_mixed, literal_narrow, literal_read,
                               literal_shorten, literal_spikes, literal_veiling)

NON_EXPLORED, EXPLORED, STEADY, MOBILE = 0, 1, 2, 3

# The FSM table of the README, written out as literal transitions.
FSM = {
    (NON_EXPLORED, 1, 0): STEADY, (NON_EXPLORED, 0, 1): EXPLORED,
    (EXPLORED, 1, 0): MOBILE, (EXPLORED, 0, 1): EXPLORED,
    (STEADY, 1, 0): STEADY, (STEADY, 0, 1): EXPLORED,
    (MOBILE, 1, 0): MOBILE, (MOBILE, 0, 1): EXPLORED,
}


def literal_scan_points(pose, ranges, angle_min, angle_increment, range_min, range_max):
    """
    Polygon vertices and hit points of a scan, one beam at a time.

    Returns
    -------
    vertices : list of (float, float)
        Laser position first, then one vertex per beam.
    hits : list of (float, float)

    """
    x, y, yaw = pose
    vertices = [(x, y)]
    hits = []
    for i, reading in enumerate(ranges):
        reading = float(reading)
        theta = yaw + (angle_min + i * angle_increment)
        if math.isfinite(reading) and range_min <= reading < range_max:
            point = (x + reading * math.cos(theta), y + reading * math.sin(theta))
            vertices.append(point)
            hits.append(point)
        elif reading == math.inf or reading >= range_max:
            vertices.append((x + range_max * math.cos(theta), y + range_max * math.sin(theta)))
        else:
            vertices.append((x, y))
    return vertices, hits


def literal_f1(cx, cy, hits, safety_radius):
    """Eq. 1-2: 1 if some hit point lies within the safety radius of the centre."""
    for hx, hy in hits:
        dx = hx - cx
        dy = hy - cy
        if math.sqrt(dx * dx + dy * dy) <= safety_radius:
            return 1
    return 0


def literal_f2(cx, cy, vertices):
    """Even-odd crossing test of the centre against the closed polygon (ray along +x)."""
    inside = False
    count = len(vertices)
    for a in range(count):
        xa, ya = vertices[a]
        xb, yb = vertices[(a + 1) % count]
        if (ya > cy) != (yb > cy) and cx < xa + (xb - xa) * (cy - ya) / (yb - ya):
            inside = not inside
    return 1 if inside else 0


def literal_update(labels, origin, resolution, pose, ranges, angle_min, angle_increment,
                   range_min, range_max, safety_radius, path=None, cells=None):
    """
    Update a label array in place over every cell; return the replan flag.

    Parameters
    ----------
    labels : (H, W) ndarray of uint8
        Labels, changed in place.
    origin : (float, float)
        Lower-left corner [m].
    resolution : float
        Cell side [m].
    pose, ranges, angle_min, angle_increment, range_min, range_max, safety_radius
        As for ``LabelGrid.update``.
    path : iterable of (int, int), optional
        The planned path's cells.
    cells : iterable of (int, int), optional
        Update only these cells (the benchmark samples the slow reference); default all.

    """
    vertices, hits = literal_scan_points(
        pose, ranges, angle_min, angle_increment, range_min, range_max)
    x0, y0 = origin
    on_path = set() if path is None else {(int(r), int(c)) for r, c in path}
    replan = False
    rows, cols = labels.shape
    if cells is None:
        cells = ((i, j) for i in range(rows) for j in range(cols))
    for i, j in cells:
        cx = x0 + (j + 0.5) * resolution
        cy = y0 + (i + 0.5) * resolution
        f1 = literal_f1(cx, cy, hits, safety_radius)
        f2 = 0 if f1 else literal_f2(cx, cy, vertices)
        old = int(labels[i, j])
        new = FSM.get((old, f1, f2), old)
        labels[i, j] = new
        if (i, j) in on_path and ((old, new) == (NON_EXPLORED, STEADY)
                                  or (old, new) == (EXPLORED, MOBILE)):
            replan = True
    return replan


def tuple_astar(blocked, start, goal):
    """
    Textbook A* over (row, col) tuples: the baseline the benchmark compares against.

    Same moves and rule as the core: 8-connected, costs 1 and sqrt(2), no diagonal between two
    blocked cells, octile heuristic. Returns a list of cells or None.

    """
    rows, cols = np.shape(blocked)
    blocked = np.asarray(blocked, dtype=bool).tolist()
    sqrt2 = math.sqrt(2.0)

    def heuristic(cell):
        dr = abs(cell[0] - goal[0])
        dc = abs(cell[1] - goal[1])
        return (dr + dc) + (sqrt2 - 2.0) * min(dr, dc)

    g_score = {start: 0.0}
    parent = {start: None}
    frontier = [(heuristic(start), start)]
    closed = set()
    while frontier:
        _, cell = heapq.heappop(frontier)
        if cell in closed:
            continue
        if cell == goal:
            path = []
            while cell is not None:
                path.append(cell)
                cell = parent[cell]
            return path[::-1]
        closed.add(cell)
        r, c = cell
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                if dr == 0 and dc == 0:
                    continue
                nr, nc = r + dr, c + dc
                if not (0 <= nr < rows and 0 <= nc < cols) or blocked[nr][nc]:
                    continue
                if dr and dc and blocked[r + dr][c] and blocked[r][c + dc]:
                    continue
                cost = g_score[cell] + (sqrt2 if dr and dc else 1.0)
                if cost < g_score.get((nr, nc), math.inf):
                    g_score[(nr, nc)] = cost
                    parent[(nr, nc)] = cell
                    heapq.heappush(frontier, (cost + heuristic((nr, nc)), (nr, nc)))
    return None


def literal_surely_free(cx, cy, vertices, hits, safety_radius, radius):
    """
    Tell whether the centre is inside the polygon (f1 = 0, f2 = 1) with no boundary near.

    A boundary point is within ``radius`` when a vertex is (eq. 1's distance), or when the
    centre projects onto an edge and its distance from the edge's line is at most ``radius``.
    """
    if literal_f1(cx, cy, hits, safety_radius) or not literal_f2(cx, cy, vertices):
        return False
    count = len(vertices)
    for a in range(count):
        xa, ya = vertices[a]
        xb, yb = vertices[(a + 1) % count]
        if literal_f1(cx, cy, [(xa, ya)], radius):
            return False
        ex = xb - xa
        ey = yb - ya
        length2 = ex * ex + ey * ey
        if length2 > 0.0:
            dot = (cx - xa) * ex + (cy - ya) * ey
            cross = (cx - xa) * ey - (cy - ya) * ex
            if 0.0 <= dot <= length2 and abs(cross) / math.sqrt(length2) <= radius:
                return False
    return True


def literal_moving_hits(hits, beams, evidence, segment_gap, object_size, min_hits=0,
                        laser=(0.0, 0.0), beam_count=0, bridge_beams=0):
    """
    Mark hits that have a hit with evidence in their segment within object_size of arc.

    A segment ends between hits more than ``segment_gap`` apart, or with more than
    ``bridge_beams`` beams without a hit between them.

    Evidence counts for nothing in a free-standing segment of fewer than ``min_hits`` hits:
    both its ends open, the beam just outside each returning nothing (and existing) or a hit
    farther from ``laser`` than the end.
    """
    count = len(hits)
    segment = [0] * count
    arc = [0.0] * count
    for k in range(1, count):
        dx = hits[k][0] - hits[k - 1][0]
        dy = hits[k][1] - hits[k - 1][1]
        step = math.sqrt(dx * dx + dy * dy)
        cut = step > segment_gap or beams[k] - beams[k - 1] - 1 > bridge_beams
        segment[k] = segment[k - 1] + (1 if cut else 0)
        arc[k] = arc[k - 1] + step

    def distance(k):
        return math.hypot(hits[k][0] - laser[0], hits[k][1] - laser[1])

    def end_open(end, outside, edge_beam):
        if 0 <= outside < count and beams[outside] == beams[end] + (outside - end):
            return distance(outside) > distance(end)
        return beams[end] != edge_beam

    def counts(j):
        members = [k for k in range(count) if segment[k] == segment[j]]
        if len(members) >= min_hits:
            return True
        first, last = members[0], members[-1]
        return not (end_open(first, first - 1, 0) and end_open(last, last + 1, beam_count - 1))

    return [any(evidence[j] and counts(j) and segment[j] == segment[k]
                and abs(arc[k] - arc[j]) <= object_size
                for j in range(count)) for k in range(count)]


def literal_update_with_rule(labels, seen_free, last_hit, origin, resolution, pose, ranges,
                             angle_min, angle_increment, range_min, range_max, safety_radius,
                             rule, stamp, last_stamp, path=None, fine_seen_free=None,
                             surfaces=None, fine_hit_stamp=None, fine_first_free=None,
                             first_free=None):
    """
    Apply the dpn label rule to every cell, in place; return (replan, new last_stamp).

    ``seen_free`` (bool) and ``last_hit`` (float) are updated in place when their rule is on,
    and so is ``fine_seen_free`` (bool, the fine grid's cells of
    ``rule.fine_evidence_resolution`` from ``origin``) with the fine free evidence,
    ``surfaces`` (``real_sensor_rules.LiteralSurfaceMemory``) with the intermittent surfaces,
    and ``fine_hit_stamp`` (float, per fine cell the latest time a hit lay within
    ``fine_evidence_radius`` of it) with the burn-in, and ``fine_first_free`` (float, per fine
    cell the time of the first scan that showed it empty, ``inf`` before) with
    ``free_first_sight``; ``first_free`` likewise per label cell.
    """
    ranges = literal_read(ranges, range_min, rule.no_echo_below_range_min)
    mixed = literal_mixed(ranges, angle_increment, range_min, range_max, rule.mixed_pixel_angle,
                          rule.edge_pixel_flatness)
    spiked = literal_spikes(ranges, angle_increment, range_min, range_max, rule.spike_angle,
                            rule.edge_pixel_flatness)
    mixed = [m or k for m, k in zip(mixed, spiked)]
    ranges = [math.nan if m else r for r, m in zip(ranges, mixed)]
    vertices, hits = literal_scan_points(
        pose, ranges, angle_min, angle_increment, range_min, range_max)
    vertices = literal_shorten(vertices, ranges, range_max, range_min, rule.no_return_reach)
    beams = [i for i, reading in enumerate(ranges)
             if math.isfinite(float(reading)) and range_min <= float(reading) < range_max]
    x0, y0 = origin
    rows, cols = labels.shape

    def centre(i, j):
        return x0 + (j + 0.5) * resolution, y0 + (i + 0.5) * resolution

    def shows_motion(hx, hy):
        # A cell once surely seen free near the point, or its fine cell once surely seen free.
        if any(seen_free[i, j] and literal_f1(
                *centre(i, j), [(hx, hy)],
                max(rule.free_evidence_radius - rule.evidence_margin, 0.0))
               for i in range(rows) for j in range(cols)):
            return True
        if rule.fine_evidence_radius > 0.0:
            fine = rule.fine_evidence_resolution
            i, j = math.floor((hy - y0) / fine), math.floor((hx - x0) / fine)
            return bool(0 <= i < fine_seen_free.shape[0] and 0 <= j < fine_seen_free.shape[1]
                        and fine_seen_free[i, j])
        return False

    moving = [False] * len(hits)
    if rule.moving_object_size > 0.0:
        evidence = [shows_motion(hx, hy) for hx, hy in hits]
        if rule.range_noise_margin > 0.0 or rule.range_noise_fraction > 0.0:
            # Range noise: the point the margin farther along the beam must show it too.
            lx, ly = vertices[0]
            for k, (hx, hy) in enumerate(hits):
                reach = math.hypot(hx - lx, hy - ly)
                margin = rule.range_noise_margin + rule.range_noise_fraction * reach
                far = (hx + (hx - lx) * margin / reach, hy + (hy - ly) * margin / reach)
                evidence[k] = evidence[k] and shows_motion(*far)
        if rule.surface_time > 0.0:
            # Intermittent surfaces: no evidence on a known surface.
            shape = (math.ceil(rows * resolution / rule.noise_margin - 1e-9),
                     math.ceil(cols * resolution / rule.noise_margin - 1e-9))
            known = surfaces.surface_hits(hits, stamp, shape)
            evidence = [e and not s for e, s in zip(evidence, known)]
            # Veiling hits: no evidence of their own.
            veiling = literal_veiling(ranges, angle_increment, range_min, range_max,
                                      rule.veiling_angle)
            evidence = [e and not veiling[b] for e, b in zip(evidence, beams)]
            # Narrow things: no evidence in a narrow segment.
            narrow = literal_narrow(hits, beams, rule.segment_gap, rule.object_min_width,
                                    rule.segment_bridge_beams)
            evidence = [e and not n for e, n in zip(evidence, narrow)]
        moving = literal_moving_hits(hits, beams, evidence, rule.segment_gap,
                                     rule.moving_object_size, rule.object_min_hits,
                                     vertices[0], len(ranges), rule.segment_bridge_beams)
    moving_hits = [h for h, m in zip(hits, moving) if m]
    if rule.mobile_expiry > 0.0 or rule.free_burn_in > 0.0 or rule.free_first_sight > 0.0:
        if stamp < last_stamp:
            # Time went back: no hit is newer than now, no cell first seen later.
            if rule.mobile_expiry > 0.0:
                np.minimum(last_hit, stamp, out=last_hit)
            if rule.free_burn_in > 0.0:
                np.minimum(fine_hit_stamp, stamp, out=fine_hit_stamp)
            if rule.free_first_sight > 0.0:
                np.minimum(fine_first_free, stamp, out=fine_first_free)
                np.minimum(first_free, stamp, out=first_free)
        last_stamp = stamp
    on_path = set() if path is None else {(int(r), int(c)) for r, c in path}
    replan = False
    newly_seen = []
    for i in range(rows):
        for j in range(cols):
            cx, cy = centre(i, j)
            f1 = literal_f1(cx, cy, hits, safety_radius)
            f2 = 0 if f1 else literal_f2(cx, cy, vertices)
            old = int(labels[i, j])
            new = FSM.get((old, f1, f2), old)
            if rule.free_evidence_radius > 0.0:
                if f1 and rule.moving_object_size > 0.0:
                    # Object level: hit cells are mobile near a moving object, else steady.
                    new = MOBILE if literal_f1(cx, cy, moving_hits, safety_radius) else STEADY
                elif f1 and old == EXPLORED and not seen_free[i, j]:
                    new = STEADY                 # conservative free space
                # Burn-in: not while a hit of the last free_burn_in seconds was within r.
                fresh = not (rule.free_burn_in > 0.0
                             and last_hit[i, j] > stamp - rule.free_burn_in)
                if fresh and literal_surely_free(cx, cy, vertices, hits, safety_radius,
                                                 rule.free_evidence_radius):
                    newly_seen.append((i, j))
            if rule.mobile_expiry > 0.0:
                if f1:
                    last_hit[i, j] = stamp
                elif (not f2 and new == MOBILE
                      and stamp - last_hit[i, j] >= rule.mobile_expiry):
                    new = EXPLORED
            labels[i, j] = new
            if (i, j) in on_path and old in (NON_EXPLORED, EXPLORED) and new in (STEADY, MOBILE):
                replan = True
    for i, j in newly_seen:
        if rule.free_first_sight > 0.0:
            # A second look: not before free_first_sight after the first scan that showed
            # the cell surely empty.
            if seen_free[i, j]:
                continue
            if math.isinf(first_free[i, j]):
                first_free[i, j] = stamp
            if stamp - first_free[i, j] < rule.free_first_sight:
                continue
        seen_free[i, j] = True
    if rule.fine_evidence_radius > 0.0:
        fine = rule.fine_evidence_resolution
        radius = rule.fine_evidence_radius
        returns = hits
        # The scan as the fine grid takes it: no farther than fine_evidence_range.
        vertices, hits = literal_scan_points(
            pose, literal_fine_ranges(ranges, range_min, range_max, rule.no_return_reach),
            angle_min, angle_increment, range_min,
            min(range_max, max(rule.fine_evidence_range, range_min)))
        for i in range(fine_seen_free.shape[0]):
            for j in range(fine_seen_free.shape[1]):
                cx, cy = x0 + (j + 0.5) * fine, y0 + (i + 0.5) * fine
                # Burn-in: not while a hit of the last free_burn_in seconds was near.
                if rule.free_burn_in > 0.0 and fine_hit_stamp[i, j] > stamp - rule.free_burn_in:
                    continue
                if fine_seen_free[i, j] or not literal_surely_free(cx, cy, vertices, hits,
                                                                   radius, radius):
                    continue
                if rule.free_first_sight > 0.0:
                    # A second look: not before free_first_sight after the first scan that
                    # showed the cell empty.
                    if math.isinf(fine_first_free[i, j]):
                        fine_first_free[i, j] = stamp
                    if stamp - fine_first_free[i, j] < rule.free_first_sight:
                        continue
                fine_seen_free[i, j] = True
        if rule.free_burn_in > 0.0:
            # Then this scan's returns (not the fine scan's vertices) stamp their discs.
            for i in range(fine_seen_free.shape[0]):
                for j in range(fine_seen_free.shape[1]):
                    if literal_f1(x0 + (j + 0.5) * fine, y0 + (i + 0.5) * fine, returns,
                                  radius):
                        fine_hit_stamp[i, j] = stamp
    return replan, last_stamp
