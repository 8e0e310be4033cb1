"""
How a real laser's readings are taken: no-echo codes and how far a beam with no return clears.

REP 117 reads a range below ``range_min`` as invalid and ``+inf`` (or ``range >= range_max``)
as no return, which shows the whole beam out to ``range_max`` empty. Real lasers differ:

- old drivers write a beam with no echo as a tiny range (the Hokuyo driver of the leg_tracker
  recordings: 0.000-0.019 m), so a no-echo beam reads as invalid and shows nothing empty
  (`read_no_echo`, ``LabelRule.no_echo_below_range_min``);
- weak echoes (dark or far surfaces, grazing incidence) drop out well before ``range_max``,
  so a beam with no return may pass a surface it does not see (`shorten_no_returns`,
  `no_return_as_reading`, ``LabelRule.no_return_reach``);
- at a depth edge a beam whose spot falls on both surfaces returns a range between them (a
  *mixed pixel*), a point floating in free space (`mixed_pixels`, read as invalid with
  ``LabelRule.mixed_pixel_angle``); the hits beside a depth edge and those of surfaces seen at
  grazing incidence veil (`veiling_points`, as ROS ``laser_filters``' shadow filter), and show
  no motion with ``LabelRule.veiling_angle``; a lone hit that veils towards both neighbours,
  both nearer or both farther than it (`spikes`: a mixed pixel beside another, a speckle), is
  read as invalid with ``LabelRule.spike_angle``.

"""

import math

import numpy as np


def read_no_echo(ranges, range_min, on):
    """
    Return the ranges with no-echo codes (finite, ``0 <= range < range_min``) as ``+inf``.

    Parameters
    ----------
    ranges : (L,) ndarray of float64
        Checked ranges [m]; not changed.
    range_min : float
        [m]
    on : bool
        False returns ``ranges`` itself.

    Returns
    -------
    (L,) ndarray of float64

    """
    if not on:
        return ranges
    code = np.isfinite(ranges) & (ranges >= 0.0) & (ranges < range_min)
    if not code.any():
        return ranges
    read = ranges.copy()
    read[code] = math.inf
    return read


def no_return_beams(ranges, range_max):
    """Return the beams with no return, ``range >= range_max`` (``+inf`` too), (L,) bool."""
    return ranges >= range_max


def shorten_no_returns(vertices_x, vertices_y, ranges, range_min, range_max, reach):
    """
    Move the polygon vertices of the beams with no return to ``reach`` of their length.

    A no-return beam's vertex lies at ``range_max`` (``scan_polygon``); it is moved to
    ``laser + (vertex - laser) * reach``, or onto the laser when ``reach * range_max`` is below
    ``range_min``.

    Parameters
    ----------
    vertices_x, vertices_y : (L + 2,) ndarray of float64
        The closed polygon [m] (laser, one vertex per beam, laser), changed in place.
    ranges : (L,) ndarray of float64
        The ranges the polygon was made from [m].
    range_min, range_max : float
        [m]
    reach : float
        Share of ``range_max`` a no-return beam shows empty, in ``[0, 1]``.

    """
    beams = np.flatnonzero(no_return_beams(ranges, range_max)) + 1
    if not beams.size:
        return
    x, y = vertices_x[0], vertices_y[0]
    if reach * range_max < range_min:
        vertices_x[beams] = x
        vertices_y[beams] = y
        return
    vertices_x[beams] = x + (vertices_x[beams] - x) * reach
    vertices_y[beams] = y + (vertices_y[beams] - y) * reach


def no_return_as_reading(ranges, range_min, range_max, reach):
    """
    Return the ranges with each no-return beam read as a return at ``reach * range_max``.

    For the fine evidence, whose polygon is made inside its kernel: a return there bounds the
    polygon as a vertex at that distance would (its disc is kept out of the surely-free space
    as every vertex's is). Below ``range_min`` the beam reads as invalid (NaN): its vertex is
    the laser.

    Parameters
    ----------
    ranges : (L,) ndarray of float64
        Checked ranges [m]; not changed.
    range_min, range_max : float
        [m]
    reach : float
        In ``[0, 1]``; 1 returns ``ranges`` itself.

    Returns
    -------
    (L,) ndarray of float64

    """
    if reach >= 1.0:
        return ranges
    beams = no_return_beams(ranges, range_max)
    if not beams.any():
        return ranges
    read = ranges.copy()
    distance = reach * range_max
    read[beams] = distance if distance >= range_min else math.nan
    return read


