"""
The package's layers, read from the import statements of every module.

- ``core/_kernels/`` is a leaf: it imports nothing of the package outside itself;
- ``core/`` imports nothing of ``ros/``, ``recording/``, ``benchmark/`` or ``tools/``;
- ``sim_bridge`` imports only ``dpn_navigator.core`` and ``dpn_navigator.ros``.
"""

import ast
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def imported_modules(path, package):
    """Return the absolute names a module imports (relative imports resolved)."""
    parts = list(path.relative_to(REPO).with_suffix('').parts)
    if parts[-1] == '__init__':
        parts = parts[:-1]
    here = parts if path.name == '__init__.py' else parts[:-1]
    names = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[:len(here) - node.level + 1]
                module = '.'.join(base + ([node.module] if node.module else []))
                names += [module] + [f'{module}.{alias.name}' for alias in node.names]
            else:
                names.append(node.module)
    return [name for name in names if name.split('.')[0] == package]


def modules(folder):
    return sorted((REPO / folder).rglob('*.py'))


@pytest.mark.parametrize('path', modules('dpn_navigator/core/_kernels'), ids=lambda p: p.name)
def test_the_kernels_are_a_leaf(path):
    outside = [name for name in imported_modules(path, 'dpn_navigator')
               if not name.startswith('dpn_navigator.core._kernels')]
    assert outside == []


@pytest.mark.parametrize('path', modules('dpn_navigator/core'),
                         ids=lambda p: str(p.relative_to(REPO / 'dpn_navigator' / 'core')))
def test_the_core_imports_no_outer_layer(path):
    outer = [name for name in imported_modules(path, 'dpn_navigator')
             if not name.startswith('dpn_navigator.core')]
    assert outer == []


@pytest.mark.parametrize('path', modules('sim_bridge'), ids=lambda p: p.name)
def test_the_simulator_uses_the_core_and_the_ros_glue_only(path):
    other = [name for name in imported_modules(path, 'dpn_navigator')
             if not name.startswith(('dpn_navigator.core', 'dpn_navigator.ros'))]
    assert other == []


def test_the_layer_reader_sees_a_forbidden_import(monkeypatch):
    module = REPO / 'dpn_navigator' / 'core' / '_kernels' / 'probe.py'
    monkeypatch.setattr(Path, 'read_text', lambda self: 'from ..cell_label import CellLabel\n')
    assert imported_modules(module, 'dpn_navigator') == [
        'dpn_navigator.core.cell_label', 'dpn_navigator.core.cell_label.CellLabel']
