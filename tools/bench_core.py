"""
Benchmark of the navigation core, each figure against the implementation it replaced.

Prints Markdown tables of medians, old and new timed interleaved in one run, with their ratio:

- the dpn rule's motion tracks, trail marks and object memory (compiled) against
  ``NumpyExtrasLabelGrid`` (the same label kernel with them in numpy around it,
  ``test/reference/numpy_label_grid.py``), on scenes of boxes that walk, with every array compared;
- ``LabelGrid.update`` (the compiled kernel) against ``NumpyLabelGrid`` (the numpy update and
  whole-grid ghost expiry it replaced, ``test/reference/numpy_label_grid.py``), under the
  paper's rule and the navigator's default rule, with the labels compared after every update;
  the paper's rule also against the literal reference of the tests
  (``test/reference/literal_reference.py``), sampled over cells and extrapolated;
- a replan's setup: the navigator's ``PlanningMasks`` (refreshed in the changed box) against
  the whole-grid masks it replaced, same paths;
- the map a node publishes: ``OccupancyGridBuffer`` (the changed box) against
  ``labels_to_occupancy_grid`` (the whole grid), same bytes;
- ``astar`` against the heapq A* it replaced (``test/reference/astar_reference.py``), on
  synthetic grids and on the calls recorded from real benchmark episodes, with every path compared.

Not a test: it reports numbers. CPU time (``time.process_time``) is reported besides wall
time where a shared machine makes wall time noise.

Run with ``make bench`` or ``python tools/bench_core.py [--quick] [--only PART]``.

"""

import argparse
import dataclasses
import importlib
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [os.path.join(HERE, '..', 'test'), os.path.join(HERE, '..', 'test', 'reference')]

from astar_reference import reference_astar  # noqa: E402, I100
from builtin_interfaces.msg import Time  # noqa: E402
from dpn_navigator.core import astar, LabelGrid, path_cost  # noqa: E402
from dpn_navigator.core._kernels import jit  # noqa: E402
from dpn_navigator.core.cell_label import blocked_mask  # noqa: E402
from dpn_navigator.core.mapping.label_grid import PAPER_RULE  # noqa: E402
from dpn_navigator.core.mapping.map_values import warm_up_map_values  # noqa: E402
from dpn_navigator.core.navigator import Navigator, NavigatorConfig  # noqa: E402
from dpn_navigator.core.navigator import warm_up_navigator  # noqa: E402
from dpn_navigator.core.planning.planning_masks import touches_blocked  # noqa: E402
from dpn_navigator.ros.conversions import labels_to_occupancy_grid  # noqa: E402
from dpn_navigator.ros.conversions import OccupancyGridBuffer  # noqa: E402
from grid_worlds import maze_grid, random_grid  # noqa: E402
from literal_reference import literal_update, tuple_astar  # noqa: E402
from numpy_label_grid import NumpyExtrasLabelGrid, NumpyLabelGrid  # noqa: E402
from scan_scenes import (ANGLE_INCREMENT, ANGLE_MIN, free_pose, hall,  # noqa: E402
                         moving_box_world, random_ranges, RANGE_MAX, RANGE_MIN, ray_cast)

SAFETY_RADIUS = 0.6


def median_ms(func, repeats):
    """Median CPU time of ``func()`` over ``repeats`` calls [ms]."""
    times = []
    for _ in range(repeats):
        start = time.process_time()
        func()
        times.append(time.process_time() - start)
    return 1e3 * statistics.median(times)


def interleaved_ms(funcs, repeats):
    """
    Median CPU time of each of ``funcs`` [ms], called in turn ``repeats`` times.

    Each call gets the round number. CPU time (user + system of this process) is what the
    work costs; on a shared machine wall time mostly measures the other processes.
    """
    times = [[] for _ in funcs]
    for k in range(repeats):
        for func, spent in zip(funcs, times):
            start = time.process_time()
            func(k)
            spent.append(time.process_time() - start)
    return [1e3 * statistics.median(spent) for spent in times]


def hall_scans(cells, resolution, scan_kind, rng, count=20):
    """Poses and ranges of ``count`` scans in a square hall of ``cells`` x ``cells``."""
    size = cells * resolution
    truth = hall(size, int(size * size / 60), rng)
    poses = [free_pose(truth, rng) for _ in range(count)]
    if scan_kind == 'hall':
        return poses, [ray_cast(truth, pose) for pose in poses]
    return poses, [random_ranges(rng) for _ in poses]


