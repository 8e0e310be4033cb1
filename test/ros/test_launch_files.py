"""
The launch file and parameter files, checked without launch_ros (not installable here).

The launch file is parsed, not run: it must name the real executables, and every parameter
file it uses must exist and hold parameters that the nodes declare.
"""

import ast
from pathlib import Path
import re

import yaml

REPO = Path(__file__).resolve().parents[2]
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
    assert "'dpn = dpn_navigator.ros.node_entry:dpn'" in setup
    assert "'pybullet_world = dpn_navigator.ros.node_entry:pybullet_world'" in setup
    files = [s for s in literal_strings(tree) if s.endswith(('.yaml', '.rviz'))]
    assert sorted(files) == ['dpn.rviz', 'dpn.yaml', 'pybullet_world.yaml']
    for name in files:
        assert (REPO / 'config' / name).is_file(), name
    assert any(isinstance(n, ast.FunctionDef) and n.name == 'generate_launch_description'
               for n in tree.body)


def dpn_parameter_defaults():
    """Return every parameter the ``dpn`` node declares, with its code default."""
    from dpn_navigator.ros.dpn_params import PARAMETERS
    return {parameter.name: parameter.default for parameter in PARAMETERS}


def test_parameter_files_hold_every_declared_parameter_at_its_code_default():
    dpn = yaml.safe_load((REPO / 'config' / 'dpn.yaml').read_text())
    # Keyed /**/dpn, so that a namespace (-r __ns:=/robot2) does not drop the file.
    assert list(dpn) == ['/**/dpn']
    assert dpn['/**/dpn']['ros__parameters'] == dpn_parameter_defaults()
    world = yaml.safe_load((REPO / 'config' / 'pybullet_world.yaml').read_text())
    assert list(world) == ['/**/pybullet_world']
    from sim_bridge.world_parameters import world_node_settings
    assert list(world['/**/pybullet_world']['ros__parameters']) == list(world_node_settings())


def test_rviz_config_shows_map_plan_scan_tf_and_robot():
    rviz = yaml.safe_load((REPO / 'config' / 'dpn.rviz').read_text())
    displays = rviz['Visualization Manager']['Displays']
    topics = {d['Class'].split('/')[-1]: d['Topic']['Value'] for d in displays if 'Topic' in d}
    assert topics['Map'] == '/compabot/map'
    assert topics['Path'] == '/compabot/plan'
    assert topics['LaserScan'] == '/compabot/scan'
    assert topics['Odometry'] == '/compabot/odom_real'
    classes = {d['Class'] for d in displays}
    assert {'rviz_default_plugins/TF', 'rviz_default_plugins/Axes'} <= classes
    assert rviz['Visualization Manager']['Global Options']['Fixed Frame'] == 'map'


def test_every_parameter_is_in_the_reference_table():
    table = {'dpn': set(), 'pybullet_world': set()}
    for line in (REPO / 'docs' / 'ros_reference.md').read_text().splitlines():
        cells = [c.strip() for c in line.split('|')]
        if len(cells) > 3 and cells[1] in table:
            table[cells[1]].update(re.findall(r'`([a-z_]+)`', cells[2]))
    assert table['dpn'] == set(dpn_parameter_defaults())
    world = yaml.safe_load((REPO / 'config' / 'pybullet_world.yaml').read_text())
    assert table['pybullet_world'] == set(world['/**/pybullet_world']['ros__parameters'])


def test_launch_namespace_argument_moves_both_nodes_and_rviz_topics():
    tree = ast.parse(LAUNCH.read_text())
    arguments = [ast.literal_eval(n.args[0]) for n in ast.walk(tree)
                 if isinstance(n, ast.Call) and getattr(n.func, 'id', None)
                 == 'DeclareLaunchArgument']
    assert 'namespace' in arguments
    nodes = {ast.literal_eval(kw['executable']): kw for kw in node_calls(tree)}
    for executable in ('pybullet_world', 'dpn'):
        assert ast.unparse(nodes[executable]['namespace']) == 'namespace'
    assert 'remappings' in nodes['rviz2']
    # Every /compabot topic the RViz config names is remapped, the goal tool's included.
    module = {}
    exec(compile(ast.Module([n for n in tree.body if isinstance(n, ast.Assign)], []),
                 str(LAUNCH), 'exec'), module)
    rviz_text = (REPO / 'config' / 'dpn.rviz').read_text()
    named = set(re.findall(r'/compabot/([\w/]+)', rviz_text))
    assert named == set(module['RVIZ_TOPICS'])
