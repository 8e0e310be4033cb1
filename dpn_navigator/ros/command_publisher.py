"""
Velocity commands on ``cmd_vel``: ``geometry_msgs/Twist`` or, on request, ``TwistStamped``.

Jazzy's diff_drive_controller (which drives a real Husky) takes ``TwistStamped`` by default;
the pybullet world and most simulators take ``Twist``. Both sides choose with a boolean
parameter, ``cmd_vel_stamped``.

"""

from geometry_msgs.msg import Twist, TwistStamped
from rclpy.duration import Duration

from .conversions import twist_to_velocity, velocity_to_twist
from .qos import COMMAND_QOS


def command_type(stamped):
    """Return the message type of ``cmd_vel``: ``TwistStamped`` if ``stamped``, else ``Twist``."""
    return TwistStamped if stamped else Twist


def command_to_velocity(msg):
    """
    Read ``(linear.x, angular.z)`` [m/s, rad/s] from a ``Twist`` or a ``TwistStamped``.

    Raises
    ------
    ValueError
        When either is not finite.

    """
    return twist_to_velocity(msg.twist if isinstance(msg, TwistStamped) else msg)


class CommandPublisher:
    """
    Publish differential-drive commands on a topic, stamped or not.

    Parameters
    ----------
    node : rclpy.node.Node
        Node the publisher is made on; its clock stamps ``TwistStamped`` headers.
    topic : str
        Topic name, relative to the node's namespace.
    stamped : bool
        Send ``TwistStamped`` (header: the node's time and ``frame_id``) instead of ``Twist``.
    frame_id : str
        Frame of the stamped command: the robot's base frame.

    """

    def __init__(self, node, topic, stamped, frame_id):
        self.clock = node.get_clock()
        self.stamped = stamped
        self.frame_id = frame_id
        self.publisher = node.create_publisher(command_type(stamped), topic, COMMAND_QOS)

    @property
    def topic_name(self):
        """Return the fully resolved topic name, e.g. ``'/compabot/cmd_vel'``."""
        return self.publisher.topic_name

    def publish(self, linear, angular):
        """Send forward speed ``linear`` [m/s] and turn rate ``angular`` [rad/s]."""
        twist = velocity_to_twist(linear, angular)
        if not self.stamped:
            self.publisher.publish(twist)
            return
        msg = TwistStamped(twist=twist)
        msg.header.stamp = self.clock.now().to_msg()
        msg.header.frame_id = self.frame_id
        self.publisher.publish(msg)

    def wait_for_delivery(self, timeout):
        """
        Wait until every subscriber acknowledged the commands sent, at most ``timeout`` [s].

        Returns
        -------
        bool
            True when all were acknowledged in time.

        """
        return self.publisher.wait_for_all_acked(Duration(seconds=timeout))
