"""
The ``pybullet_world`` node's parameters, each stated once: default, unit, range and meaning.

No ROS here: the node declares its parameters from these settings
(``pybullet_world_node``), and ``config/pybullet_world.yaml`` and the node's table in
``docs/ros_reference.md`` are written from them (``dpn_navigator.tools.parameter_files``).

"""

from dataclasses import dataclass, fields, replace
import math

from dpn_navigator.core.settings import setting, settings_of

from .husky import DriveLimits
from .robot_profiles import robot_profile, RobotBody


@dataclass(frozen=True)
class WorldNodeParameters:
    """The ``pybullet_world`` node's parameters, read once at start; each field's setting."""

    scenario: str = setting(
        'back_and_forth', '', 'built-in scenario name, or the path of any map_server '
        '`map.yaml`')
    task: int = setting(0, '', 'which start/goal pair of the scenario', 0, 1000)
    start_x: float = setting(
        math.nan, 'm', "override the task's start x, like a spawn pose; NaN: the task's")
    start_y: float = setting(
        math.nan, 'm', "override the task's start y, like a spawn pose; NaN: the task's")
    start_yaw: float = setting(
        math.nan, 'rad', "override the task's start heading; NaN: the task's")
    wanderers: int = setting(3, '', 'wandering P3-AT robots', 0, 10)
    seed: int = setting(0, '', 'seed of the wanderers and the laser artefacts', 0, 2**31 - 1)
    gui: bool = setting(False, '', 'open the pybullet GUI window')
    real_time_factor: float = setting(
        1.0, '', '1.0 = wall-clock pace; higher runs faster', 0.01, 1000.0)
    physics_rate: float = setting(
        50.0, 'Hz', 'physics ticks per simulated second', 1.0, 1000.0)
    scan_rate: float = setting(
        math.nan, 'Hz', 'scans per simulated second, 0.1 to 1000; must divide `physics_rate`; '
        "NaN: the robot profile's (10 for `husky`, 5 for `turtlebot3_burger`)")
    robot_profile: str = setting(
        'husky', '', "the simulated robot: `husky` (Clearpath Husky A200, the paper's) or "
        '`turtlebot3_burger` (ROBOTIS TurtleBot3 Burger with its LDS-01): body, speed and '
        'acceleration limits, laser mount, laser and scan rate from their data sheets '
        '([simulator.md](simulator.md#robot-profiles)); the parameters below override parts')
    robot_length: float = setting(
        math.nan, 'm', "the robot's footprint along x (its collision body); NaN: the profile's")
    robot_width: float = setting(
        math.nan, 'm', "the robot's footprint along y; NaN: the profile's")
    max_vel_x: float = setting(
        math.nan, 'm/s', "the robot's top speed, forward and back (commands are clamped to "
        "it); NaN: the profile's (Husky 1.0, TurtleBot3 Burger 0.22)")
    max_vel_theta: float = setting(
        math.nan, 'rad/s', "the robot's top turn rate; NaN: the profile's (Husky 1.5, "
        'TurtleBot3 Burger 2.84)')
    acc_lim_x: float = setting(
        math.nan, 'm/s^2', "the robot's largest change of speed; NaN: the profile's (Husky 3.0, "
        'TurtleBot3 Burger 2.5)')
    acc_lim_theta: float = setting(
        math.nan, 'rad/s^2', "the robot's largest change of turn rate; NaN: the profile's "
        '(Husky 6.0, TurtleBot3 Burger 3.2)')
    laser_profile: str = setting(
        '', '', "the simulated laser: `ideal` (the paper's perfect 640-beam, 180-degree "
        'laser), `sick_lms1xx`, `hokuyo_utm30lx`, `hokuyo_urg04lx`, `rplidar_a2` or `lds_01`, '
        'modelled on their data sheets ([simulator.md](simulator.md#laser-profiles)); empty: '
        "the robot profile's (`ideal` for `husky`, `lds_01` for `turtlebot3_burger`)")
    laser_noise: float = setting(
        math.nan, 'm', "standard deviation of the Gaussian range noise's floor; NaN: the "
        "profile's (0 for `ideal`)")
    laser_dropout: float = setting(
        math.nan, '', "share of the hits that return nothing, 0 to 1; NaN: the profile's")
    laser_max_incidence: float = setting(
        math.nan, 'rad', 'beams meeting a surface farther than this from its normal return '
        "nothing, up to pi/2 (off); NaN: the profile's")
    laser_mixed_pixel_probability: float = setting(
        math.nan, '', 'chance that a beam beside a depth jump returns a range between the two '
        "surfaces, 0 to 1; NaN: the profile's")
    laser_error_encoding: str = setting(
        '', '', 'how a beam with no valid reading is written: `rep117` (+inf no return, -inf '
        "too close), `nan`, or `tiny_codes` (the old Hokuyo driver's codes below `range_min`); "
        "empty: the profile's")
    cmd_timeout: float = setting(
        0.5, 's', 'stop when no `cmd_vel` came for this long (simulated time)', 0.01, 60.0)
    cmd_vel_stamped: bool = setting(
        False, '', 'take geometry_msgs/TwistStamped on `cmd_vel` instead of Twist')
    laser_x: float = setting(
        math.nan, 'm', 'laser position on the base, forward, -10 to 10 (published on '
        "`/tf_static`); NaN: the robot profile's (Husky 0.337, TurtleBot3 Burger -0.032)")
    laser_y: float = setting(
        math.nan, 'm', "laser position on the base, left, -10 to 10; NaN: the profile's")
    laser_z: float = setting(
        math.nan, 'm', 'height of the scan plane above the ground, 0.01 to 10; NaN: the '
        "profile's (Husky 0.20, TurtleBot3 Burger 0.182)")
    laser_yaw: float = setting(
        math.nan, 'rad', "laser heading on the base, -pi to pi; NaN: the profile's")
    laser_upside_down: bool = setting(
        False, '', 'laser mounted upside down (rolled by pi: its beams sweep clockwise)')
    odom_drift_scale: float = setting(
        0.0, '', 'relative error of the distance in the odometry (0.02: 2 % too long)', -0.4, 0.4)
    odom_drift_yaw_scale: float = setting(
        0.0, '', 'relative error of the turns in the odometry', -0.4, 0.4)
    odom_drift_yaw_per_metre: float = setting(
        0.0, 'rad/m', 'heading error the odometry adds per metre driven', -1.0, 1.0)
    odom_noise: float = setting(
        0.0, 'm/sqrt(m)', 'odometry noise of distance [m] and heading [rad] per square root of '
        'metre driven', 0.0, 1.0)
    localiser_error_xy: float = setting(
        0.0, 'm', "position error of the simulated localiser's `map -> odom`", 0.0, 10.0)
    localiser_error_yaw: float = setting(
        0.0, 'rad', "heading error of the simulated localiser's `map -> odom`", -math.pi,
        math.pi)
    localiser_rate: float = setting(
        0.0, 'Hz', 'refreshes of `map -> odom` per simulated second (published every tick, '
        'the last refresh between); 0: every tick', 0.0, 1000.0)
    map_frame: str = setting('map', '', 'frame id of the map (the fixed world frame)')
    odom_frame: str = setting('odom', '', 'frame id of the odometry frame')
    base_frame: str = setting('base_link', '', 'frame id of the robot base')
    laser_frame: str = setting('laser', '', 'frame id of the laser (the frame of the scans)')


