"""
Read any bag: ROS 1 ``.bag``, rosbag2 folders (MCAP or sqlite3), bare ``.mcap`` or ``.db3`` files.

The reader is ``rosbags`` (``rosbags.highlevel.AnyReader``), which decodes every message from
the definitions the bag carries (ROS 1 bags and rosbag2 bags from Iron on carry them; an older
rosbag2 bag without them is decoded with the Jazzy definitions). No rclpy: the messages come
out as plain records with numpy arrays, for tools and tests that need no ROS process.

Types are named in the ROS 2 form (``sensor_msgs/msg/LaserScan``), also for ROS 1 bags, whose
``tf/tfMessage`` reads as ``tf/msg/tfMessage``. Stamps are the messages' ``header.stamp`` in
integer nanoseconds; ``log_time_ns`` is when the recorder received the message.

"""

from dataclasses import dataclass
import functools
from pathlib import Path

import numpy as np

LASER_SCAN = 'sensor_msgs/msg/LaserScan'
POSE_ARRAY = 'geometry_msgs/msg/PoseArray'
#: ``/tf`` and ``/tf_static`` message types: ROS 2 (and ROS 1 tf2) and ROS 1 tf.
TF_MESSAGE_TYPES = ('tf2_msgs/msg/TFMessage', 'tf/msg/tfMessage')


class BagReadError(Exception):
    """A bag cannot be opened or read (missing, not a bag, corrupt, unknown type)."""


@dataclass(frozen=True)
class BagTopicInfo:
    """
    One topic of a bag.

    Attributes
    ----------
    name : str
        As recorded (ROS 1 names may lack the leading ``/``).
    msg_type : str
        ROS 2 form, e.g. ``sensor_msgs/msg/LaserScan``.
    count : int
        Messages in the bag.

    """

    name: str
    msg_type: str
    count: int


@dataclass(frozen=True)
class ScanRecord:
    """
    One ``sensor_msgs/LaserScan`` as read.

    Attributes
    ----------
    topic : str
    log_time_ns : int
        Receive time in the bag [ns].
    stamp_ns : int
        ``header.stamp`` [ns].
    frame_id : str
        ``header.frame_id``, as recorded.
    angle_min, angle_max, angle_increment : float
        [rad]
    time_increment, scan_time : float
        [s]
    range_min, range_max : float
        [m]
    ranges : (L,) ndarray of float32, [m]
        As recorded (REP 117 ``inf``/``NaN`` kept).
    intensities : (L,) or (0,) ndarray of float32
        Device units.

    """

    topic: str
    log_time_ns: int
    stamp_ns: int
    frame_id: str
    angle_min: float
    angle_max: float
    angle_increment: float
    time_increment: float
    scan_time: float
    range_min: float
    range_max: float
    ranges: np.ndarray
    intensities: np.ndarray


@dataclass(frozen=True)
class TransformRecord:
    """
    One transform of a ``/tf`` or ``/tf_static`` message.

    Attributes
    ----------
    parent_frame, child_frame : str
        ``header.frame_id`` and ``child_frame_id`` with leading ``/`` stripped (ROS 1 names).
    stamp_ns : int
        ``header.stamp`` [ns].
    translation : (3,) ndarray of float64, [m]
    rotation : (4,) ndarray of float64
        ``(x, y, z, w)``.
    static : bool
        From a ``tf_static`` topic.
    log_time_ns : int
        Receive time in the bag [ns].

    """

    parent_frame: str
    child_frame: str
    stamp_ns: int
    translation: np.ndarray
    rotation: np.ndarray
    static: bool
    log_time_ns: int


@dataclass(frozen=True)
class PoseArrayRecord:
    """
    One ``geometry_msgs/PoseArray``.

    Attributes
    ----------
    topic : str
    log_time_ns, stamp_ns : int
        [ns]
    frame_id : str
    positions : (N, 3) ndarray of float64, [m]
    orientations : (N, 4) ndarray of float64
        ``(x, y, z, w)`` per pose.

    """

    topic: str
    log_time_ns: int
    stamp_ns: int
    frame_id: str
    positions: np.ndarray
    orientations: np.ndarray


