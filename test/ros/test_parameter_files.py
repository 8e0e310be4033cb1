"""
Each parameter of the dpn node stated once: the settings, the declarations and the two files.

The core's configuration fields carry each setting; the node declares ``PARAMETERS`` from them;
``config/dpn.yaml`` and the table of ``docs/ros_reference.md`` are written from them. These
tests fail when any of the four disagree.

"""

import math
from pathlib import Path
import shutil

from dpn_navigator.core import FollowerConfig, NavigatorConfig
from dpn_navigator.core.mapping.label_grid import LabelRule
from dpn_navigator.core.settings import Setting, settings_of
from dpn_navigator.ros.dpn_params import declare_parameters, DpnParameters, PARAMETERS
from dpn_navigator.ros.parameter_declaration import declare_setting
from dpn_navigator.ros.safety_params import declare_safety_parameters, SafetyParameters
from dpn_navigator.tools import parameter_files
import pytest
from rcl_interfaces.msg import ParameterType
from sim_bridge.world_parameters import world_node_settings, WorldNodeParameters

REPO = Path(__file__).resolve().parents[2]
CONFIGS = {'navigator': NavigatorConfig, 'follower': FollowerConfig, 'node': DpnParameters,
           'safety': SafetyParameters}
#: ROS defaults that are not the core's: the Husky on back_and_forth.
# The node's own defaults: the scenario's map size, a map that grows (the core's is fixed), and
# what a localiser's error asks for (the benchmark's pose is exact): renewed free evidence and a
# goal approached inside its tolerance.
NODE_DEFAULTS = {'map_width', 'map_height', 'map_growth_step', 'free_evidence_renewal',
                 'goal_approach_margin'}


def test_the_files_are_written_from_the_settings():
    assert parameter_files.main(['--repo', str(REPO)]) == 0


FILES = ('config/dpn.yaml', 'config/pybullet_world.yaml', 'docs/ros_reference.md')


@pytest.mark.parametrize('path, old, new', [
    ('config/dpn.yaml', 'robot_radius: 0.6', 'robot_radius: 0.7'),
    ('config/pybullet_world.yaml', 'wanderers: 3', 'wanderers: 4'),
    ('docs/ros_reference.md', '| dpn | `segment_gap` | 0.3 |', '| dpn | `segment_gap` | 0.4 |'),
    ('docs/ros_reference.md', '| pybullet_world | `seed` | 0 |',
     '| pybullet_world | `seed` | 1 |'),
])
def test_a_file_that_drifts_is_caught_and_rewritten(tmp_path, path, old, new):
    for name in FILES:
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(REPO / name, tmp_path / name)
    text = (tmp_path / path).read_text()
    assert old in text
    (tmp_path / path).write_text(text.replace(old, new))
    assert parameter_files.main(['--repo', str(tmp_path)]) == 1
    assert parameter_files.main(['--repo', str(tmp_path), '--write']) == 0
    assert (tmp_path / path).read_text() == text


def test_every_setting_is_a_parameter_at_its_default():
    names = [parameter.name for parameter in PARAMETERS]
    assert len(names) == len(set(names))
    for target, config in CONFIGS.items():
        declared = {p.field for p in PARAMETERS if p.target == target and p.index is None}
        assert declared == set(settings_of(config)), target
    for parameter in PARAMETERS:
        assert isinstance(parameter.setting, Setting)
        if parameter.index is None and parameter.name not in NODE_DEFAULTS:
            default, setting = settings_of(CONFIGS[parameter.target])[parameter.field]
            assert (parameter.default, parameter.setting) == (default, setting), parameter.name


def test_the_label_rule_takes_the_navigators_fields_by_name():
    rule = NavigatorConfig(width=5.0, height=5.0, segment_gap=0.25, object_memory=2.0,
                           track_exclusive=False).label_rule()
    assert (rule.segment_gap, rule.object_memory, rule.track_exclusive) == (0.25, 2.0, False)
    assert set(vars(rule)) <= set(settings_of(NavigatorConfig))


