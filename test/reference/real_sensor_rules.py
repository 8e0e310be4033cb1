"""
Literal twins of the rules for real lasers: no-echo codes, no-return reach, surfaces.

Written beam by beam and hit by hit from ``LabelRule``'s definitions (``no_echo_below_range_min``,
``no_return_reach``, ``surface_time``), for ``literal_reference.literal_update_with_rule``; and
whether the laser stands (``no_return_standing_distance``), for the tests to compose with it.

"""

import math

MAX_SCAN_PERIOD = 0.5


def literal_read(ranges, range_min, no_echo):
    """Return each reading, a finite ``0 <= range < range_min`` read as ``+inf`` if asked."""
    read = []
    for reading in ranges:
        reading = float(reading)
        if no_echo and math.isfinite(reading) and 0.0 <= reading < range_min:
            reading = math.inf
        read.append(reading)
    return read


def literal_shorten(vertices, ranges, range_max, range_min, reach):
    """Return the polygon with each no-return beam's vertex moved to ``reach`` of its length."""
    x, y = vertices[0]
    shortened = [vertices[0]]
    for i, reading in enumerate(ranges):
        vx, vy = vertices[i + 1]
        if float(reading) >= range_max:                     # no return (+inf too)
            if reach * range_max < range_min:
                vx, vy = x, y
            else:
                vx, vy = x + (vx - x) * reach, y + (vy - y) * reach
        shortened.append((vx, vy))
    return shortened


def literal_fine_ranges(ranges, range_min, range_max, reach):
    """Return the ranges of the fine evidence: a no-return beam a return at its reach."""
    if reach >= 1.0:
        return list(ranges)
    distance = reach * range_max
    return [(distance if distance >= range_min else math.nan) if float(r) >= range_max
            else float(r) for r in ranges]


class LiteralSurfaceMemory:
    """
    The intermittent surfaces' buckets as a dict of places, one hit at a time.

    ``buckets[(row, col)] = (hit_time, filled)``; a place not in it holds nothing.
    """

    def __init__(self, origin, margin, surface_time, memory):
        self.origin = origin
        self.margin = margin
        self.surface_time = surface_time
        self.drain = surface_time / memory
        self.capacity = 2.0 * surface_time
        self.buckets = {}
        self.last_scan = None

    def place(self, x, y):
        """Return the place ``(row, col)`` of a point."""
        return (math.floor((y - self.origin[1]) / self.margin),
                math.floor((x - self.origin[0]) / self.margin))

    def level(self, place, now):
        """Return the hit time a place holds at ``now``."""
        if place not in self.buckets:
            return 0.0
        hit_time, filled = self.buckets[place]
        age = max(now - filled, 0.0)
        return max(hit_time - age * self.drain, 0.0)

    def surface_hits(self, hits, now, shape, fill=None):
        """Tell which hits lie within one place of a known surface; then fill the places hit."""
        rows, cols = shape
        known = []
        for x, y in hits:
            row, col = self.place(x, y)
            known.append(any(
                0 <= r < rows and 0 <= c < cols
                and self.level((r, c), now) >= self.surface_time
                for r in (row - 1, row, row + 1) for c in (col - 1, col, col + 1)))
        period = 0.0 if self.last_scan is None else min(max(now - self.last_scan, 0.0),
                                                        MAX_SCAN_PERIOD)
        self.last_scan = now
        places = set()
        for k, (x, y) in enumerate(hits):
            if fill is not None and not fill[k]:
                continue
            row, col = self.place(x, y)
            if 0 <= row < rows and 0 <= col < cols:
                places.add((row, col))
        for place in places:
            if place in self.buckets and self.buckets[place][1] == now:
                continue
            self.buckets[place] = (min(self.level(place, now) + period, self.capacity), now)
        return known


def literal_veils(ranges, i, j, angle_increment, range_min, range_max, min_angle):
    """
    Tell whether hit ``i`` veils towards hit ``j`` (``j = i - 1`` or ``i + 1``).

    In beam ``i``'s frame (x along the beam): the segment from ``i``'s point to ``j``'s runs
    ``along`` the beam and ``across`` it; it veils when it lies within ``min_angle`` of the
    beam's line, ``across < tan(min_angle) * |along|`` (``along`` not 0).
    """
    if not (0 <= j < len(ranges)):
        return False
    ri, rj = float(ranges[i]), float(ranges[j])
    if not (range_min <= ri < range_max and range_min <= rj < range_max):
        return False
    along = ri - rj * math.cos(angle_increment)
    across = abs(rj * math.sin(angle_increment))
    return along != 0.0 and across < math.tan(min_angle) * abs(along)


