"""
Planar poses ``(x, y, yaw)``: composition and angle wrapping.

A pose ``(x, y, yaw)`` [m, m, rad] places a child frame in a parent frame: its origin at
``(x, y)`` and its x axis turned by ``yaw`` counter-clockwise.

"""

import math


def wrap_angle(angle):
    """
    Wrap an angle into ``[-pi, pi)``.

    Parameters
    ----------
    angle : float
        [rad]

    Returns
    -------
    float
        The same direction in ``[-pi, pi)`` [rad].

    """
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def compose(parent, child):
    """
    Pose of ``child`` in the frame ``parent`` is given in: ``parent * child``.

    Parameters
    ----------
    parent : (float, float, float)
        Pose of frame B in frame A, e.g. the robot base in the map frame.
    child : (float, float, float)
        Pose of frame C in frame B, e.g. the laser on the robot.

    Returns
    -------
    (float, float, float)
        Pose of frame C in frame A, yaw wrapped into ``[-pi, pi)``.

    """
    x, y, yaw = parent
    cx, cy, cyaw = child
    cos_yaw = math.cos(yaw)
    sin_yaw = math.sin(yaw)
    return (x + cos_yaw * cx - sin_yaw * cy, y + sin_yaw * cx + cos_yaw * cy,
            wrap_angle(yaw + cyaw))


#: Accepted deviation of a quaternion's squared norm from 1, as tf2's buffer checks it.
QUATERNION_NORM_TOLERANCE = 1e-2


def quaternion_yaw(x, y, z, w):
    """
    Yaw of a unit quaternion: the heading of its x axis projected on the plane.

    A quaternion whose squared norm is within ``QUATERNION_NORM_TOLERANCE`` of 1 is normalised
    (float32 round-off of a publisher); one farther off is rejected, as tf2 rejects it, since
    its heading is a guess.

    Parameters
    ----------
    x, y, z, w : float
        Quaternion components.

    Returns
    -------
    float
        Yaw in ``[-pi, pi]`` [rad].

    Raises
    ------
    ValueError
        When a component is not finite, or the quaternion is not of unit length.

    """
    components = (float(x), float(y), float(z), float(w))
    if not all(math.isfinite(v) for v in components):
        raise ValueError('orientation has a non-finite component')
    scale = max(abs(v) for v in components)
    if scale == 0.0:
        raise ValueError('orientation is a zero quaternion')
    # Scaled to a largest component of 1 first, so that squaring cannot overflow.
    x, y, z, w = (v / scale for v in components)
    norm_squared = (x * x + y * y + z * z + w * w) * scale * scale
    if not abs(norm_squared - 1.0) <= QUATERNION_NORM_TOLERANCE:
        raise ValueError(f'orientation is not a unit quaternion (squared norm '
                         f'{norm_squared:.6g})')
    # Homogeneous form: exact for any positive scale of the quaternion.
    return math.atan2(2.0 * (w * z + x * y), w * w + x * x - y * y - z * z)
