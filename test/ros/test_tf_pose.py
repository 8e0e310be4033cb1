"""
Scans placed from TF (issue 29): the laser's pose at the scan's stamp, its full 3-D mount.

A probe plays a robot whose odometry has drifted (``map -> odom`` is not the identity) and whose
laser is mounted upside down and turned, announced only in TF; the ``laser_*`` parameters keep
the Husky's mount, which is wrong here. Placed from TF, the map of the known room has every wall
cell it sees and no wrong cell; placed from odometry and parameters (``pose_source: odom``), it
is wrong (so the test can fail).
"""

import math

from diagnostic_msgs.msg import DiagnosticStatus
from dpn_navigator.core.frames import TfBuffer
from dpn_navigator.core.laser_mount import mirror_scan, planar_laser_pose
from dpn_navigator.core.pose2d import compose
from dpn_navigator.ros.conversions import (make_laser_scan, occupancy_grid_values,
                                           pose_to_odometry)
from dpn_navigator.ros.dpn_node import DpnNode
from dpn_navigator.ros.qos import LATCHED_QOS, SENSOR_QOS, TF_QOS, TF_STATIC_QOS
from dpn_navigator.ros.tf_messages import tf_message, transform_stamped
from dpn_navigator.ros.tf_pose_source import FallbackTfLookup, TransformUnavailable
from nav_msgs.msg import OccupancyGrid, Odometry
from node_harness import executor_for, spin_until
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN, ray_cast
from sensor_msgs.msg import LaserScan
from tf2_msgs.msg import TFMessage

RANGE_MAX = 10.0
TRUE_POSE = (4.0, 6.0, 0.4)                 # the base in the map frame [m, m, rad]
ODOM_IN_MAP = (0.8, -0.6, 0.25)             # map -> odom: the drift the localiser corrects
MOUNT = (0.2, 0.1, 0.3, math.pi / 2)        # x, y, z [m], yaw [rad] of the laser on the base


def room():
    occupied = np.zeros((240, 240), dtype=bool)        # 12 m x 12 m at 5 cm
    occupied[:6, :] = occupied[-6:, :] = occupied[:, :6] = occupied[:, -6:] = True
    return occupied


def inverse(pose):
    x, y, yaw = pose
    c, s = math.cos(yaw), math.sin(yaw)
    return (-c * x - s * y, s * x - c * y, -yaw)


def mount_transform(stamp):
    """``base_link -> laser``: the mount, rolled by pi (upside down)."""
    x, y, z, yaw = MOUNT
    msg = transform_stamped('base_link', 'laser', (x, y, yaw), stamp, z=z)
    r = msg.transform.rotation
    r.x, r.y, r.z, r.w = math.cos(yaw / 2), math.sin(yaw / 2), 0.0, 0.0
    return msg


class RobotProbe(Node):
    """Publish TF, drifted odometry and upside-down scans; keep the maps."""

    def __init__(self, context, publish_tf=True):
        super().__init__('tf_probe', context=context)
        self.publish_tf = publish_tf
        self.tf_pub = self.create_publisher(TFMessage, '/tf', TF_QOS)
        self.static_pub = self.create_publisher(TFMessage, '/tf_static', TF_STATIC_QOS)
        self.scan_pub = self.create_publisher(LaserScan, '/compabot/scan', SENSOR_QOS)
        self.odom_pub = self.create_publisher(Odometry, '/compabot/odom', SENSOR_QOS)
        self.maps, self.status = [], []
        self.create_subscription(OccupancyGrid, '/compabot/map', self.maps.append, LATCHED_QOS)
        self.create_subscription(DiagnosticStatus, '/compabot/status', self.status.append,
                                 LATCHED_QOS)
        if publish_tf:
            self.start_tf()
        odom_pose = compose(inverse(ODOM_IN_MAP), TRUE_POSE)
        self.odom_pose = odom_pose
        laser_map = compose(TRUE_POSE, (MOUNT[0], MOUNT[1], MOUNT[3]))
        # Upside down, laser angle a looks along map angle yaw - a: the upright scan reversed
        # (the 180-degree layout is symmetric).
        self.ranges = ray_cast(room(), laser_map, 0.05, RANGE_MAX)[::-1].copy()

    def start_tf(self):
        """Publish the mount on ``/tf_static`` and from now on ``/tf`` with every scan."""
        self.publish_tf = True
        self.static_pub.publish(tf_message(mount_transform(self.get_clock().now().to_msg())))

    def send(self):
        stamp = self.get_clock().now().to_msg()
        if self.publish_tf:
            self.tf_pub.publish(tf_message(
                transform_stamped('map', 'odom', ODOM_IN_MAP, stamp),
                transform_stamped('odom', 'base_link', self.odom_pose, stamp)))
        self.odom_pub.publish(pose_to_odometry(self.odom_pose, (0.0, 0.0), stamp,
                                               frame_id='odom'))
        self.scan_pub.publish(make_laser_scan(self.ranges, ANGLE_MIN, ANGLE_INCREMENT,
                                              RANGE_MIN, RANGE_MAX, stamp))

    def status_value(self, key):
        return {kv.key: kv.value for kv in self.status[-1].values}.get(key)


