"""Tests of the dpn node in one process: real topics over DDS, scans ray-cast in a room."""

import math
import time

from diagnostic_msgs.msg import DiagnosticStatus
from dpn_navigator.conversions import (make_laser_scan, marker_points, occupancy_grid_values,
                                       pose_to_odometry)
from dpn_navigator.dpn_node import DpnNode
from dpn_navigator.qos import COMMAND_QOS, LATCHED_QOS, SENSOR_QOS
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid, Odometry
from node_harness import executor_for, spin_until
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN, ray_cast
from sensor_msgs.msg import LaserScan
from visualization_msgs.msg import MarkerArray

RANGE_MAX = 10.0
POSE = (2.0, 6.0, 0.0)


def room():
    occupied = np.zeros((240, 240), dtype=bool)        # 12 m x 12 m at 5 cm
    occupied[:6, :] = occupied[-6:, :] = occupied[:, :6] = occupied[:, -6:] = True
    return occupied


class Probe(Node):
    """Publish what the dpn node listens to; record what it publishes."""

    def __init__(self, context):
        super().__init__('probe', context=context)
        self.scan_pub = self.create_publisher(LaserScan, '/compabot/scan', SENSOR_QOS)
        self.odom_pub = self.create_publisher(Odometry, '/compabot/odom', SENSOR_QOS)
        self.goal_pub = self.create_publisher(PoseStamped, '/compabot/goal_pose', COMMAND_QOS)
        self.received = {'map': [], 'cmd': [], 'status': [], 'marker': []}
        topics = ((OccupancyGrid, '/compabot/map', 'map', LATCHED_QOS),
                  (Twist, '/compabot/cmd_vel', 'cmd', COMMAND_QOS),
                  (DiagnosticStatus, '/compabot/status', 'status', LATCHED_QOS),
                  (MarkerArray, '/compabot/marker', 'marker', LATCHED_QOS))
        for msg_type, topic, key, qos in topics:
            self.create_subscription(msg_type, topic, self.received[key].append, qos)

    def send(self, pose=POSE, scan=None, **scan_changes):
        stamp = self.get_clock().now().to_msg()
        self.odom_pub.publish(pose_to_odometry(pose, (0.0, 0.0), stamp))
        if scan is None:
            ranges = ray_cast(room(), pose, 0.05, RANGE_MAX)
            scan = make_laser_scan(ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX,
                                   stamp)
        for field, value in scan_changes.items():
            setattr(scan, field, value)
        self.scan_pub.publish(scan)

    def status_value(self, key):
        return {kv.key: kv.value for kv in self.received['status'][-1].values}[key]


@pytest.fixture
def nodes(ros_context):
    overrides = [Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
                 Parameter('goal_x', value=10.0), Parameter('goal_y', value=6.0),
                 Parameter('sensor_timeout', value=0.3)]
    dpn = DpnNode(context=ros_context, parameter_overrides=overrides)
    probe = Probe(ros_context)
    with executor_for(ros_context, dpn, probe) as executor:
        yield dpn, probe, executor


def wait_for_discovery(executor, probe):
    assert spin_until(executor, lambda: probe.scan_pub.get_subscription_count() > 0
                      and probe.odom_pub.get_subscription_count() > 0)


def test_scans_become_map_commands_markers_and_status(nodes):
    dpn, probe, executor = nodes
    wait_for_discovery(executor, probe)
    # Odometry first so that the scan can be placed, then a few scans.
    for _ in range(5):
        probe.send()
        spin_until(executor, lambda: False, timeout=0.05)
    assert spin_until(executor, lambda: probe.received['map'] and probe.received['cmd']
                      and probe.received['marker'])
    values = occupancy_grid_values(probe.received['map'][-1])
    assert values.shape == (24, 24)
    assert set(np.unique(values).tolist()) <= {-1, 0, 70, 100}
    assert np.count_nonzero(values == 0) > 50 and np.count_nonzero(values == 100) > 10
    moving = [cmd for cmd in probe.received['cmd'] if cmd.linear.x > 0.0]
    assert moving, 'the robot faces its goal in an open room: it should drive'
    for cmd in probe.received['cmd']:
        assert 0.0 <= cmd.linear.x <= 1.0 and abs(cmd.angular.z) <= 1.5
    planned = [m for m in probe.received['marker'][-1].markers if m.ns == 'planned_path']
    path = marker_points(planned[0])
    assert path.shape[0] >= 2
    assert np.allclose(path[-1], (10.0, 6.0))
    assert probe.status_value('status') == 'active'


def test_malformed_input_is_rejected_counted_and_survived(nodes):
    dpn, probe, executor = nodes
    wait_for_discovery(executor, probe)
    probe.send(angle_max=-2.0)                          # before odometry: still counted
    assert spin_until(executor, lambda: dpn.rejected['scan'] == 1)
    probe.send()
    assert spin_until(executor, lambda: dpn.pose is not None)
    probe.send(angle_max=0.5)                           # 640 ranges disagree with the angles
    probe.send(angle_increment=0.0)
    probe.send(range_max=0.05)                          # range_max <= range_min
    probe.send(angle_increment=math.nan)
    assert spin_until(executor, lambda: dpn.rejected['scan'] == 5)
    bad_odom = pose_to_odometry((math.nan, 1.0, 0.0), (0.0, 0.0),
                                probe.get_clock().now().to_msg())
    probe.odom_pub.publish(bad_odom)
    off_map = PoseStamped()
    off_map.header.frame_id = 'map'
    off_map.pose.position.x = 50.0
    probe.goal_pub.publish(off_map)
    assert spin_until(executor, lambda: dpn.rejected['odometry'] == 1
                      and dpn.rejected['goal'] == 1)
    assert spin_until(executor, lambda: probe.received['status']
                      and probe.status_value('rejected_scans') == '5'
                      and probe.status_value('rejected_goals') == '1')
    assert dpn.navigator.goal == (10.0, 6.0)            # the bad goal did not replace it
    # Still alive: a good scan is mapped and answered.
    probe.received['map'].clear()
    probe.send()
    assert spin_until(executor, lambda: probe.received['map'])


def test_stale_sensors_stop_the_robot(nodes):
    dpn, probe, executor = nodes
    wait_for_discovery(executor, probe)
    deadline = time.monotonic() + 1.0
    while time.monotonic() < deadline:                   # a healthy stream at ~20 Hz
        probe.send()
        spin_until(executor, lambda: False, timeout=0.05)
    assert any(cmd.linear.x > 0.0 for cmd in probe.received['cmd'])
    probe.received['cmd'].clear()
    stopped_at = time.monotonic()
    assert spin_until(executor, lambda: probe.received['cmd']
                      and probe.received['cmd'][-1].linear.x == 0.0, timeout=3.0)
    # No moving command after the stream stopped beyond the timeout (0.3 s) plus a tick.
    assert time.monotonic() - stopped_at < 1.0
    assert spin_until(executor, lambda: probe.status_value('sensors_stale') == 'True')
    # The stream returns: commands resume.
    probe.received['cmd'].clear()
    for _ in range(4):
        probe.send()
        spin_until(executor, lambda: False, timeout=0.05)
    assert spin_until(executor, lambda: any(c.linear.x > 0.0 for c in probe.received['cmd']))
