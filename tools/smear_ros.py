"""
Smear under load: wall cells ever labelled mobile at 1x and at a faster real-time factor.

Both nodes run as processes (``pybullet_world`` and ``dpn``, as ``make demo`` starts them) with
perfect odometry and no wanderers, so every mobile cell on a wall is the map smearing: a scan
placed at a pose that is not the one it was taken from. Runs of each real-time factor
alternate (1x, 4x, 1x, 4x, ...); each lasts ``--sim-seconds`` of simulated time or until the
navigator reports the goal reached. A probe takes every full map dpn publishes and counts the
cells within the safety radius of a true wall that are ever labelled mobile (the same belt as
the benchmark's ``walls_ever_mobile``), plus the scans dpn reports waited for or skipped.

Not a test: it prints one row per run and the medians per factor (issue 29's target: walls
ever mobile at 4x no more than at 1x + 10 cells).
``python tools/smear_ros.py --factors 1 4 --runs 3 --sim-seconds 45``.

"""

import argparse
from pathlib import Path
import statistics
import sys
import tempfile
import time

from diagnostic_msgs.msg import DiagnosticStatus
from dpn_navigator.benchmark.ground_truth import wall_belt
from dpn_navigator.core.cell_label import OCCUPANCY_MOBILE_OBSTACLE
from dpn_navigator.core.grid_geometry import GridGeometry
from dpn_navigator.core.navigator import NavigatorConfig
from dpn_navigator.ros.conversions import occupancy_grid_values
from dpn_navigator.ros.qos import LATCHED_QOS
from dpn_navigator.tools.demo import start_nodes, stop_nodes
from nav_msgs.msg import OccupancyGrid
import numpy as np
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rosgraph_msgs.msg import Clock
from sim_bridge.scenario import load_scenario

#: [m] dpn's default f1 radius: the belt around the true walls.
SAFETY_RADIUS = NavigatorConfig(1.0, 1.0).safety_radius


class MapProbe(Node):
    """Keep the wall cells ever mobile in dpn's maps, the simulated time and dpn's status."""

    def __init__(self, context, scenario, mobile_value):
        super().__init__('smear_probe', context=context)
        self.scenario = scenario
        self.mobile_value = mobile_value
        self.ever_mobile = None
        self.belt = None
        self.maps = 0
        self.sim_time = 0.0
        self.status = {}
        self.create_subscription(OccupancyGrid, '/compabot/map', self.on_map, LATCHED_QOS)
        self.create_subscription(DiagnosticStatus, '/compabot/status', self.on_status,
                                 LATCHED_QOS)
        self.create_subscription(Clock, '/clock', self.on_clock, 10)

    def on_map(self, msg):
        values = occupancy_grid_values(msg)
        if self.belt is None or self.belt.shape != values.shape:
            info = msg.info
            geometry = GridGeometry(info.width * info.resolution,
                                    info.height * info.resolution, info.resolution,
                                    (info.origin.position.x, info.origin.position.y))
            self.belt = wall_belt(self.scenario.occupied, self.scenario.geometry, geometry,
                                  SAFETY_RADIUS)
            self.ever_mobile = np.zeros(values.shape, dtype=bool)
        self.ever_mobile |= values == self.mobile_value
        self.maps += 1

    def on_status(self, msg):
        self.status = {kv.key: kv.value for kv in msg.values}

    def on_clock(self, msg):
        self.sim_time = msg.clock.sec + msg.clock.nanosec * 1e-9

    def walls_ever_mobile(self):
        if self.belt is None:
            return 0
        return int(np.count_nonzero(self.ever_mobile & self.belt))


def run_once(scenario_name, task, factor, sim_seconds, domain_id, log_dir, mobile_value,
             dpn_parameters=()):
    """Run one episode at ``factor`` x real time; return its row (a dict)."""
    scenario = load_scenario(scenario_name)
    _, processes = start_nodes(scenario_name, task, 0, 0, factor, domain_id, log_dir,
                               dpn_parameters=dpn_parameters)
    context = Context()
    rclpy.init(context=context, domain_id=domain_id)
    probe = MapProbe(context, scenario, mobile_value)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(probe)
    wall_limit = time.monotonic() + 60.0 + 3.0 * sim_seconds / factor
    try:
        while time.monotonic() < wall_limit and probe.sim_time < sim_seconds:
            executor.spin_once(timeout_sec=0.05)
            if probe.status.get('status') == 'goal_reached':
                break
            for name, process in processes.items():
                if process.poll() is not None:
                    raise RuntimeError(f'{name} exited with {process.returncode}; see '
                                       f'{log_dir}')
    finally:
        stop_nodes(processes)
        executor.shutdown()
        probe.destroy_node()
        rclpy.try_shutdown(context=context)
    return {'factor': factor, 'sim_time': round(probe.sim_time, 1), 'maps': probe.maps,
            'walls_ever_mobile': probe.walls_ever_mobile(),
            'status': probe.status.get('status', ''),
            'scans_waited': probe.status.get('scans_waited_for_pose', ''),
            'scans_skipped': probe.status.get('scans_skipped_no_pose', ''),
            'of_them_pose_gaps': probe.status.get('scans_skipped_pose_gap', '')}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--scenario', default='back_and_forth')
    parser.add_argument('--task', type=int, default=0)
    parser.add_argument('--factors', type=float, nargs='+', default=[1.0, 4.0])
    parser.add_argument('--runs', type=int, default=3, help='runs per factor, alternating')
    parser.add_argument('--sim-seconds', type=float, default=45.0)
    parser.add_argument('--domain-id', type=int, default=93)
    parser.add_argument('--dpn', nargs='*', default=[], metavar='NAME:=VALUE',
                        help='more parameters of dpn')
    parser.add_argument('--mobile-value', type=int, default=OCCUPANCY_MOBILE_OBSTACLE,
                        help="dpn's map_mobile_value")
    args = parser.parse_args(argv)
    log_dir = Path(tempfile.mkdtemp(prefix='dpn_smear_'))
    rows = []
    for run in range(args.runs):
        for factor in args.factors:
            row = run_once(args.scenario, args.task, factor, args.sim_seconds, args.domain_id,
                           log_dir / f'{run}_{factor:g}', args.mobile_value, args.dpn)
            rows.append(row)
            print(' '.join(f'{k}={v}' for k, v in row.items()), flush=True)
    for factor in args.factors:
        counts = [r['walls_ever_mobile'] for r in rows if r['factor'] == factor]
        print(f'{factor:g}x: walls ever mobile median {statistics.median(counts):g} '
              f'(runs: {counts})')
    print(f'logs: {log_dir}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
