"""
Soak: both node processes with 10 wanderers for minutes; the memory each one keeps.

The ``pybullet_world`` (back_and_forth, 10 wanderers, real time) and ``dpn`` run as processes,
as ``make demo`` starts them. Whenever the navigator reports ``goal_reached``, this process sends
it back to the other end of the task, so that it keeps mapping, planning and driving. Every 10 s
it samples each process's resident set size (``VmRSS`` in ``/proc``); the growth is the slope of
a least-squares line through the samples after the first minute (start-up allocations, the
first map and plans), in MB per hour, with its 95 % interval (the slope's standard error times
Student's t quantile for ``n - 2`` degrees of freedom).

Not a test: it prints the samples' summary. ``make soak`` (``SOAK_ARGS``: ``--minutes N``).

"""

import argparse
import math
from pathlib import Path
import sys
import tempfile
import time

from diagnostic_msgs.msg import DiagnosticStatus
from dpn_navigator.ros.qos import COMMAND_QOS, LATCHED_QOS
from dpn_navigator.tools.demo import start_nodes, stop_nodes
from geometry_msgs.msg import PoseStamped
import numpy as np
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

SAMPLE_PERIOD = 10.0        # [s]
WARM_UP = 60.0              # [s] left out of the slope


def rss_megabytes(pid):
    """Return a process's resident set size [MB], or None once it has gone."""
    try:
        for line in Path(f'/proc/{pid}/status').read_text().splitlines():
            if line.startswith('VmRSS:'):
                return int(line.split()[1]) / 1024.0
    except FileNotFoundError:
        return None
    return None


class GoalSwitcher(Node):
    """Send the navigator back and forth between two points when it reaches one."""

    def __init__(self, context, ends):
        super().__init__('soak_goals', context=context)
        self.ends = ends
        self.goal_index = 1                 # the dpn node starts with the task's goal
        self.goals_reached = 0
        self.status = {}
        self.goal_pub = self.create_publisher(PoseStamped, '/compabot/goal_pose', COMMAND_QOS)
        self.create_subscription(DiagnosticStatus, '/compabot/status', self.on_status,
                                 LATCHED_QOS)

    def on_status(self, msg):
        self.status = {kv.key: kv.value for kv in msg.values}
        if self.status.get('status') == 'goal_reached':
            self.goals_reached += 1
            self.goal_index = 1 - self.goal_index
            goal = PoseStamped()
            goal.header.frame_id = 'map'
            goal.pose.position.x, goal.pose.position.y = map(float, self.ends[self.goal_index])
            goal.pose.orientation.w = 1.0
            self.goal_pub.publish(goal)


def student_t_quantile(probability, dof):
    """
    Return the quantile of Student's t distribution with ``dof`` degrees of freedom.

    The density integrated with Simpson's rule, the quantile found by bisection (numpy only:
    scipy is no dependency of this package); within 1e-6 of ``scipy.stats.t.ppf``.
    """
    if not 0.5 <= probability < 1.0 or dof < 1:
        raise ValueError(f'need 0.5 <= probability < 1 and dof >= 1, got {probability}, {dof}')
    log_scale = (math.lgamma((dof + 1) / 2.0) - math.lgamma(dof / 2.0)
                 - 0.5 * math.log(dof * math.pi))

    def cdf(x):
        grid = np.linspace(0.0, x, 4001)
        density = np.exp(log_scale - (dof + 1) / 2.0 * np.log1p(grid * grid / dof))
        step = grid[1] - grid[0]
        integral = step / 3.0 * (density[0] + density[-1] + 4.0 * density[1:-1:2].sum()
                                 + 2.0 * density[2:-1:2].sum())
        return 0.5 + integral

    low, high = 0.0, 1.0
    while cdf(high) < probability:
        low, high = high, 2.0 * high
    for _ in range(60):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if cdf(middle) < probability else (low, middle)
    return 0.5 * (low + high)


