"""
The core's compiled kernels (numba), a leaf: nothing here imports the rest of the core.

Each module holds the kernels of one part of the core, private behind that part's public,
validating functions (``astar_search``, ``label_update``, ...); the raster helpers that several
parts share are public in ``raster``. ``jit`` holds the ``kernel`` decorator and the on-disk
cache, keyed on a digest of every source file of this package, so that an edit of any kernel,
or of ``codes``, recompiles every kernel that calls it.

"""
