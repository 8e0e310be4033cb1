"""
A guarded ``/clock``: a node's time source that drops a ``/clock`` message which is no time.

rclpy's ``TimeSource.clock_callback`` turns every ``/clock`` message into a ``Time`` with
``Time.from_msg``, which raises ``ValueError`` for negative seconds (a legal ``int32``). Raised
in the executor, that ends the node: anyone on the network could stop a node that runs on
simulated time. ``guard_clock`` swaps the node's time source for one that checks the message
first and hands a bad one to a rejection callback instead.

rclpy gives no public hook for this: the swap uses ``Node._time_source``, which every rclpy from
Humble to Rolling has; ``test_sim_clock`` fails if that changes.

"""

from rclpy.time import Time
from rclpy.time_source import TimeSource


class GuardedTimeSource(TimeSource):
    """
    A ``TimeSource`` whose ``/clock`` callback rejects a message that is not a valid time.

    Parameters
    ----------
    node : rclpy.node.Node
        The node whose ``use_sim_time`` parameter switches ``/clock`` on and off.
    on_reject : callable
        Called with a ``str`` that says what was wrong with a rejected message.

    """

    def __init__(self, *, node, on_reject):
        self._on_reject = on_reject
        super().__init__(node=node)

    def clock_callback(self, msg):
        """Set the attached clocks to the message's time, or reject the message."""
        try:
            Time.from_msg(msg.clock)
        except (ValueError, OverflowError) as error:
            self._on_reject(f'/clock {msg.clock.sec} s {msg.clock.nanosec} ns: {error}')
            return
        super().clock_callback(msg)


def guard_clock(node, on_reject):
    """
    Replace a node's rclpy time source by a ``GuardedTimeSource``.

    Call it at the end of the node's constructor: the old time source's ``/clock``
    subscription and parameter callback are removed, the new one subscribes when
    ``use_sim_time`` is true and drives the node's clock from then on.

    Parameters
    ----------
    node : rclpy.node.Node
        The node whose time source to replace.
    on_reject : callable
        Called with a ``str`` for each rejected ``/clock`` message.

    Returns
    -------
    GuardedTimeSource

    """
    old = node._time_source
    node.remove_on_set_parameters_callback(old._on_parameter_event)
    old.detach_node()
    guarded = GuardedTimeSource(node=node, on_reject=on_reject)
    guarded.attach_clock(node.get_clock())
    node._time_source = guarded
    return guarded
