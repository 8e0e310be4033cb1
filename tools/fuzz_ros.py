"""
Fuzz the two node processes over DDS from this process: thousands of messages, the nine cases.

The ``pybullet_world`` (back_and_forth, 3 wanderers) and ``dpn`` (``use_sim_time``) run as
processes, as ``make demo`` starts them. This process first replays the nine failures of issue
11 (odometry near DBL_MAX then a scan, negative ``/clock``, non-unit and huge quaternions,
time going backwards, a 1,000,000-beam scan, a second ``cmd_vel`` publisher, and, in a process
of its own, an absurd grid), then publishes hypothesis-drawn scans, odometry, goals, ``/clock``
and ``cmd_vel`` (every field, see ``test/message_strategies.py``) while it watches what the
navigator publishes. At the end it checks that both processes still run, reads their counters,
stops them with SIGINT and checks for exit code 0 and no traceback.

Not a test: it prints a summary and exits non-zero when a check fails. ``make fuzz``
(``FUZZ_ARGS``: ``--messages N``).

"""

import argparse
import math
from pathlib import Path
import signal
import subprocess
import sys
import tempfile
import time

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / 'test'))

from builtin_interfaces.msg import Time  # noqa: E402, I100
from diagnostic_msgs.msg import DiagnosticStatus  # noqa: E402
from dpn_navigator.ros.conversions import make_laser_scan, pose_to_odometry  # noqa: E402
from dpn_navigator.ros.qos import COMMAND_QOS, LATCHED_QOS, SENSOR_QOS  # noqa: E402
from dpn_navigator.tools.demo import (installed_executable, ros_environment,  # noqa: E402
                                      start_nodes, stop_nodes)
from geometry_msgs.msg import PoseStamped, Quaternion, Twist  # noqa: E402
from hypothesis import given, HealthCheck, settings, strategies as st  # noqa: E402
from message_strategies import DBL_MAX, dpn_messages, twists  # noqa: E402
from nav_msgs.msg import OccupancyGrid, Odometry  # noqa: E402
import numpy as np  # noqa: E402
import rclpy  # noqa: E402
from rclpy.context import Context  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from sensor_msgs.msg import LaserScan  # noqa: E402

MAP_VALUES = {-1, 0, 70, 100}
MAX_LINEAR, MAX_ANGULAR = 1.0, 1.5


class Fuzzer(Node):
    """Publish to every input of both nodes; record what the navigator publishes."""

    def __init__(self, context):
        super().__init__('fuzzer', context=context)
        self.pubs = {
            'scan': self.create_publisher(LaserScan, '/compabot/scan', SENSOR_QOS),
            'odometry': self.create_publisher(Odometry, '/compabot/odom', SENSOR_QOS),
            'goal': self.create_publisher(PoseStamped, '/compabot/goal_pose', COMMAND_QOS),
            'clock': self.create_publisher(Clock, '/clock', COMMAND_QOS),
            'cmd_vel': self.create_publisher(Twist, '/compabot/cmd_vel', COMMAND_QOS),
        }
        self.sent = dict.fromkeys(self.pubs, 0)
        self.bad_commands = []
        self.commands = 0
        self.bad_maps = 0
        self.maps = 0
        self.status = {}
        self.sim_status = {}
        self.create_subscription(Twist, '/compabot/cmd_vel', self.on_cmd, COMMAND_QOS)
        self.create_subscription(OccupancyGrid, '/compabot/map', self.on_map, LATCHED_QOS)
        self.create_subscription(DiagnosticStatus, '/compabot/status', self.on_status,
                                 LATCHED_QOS)
        self.create_subscription(DiagnosticStatus, '/compabot/sim/status', self.on_sim_status,
                                 LATCHED_QOS)
        self.sending_cmd_vel = False

    def send(self, kind, msg):
        self.pubs[kind].publish(msg)
        self.sent[kind] += 1

    def on_cmd(self, msg):
        if self.sending_cmd_vel:
            return                  # our own fuzzed commands are on the topic too
        self.commands += 1
        values = (msg.linear.x, msg.angular.z)
        if not (all(math.isfinite(v) for v in values) and abs(values[0]) <= MAX_LINEAR
                and abs(values[1]) <= MAX_ANGULAR):
            self.bad_commands.append(values)

    def on_map(self, msg):
        self.maps += 1
        if not set(np.unique(np.frombuffer(msg.data, np.int8)).tolist()) <= MAP_VALUES:
            self.bad_maps += 1

    def on_status(self, msg):
        self.status = {kv.key: kv.value for kv in msg.values}

    def on_sim_status(self, msg):
        self.sim_status = {kv.key: kv.value for kv in msg.values}


def spin_for(executor, seconds):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.005)


def scan(beams=640, stamp=Time()):
    return make_laser_scan(np.full(beams, 5.0, dtype=np.float32), -math.pi / 2,
                           math.pi / max(1, beams - 1), 0.1, 30.0, stamp)


def odometry(x, y, orientation=None):
    msg = pose_to_odometry((x, y, 0.0), (0.0, 0.0), Time())
    if orientation is not None:
        msg.pose.pose.orientation = orientation
    return msg


