"""
Tests of the kernels' compile settings: where the cache goes, its key, the warm-up by need.

No ROS is needed: run ``python -m pytest test/core/test_jit.py`` from the repository root.

"""

import ast
import os
from pathlib import Path
import shutil
import subprocess
import sys

from dpn_navigator.core._kernels import jit
import numba
import pytest

DIGEST = jit.SOURCES_DIGEST


def run_python(code, **env):
    """
    Run ``code`` in a fresh interpreter with this one's path and ``env``; return stdout.

    It runs in the root directory, so that it imports the package from ``PYTHONPATH`` only.

    """
    environ = dict(os.environ, PYTHONPATH=os.pathsep.join(path for path in sys.path if path))
    environ.update(env)
    return subprocess.run([sys.executable, '-c', code], env=environ, check=True,
                          capture_output=True, text=True, cwd=os.path.abspath(os.sep)).stdout


@pytest.mark.parametrize('environ, expected', [
    ({'XDG_CACHE_HOME': '/var/cache/me'}, '/var/cache/me/dpn_numba'),
    ({'XDG_CACHE_HOME': ''}, os.path.join(os.path.expanduser('~'), '.cache', 'dpn_numba')),
    ({}, os.path.join(os.path.expanduser('~'), '.cache', 'dpn_numba')),
])
def test_default_cache_dir(environ, expected):
    assert str(jit.default_cache_dir(environ)) == expected


def test_the_digest_covers_every_kernel_source_and_nothing_else(tmp_path):
    leaf = Path(jit.__file__).resolve().parent
    copy = tmp_path / '_kernels'
    shutil.copytree(leaf, copy, ignore=shutil.ignore_patterns('kernel_cache', '__pycache__'))
    assert jit.sources_digest(copy) == DIGEST
    assert len(DIGEST) == jit.DIGEST_LENGTH
    (copy / 'notes.txt').write_text('not a source')
    (copy / '__pycache__').mkdir()
    (copy / '__pycache__' / 'x.pyc').write_text('compiled')
    assert jit.sources_digest(copy) == DIGEST
    for source in sorted(copy.glob('*.py')):
        text = source.read_text()
        source.write_text(text + '\n')
        assert jit.sources_digest(copy) != DIGEST, source.name
        source.write_text(text)
    (copy / 'new_kernels.py').write_text('')
    assert jit.sources_digest(copy) != DIGEST


@pytest.mark.parametrize('base, expected', [
    ('/c', f'/c/{DIGEST}'), (f'/c/{DIGEST}', f'/c/{DIGEST}'), ('/c/0123', f'/c/0123/{DIGEST}'),
])
def test_keyed_cache_dir_nests_once(base, expected):
    assert str(jit.keyed_cache_dir(base)) == expected


@pytest.fixture
def fresh_numba_settings(monkeypatch):
    """Let a test call `jit._configure_cache` as if at import; restore everything after."""
    monkeypatch.delenv('NUMBA_CACHE_DIR', raising=False)
    monkeypatch.setattr(numba.config, 'CACHE_DIR', '')
    return monkeypatch


def test_cache_goes_under_the_users_cache_dir_keyed_on_the_sources(tmp_path,
                                                                   fresh_numba_settings):
    fresh_numba_settings.setenv('XDG_CACHE_HOME', str(tmp_path))
    jit._configure_cache()
    expected = tmp_path / 'dpn_numba' / DIGEST
    assert os.environ['NUMBA_CACHE_DIR'] == str(expected)
    assert jit.cache_dir() == str(expected)
    assert expected.is_dir()


def test_unwritable_cache_dir_leaves_numbas_own_choice(tmp_path, fresh_numba_settings):
    not_a_dir = tmp_path / 'file'
    not_a_dir.write_text('')
    fresh_numba_settings.setenv('XDG_CACHE_HOME', str(not_a_dir))
    jit._configure_cache()
    assert 'NUMBA_CACHE_DIR' not in os.environ
    assert jit.cache_dir() == ''


def test_numba_cache_dir_set_by_the_user_wins_and_a_child_keeps_it(tmp_path):
    # In a fresh interpreter, as numba reads its environment once, at import.
    code = ('import os; from dpn_navigator.core._kernels import jit; print(jit.cache_dir()); '
            'import subprocess, sys; print(subprocess.run([sys.executable, "-c", '
            '"from dpn_navigator.core._kernels import jit; print(jit.cache_dir())"], '
            'capture_output=True, text=True, check=True).stdout.strip())')
    out = run_python(code, NUMBA_CACHE_DIR=str(tmp_path / 'mine'),
                     XDG_CACHE_HOME=str(tmp_path / 'xdg')).split()
    assert out == [str(tmp_path / 'mine' / DIGEST)] * 2
    assert not (tmp_path / 'xdg').exists()


