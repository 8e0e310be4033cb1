"""Spin a node until shutdown, the Jazzy way: the ``main()`` of every node of the package."""

import rclpy
from rclpy.executors import ExternalShutdownException


def run_node(node_class, args=None):
    """
    Initialise rclpy, build ``node_class()`` and spin it until shutdown or Ctrl-C.

    ``KeyboardInterrupt`` and ``ExternalShutdownException`` end it quietly; the node is
    destroyed and rclpy shut down in ``finally``. (Jazzy's experimental ``EventsExecutor`` was
    tried: its ``spin()`` hangs with these wheels, so the default executor is used.)
    """
    rclpy.init(args=args)
    node = None
    try:
        node = node_class()
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
