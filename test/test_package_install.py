"""
The installed package: both ROS package names in the ament index, and the manifest's dependencies.

The install tests need ``colcon build`` first. ``colcon test`` runs pytest with the package's
install prefix on AMENT_PREFIX_PATH (and its site-packages on PYTHONPATH), and sets COLCON=1:
there they must run. Run by hand without that environment, they look in this repository's
install/ directory, and skip if it holds no build.
"""

from importlib import metadata
import os
from pathlib import Path
from xml.etree import ElementTree

from ament_index_python.packages import get_package_prefix
from ament_index_python.packages import get_package_share_directory
from ament_index_python.packages import get_packages_with_prefixes
import pytest

REPO = Path(__file__).resolve().parents[1]
PACKAGE = 'dpn_navigator'
#: Every name the distribution registers in the ament index.
INDEXED_PACKAGES = ('dpn_navigator', 'sim_bridge')
MARKER_DIR = Path('share', 'ament_index', 'resource_index', 'packages')

EXEC_DEPENDS = {
    'rclpy', 'sensor_msgs', 'nav_msgs', 'geometry_msgs', 'visualization_msgs', 'std_msgs',
    'diagnostic_msgs', 'python3-yaml',
    'rosgraph_msgs', 'python3-numpy', 'python3-pybullet-pip',
}
TEST_DEPENDS = {
    'ament_flake8', 'ament_index_python', 'ament_pep257', 'python3-hypothesis', 'python3-pytest',
}


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
    assert _manifest(share / 'package.xml').findtext('name') == PACKAGE


@pytest.mark.parametrize('pattern, subdir', [
    ('config/*.yaml', 'config'),
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
