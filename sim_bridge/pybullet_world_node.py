"""
The ``pybullet_world`` node: the pybullet world over ROS 2, standing in for Gazebo.

Topic names are relative to the node's namespace, ``compabot`` unless one is given (``-r
__ns:=/robot2``). Publishes ``scan`` (``sensor_msgs/LaserScan``, frame ``laser``, reliable as REP
2003 asks of sensor drivers, so best-effort and reliable subscribers match), ``odom``
(``nav_msgs/Odometry``: the Husky's pose and velocity, frame ``odom``, child ``base_link``,
reliable too; drift-free by default, so ``odom`` coincides with ``map``; the ``odom_drift_*`` and
``odom_noise`` parameters make it drift as wheel odometry does), ``sim/status``
(``diagnostic_msgs/DiagnosticStatus``, latched: simulated time, contact counts, rejected commands;
also on ``/diagnostics``) and ``sim/wanderers`` (``visualization_msgs/MarkerArray``, one cylinder
per P3-AT, ground truth in ``map``). Global: ``/clock`` (``rosgraph_msgs/Clock``, simulated time,
every tick), ``/tf`` (``map -> odom`` from ground truth, standing in for a localiser, exact or with
the ``localiser_*`` error and rate, and ``odom -> base_link``, at every odometry stamp) and
``/tf_static`` (``base_link -> laser``, the ``laser_*`` mount, upside down too); see
``sim_bridge.robot_frames`` and ``sim_bridge.odometry_drift``. Subscribes to ``cmd_vel``
(``geometry_msgs/Twist``, or ``TwistStamped`` with ``cmd_vel_stamped``): non-finite commands are
ignored with a warning and counted, the rest clamped to the Husky's limits; with no command for
``cmd_timeout`` seconds of simulated time the Husky stops, as its base controller does.

The world advances one physics tick per wall-clock timer period
``1 / (physics_rate * real_time_factor)``; when the CPU cannot keep up it runs as fast as it
can.

"""

import math

from diagnostic_msgs.msg import DiagnosticStatus
from dpn_navigator.core.planning.astar_search import warm_up_astar
from dpn_navigator.core.pose2d import compose
from dpn_navigator.ros.command_publisher import command_to_velocity, command_type
from dpn_navigator.ros.conversions import make_laser_scan, pose_to_odometry, seconds_to_time
from dpn_navigator.ros.diagnostics import diagnostic_status, DiagnosticsPublisher
from dpn_navigator.ros.names import DEFAULT_NAMESPACE
from dpn_navigator.ros.parameter_declaration import (declare_setting,
                                                     refuse_undeclared_parameters)
from dpn_navigator.ros.qos import COMMAND_QOS, SENSOR_PUBLISHER_QOS
from dpn_navigator.ros.sim_clock import guard_clock
from dpn_navigator.ros.spin import run_node
from dpn_navigator.ros.unknown_parameters import warn_unknown_parameters
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from visualization_msgs.msg import MarkerArray

from .laser_profiles import laser_config
from .odometry_drift import DriftConfig, DriftingOdometry, Localiser, LocaliserConfig
from .robot_frames import FrameNames, RobotFramePublisher
from .scenario import load_scenario
from .wanderer_markers import wanderer_markers
from .world import World, WorldConfig
from .world_parameters import robot_settings, world_node_settings, WorldNodeParameters

WARN_THROTTLE = 2.0     # [s]


