"""
The nodes' console scripts: stop signals handled first, then the node module imported.

``ros2 run dpn_navigator dpn`` and ``ros2 run sim_bridge pybullet_world`` start here. This
module imports only the standard library and `stop_signals`, so the SIGINT and SIGTERM handlers
are in place a few tens of milliseconds after the process starts, before the imports of rclpy,
numpy and the numba kernels and before the kernels' warm-up; a stop signal during any of them
ends the process at once with exit code 0 and one line on stderr, never a traceback
(`stop_signals`).

"""

from importlib import import_module

from .stop_signals import StopRequest


def _run(name, module, args):
    """Install the stop handlers, import ``module`` and run its ``main(args, stop=...)``."""
    stop = StopRequest(starting=True, name=name)
    node_main = import_module(module).main
    return node_main(args, stop=stop)


def dpn(args=None):
    """Run the ``dpn`` node (``ros2 run dpn_navigator dpn``); return the exit code."""
    return _run('dpn', 'dpn_navigator.ros.dpn_node', args)


def pybullet_world(args=None):
    """Run the ``pybullet_world`` node (``ros2 run sim_bridge pybullet_world``)."""
    return _run('pybullet_world', 'sim_bridge.pybullet_world_node', args)
