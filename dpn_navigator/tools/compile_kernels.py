"""
``compile_kernels``: compile the core's kernels into the installed package, once.

Run after an install (``ros2 run dpn_navigator compile_kernels``; ``make build`` does it), so
that a node's first start loads the kernels instead of waiting for the compiler, whatever the
user's numba cache holds (``core/_kernels/jit.py``). The kernels go to
``SHIPPED_CACHE/<digest>``, the digest of the kernel sources they were compiled from.

"""

import argparse
import os
from pathlib import Path
import subprocess
import sys
import time

from ..core._kernels import jit


def warm_up_all():
    """
    Compile (or load from the cache) every kernel of the core with a tiny call.

    Returns
    -------
    seconds : float
        Wall time it took [s].

    """
    from ..core.planning.astar_search import warm_up_astar
    from ..benchmark.baselines.costmap_grid import warm_up_costmap
    from ..core.mapping.label_grid import warm_up_label_update
    from ..core.mapping.map_values import warm_up_map_values
    from ..core.mapping.wall_continuation import warm_up_wall_continuation
    from ..core.planning.planning_masks import warm_up_planning_masks
    started = time.perf_counter()
    for warm_up in (warm_up_astar, warm_up_label_update, warm_up_costmap, warm_up_map_values,
                    warm_up_planning_masks, warm_up_wall_continuation):
        warm_up()
    return time.perf_counter() - started


def compile_kernels(directory=jit.SHIPPED_CACHE):
    """
    Compile every kernel into ``directory/<digest>``, the cache a first start copies from.

    Runs `warm_up_all` in a fresh process with ``NUMBA_CACHE_DIR`` set to ``directory``:
    kernels whose cached code matches the sources are loaded, the others compiled.

    Parameters
    ----------
    directory : path-like
        Default ``jit.SHIPPED_CACHE``, beside the kernels' sources.

    Returns
    -------
    seconds : float
        Wall time of the fresh process's `warm_up_all` [s].

    """
    os.makedirs(directory, exist_ok=True)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(directory))
    code = this_copy_program(f'from {__name__} import warm_up_all; print(warm_up_all())')
    result = subprocess.run([sys.executable, '-c', code], env=env, check=True,
                            capture_output=True, text=True)
    return float(result.stdout.split()[-1])


def this_copy_program(statements):
    """
    Return a ``python -c`` program that runs ``statements`` with this copy of the package.

    numba keys each cached kernel on its source file's path: the kernels must be compiled
    from the copy the nodes import (the installed one), not from a ``dpn_navigator`` that
    the working directory or ``PYTHONPATH`` holds too (``make build`` runs this in the source
    tree, and ``python -c`` looks in the working directory first). So the directory that
    holds this package goes first on ``sys.path``.

    """
    package_parent = str(Path(__file__).resolve().parents[2])
    return f'import sys; sys.path.insert(0, {package_parent!r}); {statements}'


def main(args=None):
    """Compile the kernels into ``jit.SHIPPED_CACHE`` (or ``--into``); print the time."""
    parser = argparse.ArgumentParser(prog='compile_kernels',
                                     description=__doc__.strip().splitlines()[0])
    parser.add_argument('--into', default=str(jit.SHIPPED_CACHE),
                        help='cache directory to compile into (default: %(default)s)')
    options = parser.parse_args(args)
    seconds = compile_kernels(options.into)
    print(f'compile_kernels: kernels ready in {jit.keyed_cache_dir(options.into)} '
          f'({seconds:.1f} s)')
    return 0
