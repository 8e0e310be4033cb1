"""
Fault test of the watchdog over DDS: when scans, odometry or ``/clock`` stop, the robot stops.

A probe drives the dpn node (on simulated time: the probe publishes ``/clock`` as the simulator
does) with a healthy stream in an open room, so that the node commands motion; then one stream
stops, or everything stops as when the simulator dies. The first zero command must follow the
last message within ``sensor_timeout`` plus one watchdog period (0.42 s by default) plus the
delivery, on the wall clock: under 0.5 s.
"""

import time

from builtin_interfaces.msg import Time
from dpn_navigator.conversions import make_laser_scan, pose_to_odometry
from dpn_navigator.dpn_node import DpnNode, WATCHDOG_PERIOD
from dpn_navigator.qos import COMMAND_QOS, SENSOR_QOS
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from node_harness import executor_for, spin_until
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN, ray_cast
from sensor_msgs.msg import LaserScan

POSE = (2.0, 6.0, 0.0)
STOP_LIMIT = 0.5            # [s] of wall time, last message to first zero command
TRIALS = 3


class SimulatorStandIn(Node):
    """Publish /clock, odometry and scans as the simulator would; record the commands."""

    def __init__(self, context):
        super().__init__('simulator_stand_in', context=context)
        self.clock_pub = self.create_publisher(Clock, '/clock', COMMAND_QOS)
        self.odom_pub = self.create_publisher(Odometry, '/compabot/odom', SENSOR_QOS)
        self.scan_pub = self.create_publisher(LaserScan, '/compabot/scan', SENSOR_QOS)
        self.commands = []          # (steady time [s], linear, angular)
        self.create_subscription(Twist, '/compabot/cmd_vel', self.on_cmd, COMMAND_QOS)
        self.sim_time = 1.0
        occupied = np.zeros((240, 240), dtype=bool)
        occupied[:6, :] = occupied[-6:, :] = occupied[:, :6] = occupied[:, -6:] = True
        self.ranges = ray_cast(occupied, POSE, 0.05, 10.0)

    def on_cmd(self, msg):
        self.commands.append((time.monotonic(), msg.linear.x, msg.angular.z))

    def tick(self, streams):
        """Advance simulated time by 20 ms and publish the given streams; return the time."""
        self.sim_time += 0.02
        stamp = Time(sec=int(self.sim_time), nanosec=int(self.sim_time % 1.0 * 1e9))
        if 'clock' in streams:
            self.clock_pub.publish(Clock(clock=stamp))
        if 'odometry' in streams:
            self.odom_pub.publish(pose_to_odometry(POSE, (0.0, 0.0), stamp))
        if 'scan' in streams:
            self.scan_pub.publish(make_laser_scan(self.ranges, ANGLE_MIN, ANGLE_INCREMENT,
                                                  RANGE_MIN, 10.0, stamp))
        return time.monotonic()


def run_for(executor, probe, seconds, streams):
    """Tick at 50 Hz for ``seconds`` of wall time; return the wall time of the last tick."""
    last = None
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        last = probe.tick(streams)
        spin_until(executor, lambda: False, timeout=0.02)
    return last


@pytest.fixture
def nodes(ros_context):
    overrides = [Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
                 Parameter('goal_x', value=10.0), Parameter('goal_y', value=6.0),
                 Parameter('use_sim_time', value=True)]
    dpn = DpnNode(context=ros_context, parameter_overrides=overrides)
    probe = SimulatorStandIn(ros_context)
    with executor_for(ros_context, dpn, probe) as executor:
        assert spin_until(executor, lambda: probe.scan_pub.get_subscription_count() > 0
                          and probe.clock_pub.get_subscription_count() > 0)
        yield dpn, probe, executor


def test_watchdog_period_leaves_room_in_the_default_timeout():
    assert 0.4 + WATCHDOG_PERIOD <= STOP_LIMIT - 0.05


@pytest.mark.parametrize('still_running', [
    ('clock', 'odometry'),          # scans stop
    ('clock', 'scan'),              # odometry stops
    ('clock',),                     # both stop, simulated time runs on
    (),                             # the simulator dies: /clock stops too
])
def test_first_zero_command_follows_the_last_message_within_half_a_second(nodes, still_running):
    dpn, probe, executor = nodes
    all_streams = ('clock', 'odometry', 'scan')
    for _ in range(TRIALS):
        run_for(executor, probe, 1.0, all_streams)
        assert any(linear > 0.0 for _, linear, _ in probe.commands[-10:]), \
            'healthy streams in an open room: the robot should drive'
        assert not dpn.stale
        last_message = time.monotonic()
        probe.commands.clear()
        run_for(executor, probe, 1.0, still_running)
        zeros = [t for t, linear, angular in probe.commands if linear == angular == 0.0]
        assert zeros, probe.commands
        assert zeros[0] - last_message < STOP_LIMIT
        moving_after = [t for t, linear, angular in probe.commands
                        if (linear, angular) != (0.0, 0.0) and t > zeros[0]]
        assert not moving_after
        assert dpn.stale
        assert spin_until(executor, lambda: dpn.last_status is not None and dpn.stale)
