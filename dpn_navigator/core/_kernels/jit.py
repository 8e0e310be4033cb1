"""
How the core's compiled kernels are built: numba settings, the on-disk cache.

Every kernel is a function of this package (``core/_kernels``) decorated with `kernel`, which
is ``numba.njit(cache=True, nogil=True)``: compiled to machine code on its first call, with no
Python objects inside (so it releases the GIL), and saved to a cache on disk so that the next
process loads it instead of compiling again.

**The cache is keyed on every kernel source.** numba keys a cached kernel on its own source
file's path and stamp only: a kernel that calls a kernel of another file, or freezes a global
of another file, keeps its old machine code when that file changes. So the cache directory is
``<base>/<digest>``, with ``digest`` (`sources_digest`) a hash of every source file of this
package: an edit of any kernel, or of the label codes in ``codes.py``, moves every kernel to a
new, empty directory and recompiles them all. Nothing outside this package is frozen into a
kernel: the FSM table is an argument of the label kernels (``cell_label.TRANSITION_BY_CODE``).

``base`` is ``$NUMBA_CACHE_DIR`` when that is set (numba's own variable), otherwise
``$XDG_CACHE_HOME/dpn_numba`` (``~/.cache/dpn_numba`` by default): an installed package's
directory may be read-only, and numba's default is a ``__pycache__`` beside the source. When
that place cannot be written either, numba's own fallback applies (a per-user directory, or
no cache, with a warning).

Each process warms up the kernels it uses, once at start (the ``warm_up_*`` function of each
part of the core), so that the first scan does not wait for the compiler or the cache.

An installed package can ship its kernels compiled: ``compile_kernels`` (``ros2 run
dpn_navigator compile_kernels``; ``make build`` runs it) compiles them for the installed copy
of the sources into ``SHIPPED_CACHE/<digest>``, next to this file, and at import this module
copies what the cache in use lacks (or holds older) from there. A first start with an empty
cache then loads the kernels instead of compiling them for about 25 CPU-s. Within a digest,
numba still keys on the source files' paths and stamps and on the CPU, so kernels shipped for
another copy of the sources or another machine are just compiled again.

"""

import contextlib
import hashlib
import os
from pathlib import Path
import shutil
import sys
import tempfile

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


#: Where ``compile_kernels`` puts the kernels it compiles for this copy of the package (in a
#: sub-directory named by `sources_digest`).
SHIPPED_CACHE = Path(__file__).resolve().parent / 'kernel_cache'

#: Characters of the hex digest that name a cache directory.
DIGEST_LENGTH = 16


def sources_digest(directory=None):
    """
    Return a hash of every kernel source: the name of the cache directory they compile into.

    Parameters
    ----------
    directory : path-like, optional
        The kernels package (this file's directory by default).

    Returns
    -------
    digest : str
        The first `DIGEST_LENGTH` hex digits of the SHA-256 of every ``*.py`` file of
        ``directory``, names and bytes, in name order.

    """
    directory = Path(__file__).resolve().parent if directory is None else Path(directory)
    digest = hashlib.sha256()
    for path in sorted(directory.glob('*.py')):
        digest.update(path.name.encode('utf-8') + b'\0')
        digest.update(path.read_bytes() + b'\0')
    return digest.hexdigest()[:DIGEST_LENGTH]


#: The digest of this copy of the kernel sources.
SOURCES_DIGEST = sources_digest()


def keyed_cache_dir(base, digest=SOURCES_DIGEST):
    """
    Return ``base/digest``, or ``base`` itself when it is already the directory of ``digest``.

    A process started with ``NUMBA_CACHE_DIR`` set by another (a worker, ``compile_kernels``'s
    child) gets the keyed directory as it is, not a directory nested in it.

    """
    base = Path(base)
    return base if base.name == digest else base / digest


def _configure_cache():
    """
    Point numba's cache at ``<base>/<digest>`` (see the module's docstring); seed it.

    ``base`` is ``NUMBA_CACHE_DIR`` when set, else `default_cache_dir`. Nothing changes when
    that directory cannot be written (numba's own fallback applies).

    """
    base = os.environ.get('NUMBA_CACHE_DIR') or default_cache_dir()
    path = keyed_cache_dir(base)
    if not _writable_dir(path):
        return
    # Read at import by numba, and by its cache locators each time a kernel is defined.
    os.environ['NUMBA_CACHE_DIR'] = str(path)
    if 'numba' in sys.modules:
        sys.modules['numba'].config.CACHE_DIR = str(path)
    seed_cache(keyed_cache_dir(SHIPPED_CACHE), path)


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

    Notes
    -----
    Each file is written under a temporary name in its directory and renamed into place
    (``os.replace``, atomic): ``make soak`` and ``make demo`` start both nodes at once, and
    both seed the cache. With a plain copy one process could read an index the other was
    still writing, take it for a miss and compile every kernel in the node (measured: ``dpn``
    ready after 75-98 s instead of 0.8 s, with 250 MB more resident memory).

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
            _copy_atomically(file, destination)
        except OSError:
            return copied
        copied += 1
    return copied


def _copy_atomically(file, destination):
    """Copy ``file`` with its time to ``destination``: whole or not at all, for any reader."""
    handle, partial = tempfile.mkstemp(dir=destination.parent, prefix='.seeding-')
    os.close(handle)
    try:
        shutil.copy2(file, partial)                   # with its time: copied once
        os.replace(partial, destination)
    except OSError:
        with contextlib.suppress(OSError):
            os.unlink(partial)
        raise


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