def test_warm_up_by_need_compiles_only_what_a_process_uses():
    # What a fresh process compiled: the kernels of the leaf with a signature.
    listing = ('import sys; from numba.core.registry import CPUDispatcher; '
               'print(sorted(f"{name[28:]}.{attr}" for name, module in list(sys.modules.items())'
               ' if name.startswith("dpn_navigator.core._kernels.") for attr, value in '
               'vars(module).items() if isinstance(value, CPUDispatcher) and value.signatures'
               ' and value.__module__ == name))')
    # The pybullet world's wanderers plan with A* and nothing else of the core.
    out = run_python('from dpn_navigator.core.planning.astar_search import warm_up_astar; '
                     'warm_up_astar(); ' + listing)
    compiled = ast.literal_eval(out.strip())
    # With a cold cache the callees compile too (as part of their callers); all are A*'s.
    assert 'astar.search' in compiled
    assert all(name.startswith('astar.') for name in compiled), compiled
    # A navigator on the labelled grid compiles none of the costmap's kernels.
    out = run_python('from dpn_navigator.core.navigator import warm_up_navigator; '
                     'warm_up_navigator(); ' + listing)
    assert 'scan_labels.scan_update' in out and 'astar.search' in out
    assert 'costmap.' not in out


def test_warm_up_compiles_the_navigators_kernels_once():
    from dpn_navigator.core._kernels import astar, fine_evidence, free_space, scan_labels
    from dpn_navigator.core.navigator import warm_up_navigator
    warm_up_navigator()
    kernels = (astar.search, scan_labels.scan_update, scan_labels.points_update,
               free_space.surely_free_update, fine_evidence.fine_moving_hits)
    signatures = [list(kernel.signatures) for kernel in kernels]
    assert all(signatures)
    warm_up_navigator()                 # ready now: no new specialisation
    assert [list(kernel.signatures) for kernel in kernels] == signatures


def test_seed_cache_copies_what_the_cache_lacks_or_holds_older(tmp_path):
    shipped = tmp_path / 'shipped' / 'core_0123'
    shipped.mkdir(parents=True)
    (shipped / 'k.nbi').write_text('index')
    (shipped / 'k.nbc').write_text('code')
    target = tmp_path / 'cache'
    assert jit.seed_cache(tmp_path / 'shipped', target) == 2
    assert (target / 'core_0123' / 'k.nbc').read_text() == 'code'
    assert jit.seed_cache(tmp_path / 'shipped', target) == 0         # once
    os.utime(target / 'core_0123' / 'k.nbi', (0, 0))                  # older: replaced
    (target / 'core_0123' / 'k.nbi').write_text('stale')
    os.utime(target / 'core_0123' / 'k.nbi', (0, 0))
    assert jit.seed_cache(tmp_path / 'shipped', target) == 1
    assert (target / 'core_0123' / 'k.nbi').read_text() == 'index'
    assert jit.seed_cache(tmp_path / 'nothing shipped', target) == 0
    assert jit.seed_cache(tmp_path / 'shipped', tmp_path / 'shipped') == 0
    not_a_dir = tmp_path / 'file'
    not_a_dir.write_text('')
    assert jit.seed_cache(tmp_path / 'shipped', not_a_dir) == 0     # unwritable: numba's turn


def test_seed_cache_never_leaves_a_partial_file(tmp_path, monkeypatch):
    # Two nodes started at once both seed the cache: a reader must find a file whole or
    # not at all. A copy that fails half way leaves the old file and no stray temporary.
    shipped = tmp_path / 'shipped' / 'core_0123'
    shipped.mkdir(parents=True)
    (shipped / 'k.nbi').write_text('index')
    target = tmp_path / 'cache'
    (target / 'core_0123').mkdir(parents=True)
    (target / 'core_0123' / 'k.nbi').write_text('old')
    os.utime(target / 'core_0123' / 'k.nbi', (0, 0))
    written = []

    def copy_half_then_fail(source, destination):
        Path(destination).write_text(Path(source).read_text()[:2])
        written.append(Path(destination))
        raise OSError('disk full')

    monkeypatch.setattr(jit.shutil, 'copy2', copy_half_then_fail)
    assert jit.seed_cache(tmp_path / 'shipped', target) == 0
    assert (target / 'core_0123' / 'k.nbi').read_text() == 'old'
    assert written and written[0] != target / 'core_0123' / 'k.nbi'
    assert sorted(p.name for p in (target / 'core_0123').iterdir()) == ['k.nbi']


