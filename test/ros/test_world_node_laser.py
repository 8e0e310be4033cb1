"""The pybullet_world node's laser parameters: a profile, its overrides, and bad values."""

import math
import time

from dpn_navigator.ros.qos import SENSOR_QOS
from node_harness import executor_for
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from sensor_msgs.msg import LaserScan
from sim_bridge.laser_profiles import laser_profile
from sim_bridge.pybullet_world_node import PybulletWorldNode


def test_a_profile_with_an_override_is_the_published_scan(ros_context):
    node = PybulletWorldNode(context=ros_context, parameter_overrides=[
        Parameter('wanderers', value=0), Parameter('real_time_factor', value=5.0),
        Parameter('laser_profile', value='hokuyo_utm30lx'),
        Parameter('laser_dropout', value=0.0),
        Parameter('laser_error_encoding', value='nan')])
    probe = Node('scan_probe', context=ros_context)
    scans = []
    probe.create_subscription(LaserScan, '/compabot/scan', scans.append, SENSOR_QOS)
    profile = laser_profile('hokuyo_utm30lx').laser
    laser = node.world.config.laser
    assert (laser.dropout, laser.error_encoding) == (0.0, 'nan')
    assert (laser.noise_std, laser.max_incidence) == (profile.noise_std, profile.max_incidence)
    with executor_for(ros_context, node, probe) as executor:
        deadline = time.monotonic() + 20.0
        while len(scans) < 2 and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.01)
    assert len(scans) >= 2
    scan = scans[-1]
    assert len(scan.ranges) == 1081
    assert scan.angle_min == pytest.approx(math.radians(-135.0), abs=1e-6)
    assert scan.angle_max == pytest.approx(math.radians(135.0), abs=1e-6)
    assert scan.angle_increment == pytest.approx(math.radians(0.25), abs=1e-7)
    assert (scan.range_min, scan.range_max) == pytest.approx((0.1, 30.0))
    assert not any(math.isinf(r) for r in scan.ranges)       # no return is NaN here


@pytest.mark.parametrize('name, value, match', [
    ('laser_profile', 'lms200', 'unknown laser profile'),
    ('laser_dropout', 1.5, 'dropout must be a probability'),
    ('laser_error_encoding', 'zero', 'error_encoding must be one of'),
])
def test_bad_laser_parameters_stop_the_node_with_a_clear_error(ros_context, name, value, match):
    with pytest.raises(ValueError, match=match):
        PybulletWorldNode(context=ros_context, parameter_overrides=[
            Parameter('wanderers', value=0), Parameter(name, value=value)])
