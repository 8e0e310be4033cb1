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
