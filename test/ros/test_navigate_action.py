"""
The ``navigate_to_pose`` action (nav2_msgs/action/NavigateToPose) over DDS, with an rclpy client.

A stand-in simulator feeds ``/clock``, odometry and scans of a robot standing in a 12 m room;
the client sends goals, reads feedback and results, cancels and preempts.
"""

import time

from action_msgs.msg import GoalStatus
from dpn_navigator.ros.dpn_node import DpnNode
from dpn_navigator.ros.navigate_action import (distance_along, GOAL_OUTSIDE_MAP, load_action_type,
                                               TF_ERROR)
from dpn_navigator.ros.qos import COMMAND_QOS
from geometry_msgs.msg import PoseStamped
from node_harness import executor_for
import numpy as np
import pytest
from rclpy.action import ActionClient
from rclpy.node import Node
from rclpy.parameter import Parameter
from sim_stand_in import SimulatorStandIn

NavigateToPose = load_action_type()
STREAMS = ('clock', 'odometry', 'scan')


@pytest.fixture(autouse=True)
def nav2_msgs_installed():
    """Fail (not skip) without nav2_msgs: package.xml depends on it, make setup builds it."""
    if NavigateToPose is None:
        pytest.fail('nav2_msgs is not installed (make setup builds the fallback/nav2_msgs '
                    'stand-in)')


def goal_msg(x, y, frame='map'):
    goal = NavigateToPose.Goal()
    goal.pose.header.frame_id = frame
    goal.pose.pose.position.x, goal.pose.pose.position.y = float(x), float(y)
    goal.pose.pose.orientation.w = 1.0
    return goal


class Harness:
    """The dpn node, the stand-in simulator and an action client in one executor."""

    def __init__(self, executor, dpn, sim, client_node):
        self.executor, self.dpn, self.sim = executor, dpn, sim
        self.client = ActionClient(client_node, NavigateToPose, '/compabot/navigate_to_pose')
        self.goal_pub = client_node.create_publisher(PoseStamped, '/compabot/goal_pose',
                                                     COMMAND_QOS)
        self.feedback = []

    def run(self, seconds=None, until=None, timeout=10.0):
        """Tick the simulator at 50 Hz of wall time until ``until()`` or for ``seconds``."""
        end = time.monotonic() + (seconds if seconds is not None else timeout)
        while time.monotonic() < end:
            self.sim.tick(STREAMS)
            self.executor.spin_once(timeout_sec=0.02)
            if until is not None and until():
                return True
        return until is None

    def send(self, goal):
        """Send a goal; return its accepted handle."""
        future = self.client.send_goal_async(
            goal, feedback_callback=lambda msg: self.feedback.append((time.monotonic(), msg)))
        assert self.run(until=future.done)
        handle = future.result()
        assert handle.accepted
        return handle

    def result(self, handle):
        future = handle.get_result_async()
        assert self.run(until=future.done)
        return future.result()


@pytest.fixture
def harness(ros_context):
    dpn = DpnNode(context=ros_context, parameter_overrides=[
        Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
        Parameter('laser_x', value=0.0), Parameter('use_sim_time', value=True)])
    sim = SimulatorStandIn(ros_context)
    client_node = Node('navigate_client', context=ros_context)
    with executor_for(ros_context, dpn, sim, client_node) as executor:
        h = Harness(executor, dpn, sim, client_node)
        assert h.run(until=lambda: h.client.server_is_ready()
                     and sim.scan_pub.get_subscription_count() > 0)
        yield h


def test_goal_feedback_and_cancel_stops_the_robot_within_half_a_second(harness):
    h = harness
    handle = h.send(goal_msg(9.0, 6.0))
    h.run(seconds=2.0)
    moving = [c for c in h.sim.commands if c[1] != 0.0 or c[2] != 0.0]
    assert moving, 'the accepted goal did not move the robot'
    # Feedback at 5 Hz: at least 1 Hz over the last 2 s, with the robot's pose and the path.
    recent = [msg for t, msg in h.feedback if t > time.monotonic() - 1.5]
    assert len(recent) >= 3
    last = h.feedback[-1][1].feedback
    assert last.current_pose.header.frame_id == 'map'
    assert last.current_pose.pose.position.x == pytest.approx(2.0)
    assert last.distance_remaining == pytest.approx(7.0, abs=1.0)
    assert last.estimated_time_remaining.sec >= 5
    assert last.navigation_time.sec + last.navigation_time.nanosec * 1e-9 > 1.0
    cancel_sent = time.monotonic()
    cancel = handle.cancel_goal_async()
    assert h.run(until=cancel.done)
    result = h.result(handle)
    assert result.status == GoalStatus.STATUS_CANCELED
    h.run(seconds=0.7)
    after = [c for c in h.sim.commands if c[0] >= cancel_sent]
    first_zero = next(t for t, v, w in after if v == w == 0.0)
    assert first_zero - cancel_sent < 0.5
    assert all(v == w == 0.0 for t, v, w in after if t >= first_zero)
    assert h.dpn.navigator.goal is None


@pytest.mark.parametrize('goal, code, text', [
    # The map grows to a goal off it, but not past map_memory_limit.
    (goal_msg(1e5, 6.0), GOAL_OUTSIDE_MAP, 'outside the map'),
    (goal_msg(5.0, 6.0, frame='odom'), TF_ERROR, "is not the map frame 'map'"),
    (goal_msg(float('nan'), 6.0), 200, 'not finite'),
])
def test_unusable_goals_end_at_once_with_an_error_code_and_message(harness, goal, code, text):
    h = harness
    result = h.result(h.send(goal))
    assert result.status == GoalStatus.STATUS_ABORTED
    assert result.result.error_code == code
    assert text in result.result.error_msg
    assert h.dpn.navigator.goal is None


def test_a_new_goal_or_goal_pose_preempts_the_running_one(harness):
    h = harness
    first = h.send(goal_msg(9.0, 6.0))
    h.run(seconds=0.5)
    second = h.send(goal_msg(9.0, 8.0))
    result = h.result(first)
    assert result.status == GoalStatus.STATUS_ABORTED
    assert 'preempted' in result.result.error_msg
    assert h.run(until=lambda: h.dpn.navigator.goal == (9.0, 8.0))
    topic_goal = PoseStamped()
    topic_goal.header.frame_id = 'map'
    topic_goal.pose.position.x, topic_goal.pose.position.y = 8.0, 4.0
    h.goal_pub.publish(topic_goal)
    result = h.result(second)
    assert result.status == GoalStatus.STATUS_ABORTED
    assert 'goal_pose' in result.result.error_msg
    assert h.dpn.navigator.goal == (8.0, 4.0)


def test_a_goal_at_the_robot_succeeds(harness):
    h = harness
    result = h.result(h.send(goal_msg(2.1, 6.0)))
    assert result.status == GoalStatus.STATUS_SUCCEEDED
    assert result.result.error_code == 0


def test_distance_along_the_path():
    path = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 2.0]])
    assert distance_along(path, (0.9, 0.1)) == pytest.approx(np.hypot(0.1, 0.1) + 2.0)
    assert distance_along(None, (0.0, 0.0)) is None
