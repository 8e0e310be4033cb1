"""
Read a recorded rosbag2 MCAP bag with a reader independent of the writer, for the tests.

The bags are written with ``rosbags``; here they are read with the MCAP project's own reader
(``mcap``) and ROS 2 decoder (``mcap-ros2-support``), which decode every message from the
schema the bag carries, not from the ROS installation. ``metadata.yaml`` is read as plain YAML
and checked against what rosbag2 (Jazzy) reads from it and against the MCAP file itself.
"""

from collections import Counter, defaultdict
from dataclasses import dataclass
from pathlib import Path

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
import yaml


@dataclass
class RecordedBag:
    """
    A bag as read back.

    Attributes
    ----------
    metadata : dict
        ``rosbag2_bagfile_information`` of ``metadata.yaml``.
    types : dict of str to str
        Message type of each topic, from the MCAP schemas.
    messages : dict of str to list of (int, object)
        ``(log_time_ns, decoded message)`` per topic, in file order.

    """

    metadata: dict
    types: dict
    messages: dict

    def counts(self):
        """Return the messages per topic."""
        return Counter({topic: len(items) for topic, items in self.messages.items()})


def read_bag(folder):
    """
    Read a bag folder and check that it is a valid rosbag2 MCAP bag.

    Checks the rosbag2 metadata fields Jazzy reads (version, storage identifier ``mcap``, the
    file list, per-topic counts, QoS, type hashes) against the MCAP file, and the MCAP profile
    and encodings (``ros2``, ``ros2msg`` schemas, ``cdr`` messages); and what rosbag2 Jazzy's
    MCAP storage writes besides: ``ros_distro: jazzy`` in ``metadata.yaml`` and in the MCAP
    file's ``rosbag2`` metadata record, and each channel's ``offered_qos_profiles`` and
    ``topic_type_hash`` (equal to the topic's ``type_description_hash``).

    Returns
    -------
    RecordedBag

    """
    folder = Path(folder)
    info = yaml.safe_load((folder / 'metadata.yaml').read_text())['rosbag2_bagfile_information']
    assert info['version'] == 9
    assert info['ros_distro'] == 'jazzy'
    assert info['storage_identifier'] == 'mcap'
    assert info['compression_mode'] == '' and info['compression_format'] == ''
    (relative,) = info['relative_file_paths']
    assert [f['path'] for f in info['files']] == [relative]
    types, messages = {}, defaultdict(list)
    with open(folder / relative, 'rb') as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        assert reader.get_header().profile == 'ros2'
        summary = reader.get_summary()
        (record,) = list(reader.iter_metadata())
        channel_metadata = {c.topic: dict(c.metadata) for c in summary.channels.values()}
        for schema, channel, message, decoded in reader.iter_decoded_messages(
                log_time_order=False):
            assert schema.encoding == 'ros2msg' and channel.message_encoding == 'cdr'
            types[channel.topic] = schema.name
            messages[channel.topic].append((message.log_time, decoded))
    assert record.name == 'rosbag2'
    serialized = yaml.safe_load(record.metadata['serialized_metadata'])
    assert serialized['ros_distro'] == 'jazzy' and serialized['version'] == 9
    bag = RecordedBag(info, types, dict(messages))
    counts = bag.counts()
    assert info['message_count'] == sum(counts.values()) == summary.statistics.message_count
    listed = {entry['topic_metadata']['name']: entry for entry in
              info['topics_with_message_count']}
    assert {name: entry['message_count'] for name, entry in listed.items()
            if entry['message_count']} == dict(counts)
    for name, entry in listed.items():
        topic = entry['topic_metadata']
        assert topic['serialization_format'] == 'cdr'
        assert topic['type_description_hash'].startswith('RIHS01_')
        assert len(topic['offered_qos_profiles']) == 1
        if name in types:
            assert types[name] == topic['type']
        channel = channel_metadata[name]
        assert set(channel) == {'offered_qos_profiles', 'topic_type_hash'}
        assert channel['topic_type_hash'] == topic['type_description_hash']
        assert yaml.safe_load(channel['offered_qos_profiles']) == topic['offered_qos_profiles']
    times = [t for items in messages.values() for t, _ in items]
    if times:
        assert info['starting_time']['nanoseconds_since_epoch'] == min(times)
        assert info['duration']['nanoseconds'] == max(times) - min(times)
    return bag


def log_times(bag, topic):
    """Return the log times of a topic's messages [ns], in file order."""
    return [t for t, _ in bag.messages[topic]]


def stamp_ns(stamp):
    """Return a decoded ``builtin_interfaces/Time`` in nanoseconds."""
    return stamp.sec * 1_000_000_000 + stamp.nanosec
