"""
A laser scan as map-frame points: the f2 polygon's vertices and the f1 hit points.

Beam ``i`` points along ``theta_i = yaw + (angle_min + i * angle_increment)`` from the laser's
position ``(x, y)``. Its polygon vertex, by REP 117:

- a valid return (finite and ``range_min <= range < range_max``) gives its hit point
  ``(x + range * cos(theta_i), y + range * sin(theta_i))``, which is also an f1 hit;
- no return (``+inf`` or ``range >= range_max``) gives the point at ``range_max`` and no hit;
- an invalid reading (NaN, ``-inf``, ``range < range_min``) gives the laser position itself and
  no hit.

The polygon is the laser position followed by one vertex per beam in beam order, closed back to
the laser position (stored explicitly as a last vertex, so edge ``k`` joins vertices ``k`` and
``k + 1``).

"""

from dataclasses import dataclass
import math

import numpy as np

#: Slack on the full-turn check [rad], for drivers that round ``angle_increment``.
_FULL_TURN_SLACK = 1e-6

#: Smallest accepted ``angle_increment`` [rad]. The finest real scanners step about 1e-4 rad
#: (0.01 degree); a bearing divided by a smaller increment is no beam index (1e-30 gives 1e30,
#: beyond an int64).
MIN_ANGLE_INCREMENT = 1e-6

#: Largest accepted ``|angle_min|`` and ``|angle_max|`` [rad]: two full turns, which admits
#: both conventions of real drivers (``[-pi, pi]`` and ``[0, 2 pi]``) with room to spare.
MAX_SCAN_ANGLE = 4.0 * math.pi

#: Largest accepted ``|x|`` and ``|y|`` of a pose [m]. A position farther out is no robot's (a
#: million kilometres), and cell arithmetic on it would overflow (``9e307 / 0.5`` is ``inf``).
MAX_POSE_COORDINATE = 1e9


@dataclass(frozen=True)
class ScanPoints:
    """
    Map-frame points of one scan.

    Attributes
    ----------
    vertices_x, vertices_y : (L + 2,) ndarray of float64
        Closed polygon [m]: the laser position, one vertex per beam, the laser position again.
    hits_x, hits_y : (K,) ndarray of float64
        Laser hit points of the valid returns [m], ``K <= L``, in beam order.
    hit_beams : (K,) ndarray of int64
        The beam index of each hit.

    """

    vertices_x: np.ndarray
    vertices_y: np.ndarray
    hits_x: np.ndarray
    hits_y: np.ndarray
    hit_beams: np.ndarray


def check_pose(pose, name='pose'):
    """
    Validate a planar pose.

    Parameters
    ----------
    pose : sequence of 3 float
        ``(x, y, yaw)`` [m, m, rad].
    name : str
        What to call it in the error message.

    Returns
    -------
    x, y, yaw : float

    Raises
    ------
    ValueError
        When the pose does not have three finite entries, or ``|x|`` or ``|y|`` exceeds
        ``MAX_POSE_COORDINATE``.

    """
    values = np.asarray(pose, dtype=np.float64)
    if values.shape != (3,):
        raise ValueError(f'{name} must be (x, y, yaw), got shape {values.shape}')
    if not np.all(np.isfinite(values)):
        raise ValueError(f'{name} must be finite, got {tuple(values.tolist())}')
    if max(abs(values[0]), abs(values[1])) > MAX_POSE_COORDINATE:
        raise ValueError(f'{name} position ({values[0]:.3g}, {values[1]:.3g}) m is beyond '
                         f'+-{MAX_POSE_COORDINATE:.0e} m')
    return float(values[0]), float(values[1]), float(values[2])


