"""
``recording/bag_reader``: any bag read into plain records, with no rclpy.

Bags of every kind the reader claims: rosbag2 folders with MCAP and sqlite3 storage and a bare
``.mcap`` file (written here with rosbags' writer), and the real ROS 1 bags of
``../shared/realdata`` (skipped when absent).
"""

import math
import subprocess
import sys

from bag_building import (LASER_SCAN, laser_scan, POSE_ARRAY, pose_array, S, TF_MESSAGE,
                          tf_message, transform_stamped, write_bag, write_ros1_bag)
from dpn_navigator.core.frames import TfBuffer
from dpn_navigator.recording.bag_reader import BagReader, BagReadError, fill_tf_buffer
import numpy as np
from numpy.testing import assert_allclose, assert_array_equal
import pytest
from realdata_paths import real_bag, real_bag_ids

YAW_90 = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))


def sample_items():
    """Two scans (one with intensities and inf/NaN), TF (dynamic and static), a PoseArray."""
    return [
        ('/tf_static', TF_MESSAGE, 1 * S, tf_message(
            transform_stamped(0, 'base_link', 'laser', (0.2, 0.0, 0.1), (1.0, 0.0, 0.0, 0.0)))),
        ('/tf', TF_MESSAGE, 1 * S, tf_message(
            transform_stamped(1 * S, 'odom', 'base_link', (0.0, 0.0, 0.0), (0, 0, 0, 1)),
            transform_stamped(1 * S, 'map', 'odom', (1.0, 0.0, 0.0), (0, 0, 0, 1)))),
        ('/scan', LASER_SCAN, 1 * S + 5, laser_scan(
            1 * S + 123, 'laser', [1.0, math.inf, math.nan, 2.5], intensities=[10, 20, 30, 40])),
        ('/tf', TF_MESSAGE, 2 * S, tf_message(
            transform_stamped(2 * S, 'odom', 'base_link', (2.0, 0.0, 0.0), YAW_90),
            transform_stamped(2 * S, 'map', 'odom', (1.0, 0.0, 0.0), (0, 0, 0, 1)))),
        ('/scan', LASER_SCAN, 2 * S + 5, laser_scan(2 * S, 'laser', [3.0, 3.0, 3.0, 3.0])),
        ('/people', POSE_ARRAY, 2 * S + 6,
         pose_array(2 * S, 'laser', [(1.0, 2.0, 0.0), (3.0, -1.0, 0.0)])),
    ]


@pytest.fixture(params=['mcap', 'sqlite3', 'bare_mcap'])
def sample_bag(request, tmp_path):
    storage = 'sqlite3' if request.param == 'sqlite3' else 'mcap'
    folder = write_bag(tmp_path / 'bag', sample_items(), storage=storage)
    if request.param == 'bare_mcap':
        (mcap,) = folder.glob('*.mcap')
        return mcap.rename(tmp_path / 'alone.mcap')
    return folder


def test_topics_and_types(sample_bag):
    with BagReader(sample_bag) as bag:
        assert {name: (info.msg_type, info.count) for name, info in bag.topics.items()} == {
            '/tf_static': (TF_MESSAGE, 1), '/tf': (TF_MESSAGE, 2), '/scan': (LASER_SCAN, 2),
            '/people': (POSE_ARRAY, 1)}
        assert bag.topics_of_type(LASER_SCAN) == ['/scan']
        assert bag.topics_of_type('tf2_msgs/msg/TFMessage') == ['/tf', '/tf_static']


def test_scans_come_out_as_records_with_header_stamps(sample_bag):
    with BagReader(sample_bag) as bag:
        first, second = bag.laser_scans('/scan')
    assert (first.stamp_ns, first.log_time_ns, first.frame_id) == (1 * S + 123, 1 * S + 5,
                                                                   'laser')
    assert first.ranges.dtype == np.float32
    assert_array_equal(first.ranges, np.array([1.0, math.inf, math.nan, 2.5], np.float32))
    assert_array_equal(first.intensities, [10, 20, 30, 40])
    assert first.angle_min == pytest.approx(-math.pi / 2)
    assert first.angle_increment == pytest.approx(math.pi / 3)
    assert (first.range_min, first.range_max) == pytest.approx((0.05, 10.0))
    assert second.stamp_ns == 2 * S and second.intensities.shape == (0,)


