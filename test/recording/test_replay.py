"""
``dpn-replay``: dpn's labelling run on recorded bags, one map per scan.

On the real ROS 1 bags of ``../shared/realdata`` (``--pose fixed``; skipped when absent), on a
bag written here of a moving, upside-down laser with TF (``map -> odom -> base_link -> laser``,
TF logged after the scans), on an episode bag of the benchmark's recorder, and on the error
paths. Every output bag is read back with the MCAP project's reader (``bag_reading``).
"""

import csv
import math
from pathlib import Path
import subprocess
import sys

from bag_building import (LASER_SCAN, laser_scan, S, TF_MESSAGE, tf_message,
                          transform_stamped, write_bag, write_ros1_bag)
from bag_reading import read_bag, stamp_ns
from dpn_navigator.core.cell_label import CellLabel, OCCUPANCY_VALUE
from dpn_navigator.core.frames import Transform3D
from dpn_navigator.recording.bag_reader import BagReader
from dpn_navigator.recording.replay_output import CSV_COLUMNS
from dpn_navigator.recording.scan_poses import grid_box
from dpn_navigator.tools import replay as replay_tool
import numpy as np
import pytest
from realdata_paths import real_bag, real_bag_ids

ROOM = (0.0, 10.0, 0.0, 6.0)        # x_min, x_max, y_min, y_max of the walls [m]
MAP_TO_ODOM = Transform3D.from_xyz_rpy(1.0, 0.5, 0.0, yaw=0.1)
BASE_TO_LASER = Transform3D.from_xyz_rpy(0.3, 0.0, 0.4, roll=math.pi, yaw=0.4)   # upside down
BEAMS = 181
SCAN_TIMES = [0.05 + 0.1 * k for k in range(50)]      # [s]; TF at 20 Hz from 0 to 5.5 s


def base_in_map(t):
    """Return the robot's true pose at ``t`` [s]: a straight drive with a steady turn."""
    return Transform3D.from_xyz_rpy(2.0 + 0.9 * t, 2.0 + 0.3 * t, 0.0, yaw=0.3 + 0.1 * t)


def room_ranges(laser, beams=BEAMS):
    """Ray-cast a laser (a Transform3D in the map) against the room's four walls."""
    angles = -math.pi / 2 + np.arange(beams) * (math.pi / (beams - 1))
    directions = np.column_stack([np.cos(angles), np.sin(angles), np.zeros(beams)])
    in_map = directions @ laser.rotation_matrix().T
    x, y = laser.translation[:2]
    ranges = np.full(beams, np.inf)
    x_min, x_max, y_min, y_max = ROOM
    for i, (dx, dy, _) in enumerate(in_map):
        for wall, origin, d in ((x_min, x, dx), (x_max, x, dx), (y_min, y, dy), (y_max, y, dy)):
            if abs(d) > 1e-12 and (wall - origin) / d > 0:
                ranges[i] = min(ranges[i], (wall - origin) / d)
    return ranges, angles


