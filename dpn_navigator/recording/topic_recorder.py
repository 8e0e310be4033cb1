"""
Record the topics of running nodes into a bag, as ``ros2 bag record`` does.

`TopicRecorder` takes a node and a `BagWriter`, subscribes to each of the bag's topics with
``raw=True`` (the callback gets the CDR bytes as they came over DDS, with no deserialising), and
writes each message at its arrival time on the node's clock: simulated time when the node runs
with ``use_sim_time``, as ``ros2 bag record --use-sim-time`` does. The demo runs one in its
monitor process (``python -m dpn_navigator.tools.demo --record DIR``).

"""

from rclpy.qos import QoSProfile

#: Subscription queue depth: deep enough that a busy recorder does not drop messages at the
#: demo's 10x real time (odometry, ``/tf`` and ``/clock`` arrive at 500 Hz then).
RECORD_DEPTH = 200


def recording_qos(offered):
    """
    Return the QoS a recorder subscribes with to a publisher offering ``offered``.

    Same reliability and durability (so a latched map is received on joining, and a
    best-effort scan stream is compatible), with a queue of at least ``RECORD_DEPTH``.

    Parameters
    ----------
    offered : rclpy.qos.QoSProfile
        The publisher's profile.

    Returns
    -------
    rclpy.qos.QoSProfile

    """
    return QoSProfile(history=offered.history, depth=max(int(offered.depth), RECORD_DEPTH),
                      reliability=offered.reliability, durability=offered.durability)


class TopicRecorder:
    """
    Subscribe to a bag's topics on a node and write every message into the bag.

    Parameters
    ----------
    node : rclpy.node.Node
        The node the subscriptions are made on; its clock dates the messages.
    writer : BagWriter
        The open bag; its topics are the ones recorded. The caller closes it.
    topics : sequence of BagTopic
        The bag's topics (as given to the writer).

    Attributes
    ----------
    writer : BagWriter
        The bag; ``writer.counts`` are the messages recorded so far, by topic.

    """

    def __init__(self, node, writer, topics):
        self.node = node
        self.writer = writer
        for topic in topics:
            node.create_subscription(
                topic.msg_type, topic.name, self._writer_of(topic.name),
                recording_qos(topic.qos), raw=True)

    def _writer_of(self, topic):
        """Return the callback that writes the serialised messages of ``topic``."""
        clock = self.node.get_clock()
        write = self.writer.write

        def on_message(data):
            write(topic, data, clock.now().nanoseconds)
        return on_message
