"""
Episode bags: the bag writer, the benchmark's episode recorder and the demo's topic recorder.

Every bag is read back with ``bag_reading.read_bag``: a reader independent of the writer (the
MCAP project's reader and ROS 2 decoder, not rosbags), which also checks ``metadata.yaml``.
"""

import importlib
import json
import math
import os
from pathlib import Path

from ament_index_python.packages import get_package_share_directory, PackageNotFoundError
from bag_reading import log_times, read_bag, stamp_ns
from dpn_navigator.benchmark import runner
from dpn_navigator.benchmark.episode import run_episode
from dpn_navigator.benchmark.episode_bag import episode_bag_name, EpisodeBagRecorder
from dpn_navigator.benchmark.protocol import EpisodeSpec
from dpn_navigator.core import OCCUPANCY_VALUE
from dpn_navigator.recording.bag_writer import (BagPathError, BagTopic, BagWriter, check_bag_path,
                                                message_type_name)
from dpn_navigator.recording.recorded_topics import episode_topics, system_topics
from dpn_navigator.recording.topic_recorder import TopicRecorder
from dpn_navigator.ros.conversions import (labels_to_occupancy_grid, make_laser_scan,
                                           seconds_to_time)
from dpn_navigator.ros.qos import LATCHED_QOS, SENSOR_QOS
from nav_msgs.msg import OccupancyGrid
import numpy as np
import pytest
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan

EPISODE_TIME = 6.0      # simulated [s]: 60 scans


def _scan(k):
    ranges = np.linspace(0.5, 5.0, 640) + k
    return make_laser_scan(ranges, -math.pi / 2, math.pi / 639, 0.1, 30.0,
                           seconds_to_time(0.1 * k))


# -- the writer --------------------------------------------------------------------------------


def test_written_messages_read_back_with_an_independent_reader(tmp_path):
    labels = np.array([[0, 1], [2, 3], [1, 1]], dtype=np.uint8)
    topics = [BagTopic('/robot/scan', LaserScan, SENSOR_QOS),
              BagTopic('/robot/map', OccupancyGrid, LATCHED_QOS),
              BagTopic('/clock', Clock, SENSOR_QOS)]
    with BagWriter(tmp_path / 'bag', topics, custom_data={'note': 'test'}) as bag:
        for k in range(5):
            stamp = seconds_to_time(0.1 * k)
            bag.write('/robot/scan', _scan(k), 100_000_000 * k)
            bag.write('/clock', Clock(clock=stamp), 100_000_000 * k)
        grid = labels_to_occupancy_grid(labels, 0.5, (-1.0, 2.0), seconds_to_time(0.4))
        bag.write('/robot/map', grid, 400_000_000)
    recorded = read_bag(tmp_path / 'bag')
    assert recorded.counts() == {'/robot/scan': 5, '/clock': 5, '/robot/map': 1}
    assert recorded.types == {'/robot/scan': 'sensor_msgs/msg/LaserScan',
                              '/robot/map': 'nav_msgs/msg/OccupancyGrid',
                              '/clock': 'rosgraph_msgs/msg/Clock'}
    assert log_times(recorded, '/clock') == [100_000_000 * k for k in range(5)]
    for k, (_, scan) in enumerate(recorded.messages['/robot/scan']):
        np.testing.assert_allclose(scan.ranges, _scan(k).ranges)
        assert stamp_ns(scan.header.stamp) == 100_000_000 * k
    ((_, decoded),) = recorded.messages['/robot/map']
    assert (decoded.info.width, decoded.info.height) == (2, 3)
    assert decoded.info.origin.position.y == 2.0
    np.testing.assert_array_equal(np.array(decoded.data, dtype=np.int8).reshape(3, 2),
                                  OCCUPANCY_VALUE[labels])
    assert recorded.metadata['custom_data'] == {'recorded_by': 'dpn_navigator', 'note': 'test'}
    qos = {entry['topic_metadata']['name']: entry['topic_metadata']['offered_qos_profiles'][0]
           for entry in recorded.metadata['topics_with_message_count']}
    assert qos['/robot/map']['durability'] == 'transient_local'     # replayed latched
    assert qos['/robot/scan']['reliability'] == 'best_effort'


