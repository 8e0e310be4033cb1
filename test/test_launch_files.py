"""
The launch file and parameter files, checked without launch_ros (not installable here).

The launch file is parsed, not run: it must name the real executables, and every parameter
file it uses must exist and hold parameters that the nodes declare.
"""

import ast
from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parents[1]
LAUNCH = REPO / 'launch' / 'dpn_sim.launch.py'


def node_calls(tree):
    """Yield the keyword arguments of every ``Node(...)`` call of a launch file."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and getattr(node.func, 'id', None) == 'Node':
            yield {kw.arg: kw.value for kw in node.keywords}


def literal_strings(node):
    return [n.value for n in ast.walk(node) if isinstance(n, ast.Constant)
            and isinstance(n.value, str)]


def test_launch_file_names_the_real_executables_and_config_files():
    tree = ast.parse(LAUNCH.read_text())
    nodes = {(ast.literal_eval(kw['package']), ast.literal_eval(kw['executable'])): kw
             for kw in node_calls(tree)}
    assert ('sim_bridge', 'pybullet_world') in nodes
    assert ('dpn_navigator', 'dpn') in nodes
    setup = (REPO / 'setup.py').read_text()
    assert "'dpn = dpn_navigator.dpn_node:main'" in setup
    assert "'pybullet_world = sim_bridge.pybullet_world_node:main'" in setup
    files = [s for s in literal_strings(tree) if s.endswith(('.yaml', '.rviz'))]
    assert sorted(files) == ['dpn.rviz', 'dpn.yaml', 'pybullet_world.yaml']
    for name in files:
        assert (REPO / 'config' / name).is_file(), name
    assert any(isinstance(n, ast.FunctionDef) and n.name == 'generate_launch_description'
               for n in tree.body)


def test_parameter_files_hold_only_declared_parameters():
    from dpn_navigator.dpn_params import FLOAT_PARAMETERS
    from dpn_navigator.safety_params import INTEGER_PARAMETERS
    dpn = yaml.safe_load((REPO / 'config' / 'dpn.yaml').read_text())
    assert set(dpn['dpn']['ros__parameters']) == set(FLOAT_PARAMETERS) | set(INTEGER_PARAMETERS)
    world = yaml.safe_load((REPO / 'config' / 'pybullet_world.yaml').read_text())
    source = (REPO / 'sim_bridge' / 'pybullet_world_node.py').read_text()
    for name in world['pybullet_world']['ros__parameters']:
        assert f"'{name}'" in source, f'{name} is not declared by pybullet_world'
    rviz = yaml.safe_load((REPO / 'config' / 'dpn.rviz').read_text())
    topics = {d['Topic']['Value'] for d in rviz['Visualization Manager']['Displays']
              if 'Topic' in d}
    assert {'/compabot/map', '/compabot/marker', '/compabot/odom_real'} <= topics
    assert rviz['Visualization Manager']['Global Options']['Fixed Frame'] == 'map'
