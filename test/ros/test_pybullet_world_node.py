"""Tests of the pybullet_world node in one process: real topics over DDS."""

import math
from pathlib import Path
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from dpn_navigator.ros.conversions import odometry_to_pose, quaternion_to_yaw, velocity_to_twist
from dpn_navigator.ros.qos import COMMAND_QOS, LATCHED_QOS, SENSOR_QOS, TF_QOS, TF_STATIC_QOS
from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry
from node_harness import executor_for
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from sim_bridge.husky import LASER_HEIGHT, LASER_MOUNT
from sim_bridge.pybullet_world_node import PybulletWorldNode
from tf2_msgs.msg import TFMessage
from tf_chain import FrameChain
import yaml


class Probe(Node):
    """Drive the world with cmd_vel and record what it publishes."""

    def __init__(self, context, command_type=Twist):
        super().__init__('world_probe', context=context)
        self.cmd_pub = self.create_publisher(command_type, '/compabot/cmd_vel', COMMAND_QOS)
        self.scans, self.odoms, self.clocks, self.statuses = [], [], [], []
        self.diagnostics = []
        self.frames = FrameChain()
        self.create_subscription(LaserScan, '/compabot/scan', self.scans.append, SENSOR_QOS)
        self.create_subscription(Odometry, '/compabot/odom', self.odoms.append, SENSOR_QOS)
        self.create_subscription(Clock, '/clock', self.clocks.append, COMMAND_QOS)
        self.create_subscription(DiagnosticStatus, '/compabot/sim/status', self.statuses.append,
                                 LATCHED_QOS)
        self.create_subscription(DiagnosticArray, '/diagnostics', self.diagnostics.append,
                                 COMMAND_QOS)
        self.create_subscription(TFMessage, '/tf', lambda m: self.frames.add(m, False), TF_QOS)
        self.create_subscription(TFMessage, '/tf_static', lambda m: self.frames.add(m, True),
                                 TF_STATIC_QOS)

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
    assert (odom.header.frame_id, odom.child_frame_id) == ('odom', 'base_link')
    start = node.world.scenario.tasks[0].start
    assert odometry_to_pose(odom)[:2] == pytest.approx(start[:2], abs=1e-6)
    stamps = [c.clock.sec + 1e-9 * c.clock.nanosec for c in probe.clocks]
    assert stamps == sorted(stamps) and stamps[-1] > 0.5
    assert probe.status('wanderers') == '1'
    assert probe.diagnostics[-1].status[0].name == '/compabot/pybullet_world'


def test_tf_chain_map_odom_base_laser_resolves_at_scan_stamps(world):
    node, probe, executor = world
    velocity = velocity_to_twist(0.5, 0.4)      # turn and drive, so the chain is not trivial
    spin_for(executor, node, 2.0, publish=lambda: probe.cmd_pub.publish(velocity))
    odom_by_stamp = {(o.header.stamp.sec, o.header.stamp.nanosec): o for o in probe.odoms}
    checked = 0
    for scan in probe.scans[1:]:
        stamp = scan.header.stamp
        translation, rotation = probe.frames.lookup('map', scan.header.frame_id, stamp)
        odom = odom_by_stamp.get((stamp.sec, stamp.nanosec))
        if odom is None:                # best-effort odometry: a message may be missing
            continue
        x, y, yaw = odometry_to_pose(odom)
        mx, my, myaw = LASER_MOUNT
        expected = (x + math.cos(yaw) * mx - math.sin(yaw) * my,
                    y + math.sin(yaw) * mx + math.cos(yaw) * my, LASER_HEIGHT)
        assert translation == pytest.approx(expected, abs=1e-6)
        laser_yaw = math.atan2(2.0 * (rotation[3] * rotation[2] + rotation[0] * rotation[1]),
                               1.0 - 2.0 * (rotation[1] ** 2 + rotation[2] ** 2))
        yaw_error = math.remainder(laser_yaw - (yaw + myaw), 2 * math.pi)
        assert yaw_error == pytest.approx(0.0, abs=1e-6)
        checked += 1
    assert checked >= 5
    assert probe.frames.parents == {'odom': 'map', 'base_link': 'odom', 'laser': 'base_link'}
    assert 'laser' in probe.frames.static and 'base_link' not in probe.frames.static
    # The robot moved: odom -> base_link is not the identity.
    last_odom = probe.odoms[-1]
    assert abs(quaternion_to_yaw(last_odom.pose.pose.orientation)) > 0.3
    assert np.hypot(*(np.array(odometry_to_pose(last_odom)[:2])
                      - node.world.scenario.tasks[0].start[:2])) > 0.3


