"""
Run one episode over ROS 2: the pybullet world and the dpn navigator as separate processes.

Both are started as the installed executables ``ros2 run`` resolves
(``<prefix>/lib/sim_bridge/pybullet_world`` and ``<prefix>/lib/dpn_navigator/dpn``), in a DDS
domain of their own on localhost. A monitor node watches the topics until the goal is reached
or the simulated time limit passes, prints the outcome and writes a Fig. 9-style PNG of the
final map with the planned and executed paths. With ``--record DIR`` a recorder node in the
same process writes every topic of both nodes into the rosbag2 MCAP bag DIR
(docs/recording.md).

``make demo`` runs ``python -m dpn_navigator.tools.demo`` on back_and_forth with 3 wanderers.

"""

import argparse
from dataclasses import dataclass, field
import math
import os
from pathlib import Path
import random
import signal
import subprocess
import sys
import time

from action_msgs.msg import GoalStatus
from ament_index_python.packages import get_package_prefix
from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid, Odometry
import numpy as np
import rclpy
from rclpy.action import ActionClient
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from visualization_msgs.msg import MarkerArray

from ..recording.bag_writer import BagPathError, BagWriter
from ..recording.recorded_topics import system_topics
from ..recording.topic_recorder import TopicRecorder
from ..ros.conversions import marker_points, occupancy_grid_values, odometry_to_pose
from ..ros.navigate_action import load_action_type
from ..ros.qos import COMMAND_QOS, LATCHED_QOS, SENSOR_QOS


def installed_executable(package, name):
    """
    Find an executable where ``ros2 run <package> <name>`` looks for it.

    Raises
    ------
    FileNotFoundError
        When the package is not in the ament index or has no such executable.

    """
    path = Path(get_package_prefix(package)) / 'lib' / package / name
    if not (path.is_file() and os.access(path, os.X_OK)):
        raise FileNotFoundError(f'{package} has no executable {name} at {path}')
    return path


def navigator_arguments(scenario, task, default_goal=True):
    """
    Return the ``dpn`` parameters for a scenario's task: what the paper's robot knows.

    With ``default_goal`` the node starts with the task's goal (``use_default_goal``); else it
    waits for one (the demo sends it through the ``navigate_to_pose`` action).
    """
    from sim_bridge.husky import LASER_MOUNT     # the navigator's config, not its code
    goal = scenario.tasks[task].goal
    parameters = {
        'map_width': scenario.width, 'map_height': scenario.height,
        'origin_x': scenario.origin[0], 'origin_y': scenario.origin[1],
        'goal_x': goal[0], 'goal_y': goal[1],
        'laser_x': LASER_MOUNT[0], 'laser_y': LASER_MOUNT[1], 'laser_yaw': LASER_MOUNT[2],
        # The map is known, as the paper's robot knows it: it need not grow.
        'map_growth_step': 0.0,
    }
    args = ['--ros-args', '-p', 'use_sim_time:=true',
            '-p', f'use_default_goal:={str(bool(default_goal)).lower()}']
    for name, value in parameters.items():
        args += ['-p', f'{name}:={float(value)!r}']
    return args