@pytest.mark.parametrize('topic', system_topics(), ids=lambda topic: topic.name)
def test_type_names_and_hashes_match_the_installed_interfaces(tmp_path, topic):
    # rosbag2 and Foxglove match types by name; the hash is what Jazzy computes for the type.
    name = message_type_name(topic.msg_type)
    package, _, type_name = name.split('/')
    with BagWriter(tmp_path / 'bag', [topic]):
        pass
    (entry,) = read_bag(tmp_path / 'bag').metadata['topics_with_message_count']
    assert entry['topic_metadata']['type'] == name
    installed = json.loads((_share_directory(package) / 'msg' / f'{type_name}.json').read_text())
    (own,) = [h for h in installed['type_hashes'] if h['type_name'] == name]
    assert entry['topic_metadata']['type_description_hash'] == own['hash_string']


def _share_directory(package):
    """Return a ROS package's share folder: from the ament index, else beside its module."""
    try:
        return Path(get_package_share_directory(package))
    except PackageNotFoundError:
        # The PyPI wheels install into the venv prefix: <prefix>/lib/python3.X/site-packages.
        module = importlib.import_module(package)
        return Path(module.__file__).resolve().parents[4] / 'share' / package


def test_an_existing_bag_is_never_overwritten(tmp_path):
    (tmp_path / 'bag').mkdir()
    with pytest.raises(BagPathError, match='exists already: a bag is never overwritten'):
        BagWriter(tmp_path / 'bag', episode_topics())


def test_a_bag_under_a_file_is_refused_clearly(tmp_path):
    (tmp_path / 'file').write_text('')
    with pytest.raises(BagPathError, match='cannot create the folder'):
        check_bag_path(tmp_path / 'file' / 'bags' / 'bag')


def test_writer_refuses_duplicate_and_unknown_topics(tmp_path):
    scan = BagTopic('/scan', LaserScan, SENSOR_QOS)
    with pytest.raises(ValueError, match='topic names must differ'):
        BagWriter(tmp_path / 'a', [scan, scan])
    with BagWriter(tmp_path / 'b', [scan]) as bag:
        with pytest.raises(KeyError, match="'/map' is not a topic of the bag"):
            bag.write('/map', OccupancyGrid(), 0)
    with pytest.raises(ValueError, match='is not a ROS 2 message class'):
        message_type_name(dict)


# -- the benchmark's episode bags --------------------------------------------------------------


class LastNavigatorView:
    """A recorder that keeps the navigator's map at the latest scan, around another one."""

    def __init__(self, inner):
        self.inner = inner
        self.calls = 0

    def __call__(self, world, navigator):
        self.inner(world, navigator)
        self.calls += 1
        self.values = OCCUPANCY_VALUE[navigator.grid.labels]


@pytest.fixture(scope='module')
def recorded_episode(back_and_forth, tmp_path_factory):
    """Run a short episode plain and recorded; return both results, the view and the bag."""
    bag = tmp_path_factory.mktemp('episode') / 'bag'
    plain = run_episode(back_and_forth, 0, 3, 5, time_limit=EPISODE_TIME)
    with EpisodeBagRecorder(bag, {'scenario': 'back_and_forth'}) as recorder:
        view = LastNavigatorView(recorder)
        recorded = run_episode(back_and_forth, 0, 3, 5, time_limit=EPISODE_TIME, recorder=view)
    return plain, recorded, view, read_bag(bag)


@pytest.fixture(scope='module')
def back_and_forth():
    from sim_bridge.scenario import load_scenario
    return load_scenario('back_and_forth')


def test_recording_does_not_change_the_episode(recorded_episode):
    plain, recorded, _, _ = recorded_episode
    assert recorded == plain        # every field but the detection's wall time
    assert plain.time == pytest.approx(EPISODE_TIME, abs=0.11)


def test_the_episode_bag_holds_every_topic_once_per_scan(recorded_episode):
    _, _, view, bag = recorded_episode
    scans = view.calls
    assert scans >= 10 * EPISODE_TIME - 1
    counts = bag.counts()
    assert {topic.name for topic in episode_topics()} == set(counts)
    assert bag.types == {topic.name: message_type_name(topic.msg_type)
                         for topic in episode_topics()}
    for topic in ('/clock', '/tf', '/compabot/scan', '/compabot/odom', '/compabot/odom_real',
                  '/compabot/map', '/compabot/sim/wanderers'):
        assert counts[topic] == scans, topic
    assert counts['/tf_static'] == 1
    # Markers and plan: at the first scan, and at least every 0.5 s after it.
    assert counts['/compabot/marker'] == counts['/compabot/plan']
    assert 2 * EPISODE_TIME <= counts['/compabot/marker'] <= scans
    assert bag.metadata['custom_data']['scenario'] == 'back_and_forth'


