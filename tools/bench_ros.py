"""
Benchmark of the two nodes over ROS 2: simulator speed and scan-to-map latency.

1. The simulator's real-time factor: the world alone in-process (``World.advance``, no ROS),
   and the ``pybullet_world`` node as a process running as fast as it can
   (``real_time_factor`` 1000), headless, back_and_forth, 640-beam scans at 10 Hz, pinned to
   one core. Simulated seconds per wall second, from ``/sim/status``.
2. The dpn node's scan-to-map latency: a probe publishes odometry and a ray-cast 640-beam scan
   at 10 Hz to the ``dpn`` process (a 100 m hall with 160 boxes and 10 walking 0.6 m boxes,
   the laser standing still for ten scans at a time; 200x200 cells of 0.5 m and 2000x2000 of
   0.05 m) and times the ``/compabot/map`` (or ``/compabot/map_updates``) that answers, wall
   clock, both ends in this machine's loopback DDS, at two ends: the probe's callback (its
   own rclpy executor included, 0.3-0.6 ms) and the reception time the probe's middleware
   stamps the message with (``MessageInfo.received_timestamp``). Node variants run in turn,
   alternating, ``--rounds`` times: the default, the dpn rule without its motion tracks,
   trails and object memory, the markers on every replan (``marker_min_period`` 0), the full
   map every second with the changed cells on ``map_updates`` in between, and with
   ``--old-tree DIR`` the default and the ``map_updates`` variant of another source tree of
   the package (the code before a change, from ``git worktree add`` or ``git archive``),
   imported instead of the installed one.

Not a test: it prints Markdown tables. Run with ``make bench-ros`` (``BENCH_ROS_ARGS``), or
``python tools/bench_ros.py [--latency-only] [--cells 200 2000] [--old-tree DIR]``.

"""

import argparse
import math
import os
from pathlib import Path
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / 'test'))

from diagnostic_msgs.msg import DiagnosticStatus  # noqa: E402, I100
from dpn_navigator.ros.conversions import make_laser_scan, pose_to_odometry  # noqa: E402
from dpn_navigator.ros.qos import COMMAND_QOS, LATCHED_QOS, SENSOR_QOS  # noqa: E402
from dpn_navigator.tools.demo import (installed_executable, ros_environment,  # noqa: E402
                                      stop_nodes)
from map_msgs.msg import OccupancyGridUpdate  # noqa: E402
from nav_msgs.msg import OccupancyGrid, Odometry  # noqa: E402
import numpy as np  # noqa: E402
import rclpy  # noqa: E402
from rclpy.context import Context  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from scan_scenes import (ANGLE_INCREMENT, ANGLE_MIN, free_pose, hall,  # noqa: E402
                         moving_box_world, RANGE_MAX, RANGE_MIN, ray_cast)
from sensor_msgs.msg import LaserScan  # noqa: E402
from sim_bridge.scenario import load_scenario  # noqa: E402
from sim_bridge.world import World, WorldConfig  # noqa: E402

CORE = 0
#: Node arguments of the variants timed against each other.
VARIANTS = {
    'default': (),
    'without tracks, trails, object memory': (
        'track_confirm_time:=0.0', 'trail_distance:=0.0', 'object_memory:=0.0'),
    'markers on every replan': ('marker_min_period:=0.0',),
    'full map every 1 s, map_updates between': ('map_publish_period:=1.0',),
}


def pin_to_one_core():
    """Run the calling (child) process on one core only."""
    os.sched_setaffinity(0, {CORE})


def world_rtf(wanderers, simulated=60.0):
    """Return simulated seconds per wall second of ``World.advance`` alone, no ROS."""
    with World(load_scenario('back_and_forth'), WorldConfig(n_wanderers=wanderers)) as world:
        world.scan()
        start = time.perf_counter()
        while world.time < simulated:
            world.advance(0.3, 0.2)
        return world.time / (time.perf_counter() - start)