@dataclass(frozen=True)
class RobotSettings:
    """The robot the node simulates: its profile with the parameters' overrides applied."""

    body: RobotBody
    drive: DriveLimits
    laser_mount: tuple          # (x, y, yaw) on the base [m, m, rad]
    laser_height: float         # [m]
    laser_profile: str
    scan_rate: float            # [Hz]


def _given(params, name, profile_value, low=None, high=None):
    """Return a NaN-defaulted parameter's value, else the profile's; check its range."""
    value = getattr(params, name)
    if math.isnan(value):
        return profile_value
    if low is not None and not (math.isfinite(value) and low <= value <= high):
        raise ValueError(f'parameter {name} = {value!r} is outside [{low}, {high}]')
    return value


def robot_settings(params):
    """
    Return the robot of ``params``: its ``robot_profile`` with the parameters set over it.

    Parameters
    ----------
    params : WorldNodeParameters
        The node's parameters.

    Returns
    -------
    RobotSettings

    Raises
    ------
    ValueError
        For an unknown profile or a value out of its range.

    """
    profile = robot_profile(params.robot_profile)
    body = replace(profile.body, length=_given(params, 'robot_length', profile.body.length),
                   width=_given(params, 'robot_width', profile.body.width))
    drive = DriveLimits(
        max_linear=_given(params, 'max_vel_x', profile.drive.max_linear),
        max_angular=_given(params, 'max_vel_theta', profile.drive.max_angular),
        max_linear_accel=_given(params, 'acc_lim_x', profile.drive.max_linear_accel),
        max_angular_accel=_given(params, 'acc_lim_theta', profile.drive.max_angular_accel))
    mount = (_given(params, 'laser_x', profile.laser_mount[0], -10.0, 10.0),
             _given(params, 'laser_y', profile.laser_mount[1], -10.0, 10.0),
             _given(params, 'laser_yaw', profile.laser_mount[2], -math.pi, math.pi))
    return RobotSettings(body, drive, mount,
                         _given(params, 'laser_z', profile.laser_height, 0.01, 10.0),
                         params.laser_profile or profile.laser_profile,
                         _given(params, 'scan_rate', profile.scan_rate, 0.1, 1000.0))


def world_node_settings():
    """Return ``{name: (default, Setting)}`` of every parameter, in declaration order."""
    return settings_of(WorldNodeParameters)


#: The parameters' names, in order.
PARAMETER_NAMES = tuple(item.name for item in fields(WorldNodeParameters))
