"""
The nodes' parameter files and tables, written from the parameters' settings.

Each parameter of the ``dpn`` node is stated once, as a setting of a configuration field
(``ros/dpn_params.PARAMETERS``), and so is each of the ``pybullet_world`` node
(``sim_bridge/world_parameters.py``). This writes the files that repeat them for users,
``config/dpn.yaml``, ``config/pybullet_world.yaml`` and the two tables of
``docs/ros_reference.md``, so they never drift: ``python -m
dpn_navigator.tools.parameter_files --write`` after a change of a setting; without
``--write`` it exits 1 when a file differs, as a test does.

"""

import argparse
import math
from pathlib import Path
import sys

from ..ros.dpn_params import PARAMETERS

#: The repository, when this runs from a source tree.
REPO = Path(__file__).resolve().parents[2]

#: Each node's parameter file: its first lines, before ``/**/<node>:``.
YAML_HEADERS = {
    'dpn': """\
# Parameters of the dpn node (ros2 run dpn_navigator dpn --ros-args --params-file config/dpn.yaml).
# The Husky on the back_and_forth scenario of the pybullet world: the node's defaults.""",
    'pybullet_world': """\
# Parameters of the pybullet world node (ros2 run sim_bridge pybullet_world --ros-args
# --params-file config/pybullet_world.yaml): the node's defaults.""",
}
YAML_FOOTER = """\
# Written from the parameters' settings by python -m dpn_navigator.tools.parameter_files --write
# (a test fails when it differs); units, ranges and meanings: docs/ros_reference.md. Keyed
# /**/<node> so that a namespace (-r __ns:=/robot2) does not drop them."""


def node_parameters(node):
    """
    Return a node's parameters: ``[(name, default, Setting)]`` in order.

    Parameters
    ----------
    node : str
        ``'dpn'`` or ``'pybullet_world'``.

    """
    if node == 'dpn':
        return [(p.name, p.default, p.setting) for p in PARAMETERS]
    from sim_bridge.world_parameters import world_node_settings
    return [(name, default, spec) for name, (default, spec) in world_node_settings().items()]


def table_begin(node):
    """Return the line before the table of ``node``'s parameters in the docs."""
    return (f'<!-- {node} parameters: written by python -m '
            'dpn_navigator.tools.parameter_files -->')


def table_end(node):
    """Return the line after the table of ``node``'s parameters in the docs."""
    return f'<!-- end of the {node} parameters -->'


def yaml_value(value):
    """Write ``value`` as YAML: ``true``, ``.nan``, ``''``, ``0.5``, ``70``, ``map``."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, float):
        return '.nan' if math.isnan(value) else repr(value)
    if isinstance(value, str):
        return value if value else "''"
    return str(value)


def doc_value(value):
    """Write ``value`` for the docs' table."""
    if isinstance(value, float) and math.isnan(value):
        return 'NaN'
    if isinstance(value, str):
        return f'`{value}`' if value else "`''`"
    return yaml_value(value)


def node_yaml(node):
    """Return the text of ``config/<node>.yaml``."""
    lines = [YAML_HEADERS[node], YAML_FOOTER, f'/**/{node}:', '  ros__parameters:']
    for name, default, spec in node_parameters(node):
        unit = f'  # [{spec.unit}]' if spec.unit else ''
        lines.append(f'    {name}: {yaml_value(default)}{unit}')
    return '\n'.join(lines) + '\n'


def node_table(node):
    """Return the table of ``node``'s parameters in ``docs/ros_reference.md``: header, rows."""
    rows = ['| node | parameter | default | range | unit | meaning |', '|---|---|---|---|---|---|']
    for name, default, spec in node_parameters(node):
        rows.append(f'| {node} | `{name}` | {doc_value(default)} | {spec.range_text(default)} | '
                    f'{spec.unit} | {spec.description} |')
    return rows


def with_tables(reference_text):
    """
    Return ``reference_text`` with each node's table rewritten between its marker lines.

    Raises
    ------
    ValueError
        When the markers of a node are missing.

    """
    lines = reference_text.split('\n')
    for node in YAML_HEADERS:
        try:
            begin, end = lines.index(table_begin(node)), lines.index(table_end(node))
        except ValueError:
            raise ValueError(f'docs/ros_reference.md lacks the lines {table_begin(node)!r} and '
                             f'{table_end(node)!r} around the {node} parameters') from None
        lines = lines[:begin + 1] + node_table(node) + lines[end:]
    return '\n'.join(lines)


def main(args=None):
    """Check (default) or write the parameter files and tables; 1 when one differs."""
    parser = argparse.ArgumentParser(prog='parameter_files',
                                     description=__doc__.strip().splitlines()[0])
    parser.add_argument('--write', action='store_true', help='rewrite the files')
    parser.add_argument('--repo', type=Path, default=REPO, help='the source tree')
    options = parser.parse_args(args)
    files = {options.repo / 'config' / f'{node}.yaml': (lambda text, node=node: node_yaml(node))
             for node in YAML_HEADERS}
    files[options.repo / 'docs' / 'ros_reference.md'] = with_tables
    stale = []
    for path, written in files.items():
        text = path.read_text()
        new = written(text)
        if new != text:
            stale.append(path)
            if options.write:
                path.write_text(new)
    for path in stale:
        print(f'parameter_files: {path} {"rewritten" if options.write else "differs"}')
    return 1 if stale and not options.write else 0


if __name__ == '__main__':
    sys.exit(main())
