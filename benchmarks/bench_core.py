"""
Benchmark of the navigation core: one ``LabelGrid.update`` and one ``astar`` call.

Prints a Markdown table with the median time of many runs, next to the literal reference of
the tests (``test/literal_reference.py``) run on the same inputs: sampled over cells and
extrapolated where it is too slow to run whole. The sampled cells are also checked against
the core's result. Not a test: it reports numbers.

Run with ``make bench`` or ``python benchmarks/bench_core.py [--quick]``.

"""

import argparse
import math
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'test'))

from dpn_navigator.core import astar, LabelGrid, path_cost  # noqa: E402, I100
from grid_worlds import maze_grid, random_grid  # noqa: E402
from literal_reference import literal_update, tuple_astar  # noqa: E402
from scan_scenes import (ANGLE_INCREMENT, ANGLE_MIN, free_pose, hall,  # noqa: E402
                         random_ranges, RANGE_MAX, RANGE_MIN, ray_cast)

SAFETY_RADIUS = 0.6


def median_ms(func, repeats):
    """Median wall time of ``func()`` over ``repeats`` calls [ms]."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return 1e3 * statistics.median(times)


def bench_update(cells, resolution, scan_kind, repeats, reference_cells, rng):
    """Time ``LabelGrid.update`` on a square grid; sample the literal reference."""
    size = cells * resolution
    truth = hall(size, int(size * size / 60), rng)
    poses = [free_pose(truth, rng) for _ in range(20)]
    if scan_kind == 'hall':
        scans = [ray_cast(truth, pose) for pose in poses]
    else:
        scans = [random_ranges(rng) for _ in poses]
    grid = LabelGrid(size, size, resolution)
    # Warm the grid up with all the scans, so that the timed updates see a realistic map.
    for pose, ranges in zip(poses, scans):
        grid.update(pose, ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX,
                    SAFETY_RADIUS)
    counter = iter(range(10 ** 9))

    def one_update():
        k = next(counter) % len(poses)
        grid.update(poses[k], scans[k], ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX,
                    SAFETY_RADIUS)

    core_ms = median_ms(one_update, repeats)
    # The reference on a sample of cells, from the same labels, checked against the core.
    before = grid.labels.copy()
    pose, ranges = poses[0], scans[0]
    grid.update(pose, ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, SAFETY_RADIUS)
    flat = rng.choice(cells * cells, size=reference_cells, replace=False)
    sample = [(int(i), int(j)) for i, j in zip(*np.unravel_index(flat, (cells, cells)))]
    start = time.perf_counter()
    literal_update(before, (0.0, 0.0), resolution, pose, ranges, ANGLE_MIN, ANGLE_INCREMENT,
                   RANGE_MIN, RANGE_MAX, SAFETY_RADIUS, cells=sample)
    per_cell = (time.perf_counter() - start) / reference_cells
    rr, cc = np.array(sample).T
    mismatches = int(np.count_nonzero(before[rr, cc] != grid.labels[rr, cc]))
    return core_ms, 1e3 * per_cell * cells * cells, mismatches


def bench_astar(kind, size, instances, repeats, rng):
    """
    Time ``astar`` corner to corner against the tuple-based textbook version.

    Returns the per-instance medians [ms] of both, and whether every path cost was equal.
    """
    core, base, equal = [], [], True
    start, goal = (0, 0), (size - 1, size - 1)
    while len(core) < instances:
        blocked = (maze_grid(size, size, rng) if kind == 'maze'
                   else random_grid(size, size, 0.25, rng))
        path = astar(blocked, start, goal)
        baseline = tuple_astar(blocked, start, goal)
        if path is None or baseline is None:      # a random grid may have no path: redraw
            continue
        equal &= math.isclose(path_cost(path), path_cost(baseline), rel_tol=1e-9)
        core.append(median_ms(lambda: astar(blocked, start, goal), repeats))
        base.append(median_ms(lambda: tuple_astar(blocked, start, goal), max(3, repeats // 4)))
    return core, base, equal


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--quick', action='store_true', help='fewer repetitions')
    parser.add_argument('--seed', type=int, default=1)
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    repeats = 20 if args.quick else 200

    print('| LabelGrid.update, 640 beams, 180 deg, 30 m, r = 0.6 m | scan | core median [ms] '
          '| literal reference [ms] (extrapolated) | ratio | sampled cells equal |')
    print('|---|---|---|---|---|---|')
    for cells, resolution, runs, sample in ((200, 0.5, repeats, 400),
                                            (2000, 0.05, max(10, repeats // 10), 60)):
        for scan_kind in ('hall', 'random'):
            core_ms, ref_ms, mismatches = bench_update(cells, resolution, scan_kind, runs,
                                                       sample, rng)
            print(f'| {cells}x{cells} cells at {resolution} m | {scan_kind} | {core_ms:.3f} '
                  f'| {ref_ms:,.0f} | {ref_ms / core_ms:,.0f}x '
                  f'| {sample - mismatches}/{sample} |')
    print()
    print('| astar, corner to corner | instances | core median [ms] (range) '
          '| tuple A* median [ms] | ratio | path costs |')
    print('|---|---|---|---|---|---|')
    for kind, size, instances, runs in (('random 25 %', 200, 10, repeats // 4),
                                        ('maze', 200, 10, repeats // 4),
                                        ('random 25 %', 1000, 3, 3), ('maze', 1000, 3, 3)):
        core, base, equal = bench_astar('maze' if kind == 'maze' else 'random', size,
                                        instances, max(3, runs), rng)
        core_ms, base_ms = statistics.median(core), statistics.median(base)
        print(f'| {kind}, {size}x{size} | {instances} | {core_ms:.2f} '
              f'({min(core):.2f} to {max(core):.2f}) | {base_ms:.2f} '
              f'| {base_ms / core_ms:.1f}x | {"all equal" if equal else "DIFFERENT"} |')


if __name__ == '__main__':
    main()
