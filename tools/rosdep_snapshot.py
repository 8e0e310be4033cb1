"""
Write test/package/rosdep_snapshot.yaml: what rosdep knows of this package's dependency keys.

``python tools/rosdep_snapshot.py <rosdistro checkout>`` reads ``rosdep/base.yaml``,
``rosdep/python.yaml`` and ``jazzy/distribution.yaml`` of a clone of
https://github.com/ros/rosdistro and keeps, for every key that ``package.xml`` (and the
generated sim_bridge manifest's keys, which are among them) names, either its rosdep rule or
the Jazzy release repository of the ROS package of that name. Keys found in neither are
listed under ``unknown`` and the script exits 1: ``rosdep install`` would fail on them.
``test/package/test_rosdep_keys.py`` checks package.xml against the snapshot.

"""

from pathlib import Path
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

import yaml

REPO = Path(__file__).resolve().parents[1]
SNAPSHOT = REPO / 'test' / 'package' / 'rosdep_snapshot.yaml'
DEPEND_TAGS = ('depend', 'build_depend', 'buildtool_depend', 'exec_depend', 'test_depend',
               'build_export_depend', 'doc_depend')


def dependency_keys(manifest=REPO / 'package.xml'):
    """Return the sorted rosdep keys a package.xml names."""
    root = ElementTree.parse(manifest).getroot()
    return sorted({e.text.strip() for tag in DEPEND_TAGS for e in root.iter(tag)})


def jazzy_packages(distribution):
    """Return ``{package: repository}`` of the Jazzy release."""
    packages = {}
    for name, repository in distribution['repositories'].items():
        release = repository.get('release')
        if release is None:
            continue
        for package in release.get('packages', [name]):
            packages[package] = name
    return packages


def main(argv=None):
    """Write the snapshot from a rosdistro checkout; exit 1 when a key is unknown."""
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    rosdistro = Path(argv[0])
    rules = {}
    for name in ('base', 'python'):
        rules.update(yaml.safe_load((rosdistro / 'rosdep' / f'{name}.yaml').read_text()))
    packages = jazzy_packages(yaml.safe_load(
        (rosdistro / 'jazzy' / 'distribution.yaml').read_text()))
    commit = subprocess.run(['git', '-C', str(rosdistro), 'rev-parse', 'HEAD'],
                            capture_output=True, text=True).stdout.strip() or 'unknown'
    snapshot = {'rosdistro_commit': commit, 'rosdep_keys': {}, 'jazzy_packages': {},
                'unknown': []}
    for key in dependency_keys():
        if key in rules:
            snapshot['rosdep_keys'][key] = {os_name: rules[key][os_name]
                                            for os_name in ('ubuntu', 'debian')
                                            if os_name in rules[key]}
        elif key in packages:
            snapshot['jazzy_packages'][key] = packages[key]
        else:
            snapshot['unknown'].append(key)
    header = ('# Written by tools/rosdep_snapshot.py from ros/rosdistro: the rosdep rules and '
              'Jazzy\n# release repositories of the keys package.xml names. Regenerate after '
              'changing them.\n')
    SNAPSHOT.write_text(header + yaml.safe_dump(snapshot, sort_keys=True, width=99))
    if snapshot['unknown']:
        print(f'unknown rosdep keys: {", ".join(snapshot["unknown"])}', file=sys.stderr)
        return 1
    print(f'{SNAPSHOT}: {len(snapshot["rosdep_keys"])} rosdep keys, '
          f'{len(snapshot["jazzy_packages"])} Jazzy packages (rosdistro {commit[:12]})')
    return 0


if __name__ == '__main__':
    sys.exit(main())