def stamp_to_ns(stamp):
    """Return a decoded ``Time`` (``sec``, ``nanosec``) in integer nanoseconds."""
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


@functools.lru_cache(maxsize=1)
def _jazzy_typestore():
    from rosbags.typesys import get_typestore, Stores
    return get_typestore(Stores.ROS2_JAZZY)


def _bag_paths(path):
    """Return the paths AnyReader takes for a bag path, or raise `BagReadError`."""
    path = Path(path)
    if not path.exists():
        raise BagReadError(f'{path} does not exist')
    if path.is_dir():
        if not (path / 'metadata.yaml').is_file():
            raise BagReadError(f'{path} is a folder without metadata.yaml, not a rosbag2 bag')
        return [path]
    if path.suffix not in ('.bag', '.mcap', '.db3'):
        raise BagReadError(f'{path} is not a bag: expected a rosbag2 folder, a .mcap or .db3 '
                           'file, or a ROS 1 .bag')
    return [path]


class BagReader:
    """
    An open bag; use as a context manager.

    Parameters
    ----------
    path : str or os.PathLike
        A rosbag2 folder (with ``metadata.yaml``), a ``.mcap`` or ``.db3`` file, or a ROS 1
        ``.bag``.

    Attributes
    ----------
    path : pathlib.Path
    topics : dict of str to BagTopicInfo
        Every topic, by name.

    Raises
    ------
    BagReadError
        When the path is not a readable bag.

    Examples
    --------
    ::

        with BagReader('recording.bag') as bag:
            (topic,) = bag.topics_of_type(LASER_SCAN)
            for scan in bag.laser_scans(topic):
                ...

    """

    def __init__(self, path):
        from rosbags.highlevel import AnyReader
        self.path = Path(path)
        paths = _bag_paths(self.path)
        try:
            self._reader = AnyReader(paths, default_typestore=_jazzy_typestore())
            self._reader.open()
        except Exception as error:     # rosbags' reader errors, OSError, bad YAML, ...
            raise BagReadError(f'cannot read the bag {self.path}: '
                               f'{error or type(error).__name__}') from error
        self.topics = {
            name: BagTopicInfo(name, info.msgtype or '', int(info.msgcount))
            for name, info in self._reader.topics.items()}

    def close(self):
        """Close the bag; a second call does nothing."""
        if self._reader is not None:
            reader, self._reader = self._reader, None
            reader.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()

    @property
    def start_time_ns(self):
        """Return the earliest receive time [ns]."""
        return int(self._reader.start_time)

    def topics_of_type(self, *msg_types):
        """Return the names of the topics of any of ``msg_types``, sorted."""
        return sorted(name for name, info in self.topics.items() if info.msg_type in msg_types)

    def messages(self, topics):
        """
        Yield ``(topic, log_time_ns, message)`` of the given topics, in receive-time order.

        Messages are rosbags' decoded dataclasses.

        Raises
        ------
        KeyError
            When a topic is not in the bag.
        BagReadError
            When a message cannot be read or decoded.

        """
        missing = [topic for topic in topics if topic not in self.topics]
        if missing:
            raise KeyError(f'not in the bag {self.path}: {", ".join(missing)} (it holds '
                           f'{", ".join(sorted(self.topics))})')
        wanted = set(topics)
        connections = [c for c in self._reader.connections if c.topic in wanted]
        if not connections:
            return
        try:
            for connection, log_time, raw in self._reader.messages(connections=connections):
                yield (connection.topic, int(log_time),
                       self._reader.deserialize(raw, connection.msgtype))
        except Exception as error:
            raise BagReadError(f'cannot read the bag {self.path}: {error}') from error

    def laser_scans(self, topic):
        """
        Yield the ``LaserScan`` messages of ``topic`` as `ScanRecord`.

        Raises
        ------
        ValueError
            When ``topic`` is not a ``LaserScan`` topic.

        """
        self._check_type(topic, (LASER_SCAN,))
        for name, log_time, msg in self.messages([topic]):
            yield ScanRecord(
                topic=name, log_time_ns=log_time, stamp_ns=stamp_to_ns(msg.header.stamp),
                frame_id=msg.header.frame_id, angle_min=float(msg.angle_min),
                angle_max=float(msg.angle_max), angle_increment=float(msg.angle_increment),
                time_increment=float(msg.time_increment), scan_time=float(msg.scan_time),
                range_min=float(msg.range_min), range_max=float(msg.range_max),
                ranges=np.asarray(msg.ranges, dtype=np.float32),
                intensities=np.asarray(msg.intensities, dtype=np.float32))

    def transforms(self, topics=None):
        """
        Yield every transform of the bag's TF topics as `TransformRecord`.

        Parameters
        ----------
        topics : sequence of str, optional
            TF topics to read; default every topic of a TF message type. A topic whose name
            ends in ``tf_static`` gives static transforms.

        """
        if topics is None:
            topics = self.topics_of_type(*TF_MESSAGE_TYPES)
        for topic in topics:
            self._check_type(topic, TF_MESSAGE_TYPES)
        for name, log_time, msg in self.messages(list(topics)):
            static = name.rstrip('/').endswith('tf_static')
            for stamped in msg.transforms:
                t, q = stamped.transform.translation, stamped.transform.rotation
                yield TransformRecord(
                    parent_frame=stamped.header.frame_id.lstrip('/'),
                    child_frame=stamped.child_frame_id.lstrip('/'),
                    stamp_ns=stamp_to_ns(stamped.header.stamp),
                    translation=np.array([t.x, t.y, t.z], dtype=np.float64),
                    rotation=np.array([q.x, q.y, q.z, q.w], dtype=np.float64),
                    static=static, log_time_ns=log_time)

    def pose_arrays(self, topic):
        """Yield the ``PoseArray`` messages of ``topic`` as `PoseArrayRecord`."""
        self._check_type(topic, (POSE_ARRAY,))
        for name, log_time, msg in self.messages([topic]):
            positions = np.array([[p.position.x, p.position.y, p.position.z]
                                  for p in msg.poses], dtype=np.float64).reshape(-1, 3)
            orientations = np.array(
                [[p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w]
                 for p in msg.poses], dtype=np.float64).reshape(-1, 4)
            yield PoseArrayRecord(name, log_time, stamp_to_ns(msg.header.stamp),
                                  msg.header.frame_id, positions, orientations)

    def _check_type(self, topic, msg_types):
        info = self.topics.get(topic)
        if info is None:
            raise KeyError(f'{topic!r} is not in the bag {self.path} (it holds '
                           f'{", ".join(sorted(self.topics))})')
        if info.msg_type not in msg_types:
            raise ValueError(f'{topic!r} holds {info.msg_type}, not {" or ".join(msg_types)}')


def fill_tf_buffer(bag, buffer):
    """
    Feed every transform of a bag's TF topics into a `TfBuffer`.

    Parameters
    ----------
    bag : BagReader
        An open bag.
    buffer : dpn_navigator.core.frames.TfBuffer
        Give it ``cache_duration_ns=None`` to keep the whole bag.

    Returns
    -------
    (int, int, list of str)
        Transforms stored, transforms refused (malformed, a second parent, a loop, or older
        than a bounded cache keeps), and the first few reasons for refusal.

    """
    from dpn_navigator.core.frames import InvalidTransformError
    stored = refused = 0
    reasons = []
    for record in bag.transforms():
        try:
            ok = buffer.set_transform(record.parent_frame, record.child_frame, record.stamp_ns,
                                      record.translation, record.rotation, record.static)
        except InvalidTransformError as error:
            ok = False
            if len(reasons) < 5:
                reasons.append(str(error))
        stored += ok
        refused += not ok
    return stored, refused, reasons