def wall_cells(shape):
    """Cells of the walls (0.3 m thick) and the band the label grid marks beside a hit."""
    walls = np.zeros(shape, dtype=bool)
    walls[:2, :] = walls[-2:, :] = walls[:, :2] = walls[:, -2:] = True
    return walls


def send_scans(executor, probe, count):
    """Send ``count`` scans with their odometry (and TF when on), 0.1 s apart."""
    for _ in range(count):
        probe.send()
        spin_until(executor, lambda: False, timeout=0.1)


def start_tf(executor, probe):
    """Start TF and let ``/tf_static`` be delivered."""
    probe.start_tf()
    spin_until(executor, lambda: False, timeout=0.3)


def run_robot(ros_context, pose_source, scans=8):
    dpn = DpnNode(context=ros_context, parameter_overrides=[
        Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
        Parameter('pose_source', value=pose_source)])
    probe = RobotProbe(ros_context)
    with executor_for(ros_context, dpn, probe) as executor:
        assert spin_until(executor, lambda: probe.scan_pub.get_subscription_count() > 0
                          and probe.odom_pub.get_subscription_count() > 0)
        spin_until(executor, lambda: False, timeout=0.3)       # /tf_static delivered
        send_scans(executor, probe, scans)
        assert spin_until(executor, lambda: len(probe.maps) >= scans - 2)
        spin_until(executor, lambda: False, timeout=0.3)
        values = occupancy_grid_values(probe.maps[-1])
        source = probe.status_value('pose_source')
        pose = dpn.pose
    return values, source, pose


def test_upside_down_laser_known_only_from_tf_maps_the_room_right(ros_context):
    values, source, pose = run_robot(ros_context, 'auto')
    assert source == 'tf'
    np.testing.assert_allclose(pose, TRUE_POSE, atol=1e-6)
    occupied = values >= 70
    walls = wall_cells(values.shape)
    assert not np.any(occupied & ~walls), 'an obstacle where the room is free'
    # The laser looks to the robot's left (mount yaw pi/2 + base yaw 0.4): it sees the top
    # wall (24 cells) and the left wall up to it, every cell of them.
    assert np.all(occupied[-1, :]) and np.all(occupied[9:, 0])


def test_the_same_robot_placed_from_odometry_and_parameters_maps_wrong(ros_context):
    values, source, _ = run_robot(ros_context, 'odom')
    assert source == 'odom'
    occupied = values >= 70
    assert np.count_nonzero(occupied & ~wall_cells(values.shape)) > 10


def test_scans_wait_for_tf_at_start_so_no_map_is_ever_wrong(ros_context):
    # The node starts before the publisher of the mount; TF comes within pose_source_wait
    # (1 s by default): the scans before it wait and are dropped, none is placed from odometry
    # with the laser_* parameters' mount (upright, at 0.337 m), which is wrong here.
    dpn = DpnNode(context=ros_context, parameter_overrides=[
        Parameter('map_width', value=12.0), Parameter('map_height', value=12.0)])
    probe = RobotProbe(ros_context, publish_tf=False)
    with executor_for(ros_context, dpn, probe) as executor:
        assert spin_until(executor, lambda: probe.scan_pub.get_subscription_count() > 0
                          and probe.odom_pub.get_subscription_count() > 0)
        send_scans(executor, probe, 3)
        assert spin_until(executor, lambda: dpn.scans_skipped >= 3)
        start_tf(executor, probe)
        send_scans(executor, probe, 4)
        assert spin_until(executor, lambda: len(probe.maps) >= 2)
        spin_until(executor, lambda: False, timeout=0.3)
        assert dpn.placer.source == 'tf' and dpn.placer.placed_from_odometry == 0
    walls = wall_cells((24, 24))
    for grid in probe.maps:
        assert not np.any((occupancy_grid_values(grid) >= 70) & ~walls)


