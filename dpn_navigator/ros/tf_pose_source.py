"""
TF lookups for the ``dpn`` node: ``tf2_ros`` when it is installed, else the core's `TfBuffer`.

One interface, `TfLookup`: ``lookup(target, source, stamp_ns)`` returns the rotation matrix and
translation of ``source`` in ``target`` at a stamp, or raises `TransformUnavailable`;
``connected(target, source)`` tells whether the buffer links the two frames at all.

- On an apt Jazzy install, `Tf2RosLookup` wraps ``tf2_ros.Buffer`` and its
  ``TransformListener``.
- On the PyPI path (no ``tf2_ros`` wheel), `FallbackTfLookup` feeds the core's
  ``frames.TfBuffer`` (tf2's rules: static transforms at all times, interpolation between the
  two samples around a stamp, no extrapolation, a 10 s cache) from ``/tf`` and ``/tf_static``
  subscriptions: ``/tf`` reliable, volatile, depth 10 (`TF_LISTENER_QOS`); ``/tf_static``
  reliable, transient local, depth 100 (tf2_ros's). Malformed transforms are dropped,
  counted and warned about.

Lookups never block: a scan whose transform has not arrived waits in the node's queue
(``scan_placement``), so the executor keeps delivering ``/tf``.

"""

import numpy as np
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from tf2_msgs.msg import TFMessage

from .names import TF_STATIC_TOPIC, TF_TOPIC
from ..core.frames import FrameLookupError, TfBuffer, Transform3D, TransformError

#: tf2_ros's ``DynamicListenerQoS`` (reliable, volatile) but depth 10, not 100: rclpy's executor
#: takes one message per subscription per wait, so under load a depth-100 reader holds a
#: backlog of 100 transforms (0.4 s of wall time from a 50 Hz simulator at 5x real time) and
#: every scan outlives ``transform_timeout`` waiting for its transform; with depth 10 the
#: newest transforms arrive within 10 messages.
TF_LISTENER_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10,
                             reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.VOLATILE)
#: tf2_ros's ``StaticListenerQoS``: a late subscriber gets every latched static transform.
TF_STATIC_LISTENER_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                                    reliability=ReliabilityPolicy.RELIABLE,
                                    durability=DurabilityPolicy.TRANSIENT_LOCAL)
WARN_THROTTLE = 2.0     # [s]


def stamp_to_nanoseconds(stamp):
    """Return a ``builtin_interfaces/Time`` as integer nanoseconds."""
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


class TransformUnavailable(Exception):
    """A transform cannot be looked up (yet): unknown frames, unconnected, or no data."""


def _matrix_and_translation(transform):
    """Return ``(R (3, 3), t (3,))`` of a core `Transform3D`."""
    return transform.rotation_matrix(), transform.translation.copy()


class FallbackTfLookup:
    """
    The core's `TfBuffer` fed from ``/tf`` and ``/tf_static`` subscriptions of ``node``.

    Attributes
    ----------
    kind : str
        ``'dpn TfBuffer'``, for the log.
    rejected : int
        Transforms dropped as malformed (a NaN, a non-unit quaternion, a second parent, a loop).

    """

    kind = 'dpn TfBuffer (no tf2_ros)'

    def __init__(self, node):
        self.buffer = TfBuffer()
        self.rejected = 0
        self._logger = node.get_logger()
        node.create_subscription(TFMessage, TF_TOPIC, lambda msg: self.add(msg, False),
                                 TF_LISTENER_QOS)
        node.create_subscription(TFMessage, TF_STATIC_TOPIC, lambda msg: self.add(msg, True),
                                 TF_STATIC_LISTENER_QOS)

    def add(self, msg, static):
        """Store every transform of a ``TFMessage``; count and warn about malformed ones."""
        for t in msg.transforms:
            tr, rot = t.transform.translation, t.transform.rotation
            try:
                stamp_ns = stamp_to_nanoseconds(t.header.stamp)
                self.buffer.set_transform(t.header.frame_id, t.child_frame_id, stamp_ns,
                                          (tr.x, tr.y, tr.z), (rot.x, rot.y, rot.z, rot.w),
                                          static=static)
            except (TransformError, ValueError) as error:
                self.rejected += 1
                self._logger.warning(f'dropped a transform ({self.rejected} so far): {error}',
                                     throttle_duration_sec=WARN_THROTTLE)

    def lookup(self, target, source, stamp_ns):
        """Return ``(R, t)`` of ``source`` in ``target`` at ``stamp_ns`` (0: the latest)."""
        try:
            return _matrix_and_translation(self.buffer.lookup(target, source, int(stamp_ns)))
        except TransformError as error:
            raise TransformUnavailable(str(error)) from None

    def sample_step(self, frame, stamp_ns):
        """Return `TfBuffer.sample_step` of ``frame`` at ``stamp_ns``, None if unknown."""
        try:
            return self.buffer.sample_step(frame, stamp_ns)
        except FrameLookupError:
            return None

    def connected(self, target, source):
        """Return whether the buffer links ``target`` and ``source`` (at any time)."""
        try:
            self.buffer.latest_common_time(target, source)
        except (FrameLookupError, TransformError):
            return False
        return True


class Tf2RosLookup:
    """``tf2_ros.Buffer`` and ``TransformListener`` on ``node`` (an apt ROS 2 install)."""

    kind = 'tf2_ros'

    def __init__(self, node, tf2_ros):
        from rclpy.time import Time
        self._time = Time
        self._tf2_ros = tf2_ros
        self.buffer = tf2_ros.Buffer(node=node)
        self.listener = tf2_ros.TransformListener(self.buffer, node, spin_thread=False)
        self.rejected = 0

    def lookup(self, target, source, stamp_ns):
        """Return ``(R, t)`` of ``source`` in ``target`` at ``stamp_ns`` (0: the latest)."""
        try:
            msg = self.buffer.lookup_transform(target, source,
                                               self._time(nanoseconds=int(stamp_ns)))
        except self._tf2_ros.TransformException as error:
            raise TransformUnavailable(str(error)) from None
        tr, rot = msg.transform.translation, msg.transform.rotation
        return _matrix_and_translation(Transform3D((tr.x, tr.y, tr.z),
                                                   (rot.x, rot.y, rot.z, rot.w)))

    def sample_step(self, frame, stamp_ns):
        """Return None: tf2_ros's buffer does not tell which samples a lookup used."""
        return None

    def connected(self, target, source):
        """Return whether the buffer links ``target`` and ``source`` at their latest time."""
        return bool(self.buffer.can_transform(target, source, self._time()))


def make_tf_lookup(node, use_tf2_ros=True):
    """
    Return the `TfLookup` of ``node``: ``tf2_ros``'s when importable (and asked for), else ours.

    Returns
    -------
    Tf2RosLookup or FallbackTfLookup

    """
    if use_tf2_ros:
        try:
            import tf2_ros
        except ImportError:
            tf2_ros = None
        if tf2_ros is not None:
            return Tf2RosLookup(node, tf2_ros)
    return FallbackTfLookup(node)


def planar_pose(rotation, translation):
    """Return the ``(x, y, yaw)`` of a 3-D pose [m, m, rad] (heading of its x axis)."""
    rotation = np.asarray(rotation)
    return (float(translation[0]), float(translation[1]),
            float(np.arctan2(rotation[1, 0], rotation[0, 0])))