def moving_laser_items(with_map=True, late_tf=0.3, lost_every=0):
    """
    Items of a bag: TF at 20 Hz logged ``late_tf`` s late, scans at 10 Hz, one too early.

    With ``lost_every`` > 0 every so many beams return nothing (a real laser's lost returns).
    """
    items = [('/tf_static', TF_MESSAGE, 0, tf_message(transform_stamped(
        0, 'base_link', 'laser', BASE_TO_LASER.translation, BASE_TO_LASER.rotation)))]
    for k in range(111):
        t = 0.05 * k
        stamp = int(round(t * S))
        odom_to_base = MAP_TO_ODOM.inverse() @ base_in_map(t)
        transforms = [transform_stamped(stamp, 'odom', 'base_link', odom_to_base.translation,
                                        odom_to_base.rotation)]
        if with_map:
            transforms.append(transform_stamped(stamp, 'map', 'odom', MAP_TO_ODOM.translation,
                                                MAP_TO_ODOM.rotation))
        items.append(('/tf', TF_MESSAGE, stamp + int(late_tf * S), tf_message(*transforms)))
    for t in [-0.5] + SCAN_TIMES:              # the first has no TF around it: skipped
        stamp = int(round(t * S)) + 10 * S      # + 10 s: no stamp 0
        ranges, _ = room_ranges(base_in_map(max(t, 0.0)) @ BASE_TO_LASER)
        if lost_every:
            ranges[lost_every // 2::lost_every] = np.inf
        items.append(('/scan', LASER_SCAN, stamp,
                      laser_scan(stamp, 'laser', ranges, range_max=20.0)))
    # The TF stamps are shifted by the same 10 s.
    shifted = []
    for topic, msg_type, log_time, message in items:
        if topic == '/tf':
            for transform in message.transforms:
                transform.header.stamp.sec += 10
            log_time += 10 * S
        shifted.append((topic, msg_type, log_time, message))
    return sorted(shifted, key=lambda item: item[2])


def distance_to_walls(x, y):
    """Distance from map points to the nearest wall of the room [m]."""
    x_min, x_max, y_min, y_max = ROOM
    return np.minimum.reduce([np.abs(x - x_min), np.abs(x - x_max), np.abs(y - y_min),
                              np.abs(y - y_max)])


def final_labels(out):
    """Return the last map of a replay's bag as labels, with its geometry."""
    bag = read_bag(out / 'replay')
    _, last = bag.messages['/map'][-1]
    values = np.array(last.data, dtype=np.int8).reshape(last.info.height, last.info.width)
    labels = np.searchsorted(np.sort(OCCUPANCY_VALUE), values)
    order = np.argsort(OCCUPANCY_VALUE)     # values sorted -> their labels
    return bag, order[labels], last.info


def check_one_map_per_scan(bag, scan_topic, expected_maps):
    """Every map stamped with its scan's stamp, one per scan, values in the node's set."""
    maps = bag.messages['/map']
    scans = bag.messages[scan_topic]
    assert len(maps) == len(scans) == expected_maps
    assert [stamp_ns(m.header.stamp) for _, m in maps] == \
        [stamp_ns(s.header.stamp) for _, s in scans]
    assert [t for t, _ in maps] == [stamp_ns(m.header.stamp) for _, m in maps]
    for _, grid in maps[::max(1, len(maps) // 10)]:
        assert set(np.unique(np.array(grid.data, dtype=np.int8))) <= {-1, 0, 70, 100}
    assert bag.counts()['/marker'] >= 1


def run(args):
    """Run dpn-replay in-process; return its exit status."""
    return replay_tool.main([str(a) for a in args])


@pytest.fixture(scope='module')
def tf_bag(tmp_path_factory):
    return write_bag(tmp_path_factory.mktemp('tf') / 'moving', moving_laser_items())


@pytest.fixture(scope='module')
def tf_replay(tf_bag, tmp_path_factory):
    out = tmp_path_factory.mktemp('replay') / 'new' / 'dir'      # --out need not exist
    assert run([tf_bag, '--out', out]) == 0
    return out


def test_a_moving_upside_down_laser_maps_the_walls_where_they_are(tf_replay, tf_bag):
    bag, labels, info = final_labels(tf_replay)
    check_one_map_per_scan(bag, '/scan', len(SCAN_TIMES))
    assert {m.header.frame_id for _, m in bag.messages['/map']} == {'map'}
    # The transforms come along (for RViz): every /tf message, /tf_static once.
    assert bag.counts()['/tf'] == 111
    ((static_time, static),) = bag.messages['/tf_static']
    assert static_time == bag.messages['/map'][0][0]
    assert [(t.header.frame_id, t.child_frame_id) for t in static.transforms] == \
        [('base_link', 'laser')]
    rows, cols = np.indices(labels.shape)
    x = info.origin.position.x + (cols + 0.5) * info.resolution
    y = info.origin.position.y + (rows + 0.5) * info.resolution
    obstacle = (labels == CellLabel.STEADY_OBSTACLE) | (labels == CellLabel.MOBILE_OBSTACLE)
    # Every obstacle cell lies within the safety radius (0.6 m) of a wall, up to a half cell.
    assert obstacle.sum() > 50
    assert distance_to_walls(x[obstacle], y[obstacle]).max() <= 0.6 + 0.5 * math.sqrt(2) * 0.5
    # Every true hit point's cell is an obstacle, steady (a wall never moves).
    with BagReader(tf_bag) as reader:
        scans = list(reader.laser_scans('/scan'))[1:]
    hits_x, hits_y = [], []
    for t, scan in zip(SCAN_TIMES, scans):
        laser = base_in_map(t) @ BASE_TO_LASER
        ranges, angles = room_ranges(laser)
        points = laser.apply(np.column_stack([ranges * np.cos(angles),
                                              ranges * np.sin(angles)]))
        hits_x.append(points[:, 0])
        hits_y.append(points[:, 1])
    cc = ((np.concatenate(hits_x) - info.origin.position.x) / info.resolution).astype(int)
    rr = ((np.concatenate(hits_y) - info.origin.position.y) / info.resolution).astype(int)
    assert np.mean(labels[rr, cc] == CellLabel.STEADY_OBSTACLE) >= 0.99
    # Inside the room, away from the walls, the seen cells are explored.
    inner = distance_to_walls(x, y) > 1.2
    inside = (x > ROOM[0]) & (x < ROOM[1]) & (y > ROOM[2]) & (y < ROOM[3]) & inner
    assert np.mean(labels[inside] == CellLabel.EXPLORED) >= 0.9


def slashed(items):
    """Return bag items with ROS 1 style frame names: a leading '/' on every frame id."""
    for _, _, _, message in items:
        for transform in getattr(message, 'transforms', []):
            transform.header.frame_id = '/' + transform.header.frame_id
            transform.child_frame_id = '/' + transform.child_frame_id
        if hasattr(message, 'ranges'):
            message.header.frame_id = '/' + message.header.frame_id
    return items


@pytest.mark.parametrize('tf_type', [TF_MESSAGE, 'tf/msg/tfMessage'])
def test_a_ros1_bag_with_tf_replays_like_the_rosbag2_one(tf_replay, tmp_path, tf_type):
    """ROS 1: Noetic types, tf2's TFMessage or the old tf/tfMessage, frames named '/odom'."""
    bag = write_ros1_bag(tmp_path / 'moving.bag', slashed(moving_laser_items()),
                         rename={TF_MESSAGE: tf_type})
    assert run([bag, '--out', tmp_path / 'out']) == 0
    _, labels, info = final_labels(tmp_path / 'out')
    _, expected, expected_info = final_labels(tf_replay)
    assert (info.width, info.height, info.origin.position.x) == \
        (expected_info.width, expected_info.height, expected_info.origin.position.x)
    np.testing.assert_array_equal(labels, expected)


def test_a_scan_with_no_pose_is_skipped_and_counted(tf_bag, tmp_path, capsys):
    assert run([tf_bag, '--out', tmp_path / 'out']) == 0
    output = capsys.readouterr().out
    assert f'{len(SCAN_TIMES)} maps from {len(SCAN_TIMES) + 1} scans of /scan (1 skipped)' \
        in output
    assert 'no transform map -> laser: ExtrapolationError' in output


def test_the_csv_has_a_row_per_map(tf_replay):
    with open(tf_replay / 'replay.csv') as stream:
        rows = list(csv.reader(stream))
    assert tuple(rows[0]) == CSV_COLUMNS
    assert len(rows) == 1 + len(SCAN_TIMES)
    bag, labels, _ = final_labels(tf_replay)
    last = [int(v) for v in rows[-1][1:5]]
    assert last == np.bincount(labels.ravel(), minlength=4).tolist()
    assert [int(r[0]) for r in rows[1:]] == [stamp_ns(m.header.stamp)
                                             for _, m in bag.messages['/map']]
    assert all(float(r[5]) > 0.0 for r in rows[1:])
    assert (tf_replay / 'replay.png').stat().st_size > 1000
    assert not (tf_replay / 'replay.gif').exists()


def test_without_a_map_frame_odom_is_the_map_frame(tmp_path):
    bag = write_bag(tmp_path / 'odom_only', moving_laser_items(with_map=False))
    assert run([bag, '--out', tmp_path / 'out', '--animate']) == 0
    replayed = read_bag(tmp_path / 'out' / 'replay')
    assert {m.header.frame_id for _, m in replayed.messages['/map']} == {'odom'}
    assert (tmp_path / 'out' / 'replay.gif').stat().st_size > 1000


def test_fixed_pose_takes_the_laser_frame_as_the_map_frame(tf_bag, tmp_path):
    assert run([tf_bag, '--out', tmp_path / 'out', '--pose', 'fixed']) == 0
    bag, labels, info = final_labels(tmp_path / 'out')
    assert {m.header.frame_id for _, m in bag.messages['/map']} == {'laser'}
    check_one_map_per_scan(bag, '/scan', len(SCAN_TIMES) + 1)
    # The laser at the origin: the grid is around it.
    assert info.origin.position.x < 0.0 < info.origin.position.x + info.width * info.resolution


def test_a_params_file_grid_too_small_for_the_scans_is_warned_about(tf_bag, tmp_path, capsys):
    params = tmp_path / 'params.yaml'
    params.write_text('/**/dpn:\n  ros__parameters:\n    map_width: 5.0\n    map_height: 5.0\n'
                      '    origin_x: 0.0\n    origin_y: 0.0\n')
    assert run([tf_bag, '--out', tmp_path / 'out', '--params-file', params]) == 0
    (line,) = capsys.readouterr().err.splitlines()
    assert line.startswith('dpn-replay: warning: the grid of the params file, 5 x 5 m at (0, 0)')
    _, last = read_bag(tmp_path / 'out' / 'replay').messages['/map'][-1]
    assert (last.info.width, last.info.height) == (10, 10)


def test_the_paper_navigator_and_a_params_file(tf_bag, tmp_path):
    params = tmp_path / 'params.yaml'
    params.write_text('/**:\n  ros__parameters:\n    resolution: 0.25\n'
                      'dpn:\n  ros__parameters:\n    map_width: 14\n    origin_x: -2.0\n'
                      '    map_mobile_value: 55\n')
    assert run([tf_bag, '--out', tmp_path / 'out', '--navigator', 'paper',
                '--params-file', params]) == 0
    bag = read_bag(tmp_path / 'out' / 'replay')
    _, last = bag.messages['/map'][-1]
    assert last.info.resolution == 0.25
    assert last.info.width == 14 / 0.25 and last.info.origin.position.x == -2.0
    assert bag.metadata['custom_data']['navigator'] == 'paper'


@pytest.mark.parametrize('name', real_bag_ids())
def test_real_recordings_replay_with_a_fixed_laser(name, tmp_path):
    path = real_bag(name)
    with BagReader(path) as reader:
        (topic,) = reader.topics_of_type(LASER_SCAN)
        count = reader.topics[topic].count
    out = tmp_path / 'out'
    assert run([path, '--out', out, '--pose', 'fixed']) == 0
    bag = read_bag(out / 'replay')
    check_one_map_per_scan(bag, '/' + topic.lstrip('/'), count)
    frames = {m.header.frame_id for _, m in bag.messages['/map']}
    assert frames == {'right_laser'} or frames == {'laser'}
    _, first_scan = bag.messages['/' + topic.lstrip('/')][0]
    with BagReader(path) as reader:
        original = next(reader.laser_scans(topic))
    np.testing.assert_array_equal(np.array(first_scan.ranges, np.float32), original.ranges)


@pytest.mark.slow
def test_a_benchmark_episode_bag_replays_into_the_same_walls(tmp_path):
    from dpn_navigator.benchmark.episode import run_episode
    from dpn_navigator.benchmark.episode_bag import EpisodeBagRecorder
    from sim_bridge.scenario import load_scenario
    scenario = load_scenario('back_and_forth')
    with EpisodeBagRecorder(tmp_path / 'episode', {'scenario': 'back_and_forth'}) as recorder:
        run_episode(scenario, 0, 2, 7, time_limit=6.0, recorder=recorder)
    episode = read_bag(tmp_path / 'episode')
    assert run([tmp_path / 'episode', '--out', tmp_path / 'out']) == 0   # --pose tf
    bag, labels, info = final_labels(tmp_path / 'out')
    check_one_map_per_scan(bag, '/compabot/scan', len(episode.messages['/compabot/scan']))
    _, node_map = episode.messages['/compabot/map'][-1]
    node_values = np.array(node_map.data, dtype=np.int8).reshape(node_map.info.height,
                                                                 node_map.info.width)
    # The node's steady cells, looked up in the replay's grid (both on 0.5 m cells from 0).
    rows, cols = np.nonzero(node_values == 100)
    x = node_map.info.origin.position.x + (cols + 0.5) * node_map.info.resolution
    y = node_map.info.origin.position.y + (rows + 0.5) * node_map.info.resolution
    rr = ((y - info.origin.position.y) / info.resolution).astype(int)
    cc = ((x - info.origin.position.x) / info.resolution).astype(int)
    assert len(rows) > 20
    assert np.mean(labels[rr, cc] == CellLabel.STEADY_OBSTACLE) >= 0.95


@pytest.mark.slow
def test_a_recorded_real_laser_with_no_one_moving_replays_with_no_mobile_cell(tmp_path):
    """
    A moving robot's bag with a real laser: by default, nothing is taken for moving.

    The simulated UTM-30LX (grazing walls return nothing, returns lost, mixed pixels) on
    back_and_forth, no wanderer: every mobile cell is wrong. With ``real_laser_switch`` 0 the
    replay keeps dpn's ideal-laser settings and takes walls for moving.
    """
    from dpn_navigator.benchmark.episode import run_episode
    from dpn_navigator.benchmark.episode_bag import EpisodeBagRecorder
    from dpn_navigator.benchmark.protocol import NAVIGATORS
    from sim_bridge.laser_profiles import laser_config
    from sim_bridge.scenario import load_scenario
    scenario = load_scenario('back_and_forth')
    with EpisodeBagRecorder(tmp_path / 'episode', {'scenario': 'back_and_forth'}) as recorder:
        run_episode(scenario, 0, 0, 7, time_limit=15.0, recorder=recorder,
                    navigator_options=NAVIGATORS['dpn_real_laser'],
                    laser=laser_config('hokuyo_utm30lx'))
    params = tmp_path / 'off.yaml'
    params.write_text('/**/dpn:\n  ros__parameters:\n    real_laser_switch: 0.0\n')
    mobile = {}
    for name, extra in (('default', []), ('off', ['--params-file', params])):
        assert run([tmp_path / 'episode', '--out', tmp_path / name, *extra]) == 0
        with open(tmp_path / name / 'replay.csv', newline='') as stream:
            mobile[name] = [int(row['cells_mobile_obstacle']) for row in csv.DictReader(stream)]
    assert len(mobile['default']) > 100
    assert max(mobile['default']) == 0
    assert sum(count > 0 for count in mobile['off']) > 0.3 * len(mobile['off'])


@pytest.mark.slow
def test_a_bag_recorded_by_dpn_benchmark_replays(tmp_path):
    """The real command line: ``dpn-benchmark --record``, one smoke episode, then replayed."""
    subprocess.run(
        [sys.executable, '-m', 'dpn_navigator.benchmark', '--maps', 'back_and_forth',
         '--tasks', '0', '--wanderers', '0', '--repeats', '1', '--out', str(tmp_path / 'bm'),
         '--record', str(tmp_path / 'bm' / 'bags'), '--no-progress', '--workers', '1',
         '--no-detection'], check=True, capture_output=True, timeout=600)
    (recorded,) = (tmp_path / 'bm' / 'bags').iterdir()
    episode = read_bag(recorded)
    assert run([recorded, '--out', tmp_path / 'out']) == 0
    bag = read_bag(tmp_path / 'out' / 'replay')
    check_one_map_per_scan(bag, '/compabot/scan', len(episode.messages['/compabot/scan']))


def bag_with(tmp_path, items, name='bag'):
    return write_bag(tmp_path / name, items)


def error_cases(tmp_path):
    scan = laser_scan(S, 'laser', [1.0, 2.0, 3.0])
    junk = tmp_path / 'junk.bag'
    junk.write_bytes(b'not a bag')
    no_scan = bag_with(tmp_path, [('/tf', TF_MESSAGE, S, tf_message(transform_stamped(
        S, 'odom', 'laser', (0, 0, 0), (0, 0, 0, 1))))], 'no_scan')
    two_scans = bag_with(tmp_path, [('/a', LASER_SCAN, S, scan), ('/b', LASER_SCAN, S, scan)],
                         'two_scans')
    no_tf = bag_with(tmp_path, [('/scan', LASER_SCAN, S, scan)], 'no_tf')
    with_tf = bag_with(tmp_path, [('/scan', LASER_SCAN, S, scan), *(
        ('/tf', TF_MESSAGE, S, tf_message(transform_stamped(
            t * S, 'odom', 'laser', (0, 0, 0), (0, 0, 0, 1)))) for t in (0, 2))], 'with_tf')
    bad_params = tmp_path / 'bad.yaml'
    bad_params.write_text('dpn:\n  ros__parameters:\n    resolution: fine\n')
    return {
        'unreadable bag': ([junk], 'cannot read the bag'),
        'missing bag': ([tmp_path / 'nothing.mcap'], 'does not exist'),
        'no scan topic': ([no_scan], 'no LaserScan topic'),
        'several scan topics': ([two_scans], '2 LaserScan topics'),
        'an unknown scan topic': ([two_scans, '--scan-topic', '/c'], 'no topic /c'),
        'no TF': ([no_tf], 'no TF in'),
        'no such map frame': ([with_tf, '--map-frame', 'world'], "no frame 'world'"),
        'bad parameter': ([no_tf, '--pose', 'fixed', '--params-file', bad_params],
                          'parameter resolution must be a number'),
    }


def test_errors_give_one_line_and_exit_2(tmp_path, capsys):
    for case, (args, message) in error_cases(tmp_path).items():
        assert run([*args, '--out', tmp_path / 'out']) == 2, case
        captured = capsys.readouterr()
        (line,) = captured.err.splitlines()
        assert line.startswith('dpn-replay: error: ') and message in line, (case, line)
        assert captured.out == ''
    assert not (tmp_path / 'out' / 'replay').exists()


def test_an_existing_output_bag_is_never_overwritten(tf_replay, tf_bag, capsys):
    assert run([tf_bag, '--out', tf_replay]) == 2
    assert 'exists already' in capsys.readouterr().err


def test_the_executable_runs_as_a_process(tmp_path):
    """The console script's entry, as ``ros2 run dpn_navigator dpn-replay`` starts it."""
    setup = (Path(__file__).resolve().parents[2] / 'setup.py').read_text()
    assert "'dpn-replay = dpn_navigator.tools.replay:main'," in setup
    junk = tmp_path / 'junk.mcap'
    junk.write_bytes(b'nothing')
    result = subprocess.run(
        [sys.executable, '-c', 'import sys; from dpn_navigator.tools.replay import main; '
         'sys.exit(main())', str(junk), '--out', str(tmp_path / 'o')],
        capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert len(result.stderr.splitlines()) == 1 and 'Traceback' not in result.stderr


@pytest.mark.parametrize('given, expected', [
    ({}, (14.0, 10.0, (-2.0, -2.0))),
    ({'width': 20.0}, (20.0, 10.0, (-5.0, -2.0))),
    ({'origin_x': -1.0}, (13.0, 10.0, (-1.0, -2.0))),
    ({'width': 8.0, 'height': 6.0, 'origin_x': 1.0, 'origin_y': 2.0},
     (8.0, 6.0, (1.0, 2.0))),
])
def test_the_grid_covers_the_extent_unless_given(given, expected):
    assert grid_box((0.0, 10.0, 0.0, 5.8), 0.5, given) == expected


def record(**fields):
    """Return a ScanRecord of 5 beams, with fields replaced."""
    from dpn_navigator.recording.bag_reader import ScanRecord
    values = {'topic': '/scan', 'log_time_ns': S, 'stamp_ns': S, 'frame_id': 'laser',
              'angle_min': -0.2, 'angle_max': 0.2, 'angle_increment': 0.1,
              'time_increment': 0.0, 'scan_time': 0.1, 'range_min': 0.1, 'range_max': 5.0,
              'ranges': np.array([1, 2, 3, 4, 5], np.float32), 'intensities': np.zeros(0)}
    values.update(fields)
    return ScanRecord(**values)


def test_scans_the_node_would_reject_are_skipped_and_counted():
    from dpn_navigator.recording.scan_poses import ScanPoses
    poses = ScanPoses('fixed')
    assert poses.place(record()).pose == (0.0, 0.0, 0.0)
    assert poses.map_frame == 'laser'
    reversed_scan = poses.place(record(angle_min=0.2, angle_max=-0.2, angle_increment=-0.1))
    assert reversed_scan.angle_min == pytest.approx(-0.2)
    np.testing.assert_array_equal(reversed_scan.ranges, [5, 4, 3, 2, 1])
    assert poses.place(record(angle_max=1.0)) is None            # 5 beams cannot span 1.2 rad
    assert poses.place(record(range_max=0.05)) is None
    assert poses.place(record(angle_increment=0.0)) is None
    assert sum(poses.skipped.values()) == 3
    assert all(reason.startswith('malformed scan') for reason in poses.skipped)


def test_a_moving_laser_gets_no_standing_hint_and_a_fixed_one_does(tf_bag, tmp_path, capsys):
    summary = replay_tool.replay(tf_bag, tmp_path / 'tf')
    assert not any('standing' in hint for hint in summary.hints)
    # The room's walls return every beam: no file is hinted at for the moving laser.
    assert summary.hints == []
    assert run([tf_bag, '--out', tmp_path / 'fixed', '--pose', 'fixed']) == 0
    err = capsys.readouterr().err
    assert 'dpn-replay: note: the laser stood still' in err
    assert 'config/dpn_standing_laser.yaml' in err
    assert run([tf_bag, '--out', tmp_path / 'paper', '--pose', 'fixed',
                '--navigator', 'paper']) == 0
    assert 'dpn_standing_laser' not in capsys.readouterr().err


def test_a_real_laser_on_the_move_switches_to_the_real_laser_settings(tmp_path, capsys):
    """As the node's Navigator does (``core.real_laser``): once, with a note saying so."""
    lossy = write_bag(tmp_path / 'lossy', moving_laser_items(lost_every=40))
    assert run([lossy, '--out', tmp_path / 'out']) == 0
    err = capsys.readouterr().err
    assert err.count('dpn-replay: note: a real laser: once it moved') == 1
    assert 'no_return_reach 0' in err and 'from 0.' in err
    # Switched off in a params file: the labels of a replay without the switch.
    params = tmp_path / 'off.yaml'
    params.write_text('dpn:\n  ros__parameters:\n    real_laser_switch: 0.0\n')
    assert run([lossy, '--out', tmp_path / 'off', '--params-file', params]) == 0
    assert 'a real laser' not in capsys.readouterr().err
    # The switch's effect: beams with no return clear nothing any more.
    explored = [int((final_labels(tmp_path / name)[1] == CellLabel.EXPLORED).sum())
                for name in ('out', 'off')]
    assert explored[0] < explored[1]


def test_the_ideal_room_never_switches(tf_replay, tf_bag):
    summary = replay_tool.replay(tf_bag, tf_replay.parent / 'again')
    assert not any('real laser' in hint for hint in summary.hints)
