"""
Parameters given at start that a node does not declare are warned about once, with a hint.

rclpy keeps such a parameter as an override and never reads it: a misspelt name silently left
its parameter at the default. Both nodes now name each one once, with the closest declared
name, and count them in their status (``ros/unknown_parameters.py``; issue 29).
"""

from dpn_navigator.ros.dpn_node import DpnNode
from dpn_navigator.ros.unknown_parameters import closest_parameter
import pytest
from rclpy.parameter import Parameter
from sim_bridge.pybullet_world_node import PybulletWorldNode


def status_values(node):
    """Return the node's last published status values by key."""
    status = node.diagnostics.last
    assert status is not None, 'no status published'
    return {kv.key: kv.value for kv in status.values}


@pytest.mark.parametrize('name, known, hint', [
    ('max_vel_X', ['max_vel_x', 'max_vel_theta', 'resolution'], 'max_vel_x'),
    ('robot_radus', ['robot_radius', 'robot_length'], 'robot_radius'),
    ('zzzz', ['robot_radius', 'resolution'], None),
])
def test_the_hint_is_the_closest_declared_name(name, known, hint):
    assert closest_parameter(name, known) == hint


def test_dpn_warns_once_per_unknown_name_and_counts_them(ros_context, tmp_path, capfd):
    params = tmp_path / 'dpn.yaml'
    params.write_text('/**/dpn:\n  ros__parameters:\n    max_vel_thetta: 1.0\n'
                      '    map_width: 12.0\n')
    dpn = DpnNode(context=ros_context, cli_args=['--ros-args', '--params-file', str(params)],
                  parameter_overrides=[Parameter('robot_radus', value=0.3),
                                       Parameter('map_height', value=12.0)])
    try:
        assert dpn.unknown_parameters == ['max_vel_thetta', 'robot_radus']
        assert dpn.params.navigator.width == 12.0        # a known name is still read
        assert status_values(dpn)['unknown_parameters'] == '2'
        err = capfd.readouterr().err
        assert err.count("unknown parameter 'robot_radus'") == 1, err
        assert "did you mean 'robot_radius'?" in err
        assert err.count("unknown parameter 'max_vel_thetta'") == 1, err
        assert "did you mean 'max_vel_theta'?" in err
        assert "unknown parameter 'map_width'" not in err
    finally:
        dpn.destroy_node()


def test_dpn_without_unknown_names_warns_nothing(ros_context, capfd):
    dpn = DpnNode(context=ros_context, parameter_overrides=[
        Parameter('map_width', value=12.0), Parameter('map_height', value=12.0),
        Parameter('use_sim_time', value=False)])
    try:
        assert dpn.unknown_parameters == []
        assert status_values(dpn)['unknown_parameters'] == '0'
        assert 'unknown parameter' not in capfd.readouterr().err
    finally:
        dpn.destroy_node()


def test_the_world_warns_about_unknown_names_too(ros_context, capfd):
    world = PybulletWorldNode(context=ros_context, parameter_overrides=[
        Parameter('wanderers', value=0), Parameter('wanderer', value=2)])
    try:
        assert world.unknown_parameters == ['wanderer']
        assert "did you mean 'wanderers'?" in capfd.readouterr().err
        world.publish_status()
        assert status_values(world)['unknown_parameters'] == '1'
    finally:
        world.destroy_node()
