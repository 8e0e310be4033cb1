"""
End to end: the installed executables, as ``ros2 run`` resolves them, in processes of their own.

The pybullet world (back_and_forth, 2 wanderers) and the dpn navigator talk over real DDS in a
domain of this test's own; a monitor node in the test process watches the topics, and reads
``/tf`` and ``/tf_static`` as any TF consumer would, and a recorder node beside it writes every
topic into a rosbag2 MCAP bag, read back with an independent reader.
"""

import math
import subprocess

from bag_reading import read_bag, stamp_ns
from diagnostic_msgs.msg import DiagnosticArray
from dpn_navigator.recording.recorded_topics import system_topics
from dpn_navigator.ros.qos import COMMAND_QOS, LATCHED_QOS, SENSOR_QOS, TF_QOS, TF_STATIC_QOS
from dpn_navigator.tools.demo import installed_executable, ros_environment, run_episode, stop_nodes
from nav_msgs.msg import OccupancyGrid, Path
import numpy as np
import pytest
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from sensor_msgs.msg import LaserScan
from tf2_msgs.msg import TFMessage
from tf_chain import FrameChain

TIME_LIMIT = 150.0      # simulated [s]; the task's shortest path is about 29 m


def test_executables_are_where_ros2_run_looks():
    for package, name in (('dpn_navigator', 'dpn'), ('dpn_navigator', 'dpn-replay'),
                          ('sim_bridge', 'pybullet_world')):
        path = installed_executable(package, name)
        assert path.parts[-3:] == ('lib', package, name)


@pytest.mark.parametrize('package, name, parameter', [
    ('dpn_navigator', 'dpn', 'map_width:=abc'),
    ('sim_bridge', 'pybullet_world', 'physics_rate:=0'),
    ('sim_bridge', 'pybullet_world', 'wanderers:=many'),
    ('dpn_navigator', 'dpn', 'map_width:=2e6'),
])
def test_a_bad_parameter_ends_the_process_with_one_line(
        ros_domain_id, package, name, parameter):
    result = subprocess.run(
        [str(installed_executable(package, name)), '--ros-args', '-p', parameter],
        env=ros_environment(ros_domain_id), capture_output=True, text=True, timeout=60)
    output = result.stdout + result.stderr
    assert result.returncode == 1, output
    assert 'Traceback' not in output
    (line,) = [line for line in output.splitlines() if 'cannot start: ' in line]
    assert parameter.split(':=')[0] in line