def test_the_episode_bag_is_in_simulated_time_order(recorded_episode):
    _, _, _, bag = recorded_episode
    clock = log_times(bag, '/clock')
    assert clock[0] == 0 and all(b - a == 100_000_000 for a, b in zip(clock, clock[1:]))
    assert [stamp_ns(msg.clock) for _, msg in bag.messages['/clock']] == clock
    for topic, items in bag.messages.items():
        times = [t for t, _ in items]
        assert times == sorted(times), topic
    for topic in ('/compabot/scan', '/compabot/map', '/compabot/odom'):
        assert [stamp_ns(msg.header.stamp) for _, msg in bag.messages[topic]] == clock, topic


def test_the_episode_bag_holds_what_the_nodes_would_publish(recorded_episode, back_and_forth):
    _, _, view, bag = recorded_episode
    _, last_map = bag.messages['/compabot/map'][-1]
    np.testing.assert_array_equal(
        np.array(last_map.data, dtype=np.int8).reshape(last_map.info.height,
                                                       last_map.info.width), view.values)
    assert last_map.header.frame_id == 'map'
    (_, static), = bag.messages['/tf_static']
    (mount,) = static.transforms
    assert (mount.header.frame_id, mount.child_frame_id) == ('base_link', 'laser')
    _, tf = bag.messages['/tf'][-1]
    assert [(t.header.frame_id, t.child_frame_id) for t in tf.transforms] == \
        [('map', 'odom'), ('odom', 'base_link')]
    _, odom = bag.messages['/compabot/odom'][-1]
    assert tf.transforms[1].transform.translation.x == odom.pose.pose.position.x
    _, scan = bag.messages['/compabot/scan'][0]
    assert len(scan.ranges) == 640 and scan.header.frame_id == 'laser'
    _, wanderers = bag.messages['/compabot/sim/wanderers'][0]
    assert len(wanderers.markers) == 3
    _, markers = bag.messages['/compabot/marker'][-1]
    assert [m.ns for m in markers.markers] == ['planned_path', 'executed_path', 'goal']
    goal = back_and_forth.tasks[0].goal
    assert (markers.markers[2].pose.position.x, markers.markers[2].pose.position.y) == \
        pytest.approx(goal)
    _, plan = bag.messages['/compabot/plan'][-1]
    assert len(plan.poses) == len(markers.markers[0].points) >= 2


def test_run_spec_logs_the_same_row_with_a_bag(monkeypatch, tmp_path):
    # The benchmark runner, on a short time limit: the row is the same, the bag is written.
    monkeypatch.setattr(runner, 'run_episode', lambda *args, **kwargs: run_episode(
        *args, time_limit=3.0, **kwargs))
    spec = EpisodeSpec('back_and_forth', 0, 2, 0, 11)
    plain = runner.run_spec(spec)
    recorded = runner.run_spec(spec, record_dir=tmp_path)
    varying = ('wall_time', 'detection_wall_time')
    assert {k: v for k, v in recorded.items() if k not in varying} == \
        {k: v for k, v in plain.items() if k not in varying}
    bag = read_bag(tmp_path / episode_bag_name(spec))
    assert bag.counts()['/compabot/scan'] == 30
    assert bag.metadata['custom_data']['seed'] == '11'
    with pytest.raises(BagPathError, match='exists already'):
        runner.check_bag_folders([spec], tmp_path)


def test_bag_names_name_the_episode():
    assert episode_bag_name(EpisodeSpec('maze', 1, 5, 2, 77)) == 'maze_task1_w5_r2_seed77'
    assert episode_bag_name(EpisodeSpec('/maps/own.yaml', 0, 0, 0, 3)) == \
        'own_task0_w0_r0_seed3'


# -- the demo's topic recorder -----------------------------------------------------------------