def node_rtf(wanderers, domain_id, log_dir, seconds=15.0):
    """Return the real-time factor of the ``pybullet_world`` process, run flat out."""
    context = Context()
    rclpy.init(context=context, domain_id=domain_id)
    node = Node('rtf_probe', context=context)
    samples = []
    node.create_subscription(
        DiagnosticStatus, '/compabot/sim/status',
        lambda msg: samples.append((time.monotonic(), float(
            {kv.key: kv.value for kv in msg.values}['time']))), LATCHED_QOS)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    command = [str(installed_executable('sim_bridge', 'pybullet_world')), '--ros-args',
               '-p', f'wanderers:={wanderers}', '-p', 'real_time_factor:=1000.0']
    with open(Path(log_dir) / f'pybullet_world_{wanderers}.log', 'w') as log:
        process = subprocess.Popen(command, env=ros_environment(domain_id), stdout=log,
                                   stderr=subprocess.STDOUT, preexec_fn=pin_to_one_core)
    try:
        deadline = time.monotonic() + seconds + 20.0
        while time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)
            # Skip start-up: measure over the last `seconds` once the stream runs.
            if samples and samples[-1][0] - samples[0][0] > seconds:
                break
    finally:
        stop_nodes({'pybullet_world': process})
        node.destroy_node()
        rclpy.try_shutdown(context=context)
    first = next(s for s in samples if s[0] - samples[0][0] > 2.0)
    last = samples[-1]
    return (last[1] - first[1]) / (last[0] - first[0])


class LatencyProbe(Node):
    """Send scans to the dpn node and time the maps that answer."""

    def __init__(self, context):
        super().__init__('latency_probe', context=context)
        self.scan_pub = self.create_publisher(LaserScan, '/compabot/scan', SENSOR_QOS)
        self.odom_pub = self.create_publisher(Odometry, '/compabot/odom', SENSOR_QOS)
        self.create_subscription(OccupancyGrid, '/compabot/map', self.on_map, LATCHED_QOS)
        self.create_subscription(OccupancyGridUpdate, '/compabot/map_updates', self.on_map,
                                 COMMAND_QOS)
        self.create_subscription(DiagnosticStatus, '/compabot/status', self.on_status,
                                 LATCHED_QOS)
        self.status = {}
        self.sent = {}
        self.latencies = []
        self.reception_latencies = []

    def on_status(self, msg):
        """Keep the dpn node's latest status values."""
        self.status = {kv.key: kv.value for kv in msg.values}

    def send_scan(self, scan):
        """Publish a scan and note when: this clock and the system clock."""
        self.sent[(scan.header.stamp.sec, scan.header.stamp.nanosec)] = (
            time.perf_counter(), time.time_ns())
        self.scan_pub.publish(scan)

    def on_map(self, msg, info):
        """
        Match a map or map update to its scan by stamp and record the latencies [s].

        Two ends: this callback (``latencies``, this process's executor included), and the
        time this subscription's middleware received the message (``reception_latencies``,
        ``MessageInfo.received_timestamp``, system clock; NaN when the RMW leaves it 0).
        """
        called = time.perf_counter()
        key = (msg.header.stamp.sec, msg.header.stamp.nanosec)
        if key not in self.sent:
            return
        sent, sent_ns = self.sent.pop(key)
        self.latencies.append(called - sent)
        received_ns = info.get('received_timestamp') or 0
        self.reception_latencies.append(1e-9 * (received_ns - sent_ns) if received_ns
                                        else math.nan)


