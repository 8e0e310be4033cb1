"""
Named robots for the world: body, drive limits, laser mount and laser, from their data sheets.

``husky`` is the Clearpath Husky A200 of the paper (``sim_bridge.husky``). ``turtlebot3_burger``
is the ROBOTIS TurtleBot3 Burger, the robot of most ROS 2 tutorials, with its LDS-01 laser:

- body 138 mm long, 178 mm wide, 192 mm high (ROBOTIS e-Manual, TurtleBot3 specifications;
  circumscribed radius 0.113 m; the ``robot_radius`` of ROBOTIS's Nav2 parameters is 0.105 m);
- maximum translational velocity 0.22 m/s, maximum rotational velocity 2.84 rad/s
  (162.72 deg/s) (e-Manual);
- acceleration limits 2.5 m/s^2 and 3.2 rad/s^2, those of ``turtlebot3_navigation2``'s
  ``burger.yaml`` (Nav2's defaults; the data sheet gives none);
- the LDS-01 at ``base_link -> base_scan`` ``(-0.032, 0, 0.172)`` m, upright
  (``turtlebot3_description``'s ``turtlebot3_burger.urdf``; ``base_link`` is 0.010 m above
  ``base_footprint``, so the scan plane is 0.182 m above the ground); the laser itself is the
  ``lds_01`` profile of ``laser_profiles``: 360 degrees in 1-degree steps, 0.12-3.5 m, 5 Hz.

The world's robot is a kinematic body either way (``world.py`` says why); a profile without a
URDF is a box of its length, width and height.

"""

from dataclasses import dataclass
import math

from .husky import DriveLimits, HUSKY_LENGTH, HUSKY_URDF, HUSKY_WIDTH, LASER_HEIGHT, \
    LASER_MOUNT
from .named_profiles import named_profile


@dataclass(frozen=True)
class RobotBody:
    """
    A robot's body in the world.

    Attributes
    ----------
    length, width : float
        Footprint along x and y, centred on the base [m].
    height : float
        Height of the box standing in for a body without URDF [m].
    urdf : str
        A model in ``pybullet_data`` ('' : a box of ``length`` x ``width`` x ``height``).

    """

    length: float
    width: float
    height: float
    urdf: str = ''

    def __post_init__(self):
        for name in ('length', 'width', 'height'):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
                raise ValueError(f'robot {name} must be a positive finite number, got '
                                 f'{value!r} m')

    @property
    def radius(self):
        """Return the radius of the circle around the footprint [m]."""
        return 0.5 * math.hypot(self.length, self.width)


@dataclass(frozen=True)
class RobotProfile:
    """
    A named robot: body, drive limits, laser mount, laser and scan rate.

    Attributes
    ----------
    name : str
        The ``robot_profile`` parameter's value.
    body : RobotBody
    drive : DriveLimits
    laser_mount : (float, float, float)
        The laser on the base ``(x, y, yaw)`` [m, m, rad].
    laser_height : float
        Height of the scan plane above the ground [m].
    laser_profile : str
        Its laser (``laser_profiles.LASER_PROFILES``).
    scan_rate : float
        The laser's scan rate [Hz].
    robot : str
        What it models.

    """

    name: str
    body: RobotBody
    drive: DriveLimits
    laser_mount: tuple
    laser_height: float
    laser_profile: str
    scan_rate: float
    robot: str


#: The profiles, by name.
ROBOT_PROFILES = {profile.name: profile for profile in (
    RobotProfile('husky', RobotBody(HUSKY_LENGTH, HUSKY_WIDTH, 0.39, HUSKY_URDF), DriveLimits(),
                 LASER_MOUNT, LASER_HEIGHT, 'ideal', 10.0, 'Clearpath Husky A200'),
    RobotProfile('turtlebot3_burger', RobotBody(0.138, 0.178, 0.192),
                 DriveLimits(max_linear=0.22, max_angular=2.84, max_linear_accel=2.5,
                             max_angular_accel=3.2),
                 (-0.032, 0.0, 0.0), 0.182, 'lds_01', 5.0, 'ROBOTIS TurtleBot3 Burger'),
)}


def robot_profile(name):
    """
    Return the `RobotProfile` called ``name``.

    Raises
    ------
    ValueError
        For an unknown name, listing the known ones.

    """
    return named_profile(ROBOT_PROFILES, 'robot profile', name)
