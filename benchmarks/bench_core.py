"""
Benchmark of the navigation core: one ``LabelGrid.update`` and one ``astar`` call.

Prints Markdown tables with the median time of many runs, next to the literal reference of
the tests (``test/literal_reference.py``) run on the same inputs: sampled over cells and
extrapolated where it is too slow to run whole. The sampled cells are also checked against
the core's result. A* is also timed against the heapq A* it replaced
(``test/astar_reference.py``), on synthetic grids and on the calls recorded from real
benchmark episodes (the navigator's replans and the wanderers' walks), with every path
compared. Not a test: it reports numbers.

Run with ``make bench`` or ``python benchmarks/bench_core.py [--quick]``.

"""

import argparse
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'test'))

from astar_reference import reference_astar  # noqa: E402, I100
from dpn_navigator.core import astar, jit, LabelGrid, path_cost  # noqa: E402
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


def kernel_start_seconds():
    """
    Time a fresh process's import of the core plus `jit.warm_up`, with an empty cache, then warm.

    Returns
    -------
    cold, warm : (float, float, float, float)
        ``(import wall, warm-up wall, import CPU, warm-up CPU)`` times [s] of the first process
        (empty cache: compiles) and of a second one (loads the cache the first wrote). CPU
        time (user + system) is what the work costs; wall time also holds the waits of a
        loaded machine.

    """
    code = ('import resource, time\n'
            'def now():\n'
            '    usage = resource.getrusage(resource.RUSAGE_SELF)\n'
            '    return time.perf_counter(), usage.ru_utime + usage.ru_stime\n'
            'wall0, cpu0 = now()\n'
            'from dpn_navigator.core import jit\n'
            'wall1, cpu1 = now()\n'
            'jit.warm_up()\n'
            'wall2, cpu2 = now()\n'
            'print(wall1 - wall0, wall2 - wall1, cpu1 - cpu0, cpu2 - cpu1)\n')
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        runs = [subprocess.run([sys.executable, '-c', code], env=env, check=True,
                               capture_output=True, text=True).stdout.split()
                for _ in range(2)]
    return tuple(tuple(float(value) for value in run) for run in runs)


