"""
rosbag2 bags with MCAP storage, from rclpy messages: for ``ros2 bag play`` and Foxglove.

A bag is a folder holding ``metadata.yaml`` (rosbag2 version 9, as Jazzy writes it) and one
``.mcap`` file whose chunks are zstd-compressed (MCAP's own compression, which every MCAP reader
undoes; the metadata lists no rosbag2 compression). Messages are serialised by rclpy
(``rclpy.serialization.serialize_message``, the CDR bytes a publisher sends) or come as those
bytes from a raw subscription. The writer is ``rosbags`` (docs/recording.md says why): it writes
each type's Jazzy message definition into the MCAP schema and its type hash into the metadata.

Two details are made as rosbag2 Jazzy's MCAP storage (``rosbag2_storage_mcap``,
``MCAPStorage::create_topic``) writes them, where rosbags differs: each MCAP channel's metadata
holds ``topic_type_hash`` (the type's ``RIHS01_`` hash) beside ``offered_qos_profiles``, and
``ros_distro`` is ``jazzy`` (rosbags writes ``rosbags``) in ``metadata.yaml`` and in the
MCAP file's ``rosbag2`` metadata record (``serialized_metadata``). `jazzy_writer_class` makes
that writer from rosbags' (pinned in requirements.txt, whose internals it extends).

"""

from dataclasses import dataclass
import functools
from io import BytesIO
import os
from pathlib import Path
import re

#: rosbag2 metadata version Jazzy writes.
METADATA_VERSION = 9
#: ``ros_distro`` of the bags written here.
ROS_DISTRO = 'jazzy'
_ROS_DISTRO_LINE = re.compile(r'^(\s*ros_distro:) .*$', re.MULTILINE)


def with_ros_distro(metadata_text, distro=ROS_DISTRO):
    """
    Return rosbag2 metadata YAML with its ``ros_distro`` line set to ``distro``.

    Parameters
    ----------
    metadata_text : str
        ``metadata.yaml`` or the ``serialized_metadata`` of an MCAP file, as rosbags dumps it.
    distro : str
        The distribution's name.

    Raises
    ------
    ValueError
        When the text holds no ``ros_distro`` line (a rosbags that dumps it otherwise).

    """
    text, count = _ROS_DISTRO_LINE.subn(lambda m: f'{m.group(1)} {distro}', metadata_text)
    if count != 1:
        raise ValueError(f'expected one ros_distro line in the bag metadata, found {count}')
    return text


@functools.lru_cache(maxsize=1)
def jazzy_writer_class():
    """
    Return a rosbags ``Writer`` whose bags carry what rosbag2 Jazzy's MCAP storage writes.

    Its MCAP storage adds ``topic_type_hash`` to each channel's metadata and both metadata
    copies say ``ros_distro: jazzy`` (see the module).

    Returns
    -------
    type
        A subclass of ``rosbags.rosbag2.Writer``.

    """
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.rosbag2.storage_mcap import Channel, McapWriter, write_channel, write_string

    class JazzyMcapStorage(McapWriter):
        """rosbags' MCAP storage, with rosbag2 Jazzy's channel metadata and distribution."""

        def add_connection(self, connection, offered_qos_profiles):
            # As rosbags' add_connection, plus the key rosbag2's create_topic adds.
            metadata = BytesIO()
            write_string(metadata, 'offered_qos_profiles')
            write_string(metadata, offered_qos_profiles)
            write_string(metadata, 'topic_type_hash')
            write_string(metadata, connection.digest or '')
            self.channels.append(Channel(connection.id, connection.msgtype, connection.topic,
                                         connection.ext.serialization_format,
                                         metadata.getvalue()))
            self.channel_stats[connection.id] = 0
            write_channel(self.chunk.bio, self.channels[-1], self.schemas)

        def close(self, version, metadata):
            super().close(version, with_ros_distro(metadata))

    class JazzyWriter(Writer):
        """rosbags' rosbag2 writer with `JazzyMcapStorage` and ``ros_distro: jazzy``."""

        STORAGE_PLUGINS = {**Writer.STORAGE_PLUGINS, StoragePlugin.MCAP: JazzyMcapStorage}

        def close(self):
            super().close()
            self.metapath.write_text(with_ros_distro(self.metapath.read_text()), 'utf8')

    return JazzyWriter


class BagPathError(ValueError):
    """A bag cannot be written where asked: the folder exists, or its parent is not writable."""


@dataclass(frozen=True)
class BagTopic:
    """
    One topic of a bag.

    Attributes
    ----------
    name : str
        Absolute topic name, e.g. ``/compabot/map``.
    msg_type : type
        The rclpy message class, e.g. ``nav_msgs.msg.OccupancyGrid``.
    qos : rclpy.qos.QoSProfile
        The QoS its publisher offers; ``ros2 bag play`` republishes with it (a latched map
        stays latched).

    """

    name: str
    msg_type: type
    qos: object


