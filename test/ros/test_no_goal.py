"""No motion without a goal: a bare ``dpn`` with the shipped config waits for one (issue 29)."""

from pathlib import Path as FilePath
import time

from dpn_navigator.ros.conversions import make_laser_scan, pose_to_odometry
from dpn_navigator.ros.dpn_node import DpnNode
from dpn_navigator.ros.qos import COMMAND_QOS, SENSOR_QOS
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Odometry
from node_harness import executor_for, spin_until
import numpy as np
from rclpy.node import Node
from rclpy.parameter import Parameter
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN, ray_cast
from sensor_msgs.msg import LaserScan

REPO = FilePath(__file__).resolve().parents[2]
CONFIG = str(REPO / 'config' / 'dpn.yaml')
RANGE_MAX = 10.0
POSE = (2.0, 6.0, 0.0)


def room():
    occupied = np.zeros((240, 240), dtype=bool)        # 12 m x 12 m at 5 cm
    occupied[:6, :] = occupied[-6:, :] = occupied[:, :6] = occupied[:, -6:] = True
    return occupied


class Feeder(Node):
    """Publish scans and odometry of a robot standing in a room; record the commands."""

    def __init__(self, context):
        super().__init__('feeder', context=context)
        self.scan_pub = self.create_publisher(LaserScan, '/compabot/scan', SENSOR_QOS)
        self.odom_pub = self.create_publisher(Odometry, '/compabot/odom', SENSOR_QOS)
        self.goal_pub = self.create_publisher(PoseStamped, '/compabot/goal_pose', COMMAND_QOS)
        self.commands = []
        self.create_subscription(Twist, '/compabot/cmd_vel',
                                 lambda msg: self.commands.append((msg.linear.x, msg.angular.z)),
                                 COMMAND_QOS)
        self.ranges = ray_cast(room(), POSE, 0.05, RANGE_MAX)

    def send(self):
        stamp = self.get_clock().now().to_msg()
        self.odom_pub.publish(pose_to_odometry(POSE, (0.0, 0.0), stamp))
        self.scan_pub.publish(make_laser_scan(self.ranges, ANGLE_MIN, ANGLE_INCREMENT,
                                              RANGE_MIN, RANGE_MAX, stamp))

    def moving(self):
        return [c for c in self.commands if c != (0.0, 0.0)]


def feed_for(executor, feeder, seconds):
    """Send scans and odometry at 20 Hz for ``seconds`` of wall time."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        feeder.send()
        spin_until(executor, lambda: False, timeout=0.05)


def test_bare_node_with_the_shipped_config_sends_no_motion_until_a_goal(ros_context):
    dpn = DpnNode(context=ros_context, cli_args=['--ros-args', '--params-file', CONFIG,
                                                 '-p', 'laser_x:=0.0'])
    assert dpn.params.goal is None and dpn.navigator.goal is None
    feeder = Feeder(ros_context)
    with executor_for(ros_context, dpn, feeder) as executor:
        assert spin_until(executor, lambda: feeder.scan_pub.get_subscription_count() > 0
                          and feeder.odom_pub.get_subscription_count() > 0
                          and feeder.goal_pub.get_subscription_count() > 0)
        feed_for(executor, feeder, 4.0)
        # The node ran: it mapped the scans and answered them with (zero) commands.
        assert len(feeder.commands) > 20
        assert np.count_nonzero(dpn.navigator.grid.labels) > 0
        assert feeder.moving() == []
        assert dpn.navigator.status.value == 'idle'
        # A goal on goal_pose starts the motion (so the silence above was the missing goal).
        goal = PoseStamped()
        goal.header.frame_id = 'map'
        goal.pose.position.x, goal.pose.position.y = 9.0, 6.0
        goal.pose.orientation.w = 1.0
        feeder.goal_pub.publish(goal)
        assert spin_until(executor, lambda: dpn.navigator.goal == (9.0, 6.0))
        feed_for(executor, feeder, 1.0)
        assert feeder.moving()
        # From standing, the first command is held to max_linear_accel (2.5 m/s^2) and
        # max_angular_accel (3.2 rad/s^2) over the first 0.1 s.
        linear, angular = feeder.moving()[0]
        assert 0.0 <= linear <= 0.25 + 1e-9 and abs(angular) <= 0.32 + 1e-9


def test_default_goal_only_when_asked_for(ros_context):
    asked = DpnNode(context=ros_context, namespace='asked', parameter_overrides=[
        Parameter('use_default_goal', value=True), Parameter('goal_x', value=3.0),
        Parameter('goal_y', value=4.0)])
    assert asked.navigator.goal == (3.0, 4.0)
    unasked = DpnNode(context=ros_context, namespace='unasked', parameter_overrides=[
        Parameter('goal_x', value=3.0), Parameter('goal_y', value=4.0)])
    assert unasked.navigator.goal is None
    for node in (asked, unasked):
        node.destroy_node()
