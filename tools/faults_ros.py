"""
Fault measurements of the node processes: how fast the robot stops, and how cleanly they exit.

1. Stop time: from the last sensor message to the first zero ``cmd_vel``, wall clock, 20
   trials each: (a) a ``dpn`` process on wall time fed by a stand-in simulator in this
   process, which then stops its scans and odometry; (b) the same on simulated time, the
   stand-in's ``/clock`` running on; (c) a real ``pybullet_world`` process killed with SIGKILL
   while the robot drives (the last message being the last one this process heard from the
   world), the ``dpn`` process (``use_sim_time``) running through all the world's restarts.
2. Exits: world + navigator pairs, busy, five at a time; each process gets SIGINT or SIGTERM;
   the exit code and whether the log holds a traceback.
3. Exits during start-up: a lone ``dpn`` or ``pybullet_world`` process gets SIGINT or SIGTERM
   at a random moment 0.2 to 3 s after its start (imports, kernel warm-up, the first
   callbacks); the exit code and whether its output holds a traceback.

Not a test: it prints min / median / max and counts. ``make faults`` (``FAULTS_ARGS``:
``--trials N``).

"""

import argparse
import contextlib
import os
from pathlib import Path
import signal
import statistics
import subprocess
import sys
import tempfile
import time

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / 'test'))

from dpn_navigator.ros.qos import COMMAND_QOS, SENSOR_QOS  # noqa: E402
from dpn_navigator.tools.demo import (installed_executable,  # noqa: E402, I100
                                      navigator_arguments, ros_environment, start_nodes,
                                      stop_nodes)
from geometry_msgs.msg import Twist  # noqa: E402
from nav_msgs.msg import Odometry  # noqa: E402
import rclpy  # noqa: E402
from rclpy.context import Context  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from sensor_msgs.msg import LaserScan  # noqa: E402
from sim_bridge.scenario import load_scenario  # noqa: E402
from sim_stand_in import SimulatorStandIn  # noqa: E402

ALL_STREAMS = ('clock', 'odometry', 'scan')
PARTS = ('wall', 'sim', 'kill', 'exits', 'startup')


def spin_for(executor, seconds, tick=None):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if tick is not None:
            tick()
        executor.spin_once(timeout_sec=0.02)


def first_zero_after(commands, since):
    return next((t - since for t, linear, angular in commands
                 if t >= since and linear == angular == 0.0), None)


def start_process(package, name, args, domain_id, log_path):
    """Start an installed executable in its own session, its output to ``log_path``."""
    with open(log_path, 'w') as log:
        return subprocess.Popen([str(installed_executable(package, name))] + args,
                                env=ros_environment(domain_id), stdout=log,
                                stderr=subprocess.STDOUT, start_new_session=True)


def start_dpn(domain_id, log_path, sim_time):
    args = ['--ros-args', '-p', 'map_width:=12.0', '-p', 'map_height:=12.0',
            '-p', 'use_default_goal:=true', '-p', 'goal_x:=10.0', '-p', 'goal_y:=6.0',
            '-p', 'laser_x:=0.0',
            '-p', f'use_sim_time:={str(sim_time)}']
    return start_process('dpn_navigator', 'dpn', args, domain_id, log_path)


