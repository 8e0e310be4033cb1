"""
The simulated robot's TF tree (REP 105): what its drivers and a localiser would publish.

``map -> odom -> base_link -> laser``:

- ``base_link -> laser`` is the laser mount (``sim_bridge.husky.LASER_MOUNT`` at
  ``LASER_HEIGHT``), published once on ``/tf_static``.
- ``odom -> base_link`` is the wheel odometry, published on ``/tf`` with every odometry
  message. Drift-free by default, when the ``odom`` frame is the ``map`` frame; with drift
  (``sim_bridge.odometry_drift``) it wanders off the true pose.
- ``map -> odom`` stands in for a localiser (AMCL, slam_toolbox): computed from its estimate
  of the true pose composed with the inverse of the odometry pose. It is the identity while the
  odometry has no drift, and is published on ``/tf`` at the same stamps.

"""

from dataclasses import dataclass
import math

from dpn_navigator.core.pose2d import compose
from dpn_navigator.ros.names import TF_STATIC_TOPIC, TF_TOPIC
from dpn_navigator.ros.qos import TF_QOS, TF_STATIC_QOS
from dpn_navigator.ros.tf_messages import tf_message, transform_stamped
from tf2_msgs.msg import TFMessage

from .odometry_drift import inverse_pose


@dataclass(frozen=True)
class FrameNames:
    """Frame ids of the robot's TF tree, REP 105 names by default."""

    map: str = 'map'          # noqa: A003 (the REP 105 name)
    odom: str = 'odom'
    base: str = 'base_link'
    laser: str = 'laser'

    def __post_init__(self):
        names = (self.map, self.odom, self.base, self.laser)
        if not all(isinstance(n, str) and n and not n.startswith('/') for n in names):
            raise ValueError(f'frame ids must be non-empty and not start with /: {names}')
        if len(set(names)) != len(names):
            raise ValueError(f'frame ids must differ from each other: {names}')


def laser_mount_transforms(frames, laser_mount, laser_height, stamp, upside_down=False):
    """
    Return the ``/tf_static`` message of the robot: ``base_link -> laser``.

    Parameters
    ----------
    frames : FrameNames
        Frame ids.
    laser_mount : (float, float, float)
        Laser pose on the base frame ``(x, y, yaw)`` [m, m, rad].
    laser_height : float
        Height of the scan plane above the base frame [m].
    stamp : builtin_interfaces.msg.Time
        Header stamp.
    upside_down : bool
        The laser is mounted upside down: rolled by pi about its x axis (its beams sweep
        clockwise seen from above).

    Returns
    -------
    TFMessage

    """
    transform = transform_stamped(frames.base, frames.laser, laser_mount, stamp, z=laser_height)
    if upside_down:
        # Rz(yaw) Rx(pi): (x, y, z, w) = (cos(yaw/2), sin(yaw/2), 0, 0).
        rotation = transform.transform.rotation
        half = 0.5 * laser_mount[2]
        rotation.x, rotation.y, rotation.z, rotation.w = math.cos(half), math.sin(half), 0.0, 0.0
    return tf_message(transform)


def robot_transforms(frames, true_pose, odom_pose, stamp):
    """
    Return the ``/tf`` message of one tick: ``map -> odom`` and ``odom -> base_link``.

    Parameters
    ----------
    frames : FrameNames
        Frame ids.
    true_pose : (float, float, float)
        Ground-truth base pose in the map frame [m, m, rad].
    odom_pose : (float, float, float)
        Odometry's base pose in the odom frame [m, m, rad].
    stamp : builtin_interfaces.msg.Time
        Time both hold at.

    Returns
    -------
    TFMessage

    """
    # map -> odom = true * odom^-1: the odom frame's pose in the map frame.
    odom_in_map = compose(true_pose, inverse_pose(odom_pose))
    return tf_message(transform_stamped(frames.map, frames.odom, odom_in_map, stamp),
                      transform_stamped(frames.odom, frames.base, odom_pose, stamp))


class RobotFramePublisher:
    """
    Publish the robot's transforms on ``/tf`` and its laser mount on ``/tf_static``.

    Parameters
    ----------
    node : rclpy.node.Node
        Node the publishers are made on.
    frames : FrameNames
        Frame ids.
    laser_mount : (float, float, float)
        Laser pose on the base frame ``(x, y, yaw)`` [m, m, rad].
    laser_height : float
        Height of the scan plane above the base frame [m].
    upside_down : bool
        The laser is mounted upside down (``laser_mount_transforms``).

    """

    def __init__(self, node, frames, laser_mount, laser_height, upside_down=False):
        self.frames = frames
        self.tf_pub = node.create_publisher(TFMessage, TF_TOPIC, TF_QOS)
        self.static_pub = node.create_publisher(TFMessage, TF_STATIC_TOPIC, TF_STATIC_QOS)
        self.static_pub.publish(laser_mount_transforms(
            frames, laser_mount, laser_height, node.get_clock().now().to_msg(), upside_down))

    def publish(self, true_pose, odom_pose, stamp):
        """
        Publish ``map -> odom`` and ``odom -> base_link`` at ``stamp``.

        Parameters
        ----------
        true_pose : (float, float, float)
            Ground-truth base pose in the map frame [m, m, rad].
        odom_pose : (float, float, float)
            Odometry's base pose in the odom frame [m, m, rad].
        stamp : builtin_interfaces.msg.Time
            Time both hold at.

        """
        self.tf_pub.publish(robot_transforms(self.frames, true_pose, odom_pose, stamp))
