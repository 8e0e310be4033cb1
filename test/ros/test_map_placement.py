"""The map centred on the start pose when no origin is given (issue 29)."""

import math

from dpn_navigator.ros.conversions import make_laser_scan, pose_to_odometry
from dpn_navigator.ros.dpn_node import DpnNode
from dpn_navigator.ros.qos import LATCHED_QOS, SENSOR_QOS
from nav_msgs.msg import OccupancyGrid, Odometry
from node_harness import executor_for, spin_until
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MIN
from sensor_msgs.msg import LaserScan
from sim_stand_in import BARE_ROBOT

START = (100.0, 50.0, 0.3)      # far from the map-frame origin [m, m, rad]


def test_the_map_is_placed_around_the_first_pose(ros_context):
    dpn = DpnNode(context=ros_context, parameter_overrides=[
        BARE_ROBOT, Parameter('map_width', value=12.0), Parameter('map_height', value=10.0),
        Parameter('origin_x', value=math.nan), Parameter('origin_y', value=math.nan),
        Parameter('laser_x', value=0.0)])
    assert dpn.params.centre_on_start
    probe = Node('placement_probe', context=ros_context)
    scan_pub = probe.create_publisher(LaserScan, '/compabot/scan', SENSOR_QOS)
    odom_pub = probe.create_publisher(Odometry, '/compabot/odom', SENSOR_QOS)
    maps = []
    probe.create_subscription(OccupancyGrid, '/compabot/map', maps.append, LATCHED_QOS)
    with executor_for(ros_context, dpn, probe) as executor:
        assert spin_until(executor, lambda: scan_pub.get_subscription_count() > 0
                          and odom_pub.get_subscription_count() > 0)
        for _ in range(3):
            stamp = probe.get_clock().now().to_msg()
            odom_pub.publish(pose_to_odometry(START, (0.0, 0.0), stamp, frame_id='odom'))
            scan_pub.publish(make_laser_scan(np.full(640, 3.0), ANGLE_MIN, ANGLE_INCREMENT,
                                             RANGE_MIN, 10.0, stamp))
            spin_until(executor, lambda: False, timeout=0.1)
        assert spin_until(executor, lambda: maps)
        assert dpn.navigator.grid.geometry.origin == pytest.approx((94.0, 45.0))
        origin = maps[-1].info.origin.position
        assert (origin.x, origin.y) == pytest.approx((94.0, 45.0))
        assert np.any(dpn.navigator.grid.labels)
        # A goal 3 m behind the robot lies on the map.
        assert dpn.set_goal(97.0, 50.0) is None


def test_half_an_origin_is_an_error(ros_context):
    with pytest.raises(ValueError, match='give both, or both NaN'):
        DpnNode(context=ros_context, parameter_overrides=[
            Parameter('origin_x', value=math.nan)])
