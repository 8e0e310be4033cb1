"""
Fuzz both nodes in this process: hypothesis draws every field of every message they take in.

The messages go to the callbacks the executor would call (``/clock`` through the node's own
time source), so an exception fails the test at the message that raised it. After each message
the test checks that the node either took it (its state shows the message) or counted exactly
one rejection, and that everything published so far is sane: finite commands within the speed
limits, map values in {-1, 0, 70, 100}. The nine cases the DDS attack found are replayed first
by ``test_safety_cases.py``; here they are among the drawn values (``NASTY_FLOATS``).
"""

import math

from builtin_interfaces.msg import Time
from dpn_navigator.ros.conversions import make_laser_scan, pose_to_odometry
from hypothesis import given, HealthCheck, settings
from hypothesis.stateful import (invariant, rule, RuleBasedStateMachine,
                                 run_state_machine_as_test)
from message_strategies import clocks, dpn_messages, twists
import numpy as np
import pytest
from rclpy.parameter import Parameter
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN
from sim_bridge.pybullet_world_node import PybulletWorldNode
from sim_stand_in import room_navigator

MAX_LINEAR, MAX_ANGULAR = 1.0, 1.5         # the dpn node's and the Husky's defaults
MAP_VALUES = {-1, 0, 70, 100}
#: 60 sequences of up to 40 messages: about 2,000 messages to the dpn node.
DPN_FUZZ_SETTINGS = settings(max_examples=60, stateful_step_count=40,
                             suppress_health_check=list(HealthCheck))
WORLD_EXAMPLES = 300


class Recorder:
    """Record what a publisher publishes, and publish it."""

    def __init__(self, publisher):
        self.messages = []
        self._publish = publisher.publish
        publisher.publish = self.publish

    def publish(self, msg):
        self.messages.append(msg)
        self._publish(msg)


def check_commands(recorder):
    for msg in recorder.messages:
        values = (msg.linear.x, msg.linear.y, msg.linear.z, msg.angular.x, msg.angular.y,
                  msg.angular.z)
        assert all(math.isfinite(v) for v in values), msg
        assert abs(msg.linear.x) <= MAX_LINEAR and abs(msg.angular.z) <= MAX_ANGULAR, msg
    recorder.messages.clear()


def check_maps(recorder):
    for msg in recorder.messages:
        assert len(msg.data) == msg.info.width * msg.info.height
        assert set(np.unique(np.frombuffer(msg.data, np.int8)).tolist()) <= MAP_VALUES
    recorder.messages.clear()


def good_scan():
    ranges = np.full(640, 4.0, dtype=np.float32)
    return make_laser_scan(ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, 10.0, Time())


class DpnFuzz(RuleBasedStateMachine):
    """Any sequence of scans, odometry, goals and /clock messages, sane ones interleaved."""

    node = commands = maps = None       # set by the test: one node for every sequence
    most_replans = 0                    # a new goal starts `replans` again: the most seen

    @rule(message=dpn_messages)
    def deliver(self, message):
        node = self.node
        kind, msg = message
        before = dict(node.rejected)
        if kind == 'scan':
            heard = node.watchdog._last['scan']
            waiting, skipped = len(node.pending_scans), node.scans_skipped
            node.on_scan(msg)
            # Taken: mapped, or waiting for its pose, or dropped for want of one (counted
            # apart, in scans_skipped_no_pose: it was not malformed).
            took = (node.watchdog._last['scan'] is not heard or node.pose is None
                    or len(node.pending_scans) > waiting or node.scans_skipped > skipped)
        elif kind == 'odometry':
            heard = node.watchdog._last['odometry']
            node.on_odom(msg)
            took = node.watchdog._last['odometry'] is not heard
            position = msg.pose.pose.position
            assert not took or node.pose[:2] == (position.x, position.y)
        elif kind == 'goal':
            goal = node.navigator.goal
            node.on_goal(msg)
            took = node.navigator.goal is not goal
            assert not took or node.navigator.goal == (msg.pose.position.x, msg.pose.position.y)
        else:
            node._time_source.clock_callback(msg)
            expected = msg.clock.sec * 10**9 + msg.clock.nanosec
            took = node.get_clock().now().nanoseconds == expected
        counted = node.rejected[kind] - before[kind]
        assert (took, counted) in ((True, 0), (False, 1)), (kind, msg, counted)
        assert all(node.rejected[k] == before[k] for k in before if k != kind)

    @rule()
    def sane_step(self):
        """Send a valid odometry and scan: the navigator maps, plans and commands."""
        node = self.node
        node.on_odom(pose_to_odometry((6.0, 6.0, 0.3), (0.0, 0.0), Time()))
        node.on_scan(good_scan())
        assert node.pose == pytest.approx((6.0, 6.0, 0.3))
        DpnFuzz.most_replans = max(DpnFuzz.most_replans, node.navigator.replans)

    @rule()
    def watchdog(self):
        self.node.on_watchdog()

    @invariant()
    def published_only_sane_values(self):
        check_commands(self.commands)
        check_maps(self.maps)


@pytest.mark.filterwarnings('error::RuntimeWarning')     # no overflow, no NaN cast
@pytest.mark.slow
def test_dpn_node_survives_any_message_and_counts_each_rejection(ros_context):
    node = room_navigator(ros_context)
    DpnFuzz.node = node
    DpnFuzz.most_replans = 0
    DpnFuzz.commands, DpnFuzz.maps = Recorder(node.cmd_pub.publisher), Recorder(node.map_pub)
    try:
        run_state_machine_as_test(DpnFuzz, settings=DPN_FUZZ_SETTINGS)
        assert sum(node.rejected.values()) > 100, node.rejected
        # It planned (a goal accepted after the last plan starts the count again at 0).
        assert DpnFuzz.most_replans > 0
    finally:
        DpnFuzz.node = DpnFuzz.commands = DpnFuzz.maps = None
        node.destroy_node()


@pytest.mark.filterwarnings('error::RuntimeWarning')     # no overflow, no NaN cast
def test_world_node_survives_any_command_and_clock(ros_context):
    world = PybulletWorldNode(context=ros_context, parameter_overrides=[
        Parameter('wanderers', value=1), Parameter('use_sim_time', value=True)])
    delivered = []

    @settings(max_examples=WORLD_EXAMPLES, suppress_health_check=list(HealthCheck))
    @given(twists(), clocks())
    def deliver(twist, clock):
        before = world.world.rejected_commands
        world.on_cmd_vel(twist)
        world._time_source.clock_callback(clock)
        finite = math.isfinite(twist.linear.x) and math.isfinite(twist.angular.z)
        assert world.world.rejected_commands - before == (0 if finite else 1)
        world.on_tick()
        v, omega = world.world.husky_velocity
        assert math.isfinite(v) and math.isfinite(omega)
        assert abs(v) <= MAX_LINEAR + 1e-9 and abs(omega) <= MAX_ANGULAR + 1e-9
        delivered.append(twist)

    try:
        deliver()
    finally:
        world.destroy_node()
    assert len(delivered) == WORLD_EXAMPLES
