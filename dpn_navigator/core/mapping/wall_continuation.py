"""
Walls that go on where the laser stops seeing them: a wall's continuation past grazing incidence.

A real laser returns nothing from a wall it meets at a grazing angle (beyond about 75 deg of
incidence for the simulated Hokuyo UTM-30LX and SICK LMS1xx; docs/simulator.md), so a robot
driving along a corridor sees its walls only near itself, and the rest of them stays
non-explored: a planner that takes unknown space for free plans through them, drives up to
them, sees them, and turns back (held-out seed 1 and the development seed 0 with the UTM-30LX:
comb, task 0, 143 m driven for a 46.7 m shortest path). The beams next to the last hits of such
a wall say where it would be: each meets the wall's line, continued, at a grazing angle, and
returns nothing, as a wall there would. `continued_walls` gives the points of those lines,
from the last hit out to where the farthest of those beams meets it; the navigator makes the
non-explored cells under them dear to enter (``ExplorationMemory``), not blocked: the wall may
end, and a cell seen free is explored and costs nothing more.

A run of beams with no return (``range >= range_max``, ``+inf`` too) continues the hits on
either side of it when the `FIT_HITS` hits there, nearest first, are valid, no two of them
farther apart than `MAX_GAP`, and the beam of the nearest meets their line (the nearest and the
farthest hit) at more than ``min_incidence`` from its normal. The run's beams, from that side
on, meet the line at a distance ``t`` from the laser and ``s`` along the line past the nearest
hit; the continuation reaches the largest ``s`` of the beams before the first that meets it
behind the laser, behind the hit, beyond ``range_max`` or beyond ``reach``.

No ROS: points in the laser's frame [m], ``x`` along its zero angle.

"""

import math

import numpy as np

from .._kernels import wall_continuation as kernels

#: Hits that give a wall's line [1].
FIT_HITS = 4
#: Largest gap between two of them [m] (a wider one is a depth edge, not one wall).
MAX_GAP = 0.3
#: Spacing of the points along a continuation [m] (a fifth of the 0.5 m cells).
POINT_STEP = 0.1


def continued_walls(ranges, angle_min, angle_increment, range_min, range_max, min_incidence,
                    reach):
    """
    Return points on the continuations of the walls a scan sees at grazing incidence.

    Parameters
    ----------
    ranges : (L,) array_like of float
        The scan's ranges [m] (NaN, ``-inf`` and readings below ``range_min`` are invalid;
        ``range >= range_max`` is no return).
    angle_min, angle_increment : float
        [rad]
    range_min, range_max : float
        [m]
    min_incidence : float
        Angle from the wall's normal beyond which the nearest hit's beam grazes it [rad], in
        ``(0, pi / 2)``.
    reach : float
        Longest continuation past the last hit [m], positive.

    Returns
    -------
    points : (N, 2) ndarray of float64
        ``(x, y)`` in the laser frame [m], every `POINT_STEP` from the last hit (excluded) to
        the continuation's end (included), for every continued wall.

    """
    if not 0.0 < min_incidence < 0.5 * math.pi:
        raise ValueError(f'min_incidence must lie in (0, pi / 2), got {min_incidence!r}')
    if not (math.isfinite(reach) and reach > 0.0):
        raise ValueError(f'reach must be positive and finite, got {reach!r}')
    return kernels.continued_walls(np.ascontiguousarray(ranges, dtype=np.float64).reshape(-1),
                                   float(angle_min), float(angle_increment), float(range_min),
                                   float(range_max), float(min_incidence), float(reach),
                                   FIT_HITS, MAX_GAP, POINT_STEP)


def warm_up_wall_continuation():
    """Compile (or load from the cache) the kernel with one tiny scan."""
    continued_walls(np.array([1.0, 1.1, 1.2, 1.3, np.inf]), 0.0, 0.1, 0.1, 5.0, 1.0, 1.0)
