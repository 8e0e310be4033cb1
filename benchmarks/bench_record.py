"""
Cost of recording a benchmark episode as a bag, and the size of the bags.

Runs the same lockstep episodes (same map, task, wanderers and seed) without and with an
`EpisodeBagRecorder`, interleaved (plain, recorded, plain, recorded, ...) in one process, and
prints per episode the median CPU time of each (the process's, so that other work on a shared
machine does not count; the episode is single-threaded), the recording's cost as the median
ratio of recorded to plain CPU time less one, the same on wall time, and the bag's size per
episode and per simulated minute. It also checks that the recorded episode's result equals the
plain one. Not a test: it reports numbers.

Run with ``python benchmarks/bench_record.py [--rounds 3] [--maps back_and_forth maze]``
(after ``make build`` and ``source install/setup.bash``).

"""

import argparse
import os
from pathlib import Path
import statistics
import tempfile
import time

from dpn_navigator.benchmark.episode import run_episode, task_setup
from dpn_navigator.benchmark.episode_bag import EpisodeBagRecorder
from dpn_navigator.core import jit
from sim_bridge.scenario import load_scenario


def folder_size(path):
    """Return the size of the files in a folder [bytes]."""
    return sum(f.stat().st_size for f in Path(path).iterdir() if f.is_file())


def bench_episode(scenario, task, wanderers, seed, rounds, scratch):
    """Time one episode plain and recorded, interleaved; return a dict of results."""
    setup = task_setup(scenario, task)
    plain, recorded, plain_wall, recorded_wall, sizes = [], [], [], [], []
    results = set()
    for round_index in range(rounds):
        started, wall = time.process_time(), time.perf_counter()
        results.add(run_episode(scenario, task, wanderers, seed, setup=setup))
        plain.append(time.process_time() - started)
        plain_wall.append(time.perf_counter() - wall)
        bag = Path(scratch) / f'{scenario.name}_{task}_{wanderers}_{round_index}'
        started, wall = time.process_time(), time.perf_counter()
        with EpisodeBagRecorder(bag) as recorder:
            result = run_episode(scenario, task, wanderers, seed, setup=setup,
                                 recorder=recorder)
        recorded.append(time.process_time() - started)
        recorded_wall.append(time.perf_counter() - wall)
        results.add(result)
        sizes.append(folder_size(bag))
    return {
        'episode': f'{scenario.name} task {task}, {wanderers} wanderers',
        'sim_time': result.time,
        'plain': statistics.median(plain),
        'recorded': statistics.median(recorded),
        'cost': statistics.median([r / p for p, r in zip(plain, recorded)]) - 1.0,
        'wall_cost': statistics.median(
            [r / p for p, r in zip(plain_wall, recorded_wall)]) - 1.0,
        'bag_mb': statistics.median(sizes) / 1e6,
        'mb_per_min': statistics.median(sizes) / 1e6 / (result.time / 60.0),
        'same_result': len(results) == 1,
    }


def main():
    """Run the benchmark and print a Markdown table."""
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--maps', nargs='+', default=['back_and_forth', 'maze', 'warehouse'])
    parser.add_argument('--task', type=int, default=0)
    parser.add_argument('--wanderers', type=int, default=5)
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--rounds', type=int, default=3)
    args = parser.parse_args()
    jit.warm_up()
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for name in args.maps:
            scenario = load_scenario(name)
            rows.append(bench_episode(scenario, args.task, args.wanderers, args.seed,
                                      args.rounds, scratch))
            print(f'# done {name}', flush=True)
    print(f'\n{args.rounds} rounds, interleaved; medians; {os.cpu_count()} CPUs\n')
    print('| episode | simulated [s] | plain CPU [s] | recorded CPU [s] | cost (CPU) | '
          'cost (wall) | bag [MB] | MB per simulated min | same result |')
    print('|---|---|---|---|---|---|---|---|---|')
    for row in rows:
        print(f"| {row['episode']} | {row['sim_time']:.1f} | {row['plain']:.2f} | "
              f"{row['recorded']:.2f} | {100 * row['cost']:+.1f} % | "
              f"{100 * row['wall_cost']:+.1f} % | {row['bag_mb']:.2f} | "
              f"{row['mb_per_min']:.2f} | {'yes' if row['same_result'] else 'NO'} |")


if __name__ == '__main__':
    main()
