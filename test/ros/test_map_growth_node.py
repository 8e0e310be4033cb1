"""
The dpn node publishes its grown map (issue 29): a robot at the corner of the default map.

With the default origin (0, 0) a robot whose odometry starts at (0, 0) stands on the map's
corner; the map grows around it by whole blocks (``map_growth_step``), the published
``OccupancyGrid`` carries the new size and origin, a goal 3 m behind the robot is accepted,
and a growth beyond ``map_memory_limit`` is refused, logged and counted.
"""

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

START = (0.0, 0.0, 0.0)


def drive_scans(executor, probe, dpn, scans=3):
    """Send ``scans`` scans of 3 m ranges at START; return the maps received."""
    scan_pub = probe.create_publisher(LaserScan, '/compabot/scan', SENSOR_QOS)
    odom_pub = probe.create_publisher(Odometry, '/compabot/odom', SENSOR_QOS)
    maps = []
    probe.create_subscription(OccupancyGrid, '/compabot/map', maps.append, LATCHED_QOS)
    assert spin_until(executor, lambda: scan_pub.get_subscription_count() > 0
                      and odom_pub.get_subscription_count() > 0)
    for _ in range(scans):
        stamp = probe.get_clock().now().to_msg()
        odom_pub.publish(pose_to_odometry(START, (0.0, 0.0), stamp, frame_id='odom'))
        scan_pub.publish(make_laser_scan(np.full(640, 3.0), ANGLE_MIN, ANGLE_INCREMENT,
                                         RANGE_MIN, 10.0, stamp))
        spin_until(executor, lambda: False, timeout=0.1)
    assert spin_until(executor, lambda: maps and maps[-1].info.width
                      == dpn.navigator.grid.geometry.cols, timeout=5.0)
    return maps


def test_the_node_publishes_the_grown_map(ros_context):
    dpn = DpnNode(context=ros_context, parameter_overrides=[
        Parameter('map_width', value=12.0), Parameter('map_height', value=10.0),
        Parameter('laser_x', value=0.0), Parameter('pose_source', value='odom')])
    probe = Node('growth_probe', context=ros_context)
    with executor_for(ros_context, dpn, probe) as executor:
        assert dpn.params.navigator.map_growth_step == 5.0       # on by default in the node
        maps = drive_scans(executor, probe, dpn)
        geometry = dpn.navigator.grid.geometry
        assert dpn.navigator.map_growths >= 1
        assert geometry.origin == pytest.approx((-5.0, -5.0))
        assert geometry.shape == (30, 34)
        info = maps[-1].info
        assert (info.width, info.height) == (geometry.cols, geometry.rows)
        assert (info.origin.position.x, info.origin.position.y) == pytest.approx((-5.0, -5.0))
        grid = np.array(maps[-1].data, dtype=np.int8).reshape(info.height, info.width)
        # The wall 3 m ahead of the robot, at x = 3, is in the map at its place.
        row, col = dpn.navigator.grid.geometry.world_to_cell(3.0, 0.0)
        assert grid[row, col] == 100
        # Cells behind the robot (x < 0), once off the map, were seen free.
        row, col = dpn.navigator.grid.geometry.world_to_cell(1.0, -0.25)
        assert grid[row, col] == 0
        assert dpn.set_goal(-3.0, 0.0) is None
        assert dpn.diagnostics.last is not None
        values = {kv.key: kv.value for kv in dpn.diagnostics.last.values}
        assert int(values['map_growths']) == dpn.navigator.map_growths
        assert values['map_growth_refusals'] == '0'


def test_the_memory_limit_refuses_growth_logged_and_counted(ros_context, capfd):
    dpn = DpnNode(context=ros_context, parameter_overrides=[
        Parameter('map_width', value=12.0), Parameter('map_height', value=10.0),
        Parameter('laser_x', value=0.0), Parameter('pose_source', value='odom'),
        Parameter('map_memory_limit', value=1.0),
        Parameter('map_growth_step', value=200.0)])
    probe = Node('growth_probe', context=ros_context)
    with executor_for(ros_context, dpn, probe) as executor:
        maps = drive_scans(executor, probe, dpn)
        assert dpn.navigator.map_growths == 0
        assert dpn.navigator.map_growth_refusals >= 1
        assert (maps[-1].info.width, maps[-1].info.height) == (24, 20)
        values = {kv.key: kv.value for kv in dpn.diagnostics.last.values}
        assert int(values['map_growth_refusals']) == dpn.navigator.map_growth_refusals
        reason = dpn.set_goal(-3.0, 0.0)
        assert reason is not None and 'map_memory_limit 1 MB' in reason
        assert 'map growth refused' in capfd.readouterr().err
