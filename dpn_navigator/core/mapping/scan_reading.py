"""
How a real laser's readings are taken: no-echo codes and how far a beam with no return clears.

REP 117 reads a range below ``range_min`` as invalid and ``+inf`` (or ``range >= range_max``)
as no return, which shows the whole beam out to ``range_max`` empty. Real lasers differ:

- old drivers write a beam with no echo as a tiny range (the Hokuyo driver of the leg_tracker
  recordings: 0.000-0.019 m), so a no-echo beam reads as invalid and shows nothing empty
  (`read_no_echo`, ``LabelRule.no_echo_below_range_min``);
- weak echoes (dark or far surfaces, grazing incidence) drop out well before ``range_max``,
  so a beam with no return may pass a surface it does not see (`shorten_no_returns`,
  `no_return_as_reading`, ``LabelRule.no_return_reach``).

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