def test_topic_recorder_records_what_nodes_publish(ros_context, tmp_path):
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    publisher_node = Node('talker', context=ros_context)
    map_pub = publisher_node.create_publisher(OccupancyGrid, '/robot/map', LATCHED_QOS)
    scan_pub = publisher_node.create_publisher(LaserScan, '/robot/scan', SENSOR_QOS)
    grid = labels_to_occupancy_grid(np.ones((4, 5), np.uint8), 0.5, (0.0, 0.0),
                                    seconds_to_time(0.0))
    map_pub.publish(grid)       # before the recorder joins: it must still get it (latched)
    topics = [BagTopic('/robot/map', OccupancyGrid, LATCHED_QOS),
              BagTopic('/robot/scan', LaserScan, SENSOR_QOS)]
    recorder_node = Node('recorder', context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(publisher_node)
    executor.add_node(recorder_node)
    with BagWriter(tmp_path / 'bag', topics) as bag:
        recorder = TopicRecorder(recorder_node, bag, topics)
        sent = 0
        for _ in range(400):
            executor.spin_once(timeout_sec=0.01)
            if recorder_node.count_publishers('/robot/scan') and sent < 20 and \
                    scan_pub.get_subscription_count():
                scan_pub.publish(_scan(sent))
                sent += 1
            if bag.counts['/robot/scan'] >= 15 and bag.counts['/robot/map']:
                break
    executor.shutdown()
    assert recorder.writer is bag
    recorded = read_bag(tmp_path / 'bag')
    assert recorded.counts()['/robot/map'] == 1
    assert recorded.counts()['/robot/scan'] >= 15
    ((_, received),) = recorded.messages['/robot/map']
    assert bytes(np.array(received.data, dtype=np.int8)) == bytes(grid.data)
    times = log_times(recorded, '/robot/scan')
    assert times == sorted(times) and times[0] > 0      # wall time: the node has no sim time
    scans = [msg for _, msg in recorded.messages['/robot/scan']]
    assert [round(s.ranges[0] - 0.5) for s in scans] == list(range(len(scans)))


def test_demo_refuses_an_existing_bag_before_starting(tmp_path, capsys):
    from dpn_navigator.tools import demo
    (tmp_path / 'bag').mkdir()
    with pytest.raises(SystemExit) as exit_info:
        demo.main(['--record', str(tmp_path / 'bag'), '--out', str(tmp_path / 'out')])
    assert exit_info.value.code == 2
    error = capsys.readouterr().err
    assert '--record:' in error and 'exists already' in error and 'Traceback' not in error
    assert not (tmp_path / 'out').exists()      # nothing was started
    assert os.listdir(tmp_path / 'bag') == []


# -- the Foxglove layout -----------------------------------------------------------------------

LAYOUT = Path(__file__).resolve().parents[2] / 'config' / 'dpn_foxglove_layout.json'


def _panel_ids(tree):
    """Return the panel ids of a Foxglove layout tree (a panel id or a split)."""
    if isinstance(tree, str):
        return [tree]
    return _panel_ids(tree['first']) + _panel_ids(tree['second'])


def test_foxglove_layout_shows_the_bag_topics_like_the_rviz_config():
    import yaml
    layout = json.loads(LAYOUT.read_text())
    panels = _panel_ids(layout['layout'])
    assert sorted(panels) == sorted(layout['configById'])
    three_d = layout['configById']['3D!dpn']
    bag_topics = {topic.name for topic in episode_topics()}
    shown = {name for name, settings in three_d['topics'].items() if settings['visible']}
    assert shown <= bag_topics
    # Every topic the RViz config displays is shown in the 3D panel too.
    rviz = yaml.safe_load((LAYOUT.parent / 'dpn.rviz').read_text())
    rviz_topics = {d['Topic']['Value'] for d in rviz['Visualization Manager']['Displays']
                   if d.get('Enabled') and 'Topic' in d}
    assert rviz_topics <= shown
    assert three_d['followTf'] == 'map'
    assert three_d['topics']['/compabot/map']['colorMode'] == 'map'
    for panel in panels:
        settings = layout['configById'][panel]
        paths = [p['value'] for p in settings.get('paths', [])] + \
            [settings.get('topicPath', '')]
        for path in filter(None, paths):
            assert path.split('.')[0] in bag_topics, path
