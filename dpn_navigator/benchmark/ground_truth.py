"""
Ground truth for the map measures: which grid cells a wall or a wanderer explains.

f1 labels as obstacle every cell whose centre lies within the safety radius ``r`` of a laser
hit, and a hit lies on a wall or on a wanderer. So a wall explains the cells whose centre lies
within ``r`` of the wall (its *f1 belt*), and a wanderer of circumscribed radius ``R`` explains
the cells whose centre lies within ``R + r`` of the wanderer's centre.

"""

import math

import numpy as np


def wall_belt(truth_occupied, truth_geometry, geometry, safety_radius):
    """
    Mark the cells of the navigator's grid whose centre lies within ``r`` of a wall.

    The walls are the true occupied pixels, each a square of side ``truth_geometry.resolution``
    (the simulator builds its wall boxes from them); a cell is in the belt when the distance
    from its centre to the nearest point of a wall pixel is at most ``r``.

    Parameters
    ----------
    truth_occupied : (h, w) ndarray of bool
        The true walls on ``truth_geometry`` (usually finer than the navigator's grid).
    truth_geometry : GridGeometry
        The ground-truth grid.
    geometry : GridGeometry
        The navigator's grid.
    safety_radius : float
        f1's ``r`` [m], finite and non-negative.

    Returns
    -------
    belt : (H, W) ndarray of bool
        On ``geometry``.

    Raises
    ------
    ValueError
        If ``truth_occupied`` does not have ``truth_geometry``'s shape or ``r`` is not a finite
        non-negative number.

    """
    truth_occupied = np.asarray(truth_occupied, dtype=bool)
    if truth_occupied.shape != truth_geometry.shape:
        raise ValueError(f'truth_occupied has shape {truth_occupied.shape}, its geometry says '
                         f'{truth_geometry.shape}')
    safety_radius = float(safety_radius)
    if not (math.isfinite(safety_radius) and safety_radius >= 0.0):
        raise ValueError(f'safety_radius must be finite and >= 0, got {safety_radius!r} m')
    pixel_rr, pixel_cc = np.nonzero(truth_occupied)
    pixel_x, pixel_y = truth_geometry.cell_to_world(pixel_rr, pixel_cc)
    half = 0.5 * truth_geometry.resolution
    home_rr, home_cc = geometry.world_to_cell(pixel_x, pixel_y)
    # Every cell that can qualify lies within this many cells of the pixel's own cell.
    reach = math.ceil((safety_radius + half) / geometry.resolution) + 1
    belt = np.zeros(geometry.shape, dtype=bool)
    for dr in range(-reach, reach + 1):
        for dc in range(-reach, reach + 1):
            rr = home_rr + dr
            cc = home_cc + dc
            centre_x, centre_y = geometry.cell_to_world(rr, cc)
            gap_x = np.maximum(np.abs(centre_x - pixel_x) - half, 0.0)
            gap_y = np.maximum(np.abs(centre_y - pixel_y) - half, 0.0)
            inside = geometry.contains_cell(rr, cc) & (np.hypot(gap_x, gap_y) <= safety_radius)
            belt[rr[inside], cc[inside]] = True
    return belt


def near_any(x, y, centres_xy, reach):
    """
    Tell which points lie within ``reach`` of any of some centres.

    Parameters
    ----------
    x, y : (N,) array_like of float
        Points [m], e.g. cell centres.
    centres_xy : (K, 2) array_like of float
        Centres [m], e.g. wanderer positions; ``K`` may be 0.
    reach : float
        Distance [m]; a point exactly at it counts as near.

    Returns
    -------
    near : (N,) ndarray of bool

    """
    centres_xy = np.asarray(centres_xy, dtype=np.float64).reshape(-1, 2)
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    distance = np.hypot(x[:, None] - centres_xy[None, :, 0], y[:, None] - centres_xy[None, :, 1])
    return (distance <= reach).any(axis=1)


def wanderer_hit_points(laser_pose, ranges, angle_min, angle_increment, range_min, range_max,
                        beam_wanderer):
    """
    Return the hit points of the beams that hit a wanderer, as the navigator's f1 sees them.

    The points are computed with the expressions of the core's ``scan_points`` for the beams
    concerned only, so they are bit-for-bit the f1 hits the navigator folds in from the same
    scan and laser pose.

    Parameters
    ----------
    laser_pose : (float, float, float)
        The laser pose the navigator uses ``(x, y, yaw)`` [m, m, rad].
    ranges : (L,) array_like of float
        The scan's ranges [m].
    angle_min, angle_increment, range_min, range_max : float
        The scan's beam layout [rad] and valid interval [m].
    beam_wanderer : (L,) ndarray of int
        Which wanderer each beam hit, -1 for none (``World.scan_wanderer_beams``).

    Returns
    -------
    hits_x, hits_y : (M,) ndarray of float64
        Map-frame hit points on wanderers [m] of the valid returns.

    """
    ranges = np.asarray(ranges, dtype=np.float64)
    beam_wanderer = np.asarray(beam_wanderer)
    if beam_wanderer.shape != ranges.shape:
        raise ValueError(f'beam_wanderer has shape {beam_wanderer.shape}, ranges '
                         f'{ranges.shape}')
    beams = np.flatnonzero((beam_wanderer >= 0) & (ranges >= range_min) & (ranges < range_max))
    x, y, yaw = laser_pose
    theta = yaw + (angle_min + beams * angle_increment)
    return x + ranges[beams] * np.cos(theta), y + ranges[beams] * np.sin(theta)