def veiling_points(ranges, angle_increment, range_min, range_max, min_angle):
    """
    Find the veiling hits of a scan, as ROS ``laser_filters``' shadow filter does.

    At a depth edge a beam whose spot falls on both the nearer object and what lies behind
    returns a range between the two (a *mixed pixel*): a point floating in space that is free.
    Seen from the laser, the segment from such a point to a neighbouring hit is nearly
    parallel to the beam. A valid hit ``i`` is veiling when, for a valid neighbour ``j``
    (``i - 1`` or ``i + 1``), the angle at ``i`` between the beam (looking back to the laser)
    and the segment to ``j`` is below ``min_angle`` or above ``pi - min_angle``:
    ``ScanShadowsFilter`` of ``laser_filters`` with a window of 1 (its
    ``ShadowDetector::isShadow``, ``min_angle`` / ``max_angle = pi - min_angle``). It also
    finds the hits on either side of a real depth edge, and those of a surface seen at an
    incidence steeper than ``pi / 2 - min_angle``.

    Parameters
    ----------
    ranges : (L,) ndarray of float64
        Checked ranges [m].
    angle_increment : float
        [rad]
    range_min, range_max : float
        Valid hits lie in ``[range_min, range_max)`` [m].
    min_angle : float
        [rad], in ``[0, pi / 2]``; 0 finds none.

    Returns
    -------
    (L,) ndarray of bool

    """
    ranges, veiling, sides = _edge_test(ranges, angle_increment, range_min, range_max,
                                        min_angle, 2)
    if sides is None:
        return veiling
    to_before, to_after = sides
    veiling[1:] |= to_before
    veiling[:-1] |= to_after
    return veiling


def mixed_pixels(ranges, angle_increment, range_min, range_max, min_angle, flatness=0.0):
    """
    Find the hits that lie between their two neighbours in depth, veiling towards both.

    A mixed pixel floats between the nearer object of a depth edge and what lies behind it:
    the segments to its neighbours on either side are both within ``min_angle`` of its beam
    (`veiling_points`), one neighbour nearer and one farther. The edge hit of an object
    veils only towards the far side, and is kept. A flat wall met more than
    ``pi / 2 - min_angle`` from its normal veils both ways too: with ``flatness`` > 0 [m], a
    hit within that distance, along its beam, of the line through its two neighbours' points
    lies on a flat surface with them and is kept (0: off). Parameters and result as
    `veiling_points`'s: the (L,) bool array of the mixed pixels.
    """
    return _veiling_both_ways(ranges, angle_increment, range_min, range_max, min_angle, 1,
                              flatness)


def spikes(ranges, angle_increment, range_min, range_max, min_angle, flatness=0.0):
    """
    Find the spikes of a scan: hits that veil towards both neighbours, which lie on one side.

    A spike stands alone in depth: both neighbouring hits are nearer than it, or both farther,
    and the segments to both lie within ``min_angle`` of its beam (`veiling_points`). Two
    mixed pixels side by side at a depth edge (each between the surfaces, the nearer one's
    neighbour is the farther one) and speckle (a lone return off nothing) are spikes; so is a
    thing one beam wide, which a laser cannot tell from them (ROS ``laser_filters``' speckle
    filter drops them too, by their range difference). Together with `mixed_pixels` these are
    the hits that veil towards both sides. ``flatness`` [m] as `mixed_pixels`'s: range noise
    on a wall at grazing incidence makes spikes too. Parameters and result as
    `veiling_points`'s: the (L,) bool array of the spikes.
    """
    return _veiling_both_ways(ranges, angle_increment, range_min, range_max, min_angle, -1,
                              flatness)


