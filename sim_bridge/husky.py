"""
The Husky A200: dimensions, laser mount, velocity limits and differential-drive kinematics.

Numbers come from Clearpath's ``husky_description`` and ``husky_control`` and from the
``husky/husky.urdf`` that ships with ``pybullet_data`` (the model the world loads). The base
frame is ``base_footprint``: on the ground under the robot's centre, x forward, y left.

"""

from dataclasses import dataclass
import math

from dpn_navigator.core.pose2d import wrap_angle

#: The Husky model in ``pybullet_data``.
HUSKY_URDF = 'husky/husky.urdf'
#: Overall footprint with bumpers, length x width [m].
HUSKY_LENGTH = 0.99
HUSKY_WIDTH = 0.67
#: Radius of the circle around the footprint [m].
HUSKY_RADIUS = 0.5 * math.hypot(HUSKY_LENGTH, HUSKY_WIDTH)

#: Pose of the laser's focal point on the base frame ``(x, y, yaw)`` [m, m, rad]: 0.337 m ahead
#: of the base centre, where ``husky_description`` puts its SICK LMS1xx (top plate at x 0.0812 m,
#: mount 0.2206 m ahead of it, focal point 0.0352 m ahead of the mount), reported upright and
#: counter-clockwise, as a ROS driver configured for the mount would.
LASER_MOUNT = (0.3370, 0.0, 0.0)
#: Height of the scan plane above the ground [m]. Not the top-plate mount of
#: ``husky_description`` (0.4529 m): that plane passes over the P3-AT wanderers, whose body is
#: 0.08 to 0.277 m high, so the navigator would never see them. 0.20 m is a front-bumper mount,
#: cutting the P3-AT chassis and wheels and every wall; rays ignore the Husky's own body by
#: collision mask.
LASER_HEIGHT = 0.20


def _check_limit(value, name, allow_none=False):
    if allow_none and value is None:
        return
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
        raise ValueError(f'{name} must be a positive finite number, got {value!r}')


@dataclass(frozen=True)
class DriveLimits:
    """
    Velocity and acceleration limits of the base.

    Parameters
    ----------
    max_linear : float
        Largest forward or backward speed [m/s] (the Husky's top speed is 1.0 m/s).
    max_angular : float
        Largest turn rate [rad/s].
    max_linear_accel : float or None
        Largest change of speed [m/s^2]; None for an instant change. 3.0 m/s^2 is
        ``husky_control``'s diff-drive controller limit.
    max_angular_accel : float or None
        Largest change of turn rate [rad/s^2]; None for an instant change (``husky_control``:
        6.0 rad/s^2).

    """

    max_linear: float = 1.0
    max_angular: float = 1.5
    max_linear_accel: float = 3.0
    max_angular_accel: float = 6.0

    def __post_init__(self):
        _check_limit(self.max_linear, 'max_linear')
        _check_limit(self.max_angular, 'max_angular')
        _check_limit(self.max_linear_accel, 'max_linear_accel', allow_none=True)
        _check_limit(self.max_angular_accel, 'max_angular_accel', allow_none=True)


def clamp_command(v, omega, limits):
    """
    Clamp a velocity command to the limits.

    Parameters
    ----------
    v, omega : float
        Commanded forward speed [m/s] and turn rate [rad/s]; finite.
    limits : DriveLimits
        The limits.

    Returns
    -------
    v, omega : float
        Each clipped to ``[-max, max]``.

    """
    v = min(max(float(v), -limits.max_linear), limits.max_linear)
    omega = min(max(float(omega), -limits.max_angular), limits.max_angular)
    return v, omega


def ramp(current, target, max_accel, dt):
    """
    Move a velocity towards its target by at most ``max_accel * dt``.

    Parameters
    ----------
    current, target : float
        Present and wanted velocity (any unit ``u``).
    max_accel : float or None
        Largest rate of change [u/s]; None to jump to ``target``.
    dt : float
        Time step [s].

    Returns
    -------
    float
        The new velocity.

    """
    if max_accel is None:
        return target
    step = max_accel * dt
    return min(max(target, current - step), current + step)


def integrate_pose(pose, v, omega, dt):
    """
    Advance a differential-drive pose at constant velocity, exactly along the arc.

    Parameters
    ----------
    pose : (float, float, float)
        ``(x, y, yaw)`` in the map frame [m, m, rad].
    v, omega : float
        Forward speed [m/s] and turn rate [rad/s].
    dt : float
        Time step [s].

    Returns
    -------
    (float, float, float)
        The pose after ``dt``, yaw wrapped to ``[-pi, pi)``.

    """
    x, y, yaw = pose
    turn = omega * dt
    if abs(turn) < 1e-9:
        x += v * dt * math.cos(yaw + 0.5 * turn)
        y += v * dt * math.sin(yaw + 0.5 * turn)
    else:
        radius = v / omega
        x += radius * (math.sin(yaw + turn) - math.sin(yaw))
        y -= radius * (math.cos(yaw + turn) - math.cos(yaw))
    return x, y, wrap_angle(yaw + turn)