def message_type_name(msg_type):
    """
    Return the ROS 2 name of an rclpy message class, e.g. ``'nav_msgs/msg/OccupancyGrid'``.

    Raises
    ------
    ValueError
        When ``msg_type`` is not a generated message class (``<package>.msg``).

    """
    package, _, kind = msg_type.__module__.partition('.')
    if not kind.startswith('msg'):
        raise ValueError(f'{msg_type!r} is not a ROS 2 message class')
    return f'{package}/msg/{msg_type.__name__}'


@functools.lru_cache(maxsize=1)
def _typestore():
    """Return rosbags' store of the Jazzy message definitions (built once)."""
    from rosbags.typesys import get_typestore, Stores
    return get_typestore(Stores.ROS2_JAZZY)


def _bag_qos(profile):
    """Return an rclpy ``QoSProfile`` as rosbags' ``Qos`` (the metadata's offered profile)."""
    from rosbags.interfaces import (Qos, QosDurability, QosHistory, QosLiveliness,
                                    QosReliability, QosTime)

    def duration(value):
        nanoseconds = value.nanoseconds
        return QosTime(nanoseconds // 1_000_000_000, nanoseconds % 1_000_000_000)

    return Qos(
        history=QosHistory[profile.history.name], depth=int(profile.depth),
        reliability=QosReliability[profile.reliability.name],
        durability=QosDurability[profile.durability.name],
        deadline=duration(profile.deadline), lifespan=duration(profile.lifespan),
        liveliness=QosLiveliness[profile.liveliness.name],
        liveliness_lease_duration=duration(profile.liveliness_lease_duration),
        avoid_ros_namespace_conventions=bool(profile.avoid_ros_namespace_conventions))


def check_bag_path(path):
    """
    Check that a new bag can be written at ``path``; create its parent folder.

    Parameters
    ----------
    path : str or os.PathLike
        The bag folder to be; it must not exist.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    BagPathError
        When ``path`` exists or its parent cannot be created or written to.

    """
    path = Path(path)
    if path.exists():
        raise BagPathError(f'{path} exists already: a bag is never overwritten; remove it or '
                           'record somewhere else')
    parent = path.parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise BagPathError(f'cannot create the folder {parent} for the bag {path.name}: '
                           f'{error.strerror or error}') from error
    if not os.access(parent, os.W_OK | os.X_OK):
        raise BagPathError(f'cannot write the bag {path.name} into {parent}: permission denied')
    return path


class BagWriter:
    """
    Write one rosbag2 MCAP bag; use as a context manager.

    Parameters
    ----------
    path : str or os.PathLike
        The bag folder; must not exist (`check_bag_path`).
    topics : sequence of BagTopic
        Every topic the bag will hold, with distinct names.
    custom_data : dict of str to str, optional
        Written into the metadata's ``custom_data`` (what was recorded: scenario, seed, ...).

    Attributes
    ----------
    path : pathlib.Path
        The bag folder.
    counts : dict of str to int
        Messages written so far, by topic.

    Raises
    ------
    BagPathError
        See `check_bag_path`.
    ValueError
        When two topics share a name.

    """

    def __init__(self, path, topics, custom_data=None):
        from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin
        names = [topic.name for topic in topics]
        if len(set(names)) != len(names):
            raise ValueError(f'topic names must differ: {names}')
        self.path = check_bag_path(path)
        self._writer = jazzy_writer_class()(self.path, version=METADATA_VERSION,
                                            storage_plugin=StoragePlugin.MCAP)
        self._writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
        for key, value in {'recorded_by': 'dpn_navigator', **(custom_data or {})}.items():
            self._writer.set_custom_data(str(key), str(value))
        try:
            self._writer.open()
        except Exception as error:      # rosbags' WriterError, or an OSError under it
            raise BagPathError(f'cannot open the bag {self.path}: {error}') from error
        store = _typestore()
        self._connections = {
            topic.name: self._writer.add_connection(
                topic.name, message_type_name(topic.msg_type), typestore=store,
                offered_qos_profiles=[_bag_qos(topic.qos)])
            for topic in topics}
        self.counts = dict.fromkeys(names, 0)

    def write(self, topic, message, time_ns):
        """
        Write one message.

        Parameters
        ----------
        topic : str
            One of the bag's topic names.
        message : rclpy message, or bytes
            The message, or its CDR serialisation (from a raw subscription).
        time_ns : int
            Receive (log) time [ns]; the bag's clock, simulated time here.

        Raises
        ------
        KeyError
            When the topic is not one of the bag's.

        """
        from rclpy.serialization import serialize_message
        if topic not in self._connections:
            raise KeyError(f'{topic!r} is not a topic of the bag {self.path} '
                           f'({", ".join(self._connections)})')
        data = message if isinstance(message, (bytes, bytearray, memoryview)) \
            else serialize_message(message)
        self._writer.write(self._connections[topic], int(time_ns), data)
        self.counts[topic] += 1

    def close(self):
        """Finish the MCAP file and write ``metadata.yaml``; a second call does nothing."""
        if self._writer is not None:
            writer, self._writer = self._writer, None
            writer.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()
