"""
The failures the DDS attack on the nodes found (issue 11), one test each, in this process.

Each test fails on the code before the fix: an exception escapes a callback, a bad message is
taken for a good one, or the navigator stays without a plan.
"""

import math
import time

from builtin_interfaces.msg import Time
from dpn_navigator.core import Navigator, NavigatorConfig, NavigatorStatus
from dpn_navigator.ros.conversions import (make_laser_scan, odometry_to_pose, pose_to_odometry,
                                           quaternion_to_yaw)
from dpn_navigator.ros.dpn_node import DpnNode
from dpn_navigator.ros.dpn_params import MAX_GRID_CELLS
from dpn_navigator.ros.qos import COMMAND_QOS
from geometry_msgs.msg import Quaternion, Twist
from node_harness import executor_for, spin_until
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN
from sim_stand_in import BARE_ROBOT, room_navigator

DBL_MAX_ISH = 9e307


def room_scan(stamp=Time()):
    return make_laser_scan(np.full(640, 4.0, dtype=np.float32), ANGLE_MIN, ANGLE_INCREMENT,
                           RANGE_MIN, 10.0, stamp)


def odometry(pose):
    return pose_to_odometry(pose, (0.0, 0.0), Time())


@pytest.fixture
def dpn(ros_context):
    node = room_navigator(ros_context)
    yield node
    node.destroy_node()


@pytest.mark.parametrize('x, y', [(DBL_MAX_ISH, 6.0), (6.0, -DBL_MAX_ISH), (1.1e9, 0.0)])
def test_odometry_beyond_any_map_is_rejected_and_the_next_scan_mapped(dpn, x, y):
    dpn.on_odom(odometry((6.0, 6.0, 0.0)))
    dpn.on_odom(odometry((x, y, 0.0)))
    assert dpn.rejected['odometry'] == 1
    assert dpn.pose == (6.0, 6.0, 0.0)
    dpn.on_scan(room_scan())
    assert dpn.rejected['scan'] == 0
    assert dpn.watchdog._last['scan'] is not None


def test_navigator_rejects_a_pose_beyond_any_map():
    navigator = Navigator(NavigatorConfig(width=12.0, height=12.0))
    with pytest.raises(ValueError, match='beyond'):
        navigator.decide(0.0, (DBL_MAX_ISH, 0.0, 0.0))
    with pytest.raises(ValueError, match='goal position .* beyond'):
        navigator.set_goal(DBL_MAX_ISH, -DBL_MAX_ISH)


def test_negative_clock_seconds_are_rejected_over_dds_and_time_keeps(dpn, ros_context):
    probe = Node('clock_probe', context=ros_context)
    clock_pub = probe.create_publisher(Clock, '/clock', COMMAND_QOS)
    with executor_for(ros_context, probe) as executor:
        executor.add_node(dpn)
        assert spin_until(executor, lambda: clock_pub.get_subscription_count() > 0)
        clock_pub.publish(Clock(clock=Time(sec=12, nanosec=0)))
        assert spin_until(executor, lambda: dpn.now_seconds() == 12.0)
        clock_pub.publish(Clock(clock=Time(sec=-5, nanosec=0)))
        assert spin_until(executor, lambda: dpn.rejected['clock'] == 1)
        clock_pub.publish(Clock(clock=Time(sec=13, nanosec=0)))
        assert spin_until(executor, lambda: dpn.now_seconds() == 13.0)
        executor.remove_node(dpn)


@pytest.mark.parametrize('scale', [2.0, 0.5, 1e200, 1.7e308])
def test_non_unit_quaternions_are_rejected_as_odometry(dpn, scale):
    msg = odometry((6.0, 6.0, 0.0))
    msg.pose.pose.orientation = Quaternion(x=0.0, y=0.0, z=scale * math.sin(math.pi / 4),
                                           w=scale * math.cos(math.pi / 4))
    with pytest.raises(ValueError, match='unit quaternion'):
        odometry_to_pose(msg)
    dpn.on_odom(msg)
    assert (dpn.rejected['odometry'], dpn.pose) == (1, None)
    dpn.on_odom(odometry((6.0, 6.0, 0.0)))
    dpn.on_scan(room_scan())                  # a good scan is no bad scan after it
    assert dpn.rejected == {'scan': 0, 'odometry': 1, 'goal': 0, 'clock': 0}


def test_nearly_unit_quaternion_is_normalised():
    yaw = 1.2
    q = Quaternion(z=1.004 * math.sin(yaw / 2), w=1.004 * math.cos(yaw / 2))
    assert quaternion_to_yaw(q) == pytest.approx(yaw, abs=1e-12)


def test_navigator_plans_again_after_time_goes_backwards():
    navigator = Navigator(NavigatorConfig(width=12.0, height=12.0))
    navigator.set_goal(10.0, 6.0)
    out = navigator.decide(500.0, (-3.0, 6.0, 0.0))          # off the map: no path
    assert out.status is NavigatorStatus.NO_PATH
    out = navigator.decide(2.0, (2.0, 6.0, 0.0))             # the simulator restarted
    assert out.replanned and out.status is NavigatorStatus.ACTIVE
    assert out.command.linear > 0.0


def test_forget_timer_restarts_after_time_goes_backwards():
    navigator = Navigator(NavigatorConfig(width=12.0, height=12.0, forget_obstacles_after=5.0))
    navigator.set_goal(10.0, 6.0)
    navigator.decide(500.0, (-3.0, 6.0, 0.0))
    navigator.decide(1.0, (-3.0, 6.0, 0.0))
    assert navigator._no_path_since == 1.0


