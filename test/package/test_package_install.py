"""
The installed package: both ROS names in the index, their manifests, launch files, dependencies.

Both ROS package names are in the ament index with manifests of their own, the installed share
directory holds what the launch file references, and every run-time import is declared.

The install tests need ``colcon build`` first. ``colcon test`` runs pytest with the package's
install prefix on AMENT_PREFIX_PATH (and its site-packages on PYTHONPATH), and sets COLCON=1:
there they must run. Run by hand without that environment, they look in this repository's
install/ directory, and skip if it holds no build.
"""

import ast
from importlib import metadata
import os
from pathlib import Path
import sys
from xml.etree import ElementTree

from ament_index_python.packages import get_package_prefix
from ament_index_python.packages import get_package_share_directory
from ament_index_python.packages import get_packages_with_prefixes
import pytest

REPO = Path(__file__).resolve().parents[2]
PACKAGE = 'dpn_navigator'
#: Every name the distribution registers in the ament index.
INDEXED_PACKAGES = ('dpn_navigator', 'sim_bridge')
MARKER_DIR = Path('share', 'ament_index', 'resource_index', 'packages')

EXEC_DEPENDS = {
    'rclpy', 'sensor_msgs', 'nav_msgs', 'geometry_msgs', 'visualization_msgs', 'std_msgs',
    'diagnostic_msgs', 'python3-yaml', 'tf2_msgs', 'map_msgs', 'rcl_interfaces',
    'builtin_interfaces',
    'ament_index_python', 'launch', 'launch_ros', 'rviz2',
    'rosgraph_msgs', 'python3-numpy', 'python3-numba', 'python3-pybullet-pip',
    'python3-rosbags-pip',
}
TEST_DEPENDS = {
    'ament_flake8', 'ament_pep257', 'python3-hypothesis', 'python3-pytest',
    'python3-mcap-pip', 'python3-mcap-ros2-support-pip',
}
#: rosdep keys of the Python modules the code imports that are not ROS packages.
PYTHON_MODULE_KEYS = {
    'numpy': 'python3-numpy', 'yaml': 'python3-yaml', 'pybullet': 'python3-pybullet-pip',
    'pybullet_data': 'python3-pybullet-pip', 'matplotlib': 'python3-matplotlib',
    'tqdm': 'python3-tqdm', 'numba': 'python3-numba', 'rosbags': 'python3-rosbags-pip',
    'PIL': 'python3-pil',
}
#: Imported only on request, by an optional feature: Ray (``dpn-benchmark --backend ray``,
#: requirements-ray.txt) has no rosdep key.
OPTIONAL_MODULES = {'ray'}
SOURCE_DIRS = ('dpn_navigator', 'sim_bridge', 'launch')


def _has_marker(prefix):
    return (Path(prefix) / MARKER_DIR / PACKAGE).is_file()


@pytest.fixture
def install_prefix(monkeypatch):
    """
    Return the install prefix of the package, putting it on AMENT_PREFIX_PATH if it is not there.

    Returns
    -------
    prefix : Path
        The prefix whose ament index holds ``dpn_navigator``.

    """
    current = [p for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]
    for prefix in current:
        if _has_marker(prefix):
            return Path(prefix)
    # colcon's default isolated layout, then --merge-install.
    for prefix in (REPO / 'install' / PACKAGE, REPO / 'install'):
        if _has_marker(prefix):
            monkeypatch.setenv('AMENT_PREFIX_PATH', os.pathsep.join([str(prefix)] + current))
            return prefix
    reason = (
        f'{PACKAGE} is not installed: no prefix on AMENT_PREFIX_PATH has it and {REPO}/install '
        'holds no build; run `make build` (or colcon build) first')
    if os.environ.get('COLCON') == '1':
        pytest.fail(f'under colcon test, {reason}')
    pytest.skip(reason)


def _manifest(path):
    root = ElementTree.parse(path).getroot()
    assert root.tag == 'package'
    return root


@pytest.mark.parametrize('package', INDEXED_PACKAGES)
def test_package_is_registered_with_the_install_prefix(install_prefix, package):
    assert package in get_packages_with_prefixes()
    assert Path(get_package_prefix(package)) == install_prefix
    share = Path(get_package_share_directory(package))
    assert share == install_prefix / 'share' / package
    assert _manifest(share / 'package.xml').findtext('name') == package


@pytest.mark.parametrize('pattern, subdir', [
    ('config/*.yaml', 'config'),
    ('config/*.rviz', 'config'),
    ('config/*.json', 'config'),
    ('launch/*.launch.py', 'launch'),
])
def test_config_and_launch_files_are_installed(install_prefix, pattern, subdir):
    share = Path(get_package_share_directory(PACKAGE))
    for source in REPO.glob(pattern):
        assert (share / subdir / source.name).is_file(), f'{source} is not installed'