def test_when_tf_comes_late_the_map_of_the_scans_placed_from_odometry_is_dropped(ros_context):
    # TF comes after the wait (none here): the first scans are placed from odometry with the
    # laser_* parameters' mount, which is wrong here; TF's arrival drops what they mapped.
    dpn = DpnNode(context=ros_context, parameter_overrides=[
        Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
        Parameter('use_default_goal', value=True), Parameter('goal_x', value=6.0),
        Parameter('goal_y', value=6.0), Parameter('pose_source_wait', value=0.0)])
    probe = RobotProbe(ros_context, publish_tf=False)
    with executor_for(ros_context, dpn, probe) as executor:
        assert spin_until(executor, lambda: probe.scan_pub.get_subscription_count() > 0
                          and probe.odom_pub.get_subscription_count() > 0)
        send_scans(executor, probe, 4)
        assert spin_until(executor, lambda: dpn.placer.placed_from_odometry >= 3)
        wrong = np.count_nonzero((occupancy_grid_values(probe.maps[-1]) >= 70)
                                 & ~wall_cells(dpn.navigator.grid.geometry.shape))
        assert wrong > 10                                  # the wrong mount did map wrong
        start_tf(executor, probe)
        send_scans(executor, probe, 4)
        assert spin_until(executor, lambda: probe.status
                          and probe.status_value('pose_source') == 'tf')
        spin_until(executor, lambda: False, timeout=0.3)
        values = occupancy_grid_values(probe.maps[-1])
        assert dpn.navigator.goal == (6.0, 6.0)            # the goal is kept
    occupied = values >= 70
    assert not np.any(occupied & ~wall_cells(values.shape)), 'an obstacle where it is free'
    assert np.all(occupied[-1, :]) and np.all(occupied[9:, 0])


def test_scans_without_their_transform_are_skipped_and_counted(ros_context):
    dpn = DpnNode(context=ros_context, parameter_overrides=[
        Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
        Parameter('pose_source', value='tf'), Parameter('transform_timeout', value=0.1)])
    probe = RobotProbe(ros_context, publish_tf=False)
    with executor_for(ros_context, dpn, probe) as executor:
        assert spin_until(executor, lambda: probe.scan_pub.get_subscription_count() > 0)
        for _ in range(4):
            probe.send()
            spin_until(executor, lambda: False, timeout=0.2)
        assert spin_until(executor, lambda: dpn.scans_skipped >= 3)
        assert spin_until(executor, lambda: probe.status
                          and int(probe.status_value('scans_skipped_no_pose')) >= 3)
        assert not np.any(dpn.navigator.grid.labels)       # nothing mapped


def test_fallback_lookup_follows_tf2_rules_and_counts_bad_transforms(ros_context):
    node = Node('lookup_host', context=ros_context)
    try:
        lookup = FallbackTfLookup(node)
        stamp = node.get_clock().now().to_msg()
        lookup.add(tf_message(mount_transform(stamp)), True)
        assert not lookup.connected('map', 'laser')
        t0 = stamp.sec * 10**9 + stamp.nanosec
        for dt, x in ((0, 1.0), (100_000_000, 2.0)):
            msg = transform_stamped('map', 'base_link', (x, 0.0, 0.0), stamp)
            msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(t0 + dt, 10**9)
            lookup.add(tf_message(msg), False)
        assert lookup.connected('map', 'laser')
        rotation, translation = lookup.lookup('map', 'laser', t0 + 50_000_000)
        assert translation[0] == pytest.approx(1.5 + 0.2)       # interpolated, plus the mount
        laser, mirrored = planar_laser_pose(rotation, translation)
        assert mirrored and laser[2] == pytest.approx(math.pi / 2)
        with pytest.raises(TransformUnavailable, match='extrapolation into the future'):
            lookup.lookup('map', 'laser', t0 + 200_000_000)
        bad = transform_stamped('map', 'other', (math.nan, 0.0, 0.0), stamp)
        lookup.add(tf_message(bad), False)
        assert lookup.rejected == 1
    finally:
        node.destroy_node()


def test_mirrored_scan_keeps_each_beam_on_its_direction():
    buffer = TfBuffer()
    buffer.set_transform('base_link', 'laser', 0, (0.0, 0.0, 0.0),
                         (math.cos(0.3), math.sin(0.3), 0.0, 0.0), static=True)
    laser, mirrored = planar_laser_pose(buffer.lookup('base_link', 'laser').rotation_matrix(),
                                        np.zeros(3))
    assert mirrored and laser[2] == pytest.approx(0.6)
    ranges = np.arange(5, dtype=np.float32)
    upright, angle_min, increment, angle_max = mirror_scan(ranges, -1.0, 0.5)
    # Beam k of the upside-down laser looks along yaw - (-1 + 0.5 k); in the upright scan it
    # is beam 4 - k at angle -1 + 0.5 (4 - k) = 1 - 0.5 k.
    assert (angle_min, increment, angle_max) == (-1.0, 0.5, 1.0)
    np.testing.assert_array_equal(upright, ranges[::-1])


def test_a_tilted_laser_is_refused():
    tilt = 0.2
    rotation = np.array([[1.0, 0.0, 0.0], [0.0, math.cos(tilt), -math.sin(tilt)],
                         [0.0, math.sin(tilt), math.cos(tilt)]])
    with pytest.raises(ValueError, match='tilted 11.5 deg'):
        planar_laser_pose(rotation, np.zeros(3))
