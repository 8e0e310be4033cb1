"""
The ``dpn`` node: ROS 2 wrapper of the navigator core, a managed (lifecycle) node.

Topic names are relative to the node's namespace, ``compabot`` unless one is given
(``-r __ns:=/robot2``). Subscribes to ``scan`` (``sensor_msgs/LaserScan``, in frame
``laser_frame``), ``odom`` (``nav_msgs/Odometry``), ``/tf`` and ``/tf_static`` (the scan's pose:
``pose_source``, ``scan_placement``) and ``goal_pose`` (``geometry_msgs/PoseStamped``, in
``map_frame``); serves the ``navigate_to_pose`` action (``nav2_msgs/action/NavigateToPose``,
``navigate_action``) and the lifecycle services (``lifecycle``). No goal, no motion: a start-up
goal only with ``use_default_goal``. Publishes ``map`` (``nav_msgs/OccupancyGrid``, latched),
``map_updates`` (``map_msgs/OccupancyGridUpdate``: the changed cells, between full maps when
``map_publish_period`` spaces them out), ``cmd_vel`` (``geometry_msgs/Twist``, or
``TwistStamped`` with ``cmd_vel_stamped``), ``plan`` (``nav_msgs/Path``, latched), ``odom_real``
(``nav_msgs/Odometry``: the pose in use, in ``map_frame``), ``marker``
(``visualization_msgs/MarkerArray``: planned path red, executed path yellow, goal green),
``status`` (``diagnostic_msgs/DiagnosticStatus``, latched: status, reason, counters) and the
same status on ``/diagnostics`` (``DiagnosticArray``).

Once its laser has moved, the node surveys its first scans and logs once, as a warning, which
of the package's parameter files would suit that laser better than the node's (ideal-laser)
defaults, as ``dpn-replay`` does (`recording.sensor_survey`). A real laser on the move makes the
navigator take the real-laser settings itself (``real_laser_switch``, `core.real_laser`): the
node logs that once, as a warning, and says when in its status (``real_laser_since``).

Malformed scans, odometry, goals and ``/clock`` messages are rejected, counted and warned about
(throttled); the node keeps running. When scans or odometry are older than ``sensor_timeout`` on
the node clock or on the steady wall clock, the robot is stopped (docs/safety.md).

"""

from collections import deque
from dataclasses import dataclass, replace
import math
import statistics
import time

from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import PoseStamped
from map_msgs.msg import OccupancyGridUpdate
from nav_msgs.msg import OccupancyGrid, Odometry, Path
from rclpy.clock import Clock, ClockType
from rclpy.lifecycle import LifecycleNode
from sensor_msgs.msg import LaserScan
from visualization_msgs.msg import MarkerArray

from .cmd_vel_monitor import CommandTopicMonitor
from .command_publisher import CommandPublisher
from .conversions import (laser_scan_fields, OccupancyGridBuffer, odometry_to_pose,
                          pose_to_odometry, stamp_to_seconds)
from .diagnostics import diagnostic_status, DiagnosticsPublisher
from .dpn_params import declare_parameters, PARAMETERS
from .lifecycle import ManagedNavigator
from .names import DEFAULT_NAMESPACE
from .navigate_action import load_action_type, NavigateToPoseServer
from .navigator_markers import ExecutedTrail, NavigatorMarkers
from .parameter_declaration import refuse_undeclared_parameters
from .qos import COMMAND_QOS, LATCHED_QOS, SENSOR_QOS
from .safety_params import declare_safety_parameters
from .scan_placement import PoseNotYet, ScanNotPlaced, ScanPlacer
from .sensor_watchdog import SensorWatchdog, steady_arrival_time
from .sim_clock import guard_clock
from .spin import run_node
from .stop_guard import StopGuard
from .tf_pose_source import make_tf_lookup, stamp_to_nanoseconds
from .unknown_parameters import warn_unknown_parameters
from ..core import Navigator, NavigatorStatus
from ..core.control.acceleration_limit import AccelerationLimiter
from ..core.mapping.map_values import warm_up_map_values
from ..core.navigator import warm_up_navigator
from ..core.numpy_cache import fill_numpy_cache
from ..core.pose_history import PoseHistory
from ..core.scan_polygon import check_scan
from ..recording.sensor_survey import changed_settings, NODE_HINT_SCANS, SensorSurvey