def test_scan_with_more_beams_than_max_beams_is_rejected_at_once(dpn):
    dpn.on_odom(odometry((6.0, 6.0, 0.0)))
    huge = make_laser_scan(np.full(1_000_000, 4.0, dtype=np.float32), ANGLE_MIN,
                           math.pi / 999_999, RANGE_MIN, 10.0, Time())
    started = time.perf_counter()
    dpn.on_scan(huge)
    assert time.perf_counter() - started < 0.05
    assert dpn.rejected['scan'] == 1
    assert dpn.watchdog._last['scan'] is None


def test_another_cmd_vel_publisher_is_warned_about_and_counted(dpn, ros_context):
    rival = Node('rival_navigator', context=ros_context)
    with executor_for(ros_context, rival) as executor:
        executor.add_node(dpn)
        dpn.on_status_timer()
        assert (dpn.cmd_vel_monitor.others, dpn.cmd_vel_monitor.conflicts) == (0, 0)
        rival.create_publisher(Twist, '/compabot/cmd_vel', COMMAND_QOS)

        def seen():
            dpn.on_status_timer()
            return dpn.cmd_vel_monitor.others == 1
        assert spin_until(executor, seen)
        assert dpn.cmd_vel_monitor.conflicts == 1
        executor.remove_node(dpn)


def test_cmd_vel_monitor_watches_the_namespaced_command_topic(ros_context):
    node = DpnNode(context=ros_context, namespace='robot2',
                   parameter_overrides=[BARE_ROBOT, Parameter('map_width', value=12.0),
                                        Parameter('map_height', value=12.0)])
    assert node.cmd_pub.topic_name == '/robot2/cmd_vel'
    rival = Node('rival_navigator', context=ros_context)
    rival.create_publisher(Twist, '/compabot/cmd_vel', COMMAND_QOS)     # another robot's
    with executor_for(ros_context, rival) as executor:
        executor.add_node(node)
        spin_until(executor, lambda: False, timeout=0.5)
        node.on_status_timer()
        assert node.cmd_vel_monitor.others == 0
        rival.create_publisher(Twist, '/robot2/cmd_vel', COMMAND_QOS)

        def seen():
            node.on_status_timer()
            return node.cmd_vel_monitor.others == 1
        assert spin_until(executor, seen)
        executor.remove_node(node)
    node.destroy_node()


@pytest.mark.parametrize('width, resolution', [(1e6, 0.01), (2100.0, 1.0)])
def test_absurd_grid_is_a_parameter_error(ros_context, width, resolution):
    overrides = [Parameter('map_width', value=width), Parameter('map_height', value=width),
                 Parameter('resolution', value=resolution)]
    with pytest.raises(ValueError, match=f'more than {MAX_GRID_CELLS:,}'):
        DpnNode(context=ros_context, parameter_overrides=overrides)


def test_fine_evidence_grid_too_large_is_a_parameter_error(ros_context):
    # 1000 m at 0.5 m is a valid label grid; its fine evidence at 0.1 m is 10,000 x 10,000.
    overrides = [Parameter('map_width', value=1000.0), Parameter('map_height', value=1000.0)]
    with pytest.raises(ValueError, match='fine_evidence_resolution 0.1 m is 10000 x 10000'):
        DpnNode(context=ros_context, parameter_overrides=overrides)
    overrides.append(Parameter('fine_evidence_resolution', value=0.2))
    # The surface memory's places (noise_margin, 0.1 m) are bounded the same way.
    with pytest.raises(ValueError, match='surface memory would have 10000 x 10000'):
        DpnNode(context=ros_context, parameter_overrides=overrides)
    overrides.append(Parameter('noise_margin', value=0.2))
    node = DpnNode(context=ros_context, parameter_overrides=overrides)
    try:
        assert node.navigator.grid.fine_evidence.seen_free.shape == (5000, 5000)
    finally:
        node.destroy_node()


def test_node_plans_again_after_sim_time_goes_backwards(dpn):
    dpn._time_source.clock_callback(Clock(clock=Time(sec=500)))
    # Off the map, farther than it may grow (map_memory_limit): no path.
    dpn.on_odom(odometry((-1e5, 6.0, 0.0)))
    dpn.on_scan(room_scan())
    assert dpn.navigator.status is NavigatorStatus.NO_PATH
    dpn._time_source.clock_callback(Clock(clock=Time(sec=2)))  # the simulator restarted
    dpn.on_odom(odometry((2.0, 6.0, 0.0)))
    dpn.on_scan(room_scan())
    assert dpn.navigator.status is NavigatorStatus.ACTIVE
    assert dpn.navigator.path is not None


@pytest.mark.parametrize('stamped', [False, True])
def test_destroying_the_node_sends_a_zero_command(ros_context, stamped):
    node = room_navigator(ros_context, False, Parameter('cmd_vel_stamped', value=stamped))
    sent = []
    publish = node.cmd_pub.publisher.publish
    node.cmd_pub.publisher.publish = lambda msg: (sent.append(msg.twist if stamped else msg),
                                                  publish(msg))
    # The first scan of a node may take longer than sensor_timeout (its kernels load), and the
    # stop guard then holds the command for stale odometry: the command is judged on the second.
    for stamp in (Time(), Time(nanosec=100_000_000)):
        node.on_odom(pose_to_odometry((2.0, 6.0, 0.0), (0.0, 0.0), stamp))
        node.on_scan(room_scan(stamp))
    assert sent and (sent[-1].linear.x, sent[-1].angular.z) != (0.0, 0.0)
    node.destroy_node()
    assert (sent[-1].linear.x, sent[-1].angular.z) == (0.0, 0.0)
