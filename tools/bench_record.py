"""
Cost of recording a benchmark episode as a bag, and the size of the bags.

Runs the same lockstep episodes (same map, task, wanderers and seed) without and with an
`EpisodeBagRecorder`, interleaved (plain, recorded, plain, recorded, ...) in one process, and
prints per episode the median CPU time of each (the process's, so that other work on a shared
machine does not count; the episode is single-threaded), the recording's cost as the median
ratio of recorded to plain CPU time less one, the same on wall time, and the bag's size per
episode and per simulated minute. It also checks that the recorded episode's result equals the
plain one. With ``--demo-rounds N`` it also runs the ROS demo (back_and_forth, 3 wanderers)
N times without and N times with ``record``, interleaved, and prints the CPU time of all three
processes (world, navigator, monitor with its recorder) per simulated second: over DDS the
episodes differ run to run, so the cost is compared per simulated second. Not a test: it
reports numbers.

Run with ``python tools/bench_record.py [--rounds 3] [--maps back_and_forth maze]``
(after ``make build`` and ``source install/setup.bash``).

"""

import argparse
import os
from pathlib import Path
import resource
import statistics
import tempfile
import time

from dpn_navigator.benchmark.episode import run_episode, task_setup
from dpn_navigator.benchmark.episode_bag import EpisodeBagRecorder
from dpn_navigator.benchmark.runner import warm_up_kernels
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


def cpu_seconds():
    """Return the CPU time of this process and of its waited-for children [s]."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def bench_demo(rounds, scratch):
    """Run the demo plain and recorded, interleaved; print CPU per simulated second."""
    import rclpy
    from dpn_navigator.tools.demo import run_episode as run_demo
    per_second = {False: [], True: []}
    sizes = []
    for round_index in range(rounds):
        for record in (False, True):
            bag = Path(scratch) / f'demo_{round_index}' if record else None
            started = cpu_seconds()
            _, episode, context, _ = run_demo(
                'back_and_forth', 0, 3, round_index, real_time_factor=10.0,
                domain_id=60 + round_index % 10, log_dir=Path(scratch) / 'logs', record=bag)
            rclpy.try_shutdown(context=context)
            per_second[record].append((cpu_seconds() - started) / episode.sim_time)
            if record:
                sizes.append(folder_size(bag) / 1e6 / (episode.sim_time / 60.0))
            print(f'# demo round {round_index}, record {record}: {episode.sim_time:.1f} s '
                  f'simulated, {per_second[record][-1]:.3f} CPU s per simulated s', flush=True)
    plain, recorded = statistics.median(per_second[False]), statistics.median(per_second[True])
    print(f'\ndemo, {rounds} rounds interleaved, medians: {plain:.3f} CPU s per simulated s '
          f'plain, {recorded:.3f} recorded: cost {100 * (recorded / plain - 1):+.1f} %; bag '
          f'{statistics.median(sizes):.2f} MB per simulated min')


def main():
    """Run the benchmark and print a Markdown table."""
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--maps', nargs='*', default=['back_and_forth', 'maze', 'warehouse'],
                        help='maps of the lockstep episodes (none: the demo only)')
    parser.add_argument('--task', type=int, default=0)
    parser.add_argument('--wanderers', type=int, default=5)
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--rounds', type=int, default=3)
    parser.add_argument('--demo-rounds', type=int, default=0,
                        help='also time the ROS demo this many times each way')
    args = parser.parse_args()
    warm_up_kernels('labels')
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        if args.demo_rounds:
            bench_demo(args.demo_rounds, scratch)
        for name in args.maps:
            scenario = load_scenario(name)
            rows.append(bench_episode(scenario, args.task, args.wanderers, args.seed,
                                      args.rounds, scratch))
            print(f'# done {name}', flush=True)
    if not rows:
        return
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
