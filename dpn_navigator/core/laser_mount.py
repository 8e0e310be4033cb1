"""
A laser's 3-D pose made planar: the pose and beam order a level, upright laser would have.

The navigator maps in the plane: it needs the laser's ``(x, y, yaw)`` in the map frame and beams
that sweep counter-clockwise seen from above. A laser in TF may be rolled: upside down (roll pi)
its laser-frame angle ``a`` looks along map angle ``yaw - a``, the mirror image of an upright
one. `planar_laser_pose` reads the planar pose and whether the beams are mirrored from the
laser's rotation in the map frame; `mirror_scan` turns a mirrored scan into the upright scan of
the same beams (ranges reversed, angles negated). A laser tilted more than ``max_tilt`` away
from level or upside down does not scan the plane and is refused: its beams would reach the
floor or the ceiling. Within ``max_tilt`` the ranges are used as they are (a range error of
``1 - cos(tilt)``, 0.1 % at 0.05 rad).

"""

import math

import numpy as np

#: Default largest tilt of the scan plane from the horizontal [rad].
DEFAULT_MAX_TILT = 0.05


def planar_laser_pose(rotation, translation, max_tilt=DEFAULT_MAX_TILT):
    """
    Return the planar pose of a laser and whether its beams are mirrored.

    Parameters
    ----------
    rotation : (3, 3) array_like of float
        Rotation matrix of the laser frame in the map frame (columns: the laser's x, y, z axes
        in map coordinates).
    translation : (3,) array_like of float
        The laser's origin in the map frame [m].
    max_tilt : float
        Largest angle between the laser's z axis and the map's z axis (or its opposite) [rad].

    Returns
    -------
    pose : (float, float, float)
        ``(x, y, yaw)`` of the laser in the map frame [m, m, rad]: its origin and the heading of
        its x axis.
    mirrored : bool
        The laser is upside down: its beams sweep clockwise seen from above (`mirror_scan`).

    Raises
    ------
    ValueError
        For a non-finite or malformed input, or a laser tilted more than ``max_tilt``.

    """
    rotation = np.asarray(rotation, dtype=np.float64)
    translation = np.asarray(translation, dtype=np.float64)
    if rotation.shape != (3, 3) or translation.shape != (3,):
        raise ValueError(f'need a (3, 3) rotation and a (3,) translation, got {rotation.shape} '
                         f'and {translation.shape}')
    if not (np.all(np.isfinite(rotation)) and np.all(np.isfinite(translation))):
        raise ValueError('the laser transform has a non-finite value')
    up = float(np.clip(rotation[2, 2], -1.0, 1.0))
    tilt = math.acos(abs(up))
    if tilt > max_tilt:
        raise ValueError(
            f'the laser is tilted {math.degrees(tilt):.1f} deg from the horizontal plane (more '
            f'than {math.degrees(max_tilt):.1f} deg): its scan is not planar')
    yaw = math.atan2(rotation[1, 0], rotation[0, 0])
    return (float(translation[0]), float(translation[1]), yaw), up < 0.0


def mirror_scan(ranges, angle_min, angle_increment):
    """
    Return the upright scan of a mirrored (upside-down) laser's beams.

    The beam at laser angle ``angle_min + k * angle_increment`` looks along angle
    ``-(angle_min + k * angle_increment)`` of the upright laser at the same place and heading;
    reversed, the beams again rise in angle.

    Parameters
    ----------
    ranges : (L,) array_like of float
        The ranges as measured [m].
    angle_min, angle_increment : float
        The scan's first angle and its step [rad].

    Returns
    -------
    ranges : (L,) ndarray of float32
        The ranges in the upright order [m].
    angle_min, angle_increment, angle_max : float
        The upright scan's angles [rad].

    """
    ranges = np.asarray(ranges, dtype=np.float32)
    last = angle_min + (len(ranges) - 1) * angle_increment
    return ranges[::-1].copy(), -last, angle_increment, -angle_min