def bench_update(cells, resolution, scan_kind, rule, repeats, reference_cells, rng):
    """
    Time ``LabelGrid.update`` against ``NumpyLabelGrid.update``, interleaved; check labels.

    Returns
    -------
    new_ms, old_ms : float
        Median CPU time per update [ms].
    literal_ms : float or None
        The literal reference extrapolated to the whole grid [ms] (paper's rule only).
    equal : bool
        Labels (and the rule's state) equal after every update.
    mismatches : int
        Sampled cells where the literal reference disagrees (0 when not run).

    """
    size = cells * resolution
    poses, scans = hall_scans(cells, resolution, scan_kind, rng)
    grids = (LabelGrid(size, size, resolution, rule=rule),
             NumpyLabelGrid(size, size, resolution, rule=rule))
    equal = True

    def updater(grid):
        def one_update(k):
            grid.update(poses[k % len(poses)], scans[k % len(poses)], ANGLE_MIN,
                        ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, SAFETY_RADIUS, stamp=0.1 * k)
        return one_update

    # Warm the grids up with all the scans, so that the timed updates see a realistic map.
    for k in range(len(poses)):
        for grid in grids:
            updater(grid)(k)
    new_ms, old_ms = interleaved_ms([updater(grid) for grid in grids], repeats)
    for name in ('labels', 'seen_free', 'last_hit'):
        if getattr(grids[0], name) is not None:
            equal &= bool(np.array_equal(getattr(grids[0], name), getattr(grids[1], name)))
    if rule != PAPER_RULE:
        return new_ms, old_ms, None, equal, 0
    # The reference on a sample of cells, from the same labels, checked against the core.
    grid = grids[0]
    before = grid.labels.copy()
    pose, ranges = poses[0], scans[0]
    grid.update(pose, ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, SAFETY_RADIUS)
    flat = rng.choice(cells * cells, size=reference_cells, replace=False)
    sample = [(int(i), int(j)) for i, j in zip(*np.unravel_index(flat, (cells, cells)))]
    start = time.process_time()
    literal_update(before, (0.0, 0.0), resolution, pose, ranges, ANGLE_MIN, ANGLE_INCREMENT,
                   RANGE_MIN, RANGE_MAX, SAFETY_RADIUS, cells=sample)
    per_cell = (time.process_time() - start) / reference_cells
    rr, cc = np.array(sample).T
    mismatches = int(np.count_nonzero(before[rr, cc] != grid.labels[rr, cc]))
    return new_ms, old_ms, 1e3 * per_cell * cells * cells, equal, mismatches


def whole_grid_plan(labels, pose, start, goal, footprint, proximity_cost):
    """Plan as the navigator did before ``PlanningMasks``: every mask from the whole grid."""
    blocked = blocked_mask(labels)
    if blocked[goal]:
        return None
    rows, cols, near = footprint
    blocked[rows, cols] &= ~near
    blocked[start] = False
    cell_cost = proximity_cost * touches_blocked(blocked)
    return astar(blocked, start, goal, cell_cost=cell_cost, cut_corners=False)


def bench_replan_setup(cells, resolution, rng, repeats):
    """
    Time one scan's refresh of the planning masks plus a short plan, against the whole grid.

    Returns the medians [ms] of the new and the old way and whether every path was equal.
    """
    size = cells * resolution
    poses, scans = hall_scans(cells, resolution, 'hall', rng)
    navigator = Navigator(NavigatorConfig(width=size, height=size, resolution=resolution))
    masks = navigator._masks
    geometry = navigator.grid.geometry
    for k in range(len(poses)):
        navigator.observe(poses[k], scans[k], ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX,
                          stamp=0.1 * k)
    masks.refresh()
    same = True
    plans = {}

    def case(k):
        pose = poses[k % len(poses)]
        start = tuple(int(v) for v in geometry.world_to_cell(pose[0], pose[1]))
        goal = (min(start[0] + 3, cells - 1), min(start[1] + 3, cells - 1))
        return pose, start, goal, navigator._footprint(pose)

    def scan(k):
        navigator.observe(poses[k % len(poses)], scans[k % len(poses)], ANGLE_MIN,
                          ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, stamp=10.0 + 0.1 * k)

    def new(k):
        # The refresh and search a replan does after the scan of this round.
        pose, start, goal, footprint = case(k)
        masks.refresh()
        plans[k] = None if masks.blocked[goal] else masks.plan(start, goal, footprint, False)

    def old(k):
        pose, start, goal, footprint = case(k)
        path = whole_grid_plan(navigator.grid.labels, pose, start, goal, footprint,
                               navigator.config.obstacle_proximity_cost)
        nonlocal same
        same &= path == plans[k]

    _, new_ms, old_ms = interleaved_ms([scan, new, old], repeats)
    return new_ms, old_ms, same