@pytest.mark.slow
def test_robot_reaches_the_goal_over_ros(ros_domain_id, tmp_path):
    scenario, episode, context, processes = run_episode(
        'back_and_forth', task=1, wanderers=2, seed=0, real_time_factor=5.0,
        time_limit=TIME_LIMIT, wall_limit=240.0, domain_id=ros_domain_id,
        log_dir=tmp_path, stop=False, record=tmp_path / 'bag')
    try:
        assert episode.reached, (episode.dpn_status, (tmp_path / 'dpn.log').read_text())
        assert episode.sim_time <= TIME_LIMIT
        goal = scenario.tasks[1].goal
        assert math.dist(episode.executed[-1], goal) <= 0.3 + 0.1   # tolerance + one odom step
        # The map carries only the four documented values, and reaches a late subscriber.
        assert episode.map_values_seen <= {-1, 0, 70, 100}
        assert {-1, 0, 100} <= episode.map_values_seen
        late = Node('late_subscriber', context=context)
        maps = []
        late.create_subscription(OccupancyGrid, '/compabot/map', maps.append, LATCHED_QOS)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(late)
        for _ in range(200):
            executor.spin_once(timeout_sec=0.05)
            if maps:
                break
        assert maps, 'a late subscriber must get the latched map'
        info = maps[0].info
        assert (info.width, info.height) == (math.ceil(scenario.width / 0.5),
                                             math.ceil(scenario.height / 0.5))
        assert set(np.unique(np.frombuffer(maps[0].data, np.int8)).tolist()) <= {-1, 0, 70, 100}
        # The marker holds the planned path, ending at the goal.
        assert episode.planned is not None and episode.planned.shape[0] >= 2
        assert np.allclose(episode.planned[-1], goal)
        # Commands stay within the Husky's limits.
        assert episode.commands > 100
        assert 0.0 <= episode.min_linear and episode.max_linear <= 1.0
        assert episode.max_angular <= 1.5
        # TF from another process: map -> odom -> base_link -> laser resolves at scan stamps.
        frames, scans, plans, diagnostics = FrameChain(), [], [], {}
        late.create_subscription(TFMessage, '/tf', lambda m: frames.add(m, False), TF_QOS)
        late.create_subscription(TFMessage, '/tf_static', lambda m: frames.add(m, True),
                                 TF_STATIC_QOS)
        late.create_subscription(LaserScan, '/compabot/scan', scans.append, SENSOR_QOS)
        late.create_subscription(Path, '/compabot/plan', plans.append, LATCHED_QOS)
        late.create_subscription(
            DiagnosticArray, '/diagnostics',
            lambda m: diagnostics.update((s.name, s) for s in m.status), COMMAND_QOS)
        resolved, errors = [], []

        def resolve():
            # A scan can arrive before its transforms (or, at first, /tf_static): try it again
            # on the next round, and keep the last error for the report.
            for scan in list(scans):
                try:
                    resolved.append(frames.lookup('map', scan.header.frame_id,
                                                  scan.header.stamp))
                    scans.remove(scan)
                except LookupError as error:
                    errors.append(error)
            return len(resolved) >= 3 and plans and len(diagnostics) >= 2

        for _ in range(400):
            executor.spin_once(timeout_sec=0.05)
            if resolve():
                break
        assert len(resolved) >= 3, (f'{len(resolved)} scans resolved; frames {frames.parents}; '
                                    f'last error: {errors[-1:]}')
        assert frames.parents == {'odom': 'map', 'base_link': 'odom', 'laser': 'base_link'}
        laser_z = [translation[2] for translation, _ in resolved]
        assert laser_z == [laser_z[0]] * len(laser_z) and laser_z[0] > 0.0
        assert math.dist(resolved[-1][0][:2], goal) < 1.0      # the robot waits at the goal
        assert plans and plans[-1].header.frame_id == 'map'
        assert {'/compabot/dpn', '/compabot/pybullet_world'} <= set(diagnostics)
        late.destroy_node()
        check_recorded_bag(tmp_path / 'bag', episode)
    finally:
        stop_nodes(processes)
        context.try_shutdown()


def check_recorded_bag(folder, episode):
    """Check the demo's bag against what the monitor saw of the same episode."""
    bag = read_bag(folder)
    counts = bag.counts()
    assert set(counts) == {topic.name for topic in system_topics()}
    assert dict(counts) == episode.bag_counts
    assert counts['/tf_static'] == 1
    # Scans at 10 Hz of simulated time; a busy machine may drop a few, as ros2 bag record would.
    assert counts['/compabot/scan'] >= 5 * episode.sim_time
    assert counts['/clock'] >= counts['/compabot/scan'] and counts['/compabot/cmd_vel'] > 100
    for topic, items in bag.messages.items():
        times = [t for t, _ in items]
        assert times == sorted(times), topic     # dated on the recorder's sim clock
    # The bag ends with the episode; a recorder short of CPU may miss the last few /clock
    # messages (50 Hz) before it is stopped, as ros2 bag record would.
    clock_end = stamp_ns(bag.messages['/clock'][-1][1].clock) / 1e9
    assert episode.sim_time - max(3.0, 0.05 * episode.sim_time) < clock_end
    assert clock_end < episode.sim_time + 1.0
    _, last_map = bag.messages['/compabot/map'][-1]
    assert set(np.unique(np.array(last_map.data, dtype=np.int8)).tolist()) <= {-1, 0, 70, 100}
    _, markers = bag.messages['/compabot/marker'][-1]
    assert [m.ns for m in markers.markers][:2] == ['planned_path', 'executed_path']