def bench_astar(kind, size, instances, repeats, rng):
    """
    Time ``astar`` corner to corner against the heapq A* it replaced and a textbook A*.

    Returns the per-instance medians [ms] of the three, whether every path equalled the
    previous A*'s, and whether every path cost equalled the textbook A*'s.
    """
    core, previous, base, same, equal = [], [], [], True, True
    start, goal = (0, 0), (size - 1, size - 1)
    while len(core) < instances:
        blocked = (maze_grid(size, size, rng) if kind == 'maze'
                   else random_grid(size, size, 0.25, rng))
        path = astar(blocked, start, goal)
        baseline = tuple_astar(blocked, start, goal)
        if path is None or baseline is None:      # a random grid may have no path: redraw
            continue
        same &= path == reference_astar(blocked, start, goal)
        equal &= math.isclose(path_cost(path), path_cost(baseline), rel_tol=1e-9)
        core.append(median_ms(lambda: astar(blocked, start, goal), repeats))
        previous.append(median_ms(lambda: reference_astar(blocked, start, goal), repeats))
        base.append(median_ms(lambda: tuple_astar(blocked, start, goal), max(3, repeats // 4)))
    return core, previous, base, same, equal


def record_astar_calls(maps, wanderers):
    """
    Run benchmark episodes and record every A* call of the navigator and of the wanderers.

    Parameters
    ----------
    maps : sequence of str
        Scenario names; task 0 of each runs once, seed 0.
    wanderers : int
        Wanderers per episode.

    Returns
    -------
    calls : dict of str to list of (tuple, dict)
        ``'navigator'`` and ``'wanderers'``: the positional and keyword arguments of each call
        (arrays copied).

    """
    from dpn_navigator.benchmark.episode import run_episode
    from dpn_navigator.core import navigator as navigator_module
    from sim_bridge import clear_paths
    from sim_bridge.scenario import load_scenario
    calls = {'navigator': [], 'wanderers': []}

    def recording(kind):
        def call(*args, **kwargs):
            args = tuple(np.array(a) if isinstance(a, np.ndarray) else a for a in args)
            kwargs = {k: np.array(v) if isinstance(v, np.ndarray) else v
                      for k, v in kwargs.items()}
            calls[kind].append((args, kwargs))
            return astar(*args, **kwargs)
        return call

    saved = navigator_module.astar, clear_paths.astar
    navigator_module.astar, clear_paths.astar = recording('navigator'), recording('wanderers')
    try:
        for name in maps:
            run_episode(load_scenario(name), 0, wanderers, 0)
    finally:
        navigator_module.astar, clear_paths.astar = saved
    return calls


def bench_recorded_calls(calls, repeats):
    """
    Time recorded A* calls with the core and with the previous heapq A*, interleaved.

    Returns
    -------
    ratios : list of float
        Per call, the previous A*'s median time over the core's.
    core_ms, previous_ms : list of float
        Per call, the medians [ms].
    same : int
        Calls where both returned the same path.

    """
    ratios, core_ms, previous_ms, same = [], [], [], 0
    for args, kwargs in calls:
        same += astar(*args, **kwargs) == reference_astar(*args, **kwargs)
        core_times, previous_times = [], []
        for _ in range(repeats):
            core_times.append(median_ms(lambda: astar(*args, **kwargs), 1))
            previous_times.append(median_ms(lambda: reference_astar(*args, **kwargs), 1))
        core_ms.append(statistics.median(core_times))
        previous_ms.append(statistics.median(previous_times))
        ratios.append(previous_ms[-1] / core_ms[-1])
    return ratios, core_ms, previous_ms, same


def bench_start():
    """Print the kernels' cold and warm start times."""
    cold, warm = kernel_start_seconds()
    print('| kernels at process start (fresh process: import of the core, then jit.warm_up) '
          '| import wall [s] | warm-up wall [s] | import CPU [s] | warm-up CPU [s] |')
    print('|---|---|---|---|---|')
    for what, times in (('cold: empty cache, compiles', cold),
                        ('warm: cache written by the cold run', warm)):
        print(f'| {what} | ' + ' | '.join(f'{value:.2f}' for value in times) + ' |')
    print(f'\nThis process: kernels ready in {jit.warm_up():.2f} s '
          f'(cache: {jit.cache_dir() or "numba default"})')
    print()


def bench_updates(rng, repeats):
    """Print the table of ``LabelGrid.update`` times."""
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


def bench_astars(rng, repeats, quick):
    """Print the tables of ``astar`` times, synthetic and recorded."""
    print('| astar, corner to corner | instances | core median [ms] (range) '
          '| previous heapq A* median [ms] | ratio | same paths | tuple A* median [ms] '
          '| ratio | path costs |')
    print('|---|---|---|---|---|---|---|---|---|')
    for kind, size, instances, runs in (('random 25 %', 200, 10, repeats // 4),
                                        ('maze', 200, 10, repeats // 4),
                                        ('random 25 %', 1000, 3, 3), ('maze', 1000, 3, 3)):
        core, previous, base, same, equal = bench_astar(
            'maze' if kind == 'maze' else 'random', size, instances, max(3, runs), rng)
        core_ms = statistics.median(core)
        previous_ms, base_ms = statistics.median(previous), statistics.median(base)
        print(f'| {kind}, {size}x{size} | {instances} | {core_ms:.2f} '
              f'({min(core):.2f} to {max(core):.2f}) | {previous_ms:.2f} '
              f'| {previous_ms / core_ms:.1f}x | {"yes" if same else "NO"} | {base_ms:.2f} '
              f'| {base_ms / core_ms:.1f}x | {"all equal" if equal else "DIFFERENT"} |')
    print()
    maps = ('back_and_forth', 'maze', 'tunnel')
    calls = record_astar_calls(maps, wanderers=5)
    print(f'| astar calls recorded in real episodes ({", ".join(maps)}; task 0, 5 wanderers) '
          '| calls | grid sizes | core median [ms] | previous heapq A* median [ms] '
          '| ratio median (quartiles) | ratio of the summed times | same paths |')
    print('|---|---|---|---|---|---|---|---|')
    for kind, recorded in calls.items():
        if not recorded:
            continue
        shapes = sorted({np.shape(args[0]) for args, _ in recorded}, key=np.prod)
        ratios, core_ms, previous_ms, same = bench_recorded_calls(
            recorded, 3 if quick else 11)
        quartiles = statistics.quantiles(ratios, n=4)
        print(f'| {kind} | {len(recorded)} '
              f'| {shapes[0][0]}x{shapes[0][1]} to {shapes[-1][0]}x{shapes[-1][1]} '
              f'| {statistics.median(core_ms):.3f} | {statistics.median(previous_ms):.3f} '
              f'| {statistics.median(ratios):.1f}x ({quartiles[0]:.1f}x to {quartiles[2]:.1f}x) '
              f'| {sum(previous_ms) / sum(core_ms):.1f}x | {same}/{len(recorded)} |')


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--quick', action='store_true', help='fewer repetitions')
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--only', choices=('start', 'update', 'astar'),
                        help='run one part: kernel start times, LabelGrid.update or astar')
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    if args.only in (None, 'start'):
        bench_start()
    if args.only in (None, 'update'):
        bench_updates(rng, 20 if args.quick else 200)
    if args.only in (None, 'astar'):
        bench_astars(rng, 20 if args.quick else 200, args.quick)


if __name__ == '__main__':
    main()
