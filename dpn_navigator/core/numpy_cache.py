"""
numpy's cache of small freed buffers, filled once at start so that a process's memory is flat.

numpy does not hand a freed array's data of under ``NUMPY_CACHE_BYTES`` back to the allocator:
it keeps up to ``NUMPY_CACHE_DEPTH`` buffers of each size in bytes for the next array of that
size (``numpy/_core/src/multiarray/alloc.c``: ``NBUCKETS`` 1024, ``NCACHE`` 7; numpy 1.x and
2.x), about 3.6 MB when every size is held. A node that runs for long meets new array sizes
for minutes (hits, segments, tracks, paths, boxes of every length), so that cache fills slowly,
and the process's resident memory grows by those 3.6 MB over its first minutes before it
levels off: the soak of issue 32 measured the dpn node's resident memory growing about
3.7 MB (its main heap 2.7 MB) over its first 4 minutes, flat after. `fill_numpy_cache` fills
it at start: the same memory, held from the first scan, and nothing that grows after.

"""

import numpy as np

#: numpy caches freed data buffers smaller than this [bytes] (its ``NBUCKETS``).
NUMPY_CACHE_BYTES = 1024
#: ... and at most this many of each size (its ``NCACHE``).
NUMPY_CACHE_DEPTH = 7


def fill_numpy_cache():
    """
    Fill numpy's cache of small freed buffers: every size below 1 KiB, ``NUMPY_CACHE_DEPTH`` each.

    Allocates ``NUMPY_CACHE_DEPTH`` arrays of every size from 1 to ``NUMPY_CACHE_BYTES - 1``
    bytes at once and frees them: numpy keeps them all. About 3.6 MB and a few milliseconds,
    once per process; calling it again allocates nothing new.

    Returns
    -------
    buffers : int
        How many buffers were allocated and handed to the cache.

    """
    held = [np.empty(size, dtype=np.uint8)
            for size in range(1, NUMPY_CACHE_BYTES) for _ in range(NUMPY_CACHE_DEPTH)]
    count = len(held)
    del held
    return count
