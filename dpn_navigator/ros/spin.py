"""
Spin a node until SIGINT or SIGTERM, then stop cleanly: the ``main()`` of every node here.

rclpy's own signal handlers shut the context down from inside the signal, while a callback may
still be publishing or the executor building its wait set: such a node ends with exit code 1 and
a traceback (``publisher's context is invalid``, ``failed to initialize wait set``), and a
second SIGINT raises ``KeyboardInterrupt`` anywhere, even in ``destroy_node``. Here rclpy is
initialised without signal handlers; SIGINT and SIGTERM only set a flag that the spin loop
reads between callbacks, and make every later one ignored. The loop then ends, the node is
destroyed while the context is still valid (``DpnNode.destroy_node`` sends its zero command
there), rclpy shuts down, and ``main`` returns 0. A node that cannot start because of its
parameters logs one error line and returns 1.

"""

import signal

import rclpy
from rclpy.exceptions import ParameterException
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.logging import get_logger
from rclpy.signals import SignalHandlerOptions

#: Longest wait for work before the loop looks at the stop flag again [s].
SPIN_POLL = 0.05
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class StopRequest:
    """
    A flag set by SIGINT and SIGTERM, whose handlers this installs.

    Attributes
    ----------
    signal_name : str or None
        The first signal received, e.g. ``'SIGTERM'``.

    """

    def __init__(self):
        self.signal_name = None
        for signum in STOP_SIGNALS:
            signal.signal(signum, self._on_signal)

    def _on_signal(self, signum, frame):
        if self.signal_name is None:
            self.signal_name = signal.Signals(signum).name
        # Later stop signals are ignored, not handled: at exit Python puts the default action
        # back for signals with a Python handler (not for ignored ones), and a second Ctrl-C
        # arriving then would kill the stopping process (exit -2) instead of letting it end.
        for stop_signal in STOP_SIGNALS:
            signal.signal(stop_signal, signal.SIG_IGN)

    @property
    def requested(self):
        """Tell whether a stop signal came."""
        return self.signal_name is not None


def run_node(node_class, args=None):
    """
    Initialise rclpy, build ``node_class()`` and spin it until SIGINT, SIGTERM or shutdown.

    Returns
    -------
    int
        The process exit code: 0 after a stop, 1 when the node's parameters are invalid.

    """
    stop = StopRequest()
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node = None
    try:
        try:
            node = node_class()
        except (ValueError, ParameterException) as error:
            get_logger(node_class.__name__).fatal(f'cannot start: {error}')
            return 1
        executor = SingleThreadedExecutor()
        executor.add_node(node)
        while not stop.requested and rclpy.ok():
            executor.spin_once(timeout_sec=SPIN_POLL)
        if stop.requested:
            node.get_logger().info(f'{stop.signal_name}: stopping')
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0