def copy_package(tmp_path):
    """Copy the dpn_navigator sources (no caches) to ``tmp_path/tree``; return the leaf."""
    package = Path(jit.__file__).resolve().parents[2]
    shutil.copytree(package, tmp_path / 'tree' / 'dpn_navigator',
                    ignore=shutil.ignore_patterns('kernel_cache', '__pycache__'))
    return tmp_path / 'tree' / 'dpn_navigator' / 'core' / '_kernels'


def test_shipped_kernels_of_these_sources_only_are_seeded(tmp_path):
    leaf = copy_package(tmp_path)
    for digest in (DIGEST, '0' * jit.DIGEST_LENGTH):
        (leaf / 'kernel_cache' / digest / 'core_0123').mkdir(parents=True)
        (leaf / 'kernel_cache' / digest / 'core_0123' / 'k.nbi').write_text(digest)
    code = 'from dpn_navigator.core._kernels import jit; print(jit.__file__)'
    out = run_python(code, NUMBA_CACHE_DIR=str(tmp_path / 'empty'),
                     PYTHONPATH=os.pathsep.join([str(tmp_path / 'tree')]
                                                + [path for path in sys.path if path]))
    assert out.strip().startswith(str(leaf))
    assert (tmp_path / 'empty' / DIGEST / 'core_0123' / 'k.nbi').read_text() == DIGEST
    assert sorted(path.name for path in (tmp_path / 'empty').iterdir()) == [DIGEST]


#: A fine-evidence call whose result comes from ``motion_evidence.moving_hits``, a kernel of
#: another file than its caller ``fine_evidence.fine_moving_hits``.
CALLER = """
import numpy as np
from dpn_navigator.core._kernels import fine_evidence, jit
xs = np.array([1.0, 1.1, 1.2, 1.3])
moving = fine_evidence.fine_moving_hits(
    np.ones((40, 40), dtype=np.bool_), 0.0, 0.0, 0.1, xs, np.full(4, 1.0),
    np.arange(4, dtype=np.int64), 0.3, 0.7, 1, 0.0, 0.0, 640, 0)
print(jit.cache_dir(), ''.join(str(int(flag)) for flag in moving))
"""


def test_an_edited_callee_recompiles_its_callers_in_other_files(tmp_path):
    leaf = copy_package(tmp_path)
    env = {'NUMBA_CACHE_DIR': str(tmp_path / 'cache'),
           'PYTHONPATH': os.pathsep.join([str(tmp_path / 'tree')]
                                         + [path for path in sys.path if path])}
    first_dir, before = run_python(CALLER, **env).split()
    assert run_python(CALLER, **env).split() == [first_dir, before]     # loaded from the cache
    callee = leaf / 'motion_evidence.py'
    text = callee.read_text()
    marker = '"""``moving_objects.moving_object_hits`` as a loop, with the same arithmetic."""\n'
    assert marker in text
    flipped = '1' if before == '0' * len(before) else '0'
    callee.write_text(text.replace(
        marker, marker + f'    return np.full(hits_x.shape[0], {flipped == "1"})\n', 1))
    second_dir, after = run_python(CALLER, **env).split()
    assert second_dir != first_dir
    assert Path(second_dir).name == jit.sources_digest(leaf)
    assert after == flipped * len(before)


def test_compile_kernels_compiles_the_copy_it_belongs_to(tmp_path):
    # numba keys a cached kernel on its source's path: compile_kernels' child must import
    # this copy, not a dpn_navigator of its working directory (make build runs it in the
    # source tree, and python -c looks there first), else the installed nodes compile again.
    from dpn_navigator.tools.compile_kernels import this_copy_program
    (tmp_path / 'dpn_navigator').mkdir()
    (tmp_path / 'dpn_navigator' / '__init__.py').write_text('raise ImportError("decoy")\n')
    code = this_copy_program('from dpn_navigator.core._kernels import jit; print(jit.__file__)')
    result = subprocess.run([sys.executable, '-c', code], cwd=tmp_path, check=True,
                            capture_output=True, text=True, env=dict(os.environ))
    assert Path(result.stdout.strip()) == Path(jit.__file__).resolve()