def bench_map_refresh(cells, resolution, rng, repeats):
    """Time a published map's conversion: the changed box against the whole grid."""
    size = cells * resolution
    poses, scans = hall_scans(cells, resolution, 'hall', rng)
    grid = LabelGrid(size, size, resolution)
    changes = grid.change_tracker()
    buffer = OccupancyGridBuffer(grid.geometry.shape)
    same = True
    stamp = Time(sec=1)

    def scan(k):
        grid.update(poses[k % len(poses)], scans[k % len(poses)], ANGLE_MIN, ANGLE_INCREMENT,
                    RANGE_MIN, RANGE_MAX, SAFETY_RADIUS)

    def new(k):
        rows, cols, _ = changes.take()
        buffer.refresh(grid.labels, rows, cols)
        buffer.message(resolution, (0.0, 0.0), stamp)

    def old(k):
        nonlocal same
        msg = labels_to_occupancy_grid(grid.labels, resolution, (0.0, 0.0), stamp)
        same &= msg.data == buffer.message(resolution, (0.0, 0.0), stamp).data

    _, new_ms, old_ms = interleaved_ms([scan, new, old], repeats)
    return new_ms, old_ms, same


def kernel_start_seconds(tree=None):
    """
    Time a fresh process's import of the core plus the dpn node warm-up, empty cache, then warm.

    Parameters
    ----------
    tree : str, optional
        A source tree to import the package from; by default the package on ``PYTHONPATH``
        (``make bench``: the installed one, with the kernels ``compile_kernels`` shipped).

    Returns
    -------
    cold, warm : (float, float, float, float)
        ``(import wall, warm-up wall, import CPU, warm-up CPU)`` times [s] of the first process
        (empty cache: compiles, or copies the shipped kernels) and of a second one (loads the
        cache the first wrote). CPU time (user + system) is what the work costs; wall time
        also holds the waits of a loaded machine.

    """
    code = ('import resource, time\n'
            'def now():\n'
            '    usage = resource.getrusage(resource.RUSAGE_SELF)\n'
            '    return time.perf_counter(), usage.ru_utime + usage.ru_stime\n'
            'wall0, cpu0 = now()\n'
            'try:\n'
            '    from dpn_navigator.core.navigator import warm_up_navigator\n'
            '    from dpn_navigator.core.mapping.map_values import warm_up_map_values\n'
            '    warm_ups = (warm_up_navigator, warm_up_map_values)\n'
            'except ImportError:  # a tree from before the kernel leaf\n'
            '    from dpn_navigator.core.jit import warm_up\n'
            '    warm_ups = (warm_up,)\n'
            'wall1, cpu1 = now()\n'
            'for warm_up in warm_ups:\n'
            '    warm_up()\n'
            'wall2, cpu2 = now()\n'
            'print(wall1 - wall0, wall2 - wall1, cpu1 - cpu0, cpu2 - cpu1)\n')
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        if tree is not None:
            env['PYTHONPATH'] = os.pathsep.join([tree, env.get('PYTHONPATH', '')])
        runs = [subprocess.run([sys.executable, '-c', code], env=env, check=True, cwd=cache,
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
    from dpn_navigator.core.planning import planning_masks
    from sim_bridge import clear_paths
    from sim_bridge.scenario import load_scenario
    calls = {'navigator': [], 'wanderers': []}

    def recording(*args, **kwargs):
        args = tuple(np.array(a) if isinstance(a, np.ndarray) else a for a in args)
        kwargs = {k: np.array(v) if isinstance(v, np.ndarray) else v
                  for k, v in kwargs.items()}
        calls['wanderers'].append((args, kwargs))
        return astar(*args, **kwargs)

    def recording_checked(blocked, start, goal, cell_cost, max_cell_cost, cut_corners):
        # Recorded as the equivalent astar call (its checks find the same largest cost).
        calls['navigator'].append(((blocked.copy(), start, goal), {
            'cell_cost': None if cell_cost is None else cell_cost.copy(),
            'cut_corners': cut_corners}))
        return saved[0](blocked, start, goal, cell_cost, max_cell_cost, cut_corners)

    saved = planning_masks.astar_checked, clear_paths.astar
    planning_masks.astar_checked, clear_paths.astar = recording_checked, recording
    try:
        for name in maps:
            run_episode(load_scenario(name), 0, wanderers, 0)
    finally:
        planning_masks.astar_checked, clear_paths.astar = saved
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


def walking_scenes(cells, resolution, boxes, scans, rng):
    """
    Poses and ranges of ``scans`` scans at 10 Hz in a hall where ``boxes`` 0.6 m boxes walk.

    The laser stands still for ten scans at a time (a robot waiting, turning, or driving slowly
    relative to the boxes), so the boxes are followed from scan to scan.
    """
    size = cells * resolution
    static = hall(size, int(size * size / 120), rng)
    seed = int(rng.integers(1 << 30))
    poses, ranges = [], []
    for step in range(scans):
        world = moving_box_world(static, step, seed, boxes=boxes)
        if step % 10 == 0:
            pose = free_pose(world, rng)
        poses.append(pose)
        ranges.append(ray_cast(world, pose))
    return poses, ranges


def bench_rule_parts(rng, rounds, scans):
    """
    Print per-scan update times of the dpn rule's parts, compiled against numpy, interleaved.

    Three rules on the same walking-box scans: the rule alone (tracks, trails and object
    memory off), with the motion tracks and trails, and the default (object memory too). Each
    scan is folded into the compiled grid (``LabelGrid``) and into ``NumpyExtrasLabelGrid``
    in turn; medians over every scan of every round, and the arrays compared after each.
    """
    default = NavigatorConfig(width=1.0, height=1.0).label_rule()
    rules = (('rule alone', dataclasses.replace(default, track_confirm_time=0.0,
                                                trail_distance=0.0, object_memory=0.0)),
             ('+ motion tracks and trails', dataclasses.replace(default, object_memory=0.0)),
             ('+ object memory (the default)', default))
    print('| LabelGrid.update per scan, dpn rule, 10 walking boxes, 640 beams, 10 Hz '
          '| cells | numpy around the kernel before [ms] | compiled [ms] | ratio '
          '| compiled / rule alone | same arrays |')
    print('|---|---|---|---|---|---|---|')
    for cells in (80, 200):
        poses, scans_ranges = walking_scenes(cells, 0.5, 10, scans, rng)
        size = cells * 0.5
        alone_ms = None
        for name, rule in rules:
            grids = (LabelGrid(size, size, 0.5, rule=rule),
                     NumpyExtrasLabelGrid(size, size, 0.5, rule=rule))
            times = ([], [])
            same = True
            for round_number in range(rounds):
                for grid in grids:
                    grid.reset()
                for k, (pose, ranges) in enumerate(zip(poses, scans_ranges)):
                    order = (0, 1) if (k + round_number) % 2 else (1, 0)
                    for which in order:
                        start = time.process_time()
                        grids[which].update(pose, ranges, ANGLE_MIN, ANGLE_INCREMENT,
                                            RANGE_MIN, RANGE_MAX, SAFETY_RADIUS,
                                            stamp=0.1 * k)
                        times[which].append(time.process_time() - start)
                    same &= bool(np.array_equal(grids[0].labels, grids[1].labels))
                    if grids[0].cell_track is not None:
                        same &= bool(np.array_equal(grids[0].cell_track,
                                                    grids[1].cell_track))
            new_ms, old_ms = (1e3 * statistics.median(spent) for spent in times)
            alone_ms = new_ms if alone_ms is None else alone_ms
            print(f'| {name} | {cells}x{cells} | {old_ms:.3f} | {new_ms:.3f} '
                  f'| {old_ms / new_ms:.1f}x | {new_ms / alone_ms:.2f} '
                  f'| {"yes" if same else "NO"} |')
    print()


def bench_start():
    """Print the kernels' cold and warm start times."""
    source_cold, source_warm = kernel_start_seconds(os.path.join(HERE, '..'))
    shipped_cold, _ = kernel_start_seconds()
    print('| kernels at process start (fresh process: import of the core, then the node warm-up) '
          '| import wall [s] | warm-up wall [s] | import CPU [s] | warm-up CPU [s] |')
    print('|---|---|---|---|---|')
    for what, times in (('cold: empty cache, nothing shipped (source tree), compiles',
                         source_cold),
                        ('warm: cache written by the cold run', source_warm),
                        ('cold: empty cache, the package on PYTHONPATH (make bench: '
                         'installed, kernels shipped by compile_kernels)', shipped_cold)):
        print(f'| {what} | ' + ' | '.join(f'{value:.2f}' for value in times) + ' |')
    started = time.perf_counter()
    warm_up_navigator()
    warm_up_map_values()
    print(f'\nThis process: kernels ready in {time.perf_counter() - started:.2f} s '
          f'(cache: {jit.cache_dir() or "numba default"})')
    print()


def bench_updates(rng, repeats):
    """Print the table of ``LabelGrid.update`` times, new against old."""
    print('| LabelGrid.update, 640 beams, 180 deg, 30 m, r = 0.6 m | scan | rule '
          '| kernel [ms] | numpy update before [ms] | ratio | labels equal '
          '| literal reference [ms] (extrapolated) | sampled cells equal |')
    print('|---|---|---|---|---|---|---|---|---|')
    rules = (('paper', PAPER_RULE), ('dpn', NavigatorConfig(width=1.0, height=1.0).label_rule()))
    for cells, resolution, runs, sample in ((200, 0.5, repeats, 400),
                                            (2000, 0.05, max(10, repeats // 10), 60)):
        for scan_kind in ('hall', 'random'):
            for rule_name, rule in rules:
                new_ms, old_ms, ref_ms, equal, mismatches = bench_update(
                    cells, resolution, scan_kind, rule, runs, sample, rng)
                literal = ('-', '-') if ref_ms is None else (
                    f'{ref_ms:,.0f}', f'{sample - mismatches}/{sample}')
                print(f'| {cells}x{cells} cells at {resolution} m | {scan_kind} | {rule_name} '
                      f'| {new_ms:.3f} | {old_ms:.3f} | {old_ms / new_ms:.1f}x '
                      f'| {"yes" if equal else "NO"} | {literal[0]} | {literal[1]} |')
    print()


def import_old_core(tree):
    """
    Import the core of another source tree of the package, beside this one.

    The tree's ``dpn_navigator`` is copied into a temporary directory as ``dpn_old_tree``
    (the core imports its own modules relatively) and imported from there.

    Returns
    -------
    module
        The old tree's ``dpn_navigator.core.mapping.label_grid``.

    """
    source = os.path.join(tree, 'dpn_navigator')
    if not os.path.isdir(os.path.join(source, 'core')):
        raise SystemExit(f'--old-tree: no dpn_navigator/core in {tree!r}')
    copy = tempfile.mkdtemp(prefix='dpn_old_tree_')
    shutil.copytree(source, os.path.join(copy, 'dpn_old_tree'),
                    ignore=shutil.ignore_patterns('__pycache__', 'kernel_cache'))
    sys.path.insert(0, copy)
    try:
        return importlib.import_module('dpn_old_tree.core.mapping.label_grid')
    except ImportError:         # a tree from before core/mapping/
        return importlib.import_module('dpn_old_tree.core.label_grid')


def bench_against_tree(tree, rng, repeats):
    """
    Print ``LabelGrid.update`` of this tree against that of ``tree``, interleaved, same scans.

    Hall scans (20 poses, each grid warmed up with all of them first); the order of the two
    alternates; labels and the rule's state compared after every update. Rule fields that
    ``tree`` lacks are not passed to it. A third grid of this tree updates with
    ``defer_evidence`` (as the node does): the time to its labels, and that of its `settle`
    after them; its arrays are compared too, once settled.
    """
    old_grid = import_old_core(tree)
    default = NavigatorConfig(width=1.0, height=1.0).label_rule()
    rules = (('paper', PAPER_RULE),
             ('dpn without tracks, trails, object memory',
              dataclasses.replace(default, track_confirm_time=0.0, trail_distance=0.0,
                                  object_memory=0.0)),
             ('dpn (the default)', default),
             ('dpn, the default without short segments in the object memory',
              dataclasses.replace(default, object_memory_short_segments=False)))
    print(f'| LabelGrid.update, hall scans, against {tree} | rule | old tree [ms] '
          '| this tree [ms] | ratio | labels ready, defer_evidence [ms] | then settle [ms] '
          '| same arrays |')
    print('|---|---|---|---|---|---|---|---|')
    for cells, resolution, runs in ((200, 0.5, repeats), (2000, 0.05, max(10, repeats // 5))):
        size = cells * resolution
        poses, scans = hall_scans(cells, resolution, 'hall', rng)
        for rule_name, rule in rules:
            # Fields the old tree does not know (rules added since) are left out; the
            # arrays then differ only where such a rule acts.
            known = {field.name for field in dataclasses.fields(old_grid.LabelRule)}
            old_rule = old_grid.LabelRule(**{name: value for name, value
                                             in dataclasses.asdict(rule).items()
                                             if name in known})
            grids = (LabelGrid(size, size, resolution, rule=rule),
                     old_grid.LabelGrid(size, size, resolution, rule=old_rule),
                     LabelGrid(size, size, resolution, rule=rule))

            def updater(grid, defer=False):
                def one_update(k):
                    grid.update(poses[k % len(poses)], scans[k % len(poses)], ANGLE_MIN,
                                ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, SAFETY_RADIUS,
                                stamp=0.1 * k, **({'defer_evidence': True} if defer else {}))
                return one_update

            for k in range(len(poses)):
                for grid in grids:
                    updater(grid)(k)
            same = True
            times = [[], [], [], []]            # this tree, old tree, labels ready, settle
            for k in range(runs):
                for index in ((0, 1, 2), (2, 1, 0), (1, 2, 0))[k % 3]:
                    start = time.process_time()
                    updater(grids[index], defer=index == 2)(k)
                    times[index].append(time.process_time() - start)
                    if index == 2:
                        start = time.process_time()
                        grids[2].settle()
                        times[3].append(time.process_time() - start)
                for other in grids[1:]:
                    for name in ('labels', 'seen_free', 'last_hit'):
                        if getattr(grids[0], name) is not None:
                            same &= bool(np.array_equal(getattr(grids[0], name),
                                                        getattr(other, name)))
                    fine = [getattr(grid, 'fine_evidence', None) for grid in (grids[0], other)]
                    if fine[0] is not None and fine[1] is not None:
                        same &= bool(np.array_equal(fine[0].seen_free, fine[1].seen_free))
            new_ms, old_ms, ready_ms, settle_ms = (1e3 * statistics.median(spent)
                                                   for spent in times)
            print(f'| {cells}x{cells} cells at {resolution} m | {rule_name} | {old_ms:.3f} '
                  f'| {new_ms:.3f} | {old_ms / new_ms:.2f}x | {ready_ms:.3f} | {settle_ms:.3f} '
                  f'| {"yes" if same else "NO"} |')
    print()


def bench_node_parts(rng, repeats):
    """Print the tables of a replan's setup and of a published map, new against old."""
    for title, same_what, bench in (
            ('per replan: masks + a short A* (after one hall scan)', 'same paths',
             bench_replan_setup),
            ('per published map: OccupancyGrid data (after one hall scan)', 'same bytes',
             bench_map_refresh)):
        print(f'| {title} | changed box [ms] | whole grid before [ms] | ratio | {same_what} |')
        print('|---|---|---|---|---|')
        for cells, resolution in ((200, 0.5), (2000, 0.5)):
            new_ms, old_ms, same = bench(cells, resolution, rng, repeats)
            print(f'| {cells}x{cells} cells | {new_ms:.3f} | {old_ms:.3f} '
                  f'| {old_ms / new_ms:.1f}x | {"yes" if same else "NO"} |')
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
    parser.add_argument('--only', choices=('start', 'rule', 'update', 'node', 'astar', 'tree'),
                        help='run one part: kernel start times, the parts of the dpn rule, '
                             'LabelGrid.update, the masks and map of the node, or astar')
    parser.add_argument('--old-tree', metavar='DIR',
                        help='also time LabelGrid.update against the package in this source '
                             'tree (such as a git worktree of an earlier commit), in the '
                             'same run; alone with --only tree')
    args = parser.parse_args(argv)
    if args.only == 'tree' and not args.old_tree:
        parser.error('--only tree needs --old-tree DIR')
    rng = np.random.default_rng(args.seed)
    if args.old_tree:
        bench_against_tree(args.old_tree, rng, 40 if args.quick else 300)
        if args.only == 'tree':
            return
    if args.only in (None, 'start'):
        bench_start()
    if args.only in (None, 'rule'):
        bench_rule_parts(rng, 3 if args.quick else 10, 100)
    if args.only in (None, 'update'):
        bench_updates(rng, 20 if args.quick else 200)
    if args.only in (None, 'node'):
        bench_node_parts(rng, 20 if args.quick else 100)
    if args.only in (None, 'astar'):
        bench_astars(rng, 20 if args.quick else 200, args.quick)


if __name__ == '__main__':
    main()
