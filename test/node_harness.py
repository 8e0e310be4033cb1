"""Run nodes in the test process: one executor for them, spun until a condition holds."""

import contextlib
import time

from rclpy.executors import SingleThreadedExecutor


@contextlib.contextmanager
def executor_for(context, *nodes):
    """
    Add nodes to a new single-threaded executor; on exit shut it down and destroy the nodes.

    Parameters
    ----------
    context : rclpy.context.Context
        The context the nodes were made in.
    *nodes : rclpy.node.Node
        Destroyed last to first.

    Yields
    ------
    executor : SingleThreadedExecutor

    """
    executor = SingleThreadedExecutor(context=context)
    for node in nodes:
        executor.add_node(node)
    try:
        yield executor
    finally:
        executor.shutdown()
        for node in reversed(nodes):
            node.destroy_node()


def spin_until(executor, condition, timeout=10.0):
    """Spin until ``condition()`` is true or ``timeout`` [s] of wall time passes; return it."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.02)
        if condition():
            return True
    return False