def test_the_node_declares_every_parameter_with_its_setting(ros_context):
    from rclpy.node import Node
    node = Node('dpn', context=ros_context)
    try:
        params = declare_parameters(node)
        safety = declare_safety_parameters(node)
        for parameter in PARAMETERS:
            value = node.get_parameter(parameter.name).value
            if isinstance(parameter.default, float) and math.isnan(parameter.default):
                assert math.isnan(value)
            else:
                assert value == parameter.default, parameter.name
            descriptor = node.describe_parameter(parameter.name)
            assert descriptor.read_only
            assert descriptor.description == parameter.setting.plain_description()
            if descriptor.type == ParameterType.PARAMETER_DOUBLE and parameter.setting.low:
                assert descriptor.floating_point_range[0].from_value == parameter.setting.low
        assert params.navigator.label_rule() == NavigatorConfig(
            width=25.0, height=20.0, free_evidence_renewal=6.0).label_rule()
        assert params.navigator.laser_offset == (0.337, 0.0, 0.0)
        assert params.navigator.follower == FollowerConfig(goal_approach_margin=0.1)
        assert params.goal is None and not params.use_default_goal     # no goal unless asked
        assert safety.max_beams == 4096
        assert LabelRule() != params.navigator.label_rule()        # dpn, not the paper
    finally:
        node.destroy_node()


def test_the_world_node_declares_its_settings(ros_context):
    from rclpy.node import Node
    node = Node('pybullet_world', context=ros_context)
    try:
        values = {name: declare_setting(node, name, default, spec)
                  for name, (default, spec) in world_node_settings().items()}
        params = WorldNodeParameters(**values)
        assert (params.scenario, params.wanderers, params.physics_rate) == (
            'back_and_forth', 3, 50.0)
        assert math.isnan(params.start_x)
        descriptor = node.describe_parameter('wanderers')
        assert (descriptor.integer_range[0].from_value, descriptor.integer_range[0].to_value) \
            == (0, 10)
        assert node.describe_parameter('scan_rate').description.endswith('[Hz]')
    finally:
        node.destroy_node()


def test_follower_gains_and_path_deviation_are_parameters(ros_context):
    from rclpy.node import Node
    from rclpy.parameter import Parameter
    node = Node('dpn', context=ros_context, parameter_overrides=[
        Parameter('heading_gain', value=3.0), Parameter('turn_in_place_angle', value=0.4),
        Parameter('slowdown_distance', value=1.0), Parameter('corner_angle', value=1.2),
        Parameter('max_path_deviation', value=2.0)])
    try:
        params = declare_parameters(node)
        follower = params.navigator.follower
        assert (follower.heading_gain, follower.turn_in_place_angle, follower.slowdown_distance,
                follower.corner_angle) == (3.0, 0.4, 1.0, 1.2)
        assert params.navigator.max_path_deviation == 2.0
    finally:
        node.destroy_node()


def test_nav2_names_with_the_old_names_as_deprecated_aliases(ros_context):
    from dpn_navigator.ros.dpn_params import DEPRECATED_ALIASES
    from rclpy.node import Node
    from rclpy.parameter import Parameter
    assert {'robot_radius', 'max_vel_x', 'max_vel_theta', 'xy_goal_tolerance'} <= {
        p.name for p in PARAMETERS}
    assert not set(DEPRECATED_ALIASES) & {p.name for p in PARAMETERS}
    old = Node('dpn', namespace='old', context=ros_context, parameter_overrides=[
        Parameter('safety_radius', value=0.4), Parameter('max_linear_speed', value=0.5)])
    both = Node('dpn', namespace='both', context=ros_context, parameter_overrides=[
        Parameter('goal_tolerance', value=0.5), Parameter('xy_goal_tolerance', value=0.2)])
    try:
        params = declare_parameters(old)
        assert params.navigator.safety_radius == 0.4
        assert params.navigator.follower.max_linear_speed == 0.5
        assert declare_parameters(both).navigator.follower.goal_tolerance == 0.2
    finally:
        old.destroy_node()
        both.destroy_node()
