"""
How the core's compiled kernels are built: numba settings, the on-disk cache, the warm-up.

Every kernel of the core is a private function decorated with `kernel`, which is
``numba.njit(cache=True, nogil=True)``: compiled to machine code on its first call, with no
Python objects inside (so it releases the GIL), and saved to a cache on disk so that the next
process loads it instead of compiling again.

The cache lives in ``$NUMBA_CACHE_DIR`` when that is set (numba's own variable), otherwise in
``$XDG_CACHE_HOME/dpn_numba`` (``~/.cache/dpn_numba`` by default): an installed package's
directory may be read-only, and numba's default is a ``__pycache__`` beside the source. When
that place cannot be written either, numba's own fallback applies (a per-user directory, or
no cache, with a warning).

A node or the benchmark calls `warm_up` once at start, so that the first scan is not the one
that waits for the compiler or the cache.

An installed package can ship its kernels compiled: ``compile_kernels`` (``ros2 run
dpn_navigator compile_kernels``; ``make build`` runs it) compiles them for the installed copy
of the sources into ``SHIPPED_CACHE``, next to this file, and at import this module copies
what the cache in use lacks (or holds older) from there. A first start with an empty cache
then loads the kernels instead of compiling them for about 25 CPU-s. The cache is keyed on the
source files' paths and stamps and on the CPU, so kernels shipped for other sources or another
machine are just compiled again.

"""

import os
from pathlib import Path
import shutil
import subprocess
import sys
import tempfile
import time

#: Sub-directory of the user's cache directory that holds the compiled kernels.
CACHE_SUBDIR = 'dpn_numba'


def default_cache_dir(environ=None):
    """
    Return where the kernels are cached when ``NUMBA_CACHE_DIR`` is not set.

    Parameters
    ----------
    environ : mapping, optional
        The environment (``os.environ`` by default).

    Returns
    -------
    path : pathlib.Path
        ``$XDG_CACHE_HOME/dpn_numba``, or ``~/.cache/dpn_numba`` when ``XDG_CACHE_HOME`` is
        unset or empty.

    """
    environ = os.environ if environ is None else environ
    base = environ.get('XDG_CACHE_HOME') or os.path.join(os.path.expanduser('~'), '.cache')
    return Path(base) / CACHE_SUBDIR


def _writable_dir(path):
    """Create ``path`` if need be; return True when a file can be written in it."""
    try:
        os.makedirs(path, exist_ok=True)
        with tempfile.TemporaryFile(dir=path):
            pass
    except OSError:
        return False
    return True


#: Where `compile_kernels` puts the kernels it compiles for this copy of the package.
SHIPPED_CACHE = Path(__file__).resolve().parent / 'kernel_cache'


def _configure_cache():
    """Point numba's cache at `default_cache_dir` unless ``NUMBA_CACHE_DIR`` says otherwise."""
    if not os.environ.get('NUMBA_CACHE_DIR'):
        path = default_cache_dir()
        if not _writable_dir(path):
            return
        # Read at import by numba, and by its cache locators each time a kernel is defined.
        os.environ['NUMBA_CACHE_DIR'] = str(path)
        if 'numba' in sys.modules:
            sys.modules['numba'].config.CACHE_DIR = str(path)
    seed_cache(SHIPPED_CACHE, os.environ['NUMBA_CACHE_DIR'])


def seed_cache(source, target):
    """
    Copy the cached kernels of ``source`` that ``target`` lacks or holds older.

    Parameters
    ----------
    source, target : path-like
        numba cache directories (``NUMBA_CACHE_DIR`` layout: one sub-directory per source
        directory, index and data files in it); a missing ``source`` copies nothing.

    Returns
    -------
    copied : int
        Files copied (0 as well when ``target`` cannot be written: numba then compiles).

    """
    source = Path(source)
    if not source.is_dir() or source.resolve() == Path(target).resolve():
        return 0
    copied = 0
    for file in source.glob('*/*'):
        destination = Path(target) / file.relative_to(source)
        try:
            if (destination.exists()
                    and destination.stat().st_mtime >= file.stat().st_mtime):
                continue
            destination.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(file, destination)           # with its time: copied once
        except OSError:
            return copied
        copied += 1
    return copied


# Before numba is imported: it reads NUMBA_CACHE_DIR once, at import.
_configure_cache()

import numba  # noqa: E402, I100

#: Options of every kernel: machine code with no Python objects, cached on disk, GIL released.
KERNEL_OPTIONS = {'cache': True, 'nogil': True}


def kernel(func):
    """
    Compile ``func`` as a kernel of the core: ``numba.njit(cache=True, nogil=True)``.

    Parameters
    ----------
    func : function
        Plain Python over numpy arrays and scalars, in numba's nopython subset.

    Returns
    -------
    numba.core.registry.CPUDispatcher
        Compiled on its first call, or loaded from the cache.

    """
    return numba.njit(**KERNEL_OPTIONS)(func)


def cache_dir():
    """Return the directory numba caches kernels in now (``''`` when it chose itself)."""
    return numba.config.CACHE_DIR


def warm_up():
    """
    Compile (or load from the cache) every kernel of the core with a tiny call.

    Returns
    -------
    seconds : float
        Wall time it took [s]: the compile time with an empty cache, the load time with a
        warm one, nearly 0 when the kernels were ready already.

    """
    from .astar_search import warm_up_astar
    from .costmap_grid import warm_up_costmap
    from .label_grid import warm_up_label_update
    from .map_values import warm_up_map_values
    from .planning_masks import warm_up_planning_masks
    started = time.perf_counter()
    warm_up_astar()
    warm_up_label_update()
    warm_up_costmap()
    warm_up_map_values()
    warm_up_planning_masks()
    return time.perf_counter() - started


def compile_kernels(directory=SHIPPED_CACHE):
    """
    Compile every kernel into ``directory``, the cache a first start copies from.

    Runs `warm_up` in a fresh process with ``NUMBA_CACHE_DIR`` set to ``directory``: kernels
    whose cached code matches the sources are loaded, the others compiled.

    Parameters
    ----------
    directory : path-like
        Default `SHIPPED_CACHE`, beside this package's sources.

    Returns
    -------
    seconds : float
        Wall time of the fresh process's `warm_up` [s].

    """
    os.makedirs(directory, exist_ok=True)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(directory))
    code = f'import sys; sys.path.insert(0, {str(Path(__file__).resolve().parents[2])!r}); ' \
        'from dpn_navigator.core import jit; print(jit.warm_up())'
    result = subprocess.run([sys.executable, '-c', code], env=env, check=True,
                            capture_output=True, text=True)
    return float(result.stdout.split()[-1])
