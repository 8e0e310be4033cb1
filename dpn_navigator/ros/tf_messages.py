"""
Planar poses as ``geometry_msgs/TransformStamped`` and ``tf2_msgs/TFMessage``.

Pure functions: a pose ``(x, y, yaw)`` [m, m, rad] of a child frame in its parent frame becomes
a transform; nothing here needs a node.

"""

from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage

from .conversions import yaw_to_quaternion


def transform_stamped(parent, child, pose, stamp, z=0.0):
    """
    Build the transform of ``child`` in ``parent`` for a planar pose.

    Parameters
    ----------
    parent, child : str
        Frame ids: the header's frame and ``child_frame_id``.
    pose : (float, float, float)
        ``(x, y, yaw)`` of the child frame's origin and x axis in the parent frame
        [m, m, rad].
    stamp : builtin_interfaces.msg.Time
        Time the transform holds at.
    z : float
        Height of the child frame's origin in the parent frame [m].

    Returns
    -------
    TransformStamped

    """
    msg = TransformStamped()
    msg.header.stamp = stamp
    msg.header.frame_id = parent
    msg.child_frame_id = child
    x, y, yaw = pose
    msg.transform.translation.x = float(x)
    msg.transform.translation.y = float(y)
    msg.transform.translation.z = float(z)
    msg.transform.rotation = yaw_to_quaternion(float(yaw))
    return msg


def tf_message(*transforms):
    """Return a ``TFMessage`` holding the given ``TransformStamped`` messages."""
    return TFMessage(transforms=list(transforms))