def start_probe(domain_id):
    """Return ``(context, probe, executor)``: a `LatencyProbe` in a context of its own."""
    context = Context()
    rclpy.init(context=context, domain_id=domain_id)
    probe = LatencyProbe(context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(probe)
    return context, probe, executor


def walking_scans(count=100):
    """Poses and ranges of ``count`` scans: a 100 m hall, 160 boxes, 10 walking boxes."""
    rng = np.random.default_rng(0)
    static = hall(100.0, 160, rng)
    poses, ranges = [], []
    for step in range(count):
        world = moving_box_world(static, step, 7, boxes=10)
        if step % 10 == 0:
            pose = free_pose(world, rng)
        poses.append(pose)
        ranges.append(ray_cast(world, pose))
    return poses, ranges


def dpn_command(tree=None):
    """
    Return the command that starts the dpn node: the installed one, or that of ``tree``.

    A source tree's node module is found where that tree keeps it (``ros/dpn_node.py``, or
    ``dpn_node.py`` in a tree from before the restructuring), so an old tree runs as well.
    """
    if tree is None:
        return [str(installed_executable('dpn_navigator', 'dpn'))]
    module = ('dpn_navigator.ros.dpn_node'
              if (Path(tree) / 'dpn_navigator' / 'ros' / 'dpn_node.py').is_file()
              else 'dpn_navigator.dpn_node')
    return [sys.executable, '-c', f'import sys; sys.path.insert(0, {str(tree)!r}); '
            f'from {module} import main; sys.exit(main())']


def scan_to_map_latency(domain_id, log_dir, scenes, cells=200, node_args=(), tree=None,
                        scans=300, rate=10.0):
    """
    Time the dpn process's scan-to-map latency on a 100 m map of ``cells`` x ``cells``.

    Parameters
    ----------
    domain_id : int
        The DDS domain of the probe and the node.
    log_dir : str
        Where the node's output goes (``dpn.log``, appended).
    scenes : (poses, ranges)
        From `walking_scans`, sent in turn.
    cells : int
        Grid side: the 100 m map at ``100 / cells`` m.
    node_args : sequence of str
        Extra ``name:=value`` parameters of the node.
    tree : str, optional
        A source tree whose ``dpn_navigator`` the node imports instead of the installed one.
    scans : int
        Scans sent.
    rate : float
        Scans per second [Hz].

    Returns
    -------
    latencies : list of float
        Scan published to its map or map update received, per scan [ms]: in the probe's
        callback.
    reception_latencies : list of float
        The same to the probe's middleware receiving it (``received_timestamp``) [ms].
    in_node : float
        The node's own median from scan callback to map published, from its status [ms].

    """
    poses, ranges = scenes
    context, probe, executor = start_probe(domain_id)
    command = dpn_command(tree) + ['--ros-args', '-p', 'map_width:=100.0',
                                   '-p', 'map_height:=100.0',
                                   '-p', f'resolution:={100.0 / cells!r}']
    for argument in node_args:
        command += ['-p', argument]
    env = ros_environment(domain_id)
    if tree is not None:
        env['PYTHONPATH'] = os.pathsep.join([str(tree), env.get('PYTHONPATH', '')])
    with open(Path(log_dir) / 'dpn.log', 'a') as log:
        process = subprocess.Popen(command, env=env, stdout=log, stderr=subprocess.STDOUT)
    try:
        deadline = time.monotonic() + 60.0
        while probe.scan_pub.get_subscription_count() == 0 and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)
        settle = time.monotonic() + 1.0                # discovery both ways
        while time.monotonic() < settle:
            executor.spin_once(timeout_sec=0.05)
        for k in range(scans):
            stamp = probe.get_clock().now().to_msg()
            pose = poses[k % len(poses)]
            probe.odom_pub.publish(pose_to_odometry(pose, (0.0, 0.0), stamp))
            executor.spin_once(timeout_sec=0.01)       # let odometry land first
            scan = make_laser_scan(ranges[k % len(poses)], ANGLE_MIN, ANGLE_INCREMENT,
                                   RANGE_MIN, RANGE_MAX, stamp)
            probe.send_scan(scan)
            next_scan = time.monotonic() + 1.0 / rate
            while time.monotonic() < next_scan:
                executor.spin_once(timeout_sec=max(0.0, next_scan - time.monotonic()))
        deadline = time.monotonic() + 2.0            # the 1 Hz status refresh
        while time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)
    finally:
        stop_nodes({'dpn': process})
        probe.destroy_node()
        rclpy.try_shutdown(context=context)
    in_node = float(probe.status.get('scan_to_map_ms_median') or 'nan')
    # Skip the warm-up.
    return ([1e3 * latency for latency in probe.latencies[5:]],
            [1e3 * latency for latency in probe.reception_latencies[5:]], in_node)


