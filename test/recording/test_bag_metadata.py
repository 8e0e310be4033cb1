"""
Bags like rosbag2 Jazzy's own: ``ros_distro: jazzy`` and each MCAP channel's type hash.

rosbag2 Jazzy's MCAP storage (``rosbag2_storage_mcap/src/mcap_storage.cpp``,
``MCAPStorage::create_topic``) gives each channel the metadata keys ``offered_qos_profiles``
and ``topic_type_hash``, writes ``ros2msg`` schemas and ``cdr`` channels under the ``ros2``
profile, and stores the bag's metadata (with ``ros_distro``) in an MCAP metadata record
``rosbag2`` (``update_metadata``); ``metadata.yaml`` lists each topic's
``type_description_hash``. Read back here with the MCAP project's reader.
"""

from bag_reading import read_bag
from dpn_navigator.recording.bag_reader import BagReader
from dpn_navigator.recording.bag_writer import BagTopic, BagWriter, with_ros_distro
from dpn_navigator.ros.qos import LATCHED_QOS, SENSOR_QOS
from mcap.reader import make_reader
from nav_msgs.msg import OccupancyGrid
import pytest
from rosbags.typesys import get_typestore, Stores
from sensor_msgs.msg import LaserScan
import yaml


@pytest.fixture
def small_bag(tmp_path):
    path = tmp_path / 'bag'
    with BagWriter(path, [BagTopic('/scan', LaserScan, SENSOR_QOS),
                          BagTopic('/map', OccupancyGrid, LATCHED_QOS)]) as writer:
        writer.write('/scan', LaserScan(), 1)
        writer.write('/map', OccupancyGrid(), 2)
    return path


def test_channels_carry_their_type_hash_and_qos(small_bag):
    store = get_typestore(Stores.ROS2_JAZZY)
    (mcap_file,) = small_bag.glob('*.mcap')
    with open(mcap_file, 'rb') as stream:
        reader = make_reader(stream)
        assert reader.get_header().profile == 'ros2'
        summary = reader.get_summary()
        (record,) = list(reader.iter_metadata())
    schemas = summary.schemas
    info = yaml.safe_load((small_bag / 'metadata.yaml').read_text())
    listed = {t['topic_metadata']['name']: t['topic_metadata']
              for t in info['rosbag2_bagfile_information']['topics_with_message_count']}
    for channel in summary.channels.values():
        msg_type = schemas[channel.schema_id].name
        assert schemas[channel.schema_id].encoding == 'ros2msg'
        assert channel.message_encoding == 'cdr'
        assert channel.metadata['topic_type_hash'] == store.hash_rihs01(msg_type)
        assert channel.metadata['topic_type_hash'] == \
            listed[channel.topic]['type_description_hash']
        assert yaml.safe_load(channel.metadata['offered_qos_profiles']) == \
            listed[channel.topic]['offered_qos_profiles']
    assert record.name == 'rosbag2'
    assert yaml.safe_load(record.metadata['serialized_metadata'])['ros_distro'] == 'jazzy'
    assert info['rosbag2_bagfile_information']['ros_distro'] == 'jazzy'


def test_the_bag_reads_back_with_both_readers(small_bag):
    assert read_bag(small_bag).counts() == {'/scan': 1, '/map': 1}
    with BagReader(small_bag) as bag:           # rosbags checks the hashes it reads
        assert [s.stamp_ns for s in bag.laser_scans('/scan')] == [0]


def test_the_distribution_line_is_replaced_once():
    text = 'rosbag2_bagfile_information:\n  relative_file_paths: []\n  ros_distro: rosbags\n'
    assert with_ros_distro(text) == text.replace('rosbags', 'jazzy')
    with pytest.raises(ValueError, match='one ros_distro line'):
        with_ros_distro('version: 9\n')
