"""
Tests of the kernels' compile settings: where the cache goes, and the warm-up.

No ROS is needed: run ``python -m pytest test/test_jit.py`` from the repository root.

"""

import os
from pathlib import Path
import shutil
import subprocess
import sys

from dpn_navigator.core import jit
import numba
import pytest


@pytest.mark.parametrize('environ, expected', [
    ({'XDG_CACHE_HOME': '/var/cache/me'}, '/var/cache/me/dpn_numba'),
    ({'XDG_CACHE_HOME': ''}, os.path.join(os.path.expanduser('~'), '.cache', 'dpn_numba')),
    ({}, os.path.join(os.path.expanduser('~'), '.cache', 'dpn_numba')),
])
def test_default_cache_dir(environ, expected):
    assert str(jit.default_cache_dir(environ)) == expected


@pytest.fixture
def fresh_numba_settings(monkeypatch):
    """Let a test call `jit._configure_cache` as if at import; restore everything after."""
    monkeypatch.delenv('NUMBA_CACHE_DIR', raising=False)
    monkeypatch.setattr(numba.config, 'CACHE_DIR', '')
    return monkeypatch


def test_cache_goes_under_the_users_cache_dir(tmp_path, fresh_numba_settings):
    fresh_numba_settings.setenv('XDG_CACHE_HOME', str(tmp_path))
    jit._configure_cache()
    assert os.environ['NUMBA_CACHE_DIR'] == str(tmp_path / 'dpn_numba')
    assert jit.cache_dir() == str(tmp_path / 'dpn_numba')
    assert (tmp_path / 'dpn_numba').is_dir()


def test_unwritable_cache_dir_leaves_numbas_own_choice(tmp_path, fresh_numba_settings):
    not_a_dir = tmp_path / 'file'
    not_a_dir.write_text('')
    fresh_numba_settings.setenv('XDG_CACHE_HOME', str(not_a_dir))
    jit._configure_cache()
    assert 'NUMBA_CACHE_DIR' not in os.environ
    assert jit.cache_dir() == ''


def test_numba_cache_dir_set_by_the_user_wins(tmp_path):
    # In a fresh interpreter, as numba reads its environment once, at import.
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / 'mine'),
               XDG_CACHE_HOME=str(tmp_path / 'xdg'),
               PYTHONPATH=os.pathsep.join(path for path in sys.path if path))
    code = 'from dpn_navigator.core import jit; print(jit.cache_dir())'
    out = subprocess.run([sys.executable, '-c', code], env=env, check=True,
                         capture_output=True, text=True).stdout
    assert out.strip() == str(tmp_path / 'mine')
    assert not (tmp_path / 'xdg').exists()


def test_warm_up_compiles_every_kernel():
    from dpn_navigator.core import astar_search, fine_evidence, label_kernel
    assert jit.warm_up() >= 0.0
    assert astar_search._search.signatures
    assert label_kernel._surely_free_update.signatures         # the fine free evidence
    assert fine_evidence._fine_moving_hits.signatures
    assert jit.warm_up() < 0.5          # ready now: a tiny call, no compiling


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


def test_shipped_kernels_are_seeded_into_an_empty_cache(tmp_path):
    # In a fresh interpreter whose jit module ships a (fake) compiled kernel.
    package = Path(jit.__file__).resolve().parents[1]
    copy = tmp_path / 'tree' / 'dpn_navigator'
    shutil.copytree(package, copy, ignore=shutil.ignore_patterns('kernel_cache',
                                                                 '__pycache__'))
    (copy / 'core' / 'kernel_cache' / 'core_0123').mkdir(parents=True)
    (copy / 'core' / 'kernel_cache' / 'core_0123' / 'k.nbi').write_text('index')
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / 'empty'),
               PYTHONPATH=os.pathsep.join([str(tmp_path / 'tree')]
                                          + [path for path in sys.path if path]))
    code = 'from dpn_navigator.core import jit; print(jit.__file__)'
    out = subprocess.run([sys.executable, '-c', code], env=env, check=True, cwd=tmp_path,
                         capture_output=True, text=True).stdout
    assert out.strip().startswith(str(copy))
    assert (tmp_path / 'empty' / 'core_0123' / 'k.nbi').read_text() == 'index'