def ros_environment(domain_id):
    """Return a copy of the environment for child processes in their own local DDS domain."""
    env = dict(os.environ)
    env['ROS_DOMAIN_ID'] = str(domain_id)
    env['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    env['PYTHONUNBUFFERED'] = '1'
    return env


def start_nodes(scenario_name, task, wanderers, seed, real_time_factor, domain_id, log_dir,
                default_goal=True, dpn_parameters=()):
    """
    Start ``pybullet_world`` and ``dpn`` as processes; return them.

    ``default_goal``: the navigator starts with the task's goal (`navigator_arguments`).
    ``dpn_parameters``: more ``name:=value`` parameters of ``dpn``.

    Their output goes to ``log_dir/pybullet_world.log`` and ``log_dir/dpn.log``.
    """
    from sim_bridge.scenario import load_scenario
    scenario = load_scenario(scenario_name)
    log_dir = Path(log_dir)
    log_dir.mkdir(parents=True, exist_ok=True)
    env = ros_environment(domain_id)
    world_args = ['--ros-args', '-p', f'scenario:={scenario_name}', '-p', f'task:={task}',
                  '-p', f'wanderers:={wanderers}', '-p', f'seed:={seed}',
                  '-p', f'real_time_factor:={float(real_time_factor)!r}']
    commands = {
        'pybullet_world': [str(installed_executable('sim_bridge', 'pybullet_world'))]
        + world_args,
        'dpn': [str(installed_executable('dpn_navigator', 'dpn'))]
        + navigator_arguments(scenario, task, default_goal)
        + [arg for parameter in dpn_parameters for arg in ('-p', parameter)],
    }
    processes = {}
    for name, command in commands.items():
        log = open(log_dir / f'{name}.log', 'w')
        processes[name] = subprocess.Popen(command, env=env, stdout=log,
                                           stderr=subprocess.STDOUT, start_new_session=True)
        log.close()
    return scenario, processes


def stop_nodes(processes, timeout=5.0):
    """Stop the processes with SIGINT, then SIGKILL those still running after ``timeout``."""
    for process in processes.values():
        if process.poll() is None:
            process.send_signal(signal.SIGINT)
    deadline = time.monotonic() + timeout
    for process in processes.values():
        try:
            process.wait(max(0.1, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def _status_values(msg):
    return {kv.key: kv.value for kv in msg.values}


@dataclass
class Episode:
    """What the monitor saw of one episode."""

    dpn_status: dict = field(default_factory=dict)
    sim_status: dict = field(default_factory=dict)
    executed: list = field(default_factory=list)
    path_length: float = 0.0
    map_msg: OccupancyGrid = None
    map_values_seen: set = field(default_factory=set)
    planned: np.ndarray = None
    wanderers: np.ndarray = None
    max_linear: float = 0.0
    max_angular: float = 0.0
    min_linear: float = 0.0
    commands: int = 0
    bag_counts: dict = None
    goal_sent: bool = False
    action_status: str = ''
    action_feedback: int = 0

    @property
    def sim_time(self):
        """Return the simulated time of the world's last status [s]."""
        return float(self.sim_status.get('time', 'nan'))

    @property
    def reached(self):
        """Tell whether the navigator reported the goal reached."""
        return self.dpn_status.get('status') == 'goal_reached'


class EpisodeMonitor(Node):
    """Record the topics of both nodes into an ``Episode``."""

    def __init__(self, context):
        super().__init__('episode_monitor', context=context,
                         parameter_overrides=[Parameter('use_sim_time', value=True)])
        self.episode = Episode()
        self.create_subscription(DiagnosticStatus, '/compabot/status', self.on_dpn_status,
                                 LATCHED_QOS)
        self.create_subscription(DiagnosticStatus, '/compabot/sim/status', self.on_sim_status,
                                 LATCHED_QOS)
        self.create_subscription(Odometry, '/compabot/odom', self.on_odom, SENSOR_QOS)
        self.create_subscription(OccupancyGrid, '/compabot/map', self.on_map, LATCHED_QOS)
        self.create_subscription(MarkerArray, '/compabot/marker', self.on_marker, LATCHED_QOS)
        self.create_subscription(MarkerArray, '/compabot/sim/wanderers', self.on_wanderers,
                                 COMMAND_QOS)
        self.create_subscription(Twist, '/compabot/cmd_vel', self.on_cmd_vel, COMMAND_QOS)
        action_type = load_action_type()
        self.action_type = action_type
        self.action = (None if action_type is None
                       else ActionClient(self, action_type, '/compabot/navigate_to_pose'))
        self.goal_pub = self.create_publisher(PoseStamped, '/compabot/goal_pose', COMMAND_QOS)

    def send_goal(self, goal):
        """
        Send ``goal`` (x, y) [m] once the navigator listens: by the ``navigate_to_pose`` action.

        Without nav2_msgs, on ``goal_pose``. Returns whether it was sent.
        """
        episode = self.episode
        if episode.goal_sent:
            return True
        if self.action is not None:
            if not self.action.server_is_ready():
                return False
            request = self.action_type.Goal()
            request.pose.header.frame_id = 'map'
            request.pose.pose.position.x, request.pose.pose.position.y = map(float, goal)
            request.pose.pose.orientation.w = 1.0
            sent = self.action.send_goal_async(request, feedback_callback=self.on_feedback)
            sent.add_done_callback(self.on_goal_response)
        else:
            if self.goal_pub.get_subscription_count() == 0:
                return False
            msg = PoseStamped()
            msg.header.frame_id = 'map'
            msg.pose.position.x, msg.pose.position.y = map(float, goal)
            msg.pose.orientation.w = 1.0
            self.goal_pub.publish(msg)
            episode.action_status = 'sent on goal_pose'
        episode.goal_sent = True
        return True

    def on_goal_response(self, future):
        """Note whether the goal was accepted; ask for its result."""
        handle = future.result()
        self.episode.action_status = 'accepted' if handle.accepted else 'rejected'
        if handle.accepted:
            handle.get_result_async().add_done_callback(self.on_result)

    def on_result(self, future):
        """Keep the action's final status (succeeded, aborted with its message, canceled)."""
        result = future.result()
        names = {GoalStatus.STATUS_SUCCEEDED: 'succeeded', GoalStatus.STATUS_ABORTED: 'aborted',
                 GoalStatus.STATUS_CANCELED: 'canceled'}
        status = names.get(result.status, str(result.status))
        message = result.result.error_msg
        self.episode.action_status = f'{status}: {message}' if message else status

    def on_feedback(self, msg):
        """Count the action's feedback messages."""
        self.episode.action_feedback += 1

    def on_dpn_status(self, msg):
        """Keep the navigator's latest status values."""
        self.episode.dpn_status = _status_values(msg)

    def on_sim_status(self, msg):
        """Keep the world's latest status values (time, contacts)."""
        self.episode.sim_status = _status_values(msg)

    def on_odom(self, msg):
        """Extend the executed path and its length."""
        x, y, _ = odometry_to_pose(msg)
        executed = self.episode.executed
        if executed:
            step = math.dist(executed[-1], (x, y))
            if step < 0.02:
                return
            self.episode.path_length += step
        executed.append((x, y))

    def on_map(self, msg):
        """Keep the latest map and every value it ever held."""
        self.episode.map_msg = msg
        self.episode.map_values_seen.update(np.unique(occupancy_grid_values(msg)).tolist())

    def on_marker(self, msg):
        """Keep the planned path."""
        for marker in msg.markers:
            if marker.ns == 'planned_path' and len(marker.points) >= 2:
                self.episode.planned = marker_points(marker)

    def on_wanderers(self, msg):
        """Keep the wanderers' latest positions."""
        self.episode.wanderers = np.array(
            [(m.pose.position.x, m.pose.position.y) for m in msg.markers]).reshape(-1, 2)

    def on_cmd_vel(self, msg):
        """Track the extremes of the commands sent to the robot."""
        episode = self.episode
        episode.commands += 1
        episode.max_linear = max(episode.max_linear, msg.linear.x)
        episode.min_linear = min(episode.min_linear, msg.linear.x)
        episode.max_angular = max(episode.max_angular, abs(msg.angular.z))


def run_episode(scenario_name='back_and_forth', task=0, wanderers=3, seed=0,
                real_time_factor=10.0, time_limit=300.0, wall_limit=600.0, domain_id=None,
                log_dir='out/demo', stop=True, record=None, via_action=True,
                dpn_parameters=()):
    """
    Start both nodes and watch until the goal is reached or a limit passes.

    Parameters
    ----------
    scenario_name : str
        Built-in scenario name or map_server yaml path.
    task, wanderers, seed : int
        Which task, how many P3-ATs, and the world's seed.
    real_time_factor : float
        Pace of the simulator: simulated seconds per wall second.
    time_limit : float
        Simulated time limit [s].
    wall_limit : float
        Wall-clock limit [s], a guard against a stalled simulation.
    domain_id : int, optional
        DDS domain of the episode; by default ``ROS_DOMAIN_ID`` if set, else a random one.
    log_dir : str or Path
        Folder for the two processes' output.
    stop : bool
        Stop the processes at the end; otherwise the caller stops them with ``stop_nodes``.
    record : str or os.PathLike, optional
        Record every topic of both nodes (``recorded_topics.system_topics``) from before
        they start until the end into this rosbag2 MCAP bag folder, which must not exist;
        ``episode.bag_counts`` then holds the messages recorded per topic.
    via_action : bool
        Send the task's goal through the ``navigate_to_pose`` action once the navigator serves
        it (``episode.action_status`` ends as its result); False: the navigator starts with
        the goal (``use_default_goal``).
    dpn_parameters : sequence of str
        More ``name:=value`` parameters of ``dpn``, after the scenario's (which they override).

    Returns
    -------
    scenario : Scenario
    episode : Episode
    monitor_context : Context
        Still initialised, so a caller can subscribe late; shut it down afterwards.
    processes : dict
        The processes, by node name.

    Raises
    ------
    BagPathError
        When ``record`` exists or cannot be written (before anything starts).

    """
    if domain_id is None:
        domain_id = int(os.environ.get('ROS_DOMAIN_ID') or random.randint(1, 101))
    bag = None if record is None else BagWriter(record, system_topics(), custom_data={
        'scenario': scenario_name, 'task': task, 'wanderers': wanderers, 'seed': seed,
        'real_time_factor': real_time_factor})
    context = Context()
    rclpy.init(context=context, domain_id=domain_id)
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    monitor = EpisodeMonitor(context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(monitor)
    recorder_node = None
    if bag is not None:
        recorder_node = Node('episode_recorder', context=context,
                             parameter_overrides=[Parameter('use_sim_time', value=True)])
        TopicRecorder(recorder_node, bag, system_topics())
        executor.add_node(recorder_node)
    episode = monitor.episode
    try:
        scenario, processes = start_nodes(scenario_name, task, wanderers, seed,
                                          real_time_factor, domain_id, log_dir,
                                          default_goal=not via_action,
                                          dpn_parameters=dpn_parameters)
    except BaseException:
        if bag is not None:
            bag.close()
        raise
    deadline = time.monotonic() + wall_limit
    try:
        while time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)
            if via_action:
                monitor.send_goal(scenario.tasks[task].goal)
            if episode.reached or episode.sim_time > time_limit:
                break
            dead = [name for name, p in processes.items() if p.poll() is not None]
            if dead:
                raise RuntimeError(f'{", ".join(dead)} exited early; see {log_dir}')
        # Let the last map and markers arrive, and the action's result.
        settle = time.monotonic() + 2.0
        for _ in range(20):
            executor.spin_once(timeout_sec=0.02)
        while (via_action and episode.action_status == 'accepted'
               and time.monotonic() < settle):
            executor.spin_once(timeout_sec=0.02)
    except BaseException:
        stop_nodes(processes)
        raise
    finally:
        if bag is not None:
            bag.close()
            episode.bag_counts = dict(bag.counts)
            recorder_node.destroy_node()
    if stop:
        stop_nodes(processes)
    monitor.destroy_node()
    return scenario, episode, context, processes


def main(argv=None):
    """Run the demo episode and report it: ``python -m dpn_navigator.tools.demo``."""
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--scenario', default='back_and_forth')
    parser.add_argument('--task', type=int, default=0)
    parser.add_argument('--wanderers', type=int, default=3)
    parser.add_argument('--seed', type=int, default=0)
    parser.add_argument('--real-time-factor', type=float, default=10.0)
    parser.add_argument('--time-limit', type=float, default=300.0, help='simulated [s]')
    parser.add_argument('--out', default='out/demo', help='folder for the PNG and the logs')
    parser.add_argument('--record', metavar='DIR',
                        help='record every topic of both nodes into the rosbag2 MCAP bag DIR '
                             '(a new folder; see docs/recording.md)')
    parser.add_argument('--dpn-param', action='append', default=[], metavar='NAME:=VALUE',
                        help='a parameter of the dpn node, as on a ros2 command line, after '
                             "the scenario's (e.g. map_growth_step:=5.0); may repeat")
    args = parser.parse_args(argv)
    for assignment in args.dpn_param:
        name, separator, _ = assignment.partition(':=')
        if not separator or not name:
            parser.error(f'--dpn-param wants NAME:=VALUE, got {assignment!r}')
    from .figures import save_map_figure
    started = time.monotonic()
    try:
        scenario, episode, context, _ = run_episode(
            args.scenario, args.task, args.wanderers, args.seed, args.real_time_factor,
            args.time_limit, log_dir=args.out, record=args.record,
            dpn_parameters=tuple(args.dpn_param))
    except BagPathError as error:
        parser.exit(2, f'{parser.prog}: error: --record: {error}\n')
    rclpy.try_shutdown(context=context)
    wall = time.monotonic() - started
    print(f'scenario {scenario.name}, task {args.task}, {args.wanderers} wanderers, '
          f'seed {args.seed}')
    print(f'goal reached:       {"yes" if episode.reached else "NO"}'
          f' (navigator status: {episode.dpn_status.get("status")}'
          f'{", " + episode.dpn_status["reason"] if episode.dpn_status.get("reason") else ""})')
    print(f'navigate_to_pose:   {episode.action_status or "not sent"} '
          f'({episode.action_feedback} feedback messages)')
    print(f'simulated time:     {episode.sim_time:.1f} s ({wall:.1f} s wall)')
    print(f'path length:        {episode.path_length:.1f} m')
    print(f'replans:            {episode.dpn_status.get("replans")}')
    print(f'collisions:         {episode.sim_status.get("wall_contacts")} with walls, '
          f'{episode.sim_status.get("wanderer_contacts")} with wanderers')
    figure = Path(args.out) / f'{scenario.name}_task{args.task}.png'
    if episode.map_msg is not None:
        info = episode.map_msg.info
        save_map_figure(
            figure, occupancy_grid_values(episode.map_msg), info.resolution,
            (info.origin.position.x, info.origin.position.y), planned=episode.planned,
            executed=episode.executed, wanderers=episode.wanderers,
            goal=scenario.tasks[args.task].goal,
            title=f'{scenario.name}, t = {episode.sim_time:.1f} s')
        print(f'map figure:         {figure}')
    if episode.bag_counts is not None:
        print(f'bag:                {args.record} ({sum(episode.bag_counts.values())} messages '
              f'on {sum(1 for n in episode.bag_counts.values() if n)} topics)')
    return 0 if episode.reached else 1


if __name__ == '__main__':
    sys.exit(main())