def edge_pixels(ranges, angle_increment, range_min, range_max, mixed_angle, spike_angle,
                flatness=0.0):
    """
    Return the hits read as invalid at depth edges: `mixed_pixels` or `spikes`, (L,) bool.

    One veiling test serves both when their angles are equal (``dpn_real_laser``'s): the
    hits that veil towards both neighbours, in depth between them or not. ``flatness`` [m]
    as `mixed_pixels`'s.
    """
    if mixed_angle != spike_angle:
        return (mixed_pixels(ranges, angle_increment, range_min, range_max, mixed_angle,
                             flatness)
                | spikes(ranges, angle_increment, range_min, range_max, spike_angle,
                         flatness))
    return _veiling_both_ways(ranges, angle_increment, range_min, range_max, mixed_angle, 0,
                              flatness)


def _veiling_both_ways(ranges, angle_increment, range_min, range_max, min_angle, order,
                       flatness=0.0):
    """
    Return the hits that veil towards both neighbours, by their order in depth, (L,) bool.

    ``order`` 1: between the neighbours (`mixed_pixels`); -1: both neighbours on one side
    (`spikes`); 0: either. With ``flatness`` > 0 [m], a hit within that distance, along its
    beam, of the line through its neighbours' points is kept (a flat surface).
    """
    ranges, found, sides = _edge_test(ranges, angle_increment, range_min, range_max,
                                      min_angle, 3)
    if sides is None:
        return found
    to_before, to_after = sides
    with np.errstate(invalid='ignore'):
        product = (ranges[:-2] - ranges[1:-1]) * (ranges[1:-1] - ranges[2:])
    ordered = product != 0.0 if order == 0 else np.sign(product) == order
    found[1:-1] = to_before[:-1] & to_after[1:] & ordered
    if flatness > 0.0:
        middle = np.flatnonzero(found[1:-1]) + 1
        if middle.size:
            flat = _off_neighbours_line(ranges, middle, angle_increment) <= flatness
            found[middle[flat]] = False
    return found


def _off_neighbours_line(ranges, middle, angle_increment):
    """
    Return how far each middle hit lies, along its beam, from the line of its neighbours [m].

    The line through the neighbours' points (at ``-angle_increment`` and ``+angle_increment``
    from the middle beam, ranges ``r0`` and ``r2``) crosses the middle beam at
    ``2 r0 r2 cos(angle_increment) / (r0 + r2)``; on a flat surface the middle hit lies there.
    ``middle`` holds beam indices with valid hits on both sides. (K,) float64.
    """
    before, after = ranges[middle - 1], ranges[middle + 1]
    crossing = 2.0 * before * after * math.cos(angle_increment) / (before + after)
    return np.abs(ranges[middle] - crossing)


def _edge_test(ranges, angle_increment, range_min, range_max, min_angle, min_beams):
    """
    Return the float64 ranges, an all-False (L,) bool result and `_veiling_sides`'s pair.

    The pair is None when ``min_angle`` is 0 or the scan has fewer than ``min_beams`` beams
    (nothing can be found).
    """
    ranges = np.asarray(ranges, dtype=np.float64)
    found = np.zeros(ranges.shape[0], dtype=bool)
    if min_angle <= 0.0 or ranges.shape[0] < min_beams:
        return ranges, found, None
    return ranges, found, _veiling_sides(ranges, angle_increment, range_min, range_max,
                                         min_angle)


def _veiling_sides(ranges, angle_increment, range_min, range_max, min_angle):
    """
    Return, for each hit, whether it veils towards the beam before and the beam after it.

    ``to_before[k]`` is about hit ``k + 1`` and its neighbour ``k``; ``to_after[k]`` about hit
    ``k`` and its neighbour ``k + 1``; both (L - 1,) bool, False unless both hits are valid.
    """
    valid = (ranges >= range_min) & (ranges < range_max)
    pair = valid[:-1] & valid[1:]
    tan_min = math.tan(min_angle)
    sides = []
    for r1, r2 in ((ranges[1:], ranges[:-1]), (ranges[:-1], ranges[1:])):
        # The segment from r1's point to r2's, in r1's beam frame: along and across the beam.
        across = np.abs(r2 * math.sin(angle_increment))
        with np.errstate(invalid='ignore'):
            along = r1 - r2 * math.cos(angle_increment)
            sides.append(pair & (along != 0.0) & (across < tan_min * np.abs(along)))
    return sides[0], sides[1]