WATCHDOG_PERIOD = 0.02          # steady clock [s]: first zero command <= sensor_timeout + this
STOP_ACK_TIMEOUT = 0.2          # wait this long for the last zero command's delivery [s]
WARN_THROTTLE = 2.0             # [s]
STATUS_PERIOD = 1.0             # status refreshed at least this often [s]
LATENCY_WINDOW = 100            # scans in the reported scan-to-map processing time
MAX_PENDING_SCANS = 10          # scans waiting for their pose; more drop the oldest
SCAN_WAIT_COUNTED = 0.005       # a scan placed this long after its arrival counts as waited [s]


@dataclass(frozen=True)
class PendingScan:
    """A checked scan waiting for its pose: message, fields, and when it came [s]."""

    msg: object
    fields: dict
    received: float         # perf_counter at the callback's start
    queued: float           # steady clock
    arrival: float          # steady clock, from the message info


class DpnNode(ManagedNavigator, LifecycleNode):
    """Map, plan and follow from scans and odometry; publish map, commands and markers."""

    def __init__(self, **node_kwargs):
        node_kwargs.setdefault('namespace', DEFAULT_NAMESPACE)
        super().__init__('dpn', **node_kwargs)
        # Inactive until activated (at the end here with autostart, else by change_state).
        self.active = False
        self.navigate = None
        self.map_placed = False
        self.params = declare_parameters(self)
        self.limits = declare_safety_parameters(self)
        refuse_undeclared_parameters(self)
        # Given at start but never declared (a misspelt name): warned about once, counted.
        self.unknown_parameters = warn_unknown_parameters(self)
        # Compile (or load) the kernels now, so that the first scan does not wait for them.
        started = time.perf_counter()
        warm_up_navigator()
        warm_up_map_values()
        compile_seconds = time.perf_counter() - started
        # numpy's cache of small freed buffers, full now rather than over the first minutes.
        fill_numpy_cache()
        self.navigator = Navigator(self.params.navigator)
        # The map as configured (or placed around the start pose), before any growth.
        self.map_config = self.params.navigator
        self.map_buffer = OccupancyGridBuffer(self.navigator.grid.geometry.shape,
                                              self.params.map_mobile_value)
        self.map_changes = self.navigator.grid.change_tracker()
        self.rejected = {'scan': 0, 'odometry': 0, 'goal': 0, 'clock': 0}
        self.scan_frame_mismatches = 0
        self.growth_refusals_logged = 0
        self.map_load_time = None
        self.watchdog = SensorWatchdog(self.params.sensor_timeout, ('scan', 'odometry'))
        self.steady_clock = Clock(clock_type=ClockType.STEADY_TIME)
        self.cmd_vel_monitor = CommandTopicMonitor()
        self.accel_limiter = AccelerationLimiter(self.params.max_linear_accel,
                                                 self.params.max_angular_accel)
        self.pose = None
        self.odom_pose = None
        # Odometry poses kept for placing scans: interpolated, never extrapolated.
        self.pose_history = PoseHistory(extrapolation=0.0)
        self.pending_scans = deque()
        self.scans_waited = 0
        self.scans_skipped = 0
        # What the laser does, until the hints are given (None after).
        self.laser_survey = SensorSurvey()
        self.laser_hints = 0
        # The first scan's time, and when the navigator took the real-laser settings [s].
        self.first_scan_time = None
        self.real_laser_since = None
        self.odom_frame_warned = False
        self.tf = (make_tf_lookup(self) if self.params.pose_source != 'odom' else None)
        self.placer = ScanPlacer(self.params.pose_source, self.params.map_frame,
                                 self.params.base_frame, self.tf, self.pose_history,
                                 self.params.max_laser_tilt, on_source=self.on_pose_source,
                                 auto_wait=self.params.pose_source_wait,
                                 max_gap=self.params.max_pose_gap)
        self.velocity = (0.0, 0.0)
        self.last_map_time = None
        self.markers = NavigatorMarkers(self.params.map_frame, self.params.marker_min_period)
        self.scan_to_map_ms = deque(maxlen=LATENCY_WINDOW)
        self.stale = False
        self.last_status = None
        # The executed path, every point of it allocated now (memory flat from the start).
        self.trail = ExecutedTrail()
        self.map_pub = self.create_publisher(OccupancyGrid, 'map', LATCHED_QOS)
        # Between full maps, the changed cells (the `<map>_updates` convention of Nav2's
        # costmaps and RViz's Map display); volatile: a late subscriber starts from a full map.
        self.map_updates_pub = (self.create_publisher(OccupancyGridUpdate, 'map_updates',
                                                      COMMAND_QOS)
                                if self.params.map_updates else None)
        self.cmd_pub = CommandPublisher(self, 'cmd_vel', self.params.cmd_vel_stamped,
                                        self.params.base_frame)
        self.odom_real_pub = self.create_publisher(Odometry, 'odom_real', COMMAND_QOS)
        self.marker_pub = self.create_publisher(MarkerArray, 'marker', LATCHED_QOS)
        self.plan_pub = self.create_publisher(Path, 'plan', LATCHED_QOS)
        self.diagnostics = DiagnosticsPublisher(self, 'status')
        # The stop on stale sensors, on a thread of its own: it runs however long a callback
        # takes; every command goes through it.
        self.stop_guard = StopGuard(self.watchdog, self.cmd_pub, self.now_seconds,
                                    self.steady_seconds, WATCHDOG_PERIOD,
                                    on_error=self.on_stop_guard_error)
        self.stop_guard.enabled = self.active
        # With the message info, so that the watchdog dates a message by its arrival.
        self.create_subscription(LaserScan, 'scan',
                                 lambda msg, info: self.on_scan(msg, info), SENSOR_QOS)
        self.create_subscription(Odometry, 'odom',
                                 lambda msg, info: self.on_odom(msg, info), SENSOR_QOS)
        self.create_subscription(PoseStamped, 'goal_pose', self.on_goal, COMMAND_QOS)
        # On the steady clock: they run when /clock stops.
        self.create_timer(WATCHDOG_PERIOD, self.on_watchdog, clock=self.steady_clock)
        self.create_timer(STATUS_PERIOD, self.on_status_timer, clock=self.steady_clock)
        guard_clock(self, lambda error: self.reject('clock', error))
        action_type = load_action_type()
        self.navigate = (NavigateToPoseServer(self, action_type) if action_type is not None
                         else None)
        if self.navigate is None:
            self.get_logger().warning('nav2_msgs is not installed: no navigate_to_pose action '
                                      '(goals on goal_pose only)')
        if self.params.goal is not None:
            self.set_goal(*self.params.goal, via='use_default_goal')
        else:
            warn_unused_goal(self)
        if self.params.autostart:
            self.trigger_configure()
            self.trigger_activate()
        self.publish_status()
        self.stop_guard.start()
        self.get_logger().info(
            f'dpn ready: {self.navigator.grid.geometry.cols}x'
            f'{self.navigator.grid.geometry.rows} cells of '
            f'{self.params.navigator.resolution} m, goal '
            f'{self.navigator.goal or "none (waiting for goal_pose)"}; kernels ready '
            f'in {compile_seconds:.2f} s')

    def now_seconds(self):
        """Return the node clock's time [s] (simulated time when use_sim_time is set)."""
        return self.get_clock().now().nanoseconds * 1e-9

    def steady_seconds(self):
        """Return the steady (monotonic wall) clock's time [s]."""
        return self.steady_clock.now().nanoseconds * 1e-9

    def arrival_seconds(self, info):
        """Return the steady-clock time [s] a message arrived at, from its ``MessageInfo``."""
        received = None if info is None else info.get('received_timestamp')
        return steady_arrival_time(self.steady_seconds(), time.time_ns(), received)

    def reject(self, kind, error):
        """Count a rejected message and warn, throttled."""
        self.rejected[kind] += 1
        self.get_logger().warning(
            f'rejected {kind} ({self.rejected[kind]} so far): {error}',
            throttle_duration_sec=WARN_THROTTLE)
        self.publish_status()

    def set_goal(self, x, y, via='goal_pose'):
        """
        Give the navigator a goal [m] in the map frame.

        Returns None, or the reason it was refused (off the map; counted).
        """
        try:
            self.navigator.set_goal(x, y)
        except ValueError as error:
            self.follow_map_growth()
            self.reject('goal', error)
            return str(error)
        self.follow_map_growth()
        self.trail.reset(None if self.pose is None else self.pose[:2])
        self.get_logger().info(f'goal accepted from {via}: ({x:.2f}, {y:.2f})')
        self.publish_status()
        return None

    def place_map(self, pose):
        """Centre the (still empty) map on ``pose``, the robot's first map-frame pose."""
        config = self.params.navigator
        origin = (pose[0] - 0.5 * config.width, pose[1] - 0.5 * config.height)
        goal = self.navigator.goal
        self.map_config = replace(config, origin=origin)
        self.clear_map(self.map_config)
        self.map_placed = True
        self.get_logger().info(f'map placed around the start pose: origin ({origin[0]:.2f}, '
                               f'{origin[1]:.2f}), {config.width} m x {config.height} m')
        if goal is not None:
            self.set_goal(*goal, via='the goal before the map was placed')

    def stop(self):
        """Drop the goal and send a zero command now (a canceled goal)."""
        self.navigator.clear_goal()
        self.cmd_pub.publish(0.0, 0.0)
        self.accel_limiter.reset(self.now_seconds())
        self.publish_status()

    def clear_map(self, config=None):
        """Start again with an empty map (as configured) and no goal, or another map."""
        self.navigator = Navigator(config or self.map_config)
        self.map_buffer = OccupancyGridBuffer(self.navigator.grid.geometry.shape,
                                              self.params.map_mobile_value)
        self.map_changes = self.navigator.grid.change_tracker()
        self.growth_refusals_logged = 0
        self.pending_scans.clear()
        self.trail.reset()
        self.last_map_time = None
        self.publish_status()

    def restart_map_for_tf(self):
        """
        Drop the map made of scans placed from odometry when TF takes over; keep the goal.

        Those scans were placed in the odometry frame with the ``laser_*`` mount: with a laser
        mounted otherwise, or ``map -> odom`` not the identity, their walls are misplaced.
        """
        goal = self.navigator.goal
        # As configured: the growth those scans asked for is dropped with them.
        self.navigator = Navigator(self.map_config)
        self.map_buffer = OccupancyGridBuffer(self.navigator.grid.geometry.shape,
                                              self.params.map_mobile_value)
        self.map_changes = self.navigator.grid.change_tracker()
        self.growth_refusals_logged = 0
        self.trail.reset()
        self.last_map_time = None
        if goal is not None:
            self.navigator.set_goal(*goal)
        self.get_logger().warning(
            f'TF now links {self.params.map_frame} to the laser: the map of the '
            f'{self.placer.placed_from_odometry} scan(s) placed from odometry and the laser_* '
            'mount is dropped and built again from TF')

    def on_goal(self, msg):
        """
        Take a goal from ``goal_pose`` (RViz's 2D Goal Pose).

        The goal must be in ``map_frame``; an empty frame id is taken as ``map_frame``. Its
        orientation is ignored: the navigator reaches a position.
        """
        if not self.active:
            self.reject('goal', 'the navigator is not active (lifecycle)')
            return
        map_frame = self.params.map_frame
        if msg.header.frame_id not in ('', map_frame):
            self.reject('goal', f'frame {msg.header.frame_id!r} is not {map_frame!r}')
            return
        if self.set_goal(msg.pose.position.x, msg.pose.position.y) is None \
                and self.navigate is not None:
            self.navigate.preempt('preempted by a goal on goal_pose')

    def on_pose_source(self, source):
        """Log where scans are placed from, the first time each source is used."""
        if source == 'tf':
            text = (f'TF {self.params.map_frame} -> <scan frame> at the scan stamp '
                    f'({self.tf.kind}); robot pose {self.params.map_frame} -> '
                    f'{self.params.base_frame}')
        else:
            text = ('odometry taken as the map pose, laser at laser_x/_y/_yaw'
                    + (' (no TF links the map frame to the laser yet)'
                       if self.params.pose_source == 'auto' else ''))
        self.get_logger().info(f'pose source: {text}')
        self.publish_status()

    def on_odom(self, msg, info=None):
        """Keep the latest finite base pose and extend the executed path."""
        try:
            pose = odometry_to_pose(msg)
            velocity = (msg.twist.twist.linear.x, msg.twist.twist.angular.z)
        except ValueError as error:
            self.reject('odometry', error)
            return
        odom_frame = self.params.odom_frame
        if (odom_frame and msg.header.frame_id not in ('', odom_frame)
                and not self.odom_frame_warned):
            self.odom_frame_warned = True
            self.get_logger().warning(
                f'odometry in frame {msg.header.frame_id!r}, not odom_frame {odom_frame!r}')
        self.odom_pose = pose
        if self.placer.source != 'tf':
            self.pose = pose
        self.velocity = velocity if all(math.isfinite(v) for v in velocity) else (0.0, 0.0)
        self.pose_history.add(stamp_to_seconds(msg.header.stamp), pose, self.velocity)
        self.stop_guard.heard('odometry', self.now_seconds(), self.arrival_seconds(info))
        if self.navigator.goal is not None and self.placer.source != 'tf':
            self.trail.extend(pose[:2])
        if self.pending_scans:
            self.place_pending_scans()

    def on_scan(self, msg, info=None):
        """Check the scan and queue it; place, map and answer the queued scans that can be."""
        if not self.active:
            return
        received = time.perf_counter()
        if len(msg.ranges) > self.limits.max_beams:
            self.reject('scan', f'{len(msg.ranges)} beams, more than max_beams '
                                f'{self.limits.max_beams}')
            return
        laser_frame = self.params.laser_frame
        if laser_frame and msg.header.frame_id != laser_frame:
            self.scan_frame_mismatches += 1
            self.reject('scan', f'frame {msg.header.frame_id!r} is not the laser frame '
                        f'{laser_frame!r} (set laser_frame, or laser_frame:="" to accept any)')
            return
        fields = laser_scan_fields(msg)
        try:
            check_scan(**fields)
        except ValueError as error:
            self.reject('scan', error)
            return
        if len(self.pending_scans) >= MAX_PENDING_SCANS:
            self.skip_scan(self.pending_scans.popleft(), 'more scans waiting than '
                           f'{MAX_PENDING_SCANS}')
        self.pending_scans.append(PendingScan(msg, fields, received, self.steady_seconds(),
                                              self.arrival_seconds(info)))
        self.place_pending_scans()

    def skip_scan(self, pending, reason):
        """Drop a queued scan, counted and warned about (throttled)."""
        self.scans_skipped += 1
        self.get_logger().warning(f'scan skipped ({self.scans_skipped} so far): {reason}',
                                  throttle_duration_sec=WARN_THROTTLE)
        self.publish_status()

    def place_pending_scans(self):
        """Handle the queued scans in order while their poses are known; drop the stale."""
        while self.pending_scans:
            pending = self.pending_scans[0]
            header = pending.msg.header
            try:
                placement = self.placer.place(header.frame_id, stamp_to_nanoseconds(
                    header.stamp), pending.fields)
            except PoseNotYet as error:
                if self.steady_seconds() - pending.queued < self.params.transform_timeout:
                    return
                self.pending_scans.popleft()
                self.skip_scan(pending, f'waited {self.params.transform_timeout} s: {error}')
                continue
            except ScanNotPlaced as error:
                self.pending_scans.popleft()
                self.skip_scan(pending, error)
                continue
            self.pending_scans.popleft()
            if self.steady_seconds() - pending.queued > SCAN_WAIT_COUNTED:
                self.scans_waited += 1
            self.handle_scan(pending, placement)

    def handle_scan(self, pending, placement):
        """Fold a placed scan into the map, decide the command, publish."""
        msg, received = pending.msg, pending.received
        now = self.now_seconds()
        if self.params.centre_on_start and not self.map_placed:
            self.place_map(placement.base_pose)
        if placement.source == 'tf':
            if self.placer.take_tf_takeover():
                self.restart_map_for_tf()
            pose = self.placer.robot_pose(None) or placement.base_pose
            self.pose = pose
            if self.navigator.goal is not None:
                self.trail.extend(pose[:2])
        try:
            # The free evidence waits until the map and the command are out (`settle`).
            self.navigator.observe(placement.base_pose, **placement.fields, stamp=now,
                                   defer_evidence=True, laser_pose=placement.laser_pose)
        except ValueError as error:
            self.reject('scan', error)
            return
        self.stop_guard.heard('scan', now, pending.arrival)
        self.survey_laser(placement)
        self.report_real_laser(now)
        self.follow_map_growth()
        stamp = msg.header.stamp
        # The map first: it is ready now, and planning can take longer.
        if (self.last_map_time is None
                or now - self.last_map_time >= self.params.map_publish_period
                or now < self.last_map_time):
            self.publish_map(stamp)
            self.last_map_time = now
            self.scan_to_map_ms.append(1e3 * (time.perf_counter() - received))
        elif self.map_updates_pub is not None and self.publish_map_update(stamp):
            self.scan_to_map_ms.append(1e3 * (time.perf_counter() - received))
        out = self.navigator.decide(now, self.pose)
        # Sent only while the sensors are fresh: never after the stop.
        self.stop_guard.publish(*self.accel_limiter.limit(out.command.linear,
                                                          out.command.angular, now))
        self.odom_real_pub.publish(pose_to_odometry(
            self.pose, self.velocity, stamp, frame_id=self.params.map_frame,
            child_frame_id=self.params.base_frame))
        status_changed = out.status is not self.last_status
        if status_changed:
            self.publish_status()
        if self.markers.due(out.replanned, status_changed, now):
            self.publish_markers(stamp, now)
        self.navigator.settle()

    def survey_laser(self, placement):
        """
        Count the scan in the laser survey; once the laser has moved, log the hints once.

        `NODE_HINT_SCANS` scans are surveyed, and the laser has moved more than
        ``sensor_survey.STANDING_DISTANCE``: a robot standing while it waits for a goal says
        nothing of its laser's returns on the move. Each hint is a warning; none when the
        parameters in use already cater for what the laser does.
        """
        survey = self.laser_survey
        if survey is None:
            return
        fields = placement.fields
        position = (placement.laser_pose or placement.base_pose)[:2]
        survey.add(fields['ranges'], fields['range_min'], fields['range_max'], position)
        if survey.scans < NODE_HINT_SCANS or survey.standing:
            return
        self.laser_survey = None
        hints = survey.hints(changed_settings(self.params.navigator), standing=False)
        for hint in hints:
            self.get_logger().warning(f'laser: {hint}')
        self.laser_hints = len(hints)

    def report_real_laser(self, now):
        """Log once, as a warning, that the navigator took the real-laser settings."""
        if self.first_scan_time is None:
            self.first_scan_time = now
        navigator = self.navigator
        if self.real_laser_since is not None or not navigator.real_laser_settings:
            return
        self.real_laser_since = now if navigator.real_laser_since is None \
            else navigator.real_laser_since
        self.get_logger().warning('laser: ' + navigator.real_laser.describe(
            navigator.real_laser_settings, self.real_laser_since - self.first_scan_time))
        self.publish_status()

    def follow_map_growth(self):
        """
        Resize the published map after the navigator's map grew; log refused growths.

        After a growth the next scan publishes a full map (an update cannot resize it).
        """
        navigator = self.navigator
        if navigator.map_growth_refusals > self.growth_refusals_logged:
            self.growth_refusals_logged = navigator.map_growth_refusals
            self.get_logger().warning(
                f'map growth refused ({navigator.map_growth_refusals} so far): '
                f'{navigator.map_growth_refusal}', throttle_duration_sec=WARN_THROTTLE)
            self.publish_status()
        geometry = navigator.grid.geometry
        if self.map_buffer.shape == geometry.shape:
            return
        self.map_buffer = OccupancyGridBuffer(geometry.shape, self.params.map_mobile_value)
        self.last_map_time = None
        self.get_logger().info(
            f'map grew to {geometry.cols}x{geometry.rows} cells ({geometry.width:g} m x '
            f'{geometry.height:g} m), origin ({geometry.origin[0]:.2f}, '
            f'{geometry.origin[1]:.2f}); {navigator.map_growths} growth(s)')
        self.publish_status()

    def publish_map(self, stamp):
        """Publish the labelled grid as an ``OccupancyGrid``."""
        geometry = self.navigator.grid.geometry
        if self.map_load_time is None:
            self.map_load_time = stamp
        # Only the cells changed since the last map are converted again.
        rows, cols, _ = self.map_changes.take()
        self.map_buffer.refresh(self.navigator.grid.labels, rows, cols)
        self.map_pub.publish(self.map_buffer.message(
            geometry.resolution, geometry.origin, stamp, frame_id=self.params.map_frame,
            load_time=self.map_load_time))

    def publish_map_update(self, stamp):
        """Publish the cells changed since the last map or update; return whether any did."""
        rows, cols, _ = self.map_changes.take()
        update = self.map_buffer.update_message(self.navigator.grid.labels, rows, cols, stamp,
                                                frame_id=self.params.map_frame)
        if update is None:
            return False
        self.map_updates_pub.publish(update)
        return True

    def publish_markers(self, stamp, now):
        """Publish the planned path (as markers and as a ``Path``), the executed path, the goal."""
        markers, plan = self.markers.messages(self.navigator.path_xy, self.trail,
                                              self.navigator.goal, stamp, now)
        self.marker_pub.publish(markers)
        self.plan_pub.publish(plan)

    def publish_status(self):
        """Publish status, reason and counters (latched ``status`` and ``/diagnostics``)."""
        status = self.navigator.status
        self.last_status = status
        level = (DiagnosticStatus.WARN if self.stale or status is NavigatorStatus.NO_PATH
                 else DiagnosticStatus.OK)
        goal = self.navigator.goal
        values = {
            'status': 'sensors_stale' if self.stale else status.value,
            'reason': self.navigator.reason,
            'replans': self.navigator.replans,
            'forgets': self.navigator.forgets,
            'goal_x': '' if goal is None else f'{goal[0]:.3f}',
            'goal_y': '' if goal is None else f'{goal[1]:.3f}',
            'rejected_scans': self.rejected['scan'],
            'rejected_odometry': self.rejected['odometry'],
            'rejected_goals': self.rejected['goal'],
            'rejected_clock': self.rejected['clock'],
            'scan_frame_mismatches': self.scan_frame_mismatches,
            # The map grew (map_growth_step), or a growth it needed was refused.
            'map_growths': self.navigator.map_growths,
            'map_growth_refusals': self.navigator.map_growth_refusals,
            # Parameters given at start that the node does not declare (warned about once).
            'unknown_parameters': len(self.unknown_parameters),
            # Hints logged on the laser (a parameter file that suits it; sensor_survey).
            'laser_hints': self.laser_hints,
            # When the navigator took the real-laser settings [s] ('' before; core.real_laser).
            'real_laser_since': ('' if self.real_laser_since is None
                                 else f'{self.real_laser_since:.3f}'),
            # Where scans are placed from: 'tf' or 'odom' ('' before the first).
            'pose_source': self.placer.source or '',
            # Scans that waited for their transform or odometry, and those dropped after
            # transform_timeout (or older than the kept odometry, or from a tilted laser).
            'scans_waited_for_pose': self.scans_waited,
            'scans_skipped_no_pose': self.scans_skipped,
            'scans_skipped_pose_gap': self.placer.gap_skips,
            'rejected_transforms': 0 if self.tf is None else self.tf.rejected,
            'sensors_stale': self.stale,
            'active': self.active,
            'cmd_vel_other_publishers': self.cmd_vel_monitor.others,
            'cmd_vel_conflicts': self.cmd_vel_monitor.conflicts,
            # Wall time from the scan callback's start to the map's publication [ms].
            'scan_to_map_ms_median': (f'{statistics.median(self.scan_to_map_ms):.3f}'
                                      if self.scan_to_map_ms else ''),
        }
        self.diagnostics.publish(diagnostic_status(
            self.get_fully_qualified_name(), self.get_namespace().strip('/') or 'dpn', level,
            'sensors stale' if self.stale else status.value, values))

    def on_watchdog(self):
        """Report stale scans or odometry (a thread stops the robot); retry queued scans."""
        if not self.active:
            return
        if self.pending_scans:
            self.place_pending_scans()
        # The stop guard's thread sends the zero commands; should it have ended, this timer does.
        stale = (self.stop_guard.stale_streams() if self.stop_guard.running
                 else self.stop_guard.check())
        if stale:
            self.accel_limiter.reset(self.now_seconds())
            if self.navigator.goal is not None:
                self.get_logger().warning(f'{" and ".join(stale)} stale: stopping',
                                          throttle_duration_sec=WARN_THROTTLE)
        if bool(stale) != self.stale:
            self.stale = bool(stale)
            self.publish_status()

    def on_status_timer(self):
        """Look for another publisher on the command topic; refresh the status."""
        topic = self.cmd_pub.topic_name
        if self.cmd_vel_monitor.check(self.count_publishers(topic)):
            self.get_logger().warning(
                f'{self.cmd_vel_monitor.others} other publisher(s) on {topic}: another node '
                'is commanding this robot', throttle_duration_sec=10.0 * WARN_THROTTLE)
        self.publish_status()

    def on_stop_guard_error(self, error):
        """Log why the stop guard's thread ended (the watchdog timer stops the robot then)."""
        self.get_logger().error(f'stop guard ended: {error}; the watchdog timer stops the robot')

    def destroy_node(self):
        """Send a zero command (waiting briefly for its delivery), then destroy the node."""
        self.stop_guard.close()
        self.cmd_pub.publish(0.0, 0.0)
        self.cmd_pub.wait_for_delivery(STOP_ACK_TIMEOUT)
        if self.navigate is not None:
            self.navigate.destroy()
        return super().destroy_node()


def warn_unused_goal(node):
    """Warn when ``goal_x``/``goal_y`` were changed but ``use_default_goal`` is off."""
    defaults = {p.name: p.default for p in PARAMETERS if p.name in ('goal_x', 'goal_y')}
    changed = [name for name, default in defaults.items()
               if node.get_parameter(name).value != default]
    if changed and not node.params.use_default_goal:
        node.get_logger().warning(
            f'{" and ".join(changed)} set but use_default_goal is false: no goal until one '
            'arrives on goal_pose (set use_default_goal:=true to start with it)')


def main(args=None, stop=None):
    """
    Run the node: ``ros2 run dpn_navigator dpn`` (through ``node_entry``).

    ``stop`` holds the stop-signal handlers ``node_entry`` installed before this module's
    imports (``spin.run_node``).

    """
    return run_node(DpnNode, args, stop)
