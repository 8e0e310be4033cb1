"""
A 2-D laser mounted anywhere in 3-D, as the planar scan the core takes.

The core (``LabelGrid.update``) takes a laser pose ``(x, y, yaw)`` in the map plane and beams
at ``angle_min + i * angle_increment`` with a positive increment, counter-clockwise seen from
above. A laser's 3-D pose in the map (from TF) may be rolled or pitched: mounted upside down
(roll pi) its beams turn clockwise seen from above, so each beam angle ``a`` lies at ``-a`` in
the plane; a driver may also count its beams clockwise (a negative ``angle_increment``). Both
come down to beams in reverse order. `planar_laser` finds the plane pose and the beam angles;
`PlanarLaser.ranges` puts the ranges in that order.

A laser whose scan plane is tilted from the horizontal by more than ``max_tilt`` is refused
(`LaserNotLevelError`): its beams reach the floor or pass over obstacles, and the map plane is
not its plane. Within ``max_tilt`` the beams are taken in the plane by their heading (a beam of
range ``r`` at tilt ``t`` lands ``r (1 - cos t)`` short of where it is drawn: 1.5 % at 10 deg).

"""

from dataclasses import dataclass
import math

import numpy as np

#: Largest tilt of the scan plane from the horizontal that is still taken as planar [rad].
MAX_LASER_TILT = math.radians(10.0)


class LaserNotLevelError(ValueError):
    """The laser's scan plane is tilted too far from the map plane to be a planar scan."""


@dataclass(frozen=True)
class PlanarLaser:
    """
    A scan's beams laid into the map plane.

    Attributes
    ----------
    pose : (float, float, float)
        The laser's ``(x, y, yaw)`` in the map plane [m, m, rad]; ``yaw`` is the heading of
        its x axis.
    angle_min, angle_increment, angle_max : float
        Plane angles of the first beam, the step (positive) and the last beam, relative to
        ``yaw`` [rad].
    reverse : bool
        Whether the ranges are taken in reverse order (`ranges`).
    upside_down : bool
        Whether the laser's z axis points down (its beams mirrored).
    tilt : float
        Angle between the laser's z axis and the vertical (up or down) [rad].

    """

    pose: tuple
    angle_min: float
    angle_increment: float
    angle_max: float
    reverse: bool
    upside_down: bool
    tilt: float

    def ranges(self, ranges):
        """Return a scan's ranges in the plane's beam order (a reversed view or as given)."""
        ranges = np.asarray(ranges)
        return ranges[::-1] if self.reverse else ranges


def planar_laser(laser_in_map, angle_min, angle_increment, beams, max_tilt=MAX_LASER_TILT):
    """
    Lay a laser's beams into the map plane.

    Parameters
    ----------
    laser_in_map : Transform3D
        Pose of the laser frame in the map frame (``lookup(map, laser)``).
    angle_min, angle_increment : float
        The scan's fields, in the laser frame [rad]; the increment may be negative (beams
        counted clockwise) but not zero.
    beams : int
        The number of ranges; the last beam lies at ``angle_min + (beams - 1) *
        angle_increment`` (the scan's ``angle_max`` is not read: drivers round it).
    max_tilt : float, optional
        Largest tilt of the scan plane accepted [rad].

    Returns
    -------
    PlanarLaser

    Raises
    ------
    LaserNotLevelError
        When the scan plane is tilted by more than ``max_tilt``.
    ValueError
        When ``angle_increment`` is zero, an angle is not finite or ``beams`` < 1.

    Examples
    --------
    >>> from dpn_navigator.core.frames import Transform3D
    >>> upside_down = Transform3D.from_xyz_rpy(1.0, 2.0, 0.3, roll=math.pi)
    >>> plane = planar_laser(upside_down, -1.5, 0.5, 7)
    >>> (plane.angle_min, plane.angle_increment, plane.angle_max, plane.reverse)
    (-1.5, 0.5, 1.5, True)

    """
    if int(beams) < 1:
        raise ValueError(f'a scan has at least one beam, got {beams!r}')
    angle_max = angle_min + (int(beams) - 1) * angle_increment
    for name, value in (('angle_min', angle_min), ('angle_increment', angle_increment)):
        if not math.isfinite(value):
            raise ValueError(f'{name} must be finite, got {value!r}')
    if angle_increment == 0.0:
        raise ValueError('angle_increment must not be 0')
    rotation = laser_in_map.rotation_matrix()
    z_up = float(rotation[2, 2])
    tilt = math.acos(min(1.0, abs(z_up)))
    if tilt > max_tilt:
        raise LaserNotLevelError(
            f'the laser is tilted {math.degrees(tilt):.1f} deg from level (roll '
            f'{math.degrees(laser_in_map.roll):.1f}, pitch {math.degrees(laser_in_map.pitch):.1f}'
            f' deg); at most {math.degrees(max_tilt):.1f} deg is taken as a planar scan')
    upside_down = z_up < 0.0
    yaw = math.atan2(rotation[1, 0], rotation[0, 0])
    sign = -1.0 if upside_down else 1.0
    first, step, last = sign * angle_min, sign * angle_increment, sign * angle_max
    reverse = step < 0.0
    if reverse:
        first, step, last = last, -step, first
    x, y, _ = laser_in_map.translation
    return PlanarLaser((float(x), float(y), yaw), float(first), float(step), float(last),
                       bool(reverse), bool(upside_down), tilt)
