"""
Spin a node until SIGINT or SIGTERM, then stop cleanly: the ``main()`` of every node here.

rclpy's own signal handlers shut the context down from inside the signal, while a callback may
still be publishing or the executor building its wait set: such a node ends with exit code 1 and
a traceback (``publisher's context is invalid``, ``failed to initialize wait set``), and a
second SIGINT raises ``KeyboardInterrupt`` anywhere, even in ``destroy_node``. Here rclpy is
initialised without signal handlers; SIGINT and SIGTERM (`stop_signals`) end the process at once
while it starts (exit code 0, one line on stderr), or, once the node spins, only set a flag that
the spin loop reads between callbacks, and make every later one ignored. The loop then ends, the
node is destroyed while the context is still valid (``DpnNode.destroy_node`` sends its zero
command there), rclpy shuts down, and ``main`` returns 0. A node that cannot start because of
its parameters logs one error line and returns 1.

"""

import rclpy
from rclpy.exceptions import ParameterException
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.logging import get_logger
from rclpy.signals import SignalHandlerOptions

from .stop_signals import StopRequest

#: Longest wait for work before the loop looks at the stop flag again [s].
SPIN_POLL = 0.05

__all__ = ['run_node', 'SPIN_POLL', 'StopRequest']


def run_node(node_class, args=None, stop=None):
    """
    Initialise rclpy, build ``node_class()`` and spin it until SIGINT, SIGTERM or shutdown.

    Parameters
    ----------
    node_class : type
        The node; built without arguments.
    args : list of str, optional
        Command-line arguments for ``rclpy.init``.
    stop : StopRequest, optional
        Handlers installed earlier (``node_entry``), in start-up mode: a stop signal before the
        node spins ends the process there. By default they are installed here.

    Returns
    -------
    int
        The process exit code: 0 after a stop, 1 when the node's parameters are invalid.

    """
    if stop is None:
        stop = StopRequest(starting=True, name=node_class.__name__)
    node = None
    try:
        rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
        try:
            node = node_class()
        except (ValueError, ParameterException) as error:
            get_logger(node_class.__name__).fatal(f'cannot start: {error}')
            return 1
        executor = SingleThreadedExecutor()
        executor.add_node(node)
        stop.started()
        while not stop.requested and rclpy.ok():
            executor.spin_once(timeout_sec=SPIN_POLL)
        if stop.requested:
            node.get_logger().info(f'{stop.signal_name}: stopping')
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        # A stop signal from here on is ignored or only sets the flag.
        stop.started()
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0