def test_transforms_and_a_buffer_filled_from_them(sample_bag):
    with BagReader(sample_bag) as bag:
        records = list(bag.transforms())
        buffer = TfBuffer(cache_duration_ns=None)
        assert fill_tf_buffer(bag, buffer) == (5, 0, [])
    assert [(r.parent_frame, r.child_frame, r.static) for r in records] == [
        ('base_link', 'laser', True), ('odom', 'base_link', False), ('map', 'odom', False),
        ('odom', 'base_link', False), ('map', 'odom', False)]
    assert_allclose(records[0].rotation, (1.0, 0.0, 0.0, 0.0))
    laser = buffer.lookup('map', 'laser', 1500_000_000)
    assert_allclose(laser.translation[:2], (1.0 + 1.0 + 0.2 * math.cos(math.pi / 4),
                                            0.2 * math.sin(math.pi / 4)), atol=1e-9)


def test_a_ros1_bag_with_old_tf_messages_and_slashed_frames(tmp_path):
    items = sample_items()
    for _, _, _, message in items:
        for transform in getattr(message, 'transforms', []):
            transform.header.frame_id = '/' + transform.header.frame_id
            transform.child_frame_id = '/' + transform.child_frame_id
    path = write_ros1_bag(tmp_path / 'old.bag', items, rename={TF_MESSAGE: 'tf/msg/tfMessage'})
    with BagReader(path) as bag:
        assert bag.topics['/tf'].msg_type == 'tf/msg/tfMessage'
        records = list(bag.transforms())
        (scan, _) = bag.laser_scans('/scan')
        (people,) = bag.pose_arrays('/people')
    assert [(r.parent_frame, r.child_frame, r.static) for r in records] == [
        ('base_link', 'laser', True), ('odom', 'base_link', False), ('map', 'odom', False),
        ('odom', 'base_link', False), ('map', 'odom', False)]
    assert scan.stamp_ns == 1 * S + 123 and people.positions.shape == (2, 3)


def test_pose_arrays(sample_bag):
    with BagReader(sample_bag) as bag:
        (people,) = bag.pose_arrays('/people')
    assert (people.stamp_ns, people.frame_id) == (2 * S, 'laser')
    assert_allclose(people.positions, [[1.0, 2.0, 0.0], [3.0, -1.0, 0.0]])
    assert people.orientations.shape == (2, 4)


def test_wrong_topics_are_refused(sample_bag):
    with BagReader(sample_bag) as bag:
        with pytest.raises(ValueError, match="'/tf' holds tf2_msgs/msg/TFMessage, not"):
            list(bag.laser_scans('/tf'))
        with pytest.raises(KeyError, match="'/nothing' is not in the bag"):
            list(bag.pose_arrays('/nothing'))


def test_unreadable_bags_are_a_clear_error(tmp_path):
    (tmp_path / 'empty').mkdir()
    (tmp_path / 'junk.bag').write_bytes(b'not a bag at all')
    (tmp_path / 'junk.mcap').write_bytes(b'\x89MCAP0\r\n garbage')
    (tmp_path / 'notes.txt').write_text('hello')
    cases = {'missing': 'does not exist', 'empty': 'without metadata.yaml',
             'junk.bag': 'cannot read the bag', 'junk.mcap': 'cannot read the bag',
             'notes.txt': 'is not a bag'}
    for name, message in cases.items():
        with pytest.raises(BagReadError, match=message):
            BagReader(tmp_path / name)


def test_the_reader_imports_no_rclpy():
    code = ('import sys; import dpn_navigator.recording.bag_reader as m; '
            'import dpn_navigator.core.frames; assert "rclpy" not in sys.modules')
    subprocess.run([sys.executable, '-c', code], check=True)


@pytest.mark.parametrize('name', real_bag_ids())
def test_real_ros1_bags(name):
    path = real_bag(name)
    with BagReader(path) as bag:
        (topic,) = bag.topics_of_type(LASER_SCAN)
        scans = list(bag.laser_scans(topic))
        assert len(scans) == bag.topics[topic].count > 0
        assert list(bag.transforms()) == []
        poses = [list(bag.pose_arrays(t)) for t in bag.topics_of_type(POSE_ARRAY)]
    stamps = np.array([scan.stamp_ns for scan in scans])
    assert np.all(np.diff(stamps) > 0)                   # about 10 Hz, in order
    assert scans[0].frame_id in ('laser', 'right_laser')
    beams = {len(scan.ranges) for scan in scans}
    assert beams in ({512}, {768})
    if poses:
        (annotations,) = poses
        assert len(annotations) == len(scans)
        assert all(p.positions.shape[1] == 3 for p in annotations)
