"""
``compile_kernels``: compile the core's kernels into the installed package, once.

Run after an install (``ros2 run dpn_navigator compile_kernels``; ``make build`` does it), so
that a node's first start loads the kernels instead of waiting for the compiler, whatever the
user's numba cache holds (``core/jit.py``).

"""

import argparse

from .core import jit


def main(args=None):
    """Compile the kernels into ``jit.SHIPPED_CACHE`` (or ``--into``); print the time."""
    parser = argparse.ArgumentParser(prog='compile_kernels',
                                     description=__doc__.strip().splitlines()[0])
    parser.add_argument('--into', default=str(jit.SHIPPED_CACHE),
                        help='cache directory to compile into (default: %(default)s)')
    options = parser.parse_args(args)
    seconds = jit.compile_kernels(options.into)
    print(f'compile_kernels: kernels ready in {options.into} ({seconds:.1f} s)')
    return 0
