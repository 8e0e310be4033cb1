"""Spin a node until shutdown, the Jazzy way: the ``main()`` of every node of the package."""

import rclpy
from rclpy.exceptions import ParameterException
from rclpy.executors import ExternalShutdownException
from rclpy.logging import get_logger


def run_node(node_class, args=None):
    """
    Initialise rclpy, build ``node_class()`` and spin it until shutdown or Ctrl-C.

    ``KeyboardInterrupt`` and ``ExternalShutdownException`` end it quietly; the node is
    destroyed and rclpy shut down in ``finally``. A ``ValueError`` or rclpy's
    ``ParameterException`` while the node is built (a bad parameter: wrong type, out of range)
    is logged as one line and ends it with exit status 1, not a traceback.
    (Jazzy's experimental ``EventsExecutor`` was tried: its ``spin()`` hangs with these wheels,
    so the default executor is used.)

    Returns
    -------
    int
        Exit status: 0, or 1 when the node could not be built.

    """
    rclpy.init(args=args)
    node = None
    try:
        try:
            node = node_class()
        except (ValueError, ParameterException) as error:
            get_logger(node_class.__name__).fatal(f'cannot start: {error}')
            return 1
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0
