"""
``config/dpn.yaml`` and the dpn rows of the parameter table, written from the parameters' settings.

Each parameter of the ``dpn`` node is stated once, as a setting of a configuration field
(``ros/dpn_params.PARAMETERS``). This writes the two files that repeat them for users, so they
never drift: ``python -m dpn_navigator.tools.parameter_files --write`` after a change of a
setting; ``--check`` (the default) exits 1 when either file differs, as a test does.

"""

import argparse
import math
from pathlib import Path
import sys

from ..ros.dpn_params import PARAMETERS

#: The repository, when this runs from a source tree.
REPO = Path(__file__).resolve().parents[2]

YAML_HEADER = """\
# Parameters of the dpn node (ros2 run dpn_navigator dpn --ros-args --params-file config/dpn.yaml).
# The Husky on the back_and_forth scenario of the pybullet world: the node's defaults. Written
# from the parameters' settings by python -m dpn_navigator.tools.parameter_files --write (a
# test fails when it differs); units, ranges and meanings: docs/ros_reference.md. Keyed /**/dpn
# so that a namespace (-r __ns:=/robot2) does not drop them.
/**/dpn:
  ros__parameters:
"""

#: The lines of ``docs/ros_reference.md`` between which the dpn rows stand.
TABLE_BEGIN = '<!-- dpn parameters: written by python -m dpn_navigator.tools.parameter_files -->'
TABLE_END = '<!-- end of the dpn parameters -->'


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
    if isinstance(value, str):
        return f'`{value}`' if value else "`''`"
    return yaml_value(value)


def dpn_yaml():
    """Return the text of ``config/dpn.yaml``."""
    lines = [YAML_HEADER.rstrip('\n')]
    for parameter in PARAMETERS:
        unit = f'  # [{parameter.setting.unit}]' if parameter.setting.unit else ''
        lines.append(f'    {parameter.name}: {yaml_value(parameter.default)}{unit}')
    return '\n'.join(lines) + '\n'


def dpn_table_rows():
    """Return the table of the dpn parameters in ``docs/ros_reference.md``: header and rows."""
    rows = ['| node | parameter | default | range | unit | meaning |', '|---|---|---|---|---|---|']
    for parameter in PARAMETERS:
        spec = parameter.setting
        rows.append(f'| dpn | `{parameter.name}` | {doc_value(parameter.default)} | '
                    f'{spec.range_text(parameter.default)} | {spec.unit} | '
                    f'{spec.description} |')
    return rows


def with_table(reference_text):
    """
    Return ``reference_text`` with the rows between `TABLE_BEGIN` and `TABLE_END` rewritten.

    Raises
    ------
    ValueError
        When the markers are missing.

    """
    lines = reference_text.split('\n')
    try:
        begin, end = lines.index(TABLE_BEGIN), lines.index(TABLE_END)
    except ValueError:
        raise ValueError(f'docs/ros_reference.md lacks the lines {TABLE_BEGIN!r} and '
                         f'{TABLE_END!r} around the dpn rows') from None
    return '\n'.join(lines[:begin + 1] + dpn_table_rows() + lines[end:])


def main(args=None):
    """Check (default) or write config/dpn.yaml and the docs' table; 1 when they differ."""
    parser = argparse.ArgumentParser(prog='parameter_files',
                                     description=__doc__.strip().splitlines()[0])
    parser.add_argument('--write', action='store_true', help='rewrite the files')
    parser.add_argument('--repo', type=Path, default=REPO, help='the source tree')
    options = parser.parse_args(args)
    files = {options.repo / 'config' / 'dpn.yaml': lambda text: dpn_yaml(),
             options.repo / 'docs' / 'ros_reference.md': with_table}
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
