"""
Small bags written by the tests themselves, with ``rosbags`` (no rclpy): scans, TF, poses.

Messages are built from rosbags' Jazzy type store and written as CDR into a rosbag2 folder
(``mcap`` or ``sqlite3`` storage). `laser_scan`, `tf_message` and `pose_array` build the
messages; `write_bag` writes ``(topic, msg_type, log_time_ns, message)`` items;
`write_ros1_bag` writes them as a ROS 1 bag (Noetic types, the old ``tf/tfMessage`` if asked).
"""

import math

import numpy as np
from rosbags.rosbag1 import Writer as Writer1
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import get_types_from_msg, get_typestore, Stores

STORE = get_typestore(Stores.ROS2_JAZZY)
S = 1_000_000_000

Time = STORE.types['builtin_interfaces/msg/Time']
Header = STORE.types['std_msgs/msg/Header']
LaserScan = STORE.types['sensor_msgs/msg/LaserScan']
TFMessage = STORE.types['tf2_msgs/msg/TFMessage']
TransformStamped = STORE.types['geometry_msgs/msg/TransformStamped']
Transform = STORE.types['geometry_msgs/msg/Transform']
Vector3 = STORE.types['geometry_msgs/msg/Vector3']
Quaternion = STORE.types['geometry_msgs/msg/Quaternion']
PoseArray = STORE.types['geometry_msgs/msg/PoseArray']
Pose = STORE.types['geometry_msgs/msg/Pose']
Point = STORE.types['geometry_msgs/msg/Point']

LASER_SCAN = 'sensor_msgs/msg/LaserScan'
TF_MESSAGE = 'tf2_msgs/msg/TFMessage'
POSE_ARRAY = 'geometry_msgs/msg/PoseArray'


def header(stamp_ns, frame_id):
    return Header(stamp=Time(sec=stamp_ns // S, nanosec=stamp_ns % S), frame_id=frame_id)


def laser_scan(stamp_ns, frame_id, ranges, angle_min=-math.pi / 2, angle_increment=None,
               range_min=0.05, range_max=10.0, intensities=None):
    """Return a LaserScan whose beams span ``angle_min`` upwards (default: -90..+90 deg)."""
    ranges = np.asarray(ranges, dtype=np.float32)
    if angle_increment is None:
        angle_increment = math.pi / max(len(ranges) - 1, 1)
    return LaserScan(
        header=header(stamp_ns, frame_id), angle_min=angle_min,
        angle_max=angle_min + angle_increment * (len(ranges) - 1),
        angle_increment=angle_increment, time_increment=0.0, scan_time=0.1,
        range_min=range_min, range_max=range_max, ranges=ranges,
        intensities=np.asarray([] if intensities is None else intensities, dtype=np.float32))


def transform_stamped(stamp_ns, parent, child, translation, rotation):
    x, y, z = translation
    qx, qy, qz, qw = rotation
    return TransformStamped(
        header=header(stamp_ns, parent), child_frame_id=child,
        transform=Transform(translation=Vector3(x=float(x), y=float(y), z=float(z)),
                            rotation=Quaternion(x=float(qx), y=float(qy), z=float(qz),
                                                w=float(qw))))


def tf_message(*transforms):
    return TFMessage(transforms=list(transforms))


def pose_array(stamp_ns, frame_id, positions):
    return PoseArray(header=header(stamp_ns, frame_id), poses=[
        Pose(position=Point(x=float(x), y=float(y), z=float(z)),
             orientation=Quaternion(x=0.0, y=0.0, z=0.0, w=1.0)) for x, y, z in positions])


def write_bag(path, items, storage='mcap'):
    """
    Write a rosbag2 folder.

    Parameters
    ----------
    path : pathlib.Path
        The folder to be.
    items : iterable of (str, str, int, object)
        ``(topic, msg_type, log_time_ns, message)``.
    storage : {'mcap', 'sqlite3'}
        The storage plugin.

    """
    plugin = {'mcap': StoragePlugin.MCAP, 'sqlite3': StoragePlugin.SQLITE3}[storage]
    connections = {}
    with Writer(path, version=9, storage_plugin=plugin) as writer:
        for topic, msg_type, time_ns, message in items:
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, msg_type, typestore=STORE)
            writer.write(connections[topic], time_ns, STORE.serialize_cdr(message, msg_type))
    return path


ROS1_STORE = get_typestore(Stores.ROS1_NOETIC)
# tf2's TFMessage (not in rosbags' Noetic store), and the old tf's message, as ROS 1 bags
# before tf2 hold it on /tf.
for _name in ('tf2_msgs/msg/TFMessage', 'tf/msg/tfMessage'):
    ROS1_STORE.register(get_types_from_msg('geometry_msgs/TransformStamped[] transforms', _name))


def to_ros1(message, rename=None):
    """Return a message of the Jazzy store as the same message of ROS 1 (``seq`` 0)."""
    name = (rename or {}).get(message.__msgtype__, message.__msgtype__)
    cls = ROS1_STORE.types[name]
    values = {}
    for field in cls.__dataclass_fields__:
        if field == '__msgtype__':
            continue
        value = getattr(message, field, 0)          # seq: absent in ROS 2
        if hasattr(value, '__msgtype__'):
            value = to_ros1(value)
        elif isinstance(value, list):
            value = [to_ros1(v) if hasattr(v, '__msgtype__') else v for v in value]
        values[field] = value
    return cls(**values)


def write_ros1_bag(path, items, rename=None):
    """
    Write a ROS 1 bag (``rosbag`` format 2.0) from Jazzy-store items, as `write_bag` takes.

    Parameters
    ----------
    path : pathlib.Path
        The ``.bag`` file to be.
    items : iterable of (str, str, int, object)
        ``(topic, msg_type, log_time_ns, message)`` of the Jazzy store.
    rename : dict of str to str, optional
        ROS 1 type names for Jazzy ones, e.g. ``{TF_MESSAGE: 'tf/msg/tfMessage'}``.

    """
    rename = rename or {}
    connections = {}
    with Writer1(path) as writer:
        for topic, msg_type, time_ns, message in items:
            ros1_type = rename.get(msg_type, msg_type)
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, ros1_type, typestore=ROS1_STORE)
            writer.write(connections[topic], time_ns,
                         ROS1_STORE.serialize_ros1(to_ros1(message, rename), ros1_type))
    return path