def check_scan_angles(beams, angle_min, angle_increment, angle_max=None):
    """
    Validate a scan's angle layout: the one check of every consumer of scan angles.

    A real sensor's beams step by at least `MIN_ANGLE_INCREMENT`, start within
    ``+-MAX_SCAN_ANGLE`` and span at most one full turn; ``angle_max``, when given, agrees with
    the beam count to within one beam.

    Parameters
    ----------
    beams : int
        Number of beams ``L``.
    angle_min : float
        Angle of the first beam in the laser frame [rad].
    angle_increment : float
        Angle between consecutive beams [rad]; at least `MIN_ANGLE_INCREMENT`.
    angle_max : float, optional
        Angle of the last beam [rad]; ``(angle_max - angle_min) / angle_increment + 1`` must be
        ``L`` to within one beam.

    Raises
    ------
    ValueError
        Naming the field that is wrong.

    """
    for name, value in (('angle_min', angle_min), ('angle_increment', angle_increment)):
        if not math.isfinite(value):
            raise ValueError(f'{name} must be finite, got {value!r}')
    if angle_increment <= 0.0:
        raise ValueError(f'angle_increment must be positive, got {angle_increment!r} rad')
    if angle_increment < MIN_ANGLE_INCREMENT:
        raise ValueError(f'angle_increment {angle_increment!r} rad is below '
                         f'{MIN_ANGLE_INCREMENT:g} rad: no real scanner steps that finely')
    if abs(angle_min) > MAX_SCAN_ANGLE:
        raise ValueError(f'angle_min {angle_min!r} rad is beyond +-{MAX_SCAN_ANGLE:.4f} rad')
    if beams > 1 and (beams - 1) * angle_increment > 2.0 * math.pi + _FULL_TURN_SLACK:
        raise ValueError(
            f'{beams} beams of {angle_increment!r} rad span more than a full turn')
    if angle_max is None:
        return
    if not math.isfinite(angle_max):
        raise ValueError(f'angle_max must be finite, got {angle_max!r}')
    if abs(angle_max) > MAX_SCAN_ANGLE:
        raise ValueError(f'angle_max {angle_max!r} rad is beyond +-{MAX_SCAN_ANGLE:.4f} rad')
    if angle_max - angle_min > 2.0 * math.pi + _FULL_TURN_SLACK:
        raise ValueError(f'angle_min={angle_min!r} to angle_max={angle_max!r} rad span more '
                         'than a full turn')
    expected = (angle_max - angle_min) / angle_increment + 1.0
    if abs(beams - expected) > 1.0:
        raise ValueError(
            f'ranges has {beams} beams but angle_min={angle_min!r}, angle_max={angle_max!r},'
            f' angle_increment={angle_increment!r} give {expected:.1f}')


def check_scan(ranges, angle_min, angle_increment, range_min, range_max, angle_max=None):
    """
    Validate the fields of a laser scan; the ranges themselves may hold any float (REP 117).

    Parameters
    ----------
    ranges : (L,) array_like of float
        Measured ranges [m].
    angle_min, angle_increment, angle_max : float
        The angle layout, checked by `check_scan_angles` [rad]; ``angle_max`` optional.
    range_min, range_max : float
        Valid range interval ``[range_min, range_max)`` [m]; finite and
        ``0 <= range_min < range_max``.

    Returns
    -------
    ranges : (L,) ndarray of float64

    Raises
    ------
    ValueError
        Naming the field that is wrong.

    """
    ranges = np.asarray(ranges, dtype=np.float64)
    if ranges.ndim != 1:
        raise ValueError(f'ranges must be one-dimensional, got shape {ranges.shape}')
    for name, value in (('range_min', range_min), ('range_max', range_max)):
        if not math.isfinite(value):
            raise ValueError(f'{name} must be finite, got {value!r}')
    check_scan_angles(ranges.shape[0], angle_min, angle_increment, angle_max)
    if range_min < 0.0 or range_max <= range_min:
        raise ValueError(
            f'need 0 <= range_min < range_max, got range_min={range_min!r}, '
            f'range_max={range_max!r} m')
    return ranges


def scan_points(pose, ranges, angle_min, angle_increment, range_min, range_max):
    """
    Convert a validated scan into its polygon vertices and hit points.

    Parameters
    ----------
    pose : (float, float, float)
        The laser's ``(x, y, yaw)`` in the map frame [m, m, rad], finite.
    ranges : (L,) ndarray of float64
        Ranges [m] as returned by :func:`check_scan`.
    angle_min, angle_increment, range_min, range_max : float
        As in :func:`check_scan`.

    Returns
    -------
    ScanPoints

    """
    x, y, yaw = pose
    theta = yaw + (angle_min + np.arange(ranges.shape[0]) * angle_increment)
    valid = (ranges >= range_min) & (ranges < range_max)     # False for NaN
    no_return = ranges >= range_max                          # True for +inf
    reach = np.where(valid, ranges, np.where(no_return, range_max, 0.0))
    vertices_x = np.empty(ranges.shape[0] + 2)
    vertices_y = np.empty(ranges.shape[0] + 2)
    vertices_x[0] = vertices_x[-1] = x
    vertices_y[0] = vertices_y[-1] = y
    # An invalid beam reaches 0 m, so its vertex is exactly (x, y).
    beam_x = vertices_x[1:-1]
    beam_y = vertices_y[1:-1]
    beam_x[...] = x + reach * np.cos(theta)
    beam_y[...] = y + reach * np.sin(theta)
    return ScanPoints(vertices_x, vertices_y, beam_x[valid], beam_y[valid], np.flatnonzero(valid))
