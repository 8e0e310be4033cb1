"""
The topics an episode bag holds, with the types and QoS their publishers offer.

One table for both recorders: the benchmark's `EpisodeBagRecorder`, which builds the messages
the nodes would have published, and the demo's `TopicRecorder`, which subscribes to the
running nodes. Names are those of the nodes in the default namespace.

"""

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import Twist
from nav_msgs.msg import OccupancyGrid, Odometry, Path
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import MarkerArray

from .bag_writer import BagTopic
from ..ros.names import DEFAULT_NAMESPACE, DIAGNOSTICS_TOPIC, TF_STATIC_TOPIC, TF_TOPIC
from ..ros.qos import COMMAND_QOS, LATCHED_QOS, SENSOR_QOS, TF_QOS, TF_STATIC_QOS


def node_topic(name):
    """Return the absolute name of a topic in the default namespace, e.g. ``/compabot/map``."""
    return f'/{DEFAULT_NAMESPACE}/{name}'


def episode_topics():
    """
    Return what an episode bag of the benchmark holds: the nodes' state and sensor topics.

    Returns
    -------
    list of BagTopic
        ``/clock``, ``/tf_static``, ``/tf``, ``scan``, ``odom``, ``odom_real``, ``map``,
        ``marker``, ``plan`` and the simulator's ``sim/wanderers``.

    """
    return [
        BagTopic('/clock', Clock, COMMAND_QOS),
        BagTopic(TF_STATIC_TOPIC, TFMessage, TF_STATIC_QOS),
        BagTopic(TF_TOPIC, TFMessage, TF_QOS),
        BagTopic(node_topic('scan'), LaserScan, SENSOR_QOS),
        BagTopic(node_topic('odom'), Odometry, SENSOR_QOS),
        BagTopic(node_topic('odom_real'), Odometry, COMMAND_QOS),
        BagTopic(node_topic('map'), OccupancyGrid, LATCHED_QOS),
        BagTopic(node_topic('marker'), MarkerArray, LATCHED_QOS),
        BagTopic(node_topic('plan'), Path, LATCHED_QOS),
        BagTopic(node_topic('sim/wanderers'), MarkerArray, COMMAND_QOS),
    ]


def system_topics():
    """
    Return what a bag of the running nodes holds: `episode_topics`, commands and statuses.

    Returns
    -------
    list of BagTopic
        `episode_topics` and ``cmd_vel`` (``Twist``), ``status``, ``sim/status`` and
        ``/diagnostics``.

    """
    return episode_topics() + [
        BagTopic(node_topic('cmd_vel'), Twist, COMMAND_QOS),
        BagTopic(node_topic('status'), DiagnosticStatus, LATCHED_QOS),
        BagTopic(node_topic('sim/status'), DiagnosticStatus, LATCHED_QOS),
        BagTopic(DIAGNOSTICS_TOPIC, DiagnosticArray, COMMAND_QOS),
    ]