def nine_cases(fuzzer, executor):
    """Replay the failures of issue 11 that arrive by message."""
    steps = [
        ('odometry', odometry(9e307, 2.0)), ('scan', scan()),                 # 1
        ('odometry', odometry(2.0, -9e307)), ('scan', scan()),
        ('clock', Clock(clock=Time(sec=-1))),                                  # 2
        ('clock', Clock(clock=Time(sec=-2**31, nanosec=2**32 - 1))),
        ('odometry', odometry(2.0, 2.0, Quaternion(z=2 * math.sin(math.pi / 4),    # 3
                                                   w=2 * math.cos(math.pi / 4)))),
        ('odometry', odometry(2.0, 2.0, Quaternion(z=1e300, w=1e300))),
        ('odometry', odometry(2.0, 2.0, Quaternion(z=DBL_MAX, w=DBL_MAX))), ('scan', scan()),
        ('clock', Clock(clock=Time(sec=100_000))),                             # 4
        ('clock', Clock(clock=Time(sec=1))),
        ('scan', scan(1_000_000)),                                             # 6
    ]
    for kind, msg in steps:
        fuzzer.send(kind, msg)
        spin_for(executor, 0.05)
    return len(steps)


def absurd_grid_exit(domain_id):
    """Case 9: start dpn with a grid of 1e12 cells; return (exit code, had a traceback)."""
    result = subprocess.run(
        [str(installed_executable('dpn_navigator', 'dpn')), '--ros-args',
         '-p', 'map_width:=1000000.0', '-p', 'resolution:=0.01'],
        env=ros_environment(domain_id), capture_output=True, text=True, timeout=60)
    return result.returncode, 'Traceback' in result.stdout + result.stderr


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--messages', type=int, default=9000,
                        help='hypothesis-drawn messages, besides the nine cases')
    parser.add_argument('--domain-id', type=int, default=91)
    parser.add_argument('--rate', type=float, default=400.0, help='messages per second')
    args = parser.parse_args(argv)
    log_dir = Path(tempfile.mkdtemp(prefix='dpn_fuzz_'))
    _, processes = start_nodes('back_and_forth', 0, 3, 0, 1.0, args.domain_id, log_dir)
    context = Context()
    rclpy.init(context=context, domain_id=args.domain_id)
    fuzzer = Fuzzer(context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(fuzzer)
    failures = []
    started = time.monotonic()
    try:
        deadline = time.monotonic() + 60.0
        while not fuzzer.status and time.monotonic() < deadline:
            spin_for(executor, 0.1)
        spin_for(executor, 2.0)
        cases = nine_cases(fuzzer, executor)
        grid_code, grid_traceback = absurd_grid_exit(args.domain_id)
        if grid_code != 1 or grid_traceback:
            failures.append(f'absurd grid: exit {grid_code}, traceback {grid_traceback}')
        period = 1.0 / args.rate
        dpn_share = int(args.messages * 0.75)

        @settings(max_examples=dpn_share, database=None, deadline=None, derandomize=True,
                  suppress_health_check=list(HealthCheck))
        @given(dpn_messages)
        def fuzz_dpn(message):
            fuzzer.send(*message)
            spin_for(executor, period)

        @settings(max_examples=args.messages - dpn_share, database=None, deadline=None,
                  derandomize=True, suppress_health_check=list(HealthCheck))
        @given(st.one_of(twists()))
        def fuzz_world(twist):
            fuzzer.send('cmd_vel', twist)
            spin_for(executor, period)

        fuzz_dpn()
        fuzzer.sending_cmd_vel = True
        fuzz_world()
        spin_for(executor, 0.5)
        fuzzer.sending_cmd_vel = False
        spin_for(executor, 2.0)             # status refreshes every second
        alive = {name: process.poll() is None for name, process in processes.items()}
        for name, is_alive in alive.items():
            if not is_alive:
                failures.append(f'{name} died with exit code {processes[name].returncode}')
        for name, process in processes.items():
            if process.poll() is None:
                process.send_signal(signal.SIGINT)
        codes = {name: process.wait(15.0) for name, process in processes.items()}
        for name, code in codes.items():
            text = (log_dir / f'{name}.log').read_text()
            if code != 0 or 'Traceback' in text:
                failures.append(f'{name}: exit {code}, traceback {"Traceback" in text}')
        if fuzzer.bad_commands:
            failures.append(f'{len(fuzzer.bad_commands)} bad commands: '
                            f'{fuzzer.bad_commands[:5]}')
        if fuzzer.bad_maps:
            failures.append(f'{fuzzer.bad_maps} maps with values outside {MAP_VALUES}')
        if fuzzer.commands == 0 or fuzzer.maps == 0:
            failures.append('the navigator published no command or no map')
        total = sum(fuzzer.sent.values())
        print(f'messages sent: {total} ({cases} of the nine cases, then '
              f'{args.messages} drawn) in {time.monotonic() - started:.0f} s: {fuzzer.sent}')
        print('dpn counters: ' + ', '.join(
            f'{key} {fuzzer.status.get(key)}' for key in (
                'rejected_scans', 'rejected_odometry', 'rejected_goals', 'rejected_clock',
                'cmd_vel_other_publishers', 'cmd_vel_conflicts', 'replans')))
        print(f"world: rejected_commands {fuzzer.sim_status.get('rejected_commands')}")
        print(f'navigator published {fuzzer.commands} commands (all finite, within limits: '
              f'{not fuzzer.bad_commands}) and {fuzzer.maps} maps (values valid: '
              f'{not fuzzer.bad_maps})')
        print(f'absurd grid: exit {grid_code}, traceback {grid_traceback}')
        print(f'processes alive at the end: {alive}; exit codes after SIGINT: {codes}')
    finally:
        stop_nodes(processes)
        executor.shutdown()
        fuzzer.destroy_node()
        rclpy.try_shutdown(context=context)
    crashes = sum(1 for line in failures if 'died' in line)
    print(f'crashes: {crashes}; failed checks: {len(failures)}')
    for line in failures:
        print(f'  FAIL {line}')
    print(f'logs: {log_dir}')
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
