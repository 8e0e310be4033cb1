"""Tests of the pybullet_world node in one process: real topics over DDS."""

import math
import time

from diagnostic_msgs.msg import DiagnosticStatus
from dpn_navigator.conversions import odometry_to_pose, velocity_to_twist
from dpn_navigator.qos import COMMAND_QOS, LATCHED_QOS, SENSOR_QOS
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from node_harness import executor_for
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from sim_bridge.pybullet_world_node import PybulletWorldNode


class Probe(Node):
    """Drive the world with cmd_vel and record what it publishes."""

    def __init__(self, context):
        super().__init__('world_probe', context=context)
        self.cmd_pub = self.create_publisher(Twist, '/compabot/cmd_vel', COMMAND_QOS)
        self.scans, self.odoms, self.clocks, self.statuses = [], [], [], []
        self.create_subscription(LaserScan, '/compabot/scan', self.scans.append, SENSOR_QOS)
        self.create_subscription(Odometry, '/compabot/odom', self.odoms.append, SENSOR_QOS)
        self.create_subscription(Clock, '/clock', self.clocks.append, COMMAND_QOS)
        self.create_subscription(DiagnosticStatus, '/sim/status', self.statuses.append,
                                 LATCHED_QOS)

    def status(self, key):
        return {kv.key: kv.value for kv in self.statuses[-1].values}[key]


@pytest.fixture
def world(ros_context):
    node = PybulletWorldNode(context=ros_context, parameter_overrides=[
        Parameter('wanderers', value=1), Parameter('real_time_factor', value=5.0)])
    probe = Probe(ros_context)
    with executor_for(ros_context, node, probe) as executor:
        yield node, probe, executor


def spin_for(executor, sim_node, simulated, publish=None):
    """Spin until ``simulated`` more seconds of simulated time pass, publishing each spin."""
    end = sim_node.world.time + simulated
    deadline = time.monotonic() + 30.0
    while sim_node.world.time < end and time.monotonic() < deadline:
        if publish is not None:
            publish()
        executor.spin_once(timeout_sec=0.01)


def test_publishes_scan_odometry_clock_and_status(world):
    node, probe, executor = world
    spin_for(executor, node, 1.0)
    assert len(probe.scans) >= 5
    scan = probe.scans[-1]
    assert scan.header.frame_id == 'laser' and len(scan.ranges) == 640
    assert scan.angle_min == pytest.approx(-math.pi / 2)
    assert scan.angle_max == pytest.approx(math.pi / 2)
    odom = probe.odoms[-1]
    assert (odom.header.frame_id, odom.child_frame_id) == ('map', 'base_link')
    start = node.world.scenario.tasks[0].start
    assert odometry_to_pose(odom)[:2] == pytest.approx(start[:2], abs=1e-6)
    stamps = [c.clock.sec + 1e-9 * c.clock.nanosec for c in probe.clocks]
    assert stamps == sorted(stamps) and stamps[-1] > 0.5
    assert probe.status('wanderers') == '1'


def test_commands_are_clamped_rejected_when_not_finite_and_time_out(world):
    node, probe, executor = world
    spin_for(executor, node, 0.2)
    too_fast = velocity_to_twist(5.0, 0.0)
    spin_for(executor, node, 2.0, publish=lambda: probe.cmd_pub.publish(too_fast))
    speed = probe.odoms[-1].twist.twist.linear.x
    assert 0.9 <= speed <= 1.0                        # clamped to the Husky's 1.0 m/s
    x_before = node.world.husky_pose[0]
    nan_twist = velocity_to_twist(math.nan, 0.0)
    probe.cmd_pub.publish(nan_twist)
    spin_for(executor, node, 0.3)
    assert node.world.rejected_commands == 1
    assert node.world.husky_pose[0] > x_before        # the last good command still holds
    # No command for longer than cmd_timeout (0.5 s): the Husky stops.
    spin_for(executor, node, 1.5)
    assert node.world.husky_velocity[0] == pytest.approx(0.0, abs=1e-9)
    assert probe.status('rejected_commands') == '1'
