"""numpy's cache of small freed buffers, filled at start: a process's memory stays flat after."""

import ctypes
import ctypes.util
import subprocess
import sys

import pytest

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
    path = ctypes.util.find_library('c')
    try:
        ctypes.CDLL(path).mallinfo2
    except (OSError, AttributeError, TypeError):
        return None
    return path


@pytest.mark.skipif(glibc_path() is None, reason='needs glibc >= 2.33 (mallinfo2)')
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