def test_twist_stamped_commands_drive_the_robot(ros_context):
    node = PybulletWorldNode(context=ros_context, parameter_overrides=[
        Parameter('wanderers', value=0), Parameter('real_time_factor', value=5.0),
        Parameter('cmd_vel_stamped', value=True)])
    probe = Probe(ros_context, command_type=TwistStamped)
    with executor_for(ros_context, node, probe) as executor:
        spin_for(executor, node, 0.2)
        command = TwistStamped(twist=velocity_to_twist(0.5, 0.0))
        command.header.frame_id = 'base_link'
        spin_for(executor, node, 1.5, publish=lambda: probe.cmd_pub.publish(command))
        assert node.world.husky_velocity[0] == pytest.approx(0.5, abs=0.05)


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


def test_code_defaults_are_those_of_the_parameter_file(ros_context):
    config = Path(__file__).resolve().parents[2] / 'config' / 'pybullet_world.yaml'
    values = yaml.safe_load(config.read_text())['/**/pybullet_world']['ros__parameters']
    node = PybulletWorldNode(context=ros_context)
    try:
        assert node.get_fully_qualified_name() == '/compabot/pybullet_world'
        for name, value in values.items():
            actual = node.get_parameter(name).value
            if isinstance(value, float) and math.isnan(value):
                assert math.isnan(actual), name
            else:
                assert actual == value and type(actual) is type(value), name
    finally:
        node.destroy_node()


def test_drifting_odometry_a_localiser_and_an_upside_down_laser_in_tf(ros_context):
    node = PybulletWorldNode(context=ros_context, parameter_overrides=[
        Parameter('wanderers', value=0), Parameter('real_time_factor', value=5.0),
        Parameter('odom_drift_scale', value=0.1),
        Parameter('odom_drift_yaw_per_metre', value=0.2),
        Parameter('laser_upside_down', value=True), Parameter('laser_x', value=0.2)])
    probe = Probe(ros_context)
    velocity = velocity_to_twist(0.8, 0.3)
    with executor_for(ros_context, node, probe) as executor:
        spin_for(executor, node, 3.0, publish=lambda: probe.cmd_pub.publish(velocity))
        # No more commands: the Husky stops after cmd_timeout (0.5 s) and stands.
        spin_for(executor, node, 1.5)
    truth = node.world.husky_pose
    stamp = probe.odoms[-1].header.stamp
    # The odometry drifted away from the truth ...
    assert math.dist(node.odometry.pose[:2], truth[:2]) > 0.1
    # ... and map -> odom (the exact localiser) puts base_link back on the truth.
    translation, _ = probe.frames.lookup('map', 'base_link', stamp)
    assert translation[:2] == pytest.approx(truth[:2], abs=1e-3)
    # The laser is mounted upside down (roll pi) 0.2 m ahead, announced on /tf_static.
    _, laser_rotation = probe.frames.lookup('base_link', 'laser', stamp)
    assert laser_rotation == pytest.approx([1.0, 0.0, 0.0, 0.0], abs=1e-9)
    assert probe.frames.static['laser'][0][0] == pytest.approx(0.2)


def test_a_turtlebot3_burger_with_its_lds_01(ros_context):
    node = PybulletWorldNode(context=ros_context, parameter_overrides=[
        Parameter('wanderers', value=0), Parameter('real_time_factor', value=5.0),
        Parameter('robot_profile', value='turtlebot3_burger')])
    probe = Probe(ros_context)
    velocity = velocity_to_twist(1.0, 0.0)            # more than the Burger can
    with executor_for(ros_context, node, probe) as executor:
        spin_for(executor, node, 2.0, publish=lambda: probe.cmd_pub.publish(velocity))
    # The LDS-01: 360 beams of 1 degree from 0, 0.12-3.5 m, 5 Hz.
    scan = probe.scans[-1]
    assert len(scan.ranges) == 360 and scan.angle_min == 0.0
    assert math.degrees(scan.angle_increment) == pytest.approx(1.0)
    assert (scan.range_min, scan.range_max) == pytest.approx((0.12, 3.5))
    assert scan.scan_time == pytest.approx(0.2)
    assert 8 <= len(probe.scans) <= 12
    # Mounted as on the Burger's URDF, 0.182 m above the ground.
    assert probe.frames.static['laser'][0] == pytest.approx((-0.032, 0.0, 0.182))
    # Commands are clamped to its 0.22 m/s.
    assert node.world.husky_velocity[0] == pytest.approx(0.22)
    assert node.world.husky_footprint == (0.138, 0.178)
