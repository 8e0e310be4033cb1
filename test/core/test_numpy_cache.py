"""numpy's cache of small freed buffers, filled at start: a process's memory stays flat after."""

import ctypes
import ctypes.util
import subprocess
import sys


#: A fresh process: array sizes below 1 KiB met in random order, two in flight at a time, as a
#: node meets them over its run; prints the allocator's bytes in use gained during that run.
RUN = """
import ctypes, sys
import numpy as np
from dpn_navigator.core.numpy_cache import fill_numpy_cache


class MallInfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in (
        'arena', 'ordblks', 'smblks', 'hblks', 'hblkhd', 'usmblks', 'fsmblks', 'uordblks',
        'fordblks', 'keepcost')]


libc = ctypes.CDLL(sys.argv[1])
libc.mallinfo2.restype = MallInfo2
sizes = np.random.default_rng(3).integers(1, 1024, 200_000).tolist()
if sys.argv[2] == 'filled':
    fill_numpy_cache()
before = libc.mallinfo2().uordblks
for first, second in zip(sizes[::2], sizes[1::2]):
    a = np.empty(first, dtype=np.uint8)
    b = np.empty(second, dtype=np.uint8)
    del a, b
print(libc.mallinfo2().uordblks - before)
"""


def glibc_path():
    """
    Return the C library's path; it must have ``mallinfo2`` (glibc >= 2.33).

    Every platform ROS 2 Jazzy supports has it (Ubuntu 24.04: glibc 2.39, Debian 12: 2.36,
    RHEL 9: 2.34), so a missing one is a broken setup, not a reason to skip.
    """
    path = ctypes.util.find_library('c')
    assert path is not None and hasattr(ctypes.CDLL(path), 'mallinfo2'), \
        f'the C library ({path}) has no mallinfo2: glibc >= 2.33 is needed'
    return path


def test_a_filled_cache_keeps_memory_flat_while_new_array_sizes_come():
    def gained(mode):
        result = subprocess.run([sys.executable, '-c', RUN, glibc_path(), mode], check=True,
                                capture_output=True, text=True)
        return int(result.stdout.split()[-1])

    unfilled, filled = gained('unfilled'), gained('filled')
    assert unfilled > 300_000, unfilled         # the cache filling: what a soak sees grow
    assert filled < 30_000, (filled, unfilled)


def test_fill_numpy_cache_allocates_every_size_below_the_cache_limit():
    from dpn_navigator.core.numpy_cache import (fill_numpy_cache, NUMPY_CACHE_BYTES,
                                                NUMPY_CACHE_DEPTH)
    assert fill_numpy_cache() == (NUMPY_CACHE_BYTES - 1) * NUMPY_CACHE_DEPTH
