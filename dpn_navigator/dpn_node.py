"""
The ``dpn`` node: ROS 2 wrapper of the navigator core.

Subscribes to ``/compabot/scan`` (``sensor_msgs/LaserScan``), ``/compabot/odom``
(``nav_msgs/Odometry``, the base pose in frame ``map``) and ``/compabot/goal_pose``
(``geometry_msgs/PoseStamped``). Publishes ``/compabot/map`` (``nav_msgs/OccupancyGrid``,
latched), ``/compabot/cmd_vel`` (``geometry_msgs/Twist``), ``/compabot/odom_real``
(``nav_msgs/Odometry``: the pose in use), ``/compabot/marker``
(``visualization_msgs/MarkerArray``: planned path red, executed path yellow, goal green) and
``/compabot/status`` (``diagnostic_msgs/DiagnosticStatus``, latched: status, reason, counters).

Malformed scans, odometry and goals are rejected, counted and warned about (throttled); the node
keeps running. When scans or odometry are older than ``sensor_timeout`` the robot is stopped.

"""

from collections import deque
import math
import statistics
import time

from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid, Odometry
import numpy as np
from rclpy.node import Node
from sensor_msgs.msg import LaserScan
from visualization_msgs.msg import MarkerArray

from .conversions import (labels_to_occupancy_grid, laser_scan_fields, line_strip_marker,
                          odometry_to_pose, pose_to_odometry, sphere_marker,
                          velocity_to_twist)
from .core import jit, Navigator, NavigatorStatus
from .core.scan_polygon import check_scan
from .dpn_params import declare_parameters
from .qos import COMMAND_QOS, LATCHED_QOS, SENSOR_QOS
from .spin import run_node

WATCHDOG_PERIOD = 0.05          # [s]
WARN_THROTTLE = 2.0             # [s]
TRAIL_STEP = 0.05               # executed-path points at least this far apart [m]
TRAIL_MAX_POINTS = 20000
MARKER_PERIOD = 0.5             # markers at most this often, besides replans [s]
STATUS_PERIOD = 1.0             # status refreshed at least this often [s]
LATENCY_WINDOW = 100            # scans in the reported scan-to-map processing time
RED, YELLOW, GREEN = (1.0, 0.0, 0.0, 1.0), (1.0, 0.85, 0.0, 1.0), (0.0, 0.8, 0.0, 1.0)