@contextlib.contextmanager
def node_in_domain(node_class, domain_id):
    """Yield ``(node, executor)`` for a node of this process in a context of its own."""
    context = Context()
    rclpy.init(context=context, domain_id=domain_id)
    node = node_class(context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    try:
        yield node, executor
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown(context=context)


def stand_in_trials(trials, domain_id, log_dir, sim_time):
    """Stop times [s] with the stand-in simulator; None where no zero command came."""
    process = start_dpn(domain_id, log_dir / f'dpn_sim{sim_time}.log', sim_time)
    times = []
    with node_in_domain(SimulatorStandIn, domain_id) as (probe, executor):
        try:
            deadline = time.monotonic() + 60.0
            while probe.scan_pub.get_subscription_count() == 0 and time.monotonic() < deadline:
                spin_for(executor, 0.1)
            for _ in range(trials):
                spin_for(executor, 1.0, lambda: probe.tick(ALL_STREAMS))
                last = probe.tick(ALL_STREAMS)
                remaining = ('clock',) if sim_time else ()
                spin_for(executor, 1.0, lambda: probe.tick(remaining))
                times.append(first_zero_after(probe.commands, last))
                probe.commands.clear()
        finally:
            stop_nodes({'dpn': process})
    return times


class WorldWatcher(Node):
    """Note when the world was last heard from and what the navigator commands."""

    def __init__(self, context):
        super().__init__('world_watcher', context=context)
        self.last_heard = None
        self.commands = []
        for msg_type, topic, qos in ((Clock, '/clock', COMMAND_QOS),
                                     (Odometry, '/compabot/odom', SENSOR_QOS),
                                     (LaserScan, '/compabot/scan', SENSOR_QOS)):
            self.create_subscription(msg_type, topic, self.on_world, qos)
        self.create_subscription(Twist, '/compabot/cmd_vel', self.on_cmd, COMMAND_QOS)

    def on_world(self, msg):
        self.last_heard = time.monotonic()

    def on_cmd(self, msg):
        self.commands.append((time.monotonic(), msg.linear.x, msg.angular.z))


def commands_after_stop(commands, since, late=0.5):
    """
    Count the non-zero commands after the first zero one and more than ``late`` after ``since``.

    Returns
    -------
    after_stop, after_late : int

    """
    stop = next((t for t, linear, angular in commands
                 if t >= since and linear == angular == 0.0), None)
    moving = [t for t, linear, angular in commands if (linear, angular) != (0.0, 0.0)]
    after_stop = 0 if stop is None else sum(1 for t in moving if t > stop)
    return after_stop, sum(1 for t in moving if t > since + late)


def world_kill_trials(trials, domain_id, log_dir, moving_after=None):
    """
    Stop times [s] after SIGKILL of the world; None where no zero command came.

    ``moving_after``, a list, gets per trial the `commands_after_stop` counts.
    """
    scenario = load_scenario('back_and_forth')
    dpn = start_process('dpn_navigator', 'dpn', navigator_arguments(scenario, 0), domain_id,
                        log_dir / 'dpn_world_kill.log')
    times = []
    with node_in_domain(WorldWatcher, domain_id) as (watcher, executor):
        try:
            for trial in range(trials):
                world = start_process(
                    'sim_bridge', 'pybullet_world',
                    ['--ros-args', '-p', 'wanderers:=3', '-p', f'seed:={trial}'], domain_id,
                    log_dir / f'world_{trial}.log')
                watcher.last_heard = None
                deadline = time.monotonic() + 60.0
                while time.monotonic() < deadline and not (
                        watcher.last_heard is not None and any(
                            (linear, angular) != (0.0, 0.0) for _, linear, angular
                            in watcher.commands[-5:])):
                    spin_for(executor, 0.1)
                spin_for(executor, 1.0)
                os.kill(world.pid, signal.SIGKILL)
                world.wait()
                spin_for(executor, 1.0)
                times.append(None if watcher.last_heard is None else first_zero_after(
                    watcher.commands, watcher.last_heard))
                if moving_after is not None and watcher.last_heard is not None:
                    moving_after.append(commands_after_stop(watcher.commands,
                                                            watcher.last_heard))
                watcher.commands.clear()
        finally:
            stop_nodes({'dpn': dpn})
    return times


def exit_trials(per_signal, domain_id, log_dir, batch_size=5):
    """Return ``{signal name: [(exit code, traceback in log), ...]}``."""
    outcomes = {'SIGINT': [], 'SIGTERM': []}
    pairs_needed = per_signal       # each pair: one SIGINT and one SIGTERM
    batch = 0
    while pairs_needed > 0:
        pairs = []
        for index in range(min(batch_size, pairs_needed)):
            pair_dir = log_dir / f'exit_{batch}_{index}'
            pairs.append((pair_dir, start_nodes('back_and_forth', 0, 3, index, 2.0, domain_id,
                                                pair_dir)[1]))
        deadline = time.monotonic() + 60.0
        while time.monotonic() < deadline and not all(
                (pair_dir / f'{name}.log').exists() and marker in (
                    pair_dir / f'{name}.log').read_text()
                for pair_dir, _ in pairs for name, marker in (
                    ('dpn', 'dpn ready'), ('pybullet_world', 'real-time factor'))):
            time.sleep(0.1)
        time.sleep(1.5)
        signalled = []
        for index, (pair_dir, processes) in enumerate(pairs):
            dpn_signal = signal.SIGINT if index % 2 == 0 else signal.SIGTERM
            world_signal = signal.SIGTERM if dpn_signal == signal.SIGINT else signal.SIGINT
            for name, signum in (('dpn', dpn_signal), ('pybullet_world', world_signal)):
                os.killpg(processes[name].pid, signum)
                signalled.append((pair_dir / f'{name}.log', signum, processes[name]))
        for log, signum, process in signalled:
            try:
                code = process.wait(15.0)
            except subprocess.TimeoutExpired:
                code = None
            outcomes[signal.Signals(signum).name].append(
                (code, 'Traceback' in log.read_text()))
        for _, processes in pairs:
            stop_nodes(processes)
        pairs_needed -= len(pairs)
        batch += 1
    return outcomes


def startup_exit_trials(per_signal, domain_id, log_dir, earliest=0.2, latest=3.0, seed=0):
    """
    Return ``{signal name: [(exit code, traceback in log, delay), ...]}``: signals at start-up.

    Each trial starts one process (``dpn`` and ``pybullet_world`` in turn) and sends it
    SIGINT or SIGTERM after a delay drawn uniformly from ``[earliest, latest]`` [s].

    """
    import random
    draw = random.Random(seed)
    outcomes = {'SIGINT': [], 'SIGTERM': []}
    for trial in range(2 * per_signal):
        signum = signal.SIGINT if trial % 2 == 0 else signal.SIGTERM
        package, name = (('dpn_navigator', 'dpn') if trial % 4 < 2
                         else ('sim_bridge', 'pybullet_world'))
        log = log_dir / f'startup_{trial}_{name}.log'
        process = start_process(package, name, [], domain_id, log)
        delay = draw.uniform(earliest, latest)
        time.sleep(delay)
        os.kill(process.pid, signum)
        try:
            code = process.wait(15.0)
        except subprocess.TimeoutExpired:
            code = None
            stop_nodes({name: process})
        outcomes[signal.Signals(signum).name].append(
            (code, 'Traceback' in log.read_text(), delay))
    return outcomes


def summary(name, times):
    measured = [t for t in times if t is not None]
    if not measured:
        return f'{name}: no zero command in {len(times)} trials'
    within = sum(1 for t in measured if t <= 0.5)
    return (f'{name}: {within}/{len(times)} within 0.5 s; min {min(measured):.3f} s, median '
            f'{statistics.median(measured):.3f} s, max {max(measured):.3f} s; all: '
            + ' '.join('-' if t is None else f'{t:.3f}' for t in times))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--trials', type=int, default=20)
    parser.add_argument('--domain-id', type=int, default=93)
    parser.add_argument('--parts', nargs='+', default=PARTS, choices=PARTS)
    args = parser.parse_args(argv)
    log_dir = Path(tempfile.mkdtemp(prefix='dpn_faults_'))
    if 'wall' in args.parts:
        print(summary('stop, sensors stop, wall time', stand_in_trials(
            args.trials, args.domain_id, log_dir, sim_time=False)), flush=True)
    if 'sim' in args.parts:
        print(summary('stop, sensors stop, sim time', stand_in_trials(
            args.trials, args.domain_id, log_dir, sim_time=True)), flush=True)
    if 'kill' in args.parts:
        moving_after = []
        print(summary('stop, world killed (SIGKILL)', world_kill_trials(
            args.trials, args.domain_id, log_dir, moving_after)), flush=True)
        print(f'non-zero commands after the first zero one: '
              f'{sum(after for after, _ in moving_after)}; more than 0.5 s after the last '
              f'world message: {sum(late for _, late in moving_after)} (in '
              f'{len(moving_after)} trials)', flush=True)
    if 'exits' in args.parts:
        for name, results in exit_trials(args.trials, args.domain_id, log_dir).items():
            clean = sum(1 for code, traceback in results if code == 0 and not traceback)
            print(f'{name}: {clean}/{len(results)} clean exits (exit code 0, no traceback); '
                  f'codes {sorted({code for code, _ in results}, key=str)}')
    if 'startup' in args.parts:
        for name, results in startup_exit_trials(args.trials, args.domain_id, log_dir).items():
            clean = sum(1 for code, traceback, _ in results if code == 0 and not traceback)
            unclean = ', '.join(f'{delay:.2f} s: exit {code}{" traceback" * traceback}'
                                for code, traceback, delay in results
                                if code != 0 or traceback)
            print(f'{name} at start-up (0.2-3 s): {clean}/{len(results)} clean exits'
                  + (f'; not clean: {unclean}' if unclean else ''), flush=True)
    print(f'logs: {log_dir}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