def _metadata_dirs(prefix):
    # site-packages of the prefix; a --symlink-install build leaves the metadata in the colcon
    # build directory instead (on PYTHONPATH once install/setup.bash is sourced).
    sites = sorted(str(p) for p in prefix.glob('lib/python3*/*-packages'))
    return sites + [str(REPO / 'build' / PACKAGE)]


def test_installed_version_is_the_manifest_version(install_prefix):
    search = _metadata_dirs(install_prefix)
    dists = list(metadata.distributions(name=PACKAGE, path=search))
    assert dists, f'no {PACKAGE} distribution metadata under {search}'
    assert dists[0].version == _manifest(REPO / 'package.xml').findtext('version')


def test_manifest_declares_the_package_and_its_dependencies():
    root = _manifest(REPO / 'package.xml')
    assert root.get('format') == '3'
    assert root.findtext('name') == PACKAGE
    assert root.findtext('license') == 'Apache-2.0'
    assert root.findtext('export/build_type') == 'ament_python'
    exec_depends = {e.text for e in root.iter('exec_depend')}
    test_depends = {e.text for e in root.iter('test_depend')}
    assert EXEC_DEPENDS <= exec_depends, f'missing exec_depend: {EXEC_DEPENDS - exec_depends}'
    assert TEST_DEPENDS <= test_depends, f'missing test_depend: {TEST_DEPENDS - test_depends}'


def test_sim_bridge_has_a_manifest_of_its_own(install_prefix):
    root = _manifest(REPO / 'package.xml')
    sim_bridge = _manifest(Path(get_package_share_directory('sim_bridge')) / 'package.xml')
    assert sim_bridge.get('format') == '3'
    assert sim_bridge.findtext('name') == 'sim_bridge'
    assert 'pybullet' in sim_bridge.findtext('description')
    for field in ('version', 'license', 'maintainer'):
        assert sim_bridge.findtext(field) == root.findtext(field), field
    depends = {e.text for e in sim_bridge.iter('exec_depend')}
    # The distribution installs sim_bridge: rosdep must install its dependencies from the root.
    assert depends - {PACKAGE} <= {e.text for e in root.iter('exec_depend')}
    assert _runtime_dependencies(['sim_bridge']) <= depends | {PACKAGE}


def test_installed_share_holds_everything_the_launch_file_references(install_prefix):
    share = Path(get_package_share_directory(PACKAGE))
    launch = share / 'launch' / 'dpn_sim.launch.py'
    tree = ast.parse(launch.read_text())
    # PathJoinSubstitution([FindPackageShare('dpn_navigator'), 'config']) + [config, '<file>'].
    files = [n.value for n in ast.walk(tree) if isinstance(n, ast.Constant)
             and isinstance(n.value, str) and n.value.endswith(('.yaml', '.rviz'))]
    assert {'dpn.yaml', 'pybullet_world.yaml', 'dpn.rviz'} <= set(files)
    for name in files:
        assert (share / 'config' / name).is_file(), f'{name} is not installed in {share}/config'
    assert 'Apache License' in (share / 'LICENSE').read_text()


def _imported_modules(paths):
    for path in paths:
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                yield from (alias.name.split('.')[0] for alias in node.names)
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                yield node.module.split('.')[0]


def _runtime_dependencies(dirs):
    """Return the rosdep keys of what the code under ``dirs`` imports (not stdlib, not ours)."""
    paths = [p for d in dirs for p in (REPO / d).rglob('*.py')]
    modules = set(_imported_modules(paths))
    modules -= set(sys.stdlib_module_names) | {'dpn_navigator', 'sim_bridge'} | OPTIONAL_MODULES
    return {PYTHON_MODULE_KEYS.get(m, m) for m in modules}


def test_every_runtime_import_is_declared():
    exec_depends = {e.text for e in _manifest(REPO / 'package.xml').iter('exec_depend')}
    needed = _runtime_dependencies(SOURCE_DIRS)
    assert {'rclpy', 'tf2_msgs', 'launch_ros', 'python3-numpy'} <= needed   # the scan works
    assert needed <= exec_depends, f'imported, not exec_depend: {needed - exec_depends}'


def test_license_file_matches_the_manifest():
    text = (REPO / 'LICENSE').read_text()
    assert _manifest(REPO / 'package.xml').findtext('license') == 'Apache-2.0'
    assert 'Apache License' in text and 'Version 2.0, January 2004' in text