def fitted_growth(times, values, confidence=0.95):
    """
    Fit a least-squares line to RSS samples; return its slope and the slope's interval.

    Parameters
    ----------
    times : sequence of float
        Sample times [s].
    values : sequence of float
        RSS [MB].
    confidence : float
        Of the two-sided interval.

    Returns
    -------
    slope, half_width : float
        [MB/h]: the slope and the half-width of its interval, the slope's standard error
        (from the residuals, ``n - 2`` degrees of freedom) times Student's t quantile; NaN
        with fewer than three samples.

    """
    t = np.asarray(times, dtype=np.float64)
    y = np.asarray(values, dtype=np.float64)
    if t.shape[0] < 3:
        return math.nan, math.nan
    centred = t - t.mean()
    spread = float(centred @ centred)
    slope = float(centred @ (y - y.mean())) / spread
    residuals = y - (y.mean() + slope * centred)
    dof = t.shape[0] - 2
    standard_error = math.sqrt(float(residuals @ residuals) / dof / spread)
    quantile = student_t_quantile(0.5 + confidence / 2.0, dof)
    return slope * 3600.0, quantile * standard_error * 3600.0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--minutes', type=float, default=10.0)
    parser.add_argument('--wanderers', type=int, default=10)
    parser.add_argument('--domain-id', type=int, default=92)
    args = parser.parse_args(argv)
    log_dir = Path(tempfile.mkdtemp(prefix='dpn_soak_'))
    scenario, processes = start_nodes('back_and_forth', 0, args.wanderers, 0, 1.0,
                                      args.domain_id, log_dir)
    task = scenario.tasks[0]
    context = Context()
    rclpy.init(context=context, domain_id=args.domain_id)
    switcher = GoalSwitcher(context, (task.start[:2], task.goal))
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(switcher)
    samples = {name: [] for name in processes}
    started = time.monotonic()
    next_sample = started
    try:
        while time.monotonic() - started < 60.0 * args.minutes:
            executor.spin_once(timeout_sec=0.1)
            now = time.monotonic()
            if now >= next_sample:
                next_sample += SAMPLE_PERIOD
                for name, process in processes.items():
                    rss = rss_megabytes(process.pid)
                    if rss is None:
                        raise RuntimeError(f'{name} exited with {process.poll()}; '
                                           f'see {log_dir}')
                    samples[name].append((now - started, rss))
    finally:
        stop_nodes(processes)
        executor.shutdown()
        switcher.destroy_node()
        rclpy.try_shutdown(context=context)
    print(f'soak: {args.minutes:g} min, {args.wanderers} wanderers, '
          f'{switcher.goals_reached} goals reached, dpn status {switcher.status.get("status")}')
    for name, points in samples.items():
        kept = [(t, rss) for t, rss in points if t >= WARM_UP]
        times, values = zip(*kept) if kept else ((), ())
        slope, half_width = fitted_growth(times, values)
        print(f'{name}: RSS {points[0][1]:.1f} MB at start, {points[-1][1]:.1f} MB at the end, '
              f'growth after the first minute {slope:+.2f} MB/h, 95 % interval '
              f'[{slope - half_width:+.2f}, {slope + half_width:+.2f}] MB/h (least squares '
              f'over {len(kept)} samples, every {SAMPLE_PERIOD:g} s)')
        # A growth that levels off (a warm-up) shows as a smaller slope in the second half.
        half = len(points) // 2
        late_slope, late_half_width = fitted_growth(*zip(*points[half:]))
        print(f'{name}: growth over the second half {late_slope:+.2f} MB/h, 95 % interval '
              f'[{late_slope - late_half_width:+.2f}, {late_slope + late_half_width:+.2f}] '
              f'MB/h; RSS every minute: '
              + ' '.join(f'{rss:.1f}' for t, rss in points[::max(1, round(60 / SAMPLE_PERIOD))]))
    print(f'logs: {log_dir}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