class DpnNode(Node):
    """Map, plan and follow from scans and odometry; publish map, commands and markers."""

    def __init__(self, **node_kwargs):
        super().__init__('dpn', **node_kwargs)
        self.params = declare_parameters(self)
        # Compile (or load) the kernels now, so that the first scan does not wait for them.
        compile_seconds = jit.warm_up()
        self.navigator = Navigator(self.params.navigator)
        self.rejected = {'scan': 0, 'odometry': 0, 'goal': 0}
        self.pose = None
        self.velocity = (0.0, 0.0)
        self.last_scan_time = None
        self.last_odom_time = None
        self.last_map_time = None
        self.last_marker_time = -math.inf
        self.scan_to_map_ms = deque(maxlen=LATENCY_WINDOW)
        self.stale = False
        self.last_status = None
        self.trail = []
        self.map_pub = self.create_publisher(OccupancyGrid, '/compabot/map', LATCHED_QOS)
        self.cmd_pub = self.create_publisher(Twist, '/compabot/cmd_vel', COMMAND_QOS)
        self.odom_real_pub = self.create_publisher(Odometry, '/compabot/odom_real', COMMAND_QOS)
        self.marker_pub = self.create_publisher(MarkerArray, '/compabot/marker', LATCHED_QOS)
        self.status_pub = self.create_publisher(DiagnosticStatus, '/compabot/status',
                                                LATCHED_QOS)
        self.create_subscription(LaserScan, '/compabot/scan', self.on_scan, SENSOR_QOS)
        self.create_subscription(Odometry, '/compabot/odom', self.on_odom, SENSOR_QOS)
        self.create_subscription(PoseStamped, '/compabot/goal_pose', self.on_goal, COMMAND_QOS)
        self.create_timer(WATCHDOG_PERIOD, self.on_watchdog)
        self.create_timer(STATUS_PERIOD, self.publish_status)
        if self.params.goal is not None:
            self.set_goal(*self.params.goal)
        self.publish_status()
        self.get_logger().info(
            f'dpn ready: {self.navigator.grid.geometry.cols}x'
            f'{self.navigator.grid.geometry.rows} cells of '
            f'{self.params.navigator.resolution} m, goal {self.navigator.goal}; kernels ready '
            f'in {compile_seconds:.2f} s')

    def now_seconds(self):
        """Return the node clock's time [s] (simulated time when use_sim_time is set)."""
        return self.get_clock().now().nanoseconds * 1e-9

    def reject(self, kind, error):
        """Count a rejected message and warn, throttled."""
        self.rejected[kind] += 1
        self.get_logger().warning(
            f'rejected {kind} ({self.rejected[kind]} so far): {error}',
            throttle_duration_sec=WARN_THROTTLE)
        self.publish_status()

    def set_goal(self, x, y):
        """Give the navigator a goal [m]; reject it (counted) when it is off the map."""
        try:
            self.navigator.set_goal(x, y)
        except ValueError as error:
            self.reject('goal', error)
            return
        self.trail = [] if self.pose is None else [self.pose[:2]]
        self.get_logger().info(f'goal accepted: ({x:.2f}, {y:.2f})')
        self.publish_status()

    def on_goal(self, msg):
        """Take a goal from ``/compabot/goal_pose`` (RViz's 2D Goal Pose)."""
        if msg.header.frame_id not in ('', 'map'):
            self.reject('goal', f'frame {msg.header.frame_id!r} is not map')
            return
        self.set_goal(msg.pose.position.x, msg.pose.position.y)

    def on_odom(self, msg):
        """Keep the latest finite base pose and extend the executed path."""
        try:
            pose = odometry_to_pose(msg)
            velocity = (msg.twist.twist.linear.x, msg.twist.twist.angular.z)
        except ValueError as error:
            self.reject('odometry', error)
            return
        self.pose = pose
        self.velocity = velocity if all(math.isfinite(v) for v in velocity) else (0.0, 0.0)
        self.last_odom_time = self.now_seconds()
        if self.navigator.goal is not None and (
                not self.trail or math.dist(self.trail[-1], pose[:2]) >= TRAIL_STEP):
            self.trail.append(pose[:2])
            del self.trail[:-TRAIL_MAX_POINTS]

    def on_scan(self, msg):
        """Fold the scan into the map, decide the command, publish."""
        received = time.perf_counter()
        now = self.now_seconds()
        fields = laser_scan_fields(msg)
        try:
            if self.pose is None:
                # The scan cannot be placed yet, but a malformed one still counts.
                check_scan(**fields)
                self.get_logger().info('waiting for odometry',
                                       throttle_duration_sec=WARN_THROTTLE)
                return
            self.navigator.observe(self.pose, **fields)
        except ValueError as error:
            self.reject('scan', error)
            return
        self.last_scan_time = now
        stamp = msg.header.stamp
        # The map first: it is ready now, and planning can take longer.
        if (self.last_map_time is None
                or now - self.last_map_time >= self.params.map_publish_period
                or now < self.last_map_time):
            self.publish_map(stamp)
            self.last_map_time = now
            self.scan_to_map_ms.append(1e3 * (time.perf_counter() - received))
        out = self.navigator.decide(now, self.pose)
        if not self.sensors_stale(now):
            self.cmd_pub.publish(velocity_to_twist(out.command.linear, out.command.angular))
        self.odom_real_pub.publish(pose_to_odometry(self.pose, self.velocity, stamp))
        status_changed = out.status is not self.last_status
        if status_changed:
            self.publish_status()
        if (out.replanned or status_changed
                or abs(now - self.last_marker_time) >= MARKER_PERIOD):
            self.publish_markers(stamp)
            self.last_marker_time = now

    def publish_map(self, stamp):
        """Publish the labelled grid as an ``OccupancyGrid``."""
        geometry = self.navigator.grid.geometry
        self.map_pub.publish(labels_to_occupancy_grid(
            self.navigator.grid.labels, geometry.resolution, geometry.origin, stamp))

    def publish_markers(self, stamp):
        """Publish the planned path, the executed path and the goal."""
        markers = MarkerArray()
        path = self.navigator.path_xy
        markers.markers.append(line_strip_marker(
            np.zeros((0, 2)) if path is None else path, 'planned_path', 0, RED, 0.1, stamp))
        markers.markers.append(line_strip_marker(self.trail, 'executed_path', 1, YELLOW, 0.08,
                                                 stamp))
        if self.navigator.goal is not None:
            markers.markers.append(sphere_marker(self.navigator.goal, 'goal', 2, GREEN, 0.4,
                                                 stamp))
        self.marker_pub.publish(markers)

    def publish_status(self):
        """Publish status, reason and counters as a latched ``DiagnosticStatus``."""
        status = self.navigator.status
        self.last_status = status
        msg = DiagnosticStatus()
        msg.name = 'dpn'
        msg.hardware_id = 'compabot'
        msg.level = (DiagnosticStatus.WARN if self.stale or status is NavigatorStatus.NO_PATH
                     else DiagnosticStatus.OK)
        msg.message = 'sensors stale' if self.stale else status.value
        goal = self.navigator.goal
        values = {
            'status': status.value, 'reason': self.navigator.reason,
            'replans': self.navigator.replans,
            'forgets': self.navigator.forgets,
            'goal_x': '' if goal is None else f'{goal[0]:.3f}',
            'goal_y': '' if goal is None else f'{goal[1]:.3f}',
            'rejected_scans': self.rejected['scan'],
            'rejected_odometry': self.rejected['odometry'],
            'rejected_goals': self.rejected['goal'],
            'sensors_stale': self.stale,
            # Wall time from the scan callback's start to the map's publication [ms].
            'scan_to_map_ms_median': (f'{statistics.median(self.scan_to_map_ms):.3f}'
                                      if self.scan_to_map_ms else ''),
        }
        msg.values = [KeyValue(key=k, value=str(v)) for k, v in values.items()]
        self.status_pub.publish(msg)

    def sensors_stale(self, now):
        """Tell whether the latest scan or odometry is older than ``sensor_timeout``."""
        timeout = self.params.sensor_timeout
        return any(last is None or now - last > timeout or now < last
                   for last in (self.last_scan_time, self.last_odom_time))

    def on_watchdog(self):
        """Stop the robot while scans or odometry are stale."""
        stale = self.sensors_stale(self.now_seconds())
        if stale:
            self.cmd_pub.publish(velocity_to_twist(0.0, 0.0))
            if self.navigator.goal is not None:
                self.get_logger().warning('scan or odometry stale: stopping',
                                          throttle_duration_sec=WARN_THROTTLE)
        if stale != self.stale:
            self.stale = stale
            self.publish_status()


def main(args=None):
    """Run the ``dpn`` node: ``ros2 run dpn_navigator dpn``."""
    run_node(DpnNode, args)