def first_map_seconds(domain_id, log_dir, scenes, tree=None):
    """
    Time a ``dpn`` process's start, with an empty numba cache, to its first map [s].

    The probe sends odometry and a scan every 0.1 s from the process's start on. ``tree``: a
    source tree imported instead of the installed package (which may ship compiled kernels,
    ``compile_kernels``). Returns ``(first map, node ready, kernels ready)`` [s]: the first
    map received, the node's "dpn ready" log line (its ROS time against the start's system
    time), and the warm-up time the node logs.
    """
    poses, ranges = scenes
    context, probe, executor = start_probe(domain_id)
    env = ros_environment(domain_id)
    env['NUMBA_CACHE_DIR'] = tempfile.mkdtemp(prefix='dpn_cold_cache_')
    if tree is not None:
        env['PYTHONPATH'] = os.pathsep.join([str(tree), env.get('PYTHONPATH', '')])
    log_path = Path(log_dir) / f'dpn_cold_{len(os.listdir(log_dir))}.log'
    started = time.perf_counter()
    started_system = time.time()
    with open(log_path, 'w') as log:
        process = subprocess.Popen(
            dpn_command(tree) + ['--ros-args', '-p', 'map_width:=100.0', '-p',
                                 'map_height:=100.0'], env=env, stdout=log,
            stderr=subprocess.STDOUT)
    try:
        k = 0
        while not probe.latencies and time.perf_counter() - started < 120.0:
            stamp = probe.get_clock().now().to_msg()
            probe.odom_pub.publish(pose_to_odometry(poses[k % len(poses)], (0.0, 0.0), stamp))
            executor.spin_once(timeout_sec=0.01)
            probe.send_scan(make_laser_scan(ranges[k % len(poses)], ANGLE_MIN,
                                            ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, stamp))
            k += 1
            deadline = time.monotonic() + 0.1
            while not probe.latencies and time.monotonic() < deadline:
                executor.spin_once(timeout_sec=0.02)
        first_map = time.perf_counter() - started
    finally:
        stop_nodes({'dpn': process})
        probe.destroy_node()
        rclpy.try_shutdown(context=context)
        shutil.rmtree(env['NUMBA_CACHE_DIR'], ignore_errors=True)
    ready = node_ready = math.nan
    for line in log_path.read_text().splitlines():
        if 'kernels ready in' in line:
            ready = float(line.split('kernels ready in')[1].split()[0])
            node_ready = float(line.split('[')[2].split(']')[0]) - started_system
    return first_map, node_ready, ready


def cold_start_table(domain_id, log_dir):
    """Print the node's start to first map with an empty cache, shipped kernels or none."""
    scenes = walking_scans(10)
    print('| dpn process start, empty NUMBA_CACHE_DIR, 200x200 cells | first map received [s] '
          '| node ready (its log) [s] | of which kernels ready [s] |')
    print('|---|---|---|---|')
    for name, tree in (('installed package, kernels shipped (compile_kernels)', None),
                       ('source tree, nothing shipped: compiles', HERE.parent)):
        first_map, node_ready, ready = first_map_seconds(domain_id, log_dir, scenes, tree)
        print(f'| {name} | {first_map:.2f} | {node_ready:.2f} | {ready:.2f} |')
    print()