def literal_veiling(ranges, angle_increment, range_min, range_max, min_angle):
    """Return, beam by beam, whether a hit veils towards either neighbour."""
    if min_angle <= 0.0:
        return [False] * len(ranges)
    return [literal_veils(ranges, i, i - 1, angle_increment, range_min, range_max, min_angle)
            or literal_veils(ranges, i, i + 1, angle_increment, range_min, range_max, min_angle)
            for i in range(len(ranges))]


def literal_mixed(ranges, angle_increment, range_min, range_max, min_angle, flatness=0.0):
    """
    Return, beam by beam, whether a hit lies between both neighbours, veiling to both.

    With ``flatness`` > 0, not when it lies within that distance of the line through its
    neighbours' points (a flat surface).
    """
    def placed(before, middle, after):
        between = (before < middle < after) or (before > middle > after)
        return between and not (flatness > 0.0 and literal_off_line(
            before, middle, after, angle_increment) <= flatness)

    return _literal_both_ways(ranges, angle_increment, range_min, range_max, min_angle, placed)


def literal_off_line(before, middle, after, angle_increment):
    """
    How far the middle hit lies from the line of its neighbours' points, along its beam [m].

    In the middle beam's frame (its beam along +x) the neighbours' points lie at
    ``-angle_increment`` and ``+angle_increment``; the line through them meets the x axis.
    """
    ax, ay = before * math.cos(-angle_increment), before * math.sin(-angle_increment)
    bx, by = after * math.cos(angle_increment), after * math.sin(angle_increment)
    # The point of the line a + t (b - a) with y = 0.
    t = -ay / (by - ay)
    return abs(middle - (ax + t * (bx - ax)))


def literal_spikes(ranges, angle_increment, range_min, range_max, min_angle, flatness=0.0):
    """
    Return, beam by beam, whether a hit lies past or before both neighbours, veiling to both.

    With ``flatness`` > 0, not when it lies within that distance of the line through its
    neighbours' points (a flat surface).
    """
    def placed(before, middle, after):
        alone = (middle > max(before, after)) or (middle < min(before, after))
        return alone and not (flatness > 0.0 and literal_off_line(
            before, middle, after, angle_increment) <= flatness)

    return _literal_both_ways(ranges, angle_increment, range_min, range_max, min_angle, placed)


def _literal_both_ways(ranges, angle_increment, range_min, range_max, min_angle, placed):
    """Return, beam by beam, whether a hit ``placed(before, middle, after)`` veils to both."""
    found = [False] * len(ranges)
    if min_angle <= 0.0:
        return found
    for i in range(1, len(ranges) - 1):
        before, middle, after = (float(ranges[i - 1]), float(ranges[i]),
                                 float(ranges[i + 1]))
        found[i] = (placed(before, middle, after)
                    and literal_veils(ranges, i, i - 1, angle_increment, range_min, range_max,
                                      min_angle)
                    and literal_veils(ranges, i, i + 1, angle_increment, range_min, range_max,
                                      min_angle))
    return found


def literal_narrow(hits, beams, segment_gap, min_width, bridge_beams=0):
    """
    Return, hit by hit, whether the end hits of its segment lie less than ``min_width`` apart.

    A hit's segment: the hits reached from it through consecutive hits at most
    ``segment_gap`` apart with at most ``bridge_beams`` beams without a hit between them.
    """
    if min_width <= 0.0:
        return [False] * len(hits)

    def joined(a, b):
        return (beams[b] - beams[a] - 1 <= bridge_beams
                and math.sqrt((hits[b][0] - hits[a][0]) ** 2
                              + (hits[b][1] - hits[a][1]) ** 2) <= segment_gap)

    narrow = []
    for k in range(len(hits)):
        first = last = k
        while first > 0 and joined(first - 1, first):
            first -= 1
        while last + 1 < len(hits) and joined(last, last + 1):
            last += 1
        width = math.hypot(hits[last][0] - hits[first][0], hits[last][1] - hits[first][1])
        narrow.append(width < min_width)
    return narrow


class LiteralStanding:
    """
    Whether the laser stands (``no_return_standing_distance``), from its definition.

    The laser stands once it has stayed within ``distance`` of the place where it came to
    rest for ``time``; a position farther away is a new place, and it moves.
    """

    def __init__(self, distance, time):
        self.distance = distance
        self.time = time
        self.place = None
        self.arrived = None
        self.standing = False

    def step(self, x, y, stamp):
        """Take the laser's position at ``stamp``; return True when it stood and moves now."""
        if self.place is None or math.hypot(x - self.place[0], y - self.place[1]) > self.distance:
            stood = self.standing
            self.place, self.arrived, self.standing = (x, y), stamp, False
            return stood
        self.arrived = min(self.arrived, stamp)
        self.standing = stamp - self.arrived >= self.time
        return False
