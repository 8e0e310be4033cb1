"""
Every dependency key of package.xml is one rosdep resolves (issue 29).

``rosdep install --from-paths src --ignore-src -y`` fails on a key it does not know. The
snapshot (``test/package/rosdep_snapshot.yaml``, written by ``tools/rosdep_snapshot.py`` from a
ros/rosdistro checkout: its ``rosdep/base.yaml``, ``rosdep/python.yaml`` and
``jazzy/distribution.yaml``) holds the rule or the Jazzy release of each key; a key added to
package.xml without a rule there fails this test until the snapshot is regenerated, which
reports keys rosdep does not know.
"""

from pathlib import Path
import sys

import yaml

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / 'tools'))

from rosdep_snapshot import dependency_keys  # noqa: E402, I100 (the tool, not a package)

SNAPSHOT = yaml.safe_load((REPO / 'test' / 'package' / 'rosdep_snapshot.yaml').read_text())


def test_every_key_of_package_xml_resolves_in_rosdistro():
    known = set(SNAPSHOT['rosdep_keys']) | set(SNAPSHOT['jazzy_packages'])
    keys = set(dependency_keys(REPO / 'package.xml'))
    assert keys, 'no dependency keys read from package.xml'
    assert SNAPSHOT['unknown'] == []
    assert keys <= known, f'not rosdep keys: {sorted(keys - known)}'


def test_pip_keys_resolve_to_pip_on_ubuntu():
    # The pip keys need PIP_BREAK_SYSTEM_PACKAGES=1 on Ubuntu 24.04 (docs/setup.md).
    for key in ('python3-pybullet-pip', 'python3-rosbags-pip', 'mcap-ros2-support'):
        assert 'pip' in SNAPSHOT['rosdep_keys'][key]['ubuntu'], key


def test_the_keys_rosdep_does_not_know_are_gone():
    keys = set(dependency_keys(REPO / 'package.xml'))
    assert not keys & {'python3-mcap-pip', 'python3-mcap-ros2-support-pip'}