def latency_tables(domain_id, log_dir, cells_list, rounds, scans, old_tree):
    """Print the scan-to-map latency of every variant, alternated, per grid size."""
    scenes = walking_scans(scans)          # none repeats: every scan changes some cells
    variants = [(name, args, None) for name, args in VARIANTS.items()]
    if old_tree:
        variants.append(('default, old tree', (), old_tree))
        variants.append(('full map every 1 s, map_updates between, old tree',
                         VARIANTS['full map every 1 s, map_updates between'], old_tree))
    for cells in cells_list:
        results = {name: [] for name, _, _ in variants}
        for round_number in range(rounds):
            order = variants if round_number % 2 == 0 else variants[::-1]
            for name, args, tree in order:
                results[name].append(scan_to_map_latency(
                    domain_id, log_dir, scenes, cells, args, tree, scans))
        print(f'| dpn scan-to-map, {cells}x{cells} cells, 640 beams at 10 Hz, 10 walking boxes '
              '| scans | over ROS median [ms], per round | all rounds: median / 90 % / 99 % '
              "[ms] | to the probe's middleware: median / 90 % [ms] "
              '| in the node (its status), per round [ms] |')
        print('|---|---|---|---|---|---|')
        for name, _, _ in variants:
            runs = results[name]
            every = [latency for latencies, _, _ in runs for latency in latencies]
            received = [latency for _, latencies, _ in runs for latency in latencies]
            quantiles = np.percentile(every, [50, 90, 99]) if every else [math.nan] * 3
            reception = np.percentile(received, [50, 90]) if received else [math.nan] * 2
            medians = [statistics.median(latencies or [math.nan]) for latencies, _, _ in runs]
            print(f'| {name} | {len(every)} '
                  f'| {" / ".join(f"{median:.2f}" for median in medians)} '
                  f'| {quantiles[0]:.2f} / {quantiles[1]:.2f} / {quantiles[2]:.2f} '
                  f'| {reception[0]:.2f} / {reception[1]:.2f} '
                  f'| {" / ".join(f"{in_node:.2f}" for _, _, in_node in runs)} |')
        print()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--domain-id', type=int,
                        default=int(os.environ.get('ROS_DOMAIN_ID') or 77))
    parser.add_argument('--latency-only', action='store_true',
                        help='skip the simulator real-time factors')
    parser.add_argument('--cells', type=int, nargs='*', default=[200, 2000],
                        help='grid sides of the latency runs (a 100 m map)')
    parser.add_argument('--rounds', type=int, default=2, help='alternations of the variants')
    parser.add_argument('--scans', type=int, default=300, help='scans per latency run')
    parser.add_argument('--old-tree', help='a source tree of the package to time as well')
    parser.add_argument('--cold-start', action='store_true',
                        help='also time a node start to its first map with an empty cache')
    args = parser.parse_args(argv)
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    log_dir = tempfile.mkdtemp(prefix='dpn_bench_ros_')
    if not args.latency_only:
        os.sched_setaffinity(0, {CORE})
        print('| simulator, back_and_forth, 640 beams at 10 Hz, 50 Hz physics, one core '
              '| 0 wanderers | 10 wanderers |')
        print('|---|---|---|')
        print(f'| World.advance in-process (no ROS) | {world_rtf(0):.1f}x '
              f'| {world_rtf(10):.1f}x |')
        os.sched_setaffinity(0, set(range(os.cpu_count())))
        print(f'| pybullet_world node, publishing scan, odom, /clock | '
              f'{node_rtf(0, args.domain_id, log_dir):.1f}x '
              f'| {node_rtf(10, args.domain_id, log_dir):.1f}x |')
        print()
    if args.cold_start:
        cold_start_table(args.domain_id, log_dir)
    latency_tables(args.domain_id, log_dir, args.cells, args.rounds, args.scans,
                   args.old_tree)
    print(f'(process logs: {log_dir})')


if __name__ == '__main__':
    main()
