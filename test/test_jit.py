"""
Tests of the kernels' compile settings: where the cache goes, and the warm-up.

No ROS is needed: run ``python -m pytest test/test_jit.py`` from the repository root.

"""

import os
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
    from dpn_navigator.core import astar_search
    assert jit.warm_up() >= 0.0
    assert astar_search._search.signatures
    assert jit.warm_up() < 0.5          # ready now: a tiny call, no compiling
