"""
Status of a node as ``diagnostic_msgs``: a latched ``status`` topic and ``/diagnostics``.

``/diagnostics`` (``DiagnosticArray``) is what diagnostic_aggregator and rqt_robot_monitor read;
the latched ``DiagnosticStatus`` on the node's relative ``status`` topic lets a late subscriber
(a test, a monitor) read the last status at once.

"""

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from .names import DIAGNOSTICS_TOPIC
from .qos import COMMAND_QOS, LATCHED_QOS


def diagnostic_status(name, hardware_id, level, message, values):
    """
    Build a ``DiagnosticStatus``.

    Parameters
    ----------
    name, hardware_id : str
        Who reports: the node's fully qualified name, and the device it stands for.
    level : bytes
        ``DiagnosticStatus.OK``, ``WARN``, ``ERROR`` or ``STALE``.
    message : str
        One-line summary.
    values : dict
        Key-value pairs; values are turned into strings with ``str``.

    Returns
    -------
    DiagnosticStatus

    """
    msg = DiagnosticStatus(name=name, hardware_id=hardware_id, level=level, message=message)
    msg.values = [KeyValue(key=key, value=str(value)) for key, value in values.items()]
    return msg


class DiagnosticsPublisher:
    """
    Publish a node's status on its latched ``status`` topic and on ``/diagnostics``.

    Parameters
    ----------
    node : rclpy.node.Node
        Node the publishers are made on; its clock stamps the arrays.
    status_topic : str
        Topic of the latched ``DiagnosticStatus``, relative to the node's namespace.

    Attributes
    ----------
    last : diagnostic_msgs.msg.DiagnosticStatus or None
        The status published last.

    """

    def __init__(self, node, status_topic='status'):
        self.clock = node.get_clock()
        self.status_pub = node.create_publisher(DiagnosticStatus, status_topic, LATCHED_QOS)
        self.array_pub = node.create_publisher(DiagnosticArray, DIAGNOSTICS_TOPIC, COMMAND_QOS)
        self.last = None

    def publish(self, status):
        """Publish one ``DiagnosticStatus`` on both topics."""
        self.last = status
        self.status_pub.publish(status)
        array = DiagnosticArray(status=[status])
        array.header.stamp = self.clock.now().to_msg()
        self.array_pub.publish(array)