class PybulletWorldNode(Node):
    """Run a pybullet world and exchange its sensors and commands over ROS topics."""

    def __init__(self, **node_kwargs):
        node_kwargs.setdefault('namespace', DEFAULT_NAMESPACE)
        super().__init__('pybullet_world', **node_kwargs)
        values = {name: declare_setting(self, name, default, spec)
                  for name, (default, spec) in world_node_settings().items()}
        params = WorldNodeParameters(**values)
        refuse_undeclared_parameters(self)
        # Given at start but never declared (a misspelt name): warned about once, counted.
        self.unknown_parameters = warn_unknown_parameters(self)
        scenario_name, task = params.scenario, params.task
        start = (params.start_x, params.start_y, params.start_yaw)
        wanderers, seed, gui = params.wanderers, params.seed, params.gui
        self.real_time_factor = params.real_time_factor
        physics_rate = params.physics_rate
        self.cmd_timeout = params.cmd_timeout
        cmd_vel_stamped = params.cmd_vel_stamped
        self.frames = FrameNames(params.map_frame, params.odom_frame, params.base_frame,
                                 params.laser_frame)

        scenario = load_scenario(scenario_name)
        if task >= len(scenario.tasks):
            raise ValueError(f'scenario {scenario.name!r} has {len(scenario.tasks)} tasks; '
                             f'task {task} does not exist')
        default_start = scenario.tasks[task].start
        start = tuple(default_start[k] if math.isnan(start[k]) else start[k] for k in range(3))
        robot = robot_settings(params)
        scan_rate = robot.scan_rate
        laser = laser_config(
            robot.laser_profile, noise_std=params.laser_noise, dropout=params.laser_dropout,
            max_incidence=params.laser_max_incidence,
            mixed_pixel_probability=params.laser_mixed_pixel_probability,
            error_encoding=params.laser_error_encoding, mount=robot.laser_mount,
            height=robot.laser_height, upside_down=params.laser_upside_down)
        config = WorldConfig(physics_rate=physics_rate, scan_rate=scan_rate,
                             n_wanderers=wanderers, seed=seed, gui=gui, drive=robot.drive,
                             body=robot.body, laser=laser)
        self.odometry = DriftingOdometry(
            DriftConfig(params.odom_drift_scale, params.odom_drift_yaw_scale,
                        params.odom_drift_yaw_per_metre, params.odom_noise), start, seed)
        self.localiser = Localiser(LocaliserConfig(params.localiser_error_xy,
                                                   params.localiser_error_yaw,
                                                   params.localiser_rate), seed)
        # The wanderers plan with the core's A* kernel: compile (or load) it before the first
        # tick rather than in the middle of one.
        warm_up_astar()
        self.world = World(scenario, config, start=start)
        self.goal = scenario.tasks[task].goal
        self.command = (0.0, 0.0)
        self.last_command_time = -math.inf
        self.scan_pub = self.create_publisher(LaserScan, 'scan', SENSOR_PUBLISHER_QOS)
        self.odom_pub = self.create_publisher(Odometry, 'odom', SENSOR_PUBLISHER_QOS)
        self.clock_pub = self.create_publisher(Clock, '/clock', COMMAND_QOS)
        self.diagnostics = DiagnosticsPublisher(self, 'sim/status')
        self.wanderer_pub = self.create_publisher(MarkerArray, 'sim/wanderers', COMMAND_QOS)
        self.robot_frames = RobotFramePublisher(self, self.frames, config.laser.mount,
                                                config.laser.height, config.laser.upside_down)
        self.create_subscription(command_type(cmd_vel_stamped), 'cmd_vel', self.on_cmd_vel,
                                 COMMAND_QOS)
        self.create_timer(1.0 / (physics_rate * self.real_time_factor), self.on_tick)
        # Only with use_sim_time (another simulator's /clock): a bad /clock must not end it.
        guard_clock(self, lambda error: self.get_logger().warning(
            f'ignored /clock: {error}', throttle_duration_sec=WARN_THROTTLE))
        self.get_logger().info(
            f'{scenario.name}: task {task}, start {start}, goal {self.goal}, '
            f'{wanderers} wanderers, robot {params.robot_profile}, laser '
            f'{robot.laser_profile} at {scan_rate:g} Hz, real-time factor '
            f'{self.real_time_factor}')

    def on_cmd_vel(self, msg):
        """Keep the latest finite command; ignore and count a non-finite one."""
        try:
            self.command = command_to_velocity(msg)
        except ValueError as error:
            self.world.rejected_commands += 1
            self.get_logger().warning(
                f'ignored cmd_vel ({self.world.rejected_commands} so far): {error}',
                throttle_duration_sec=WARN_THROTTLE)
            return
        self.last_command_time = self.world.time

    def on_tick(self):
        """Advance one physics tick and publish what is due."""
        world = self.world
        if world.scan_due:
            self.publish_scan()
        v, omega = self.command
        if world.time - self.last_command_time > self.cmd_timeout:
            v, omega = 0.0, 0.0
        world.step(v, omega)
        stamp = seconds_to_time(world.time)
        self.clock_pub.publish(Clock(clock=stamp))
        pose = world.husky_pose
        frames = self.frames
        # The odometry pose: the true pose unless drift is set (the velocity stays the true one).
        odom_pose = self.odometry.update(pose)
        self.odom_pub.publish(pose_to_odometry(odom_pose, world.husky_velocity, stamp,
                                               frame_id=frames.odom, child_frame_id=frames.base))
        # map -> odom as the localiser has it, published as its pose estimate of the base.
        odom_in_map = self.localiser.update(world.time, pose, odom_pose)
        self.robot_frames.publish(compose(odom_in_map, odom_pose), odom_pose, stamp)

    def publish_scan(self):
        """Publish the scan of this tick, the wanderers and the status."""
        world = self.world
        scan = world.scan()
        stamp = seconds_to_time(scan.stamp)
        self.scan_pub.publish(make_laser_scan(
            scan.ranges, scan.angle_min, scan.angle_increment, scan.range_min, scan.range_max,
            stamp, frame_id=self.frames.laser, scan_time=1.0 / world.config.scan_rate))
        self.publish_wanderers(stamp)
        self.publish_status()

    def publish_wanderers(self, stamp):
        """Publish one cylinder marker per wanderer at its true position."""
        self.wanderer_pub.publish(wanderer_markers(
            self.world.wanderer_positions, self.world.wanderer_radius, stamp, self.frames.map))

    def publish_status(self):
        """Publish simulated time, contacts and counters as a latched ``DiagnosticStatus``."""
        world = self.world
        contacts = world.contacts
        values = {
            'time': f'{world.time:.3f}',
            'wall_contacts': contacts.wall_events,
            'wanderer_contacts': contacts.wanderer_events,
            'first_contact_time': ('' if contacts.first_contact_time is None
                                   else f'{contacts.first_contact_time:.3f}'),
            'rejected_commands': world.rejected_commands,
            'goal_x': f'{self.goal[0]:.3f}',
            'goal_y': f'{self.goal[1]:.3f}',
            'wanderers': len(world.wanderer_positions),
            'unknown_parameters': len(self.unknown_parameters),
        }
        self.diagnostics.publish(diagnostic_status(
            self.get_fully_qualified_name(), 'sim', DiagnosticStatus.OK,
            f't = {world.time:.1f} s, {contacts.events} contacts', values))

    def destroy_node(self):
        """Close the pybullet client with the node."""
        self.world.close()
        return super().destroy_node()


def main(args=None, stop=None):
    """
    Run the node: ``ros2 run sim_bridge pybullet_world`` (through ``node_entry``).

    ``stop`` holds the stop-signal handlers ``node_entry`` installed before this module's
    imports (``spin.run_node``).

    """
    return run_node(PybulletWorldNode, args, stop)
