"""
Your own navigator in the benchmark: the protocol it implements and how ``--navigator`` loads it.

``dpn-benchmark --navigator package.module:Class`` imports ``package.module`` (from the Python
path: install your package, or set ``PYTHONPATH``) and runs every episode with ``Class``. The
class implements `BenchmarkNavigator`:

- ``Class(config)``: ``config`` is the episode's ``NavigatorConfig`` (the map's size and
  origin, the laser's mount, the robot's limits); use what you need of it.
- ``set_goal(x, y)``: the goal in the map frame [m], once, before the first step.
- ``step(stamp, pose, ranges, angle_min, angle_increment, range_min, range_max)``: one scan
  (10 Hz, ``sensor_msgs/LaserScan`` fields, ranges as a float64 array, ``+inf`` for no
  return) and the robot's pose ``(x, y, yaw)`` in the map frame [m, m, rad] when it was taken
  (with ``--pose-noise``, a noisy estimate); return the velocity command, either a
  ``NavigatorOutput`` (``.command.linear``, ``.command.angular``, ``.status``) or a pair
  ``(linear, angular)`` [m/s, rad/s]. The command is held until the next scan.

The four built-in navigators (``core.navigator.Navigator``, and the reference navigators,
which are ``Navigator``s on other maps or its subclass ``Nav2Navigator``) implement it. The
benchmark judges a plug-in as every navigator: success is the true pose within the goal
tolerance with no contact; it may report arrival or no path through a ``NavigatorStatus`` in
its output, which only ends the episode early (arrival) or names the failure (no path). A
plug-in has no labelled map, so its detection and map-quality columns are empty or 0.

"""

import importlib
import math
import typing

from ..core.control.path_follower import VelocityCommand
from ..core.navigator import NavigatorOutput, NavigatorStatus


@typing.runtime_checkable
class BenchmarkNavigator(typing.Protocol):
    """What a navigator implements to run in the benchmark (see the module)."""

    def set_goal(self, x, y):
        """Take the goal in the map frame [m]."""

    def step(self, stamp, pose, ranges, angle_min, angle_increment, range_min, range_max):
        """Fold one scan in and return the velocity command (see the module)."""


def load_navigator_class(spec):
    """
    Import ``'package.module:Class'`` and return the class.

    Raises
    ------
    ValueError
        When the text is not of that form, the module does not import, the class is missing,
        or it lacks ``set_goal`` or ``step``.

    """
    module_name, colon, class_name = str(spec).partition(':')
    if not colon or not module_name or not class_name:
        raise ValueError(f'a plug-in navigator is given as package.module:Class, got {spec!r}')
    try:
        module = importlib.import_module(module_name)
    except ImportError as exc:
        raise ValueError(f'cannot import {module_name!r} for --navigator {spec}: {exc}') from exc
    cls = getattr(module, class_name, None)
    if not isinstance(cls, type):
        raise ValueError(f'{module_name!r} has no class {class_name!r}')
    missing = [name for name in ('set_goal', 'step') if not callable(getattr(cls, name, None))]
    if missing:
        raise ValueError(f'{spec} does not implement the navigator protocol: no '
                         f'{" or ".join(missing)} (docs/benchmark.md)')
    return cls


class PluginNavigator:
    """
    A plug-in navigator as the episode loop sees a built-in one.

    Parameters
    ----------
    navigator : BenchmarkNavigator
        The plug-in's instance.

    Attributes
    ----------
    status : NavigatorStatus
        From the last output (``ACTIVE`` when the plug-in returns a bare pair).
    grid, path : None
        A plug-in has no labelled map and no path the benchmark reads.
    replans, forgets : int
        The plug-in's own attributes of these names when it has them, else 0.

    """

    grid = None
    path = None

    def __init__(self, navigator):
        self.navigator = navigator
        self.status = NavigatorStatus.IDLE

    def set_goal(self, x, y):
        """Pass the goal on."""
        self.navigator.set_goal(x, y)
        self.status = NavigatorStatus.ACTIVE

    def step(self, stamp, pose, ranges, angle_min, angle_increment, range_min, range_max):
        """
        Run the plug-in's step and return a `NavigatorOutput`.

        Raises
        ------
        ValueError
            When the plug-in returns something that is not a command, or a non-finite one.

        """
        out = self.navigator.step(stamp, pose, ranges, angle_min, angle_increment, range_min,
                                  range_max)
        if isinstance(out, NavigatorOutput):
            command, status = out.command, out.status
        else:
            try:
                linear, angular = (float(value) for value in out)
            except (TypeError, ValueError) as exc:
                raise ValueError(f'a navigator step returned {out!r}: return a '
                                 'NavigatorOutput or (linear, angular)') from exc
            command, status = VelocityCommand(linear, angular), NavigatorStatus.ACTIVE
        if not (math.isfinite(command.linear) and math.isfinite(command.angular)):
            raise ValueError(f'a navigator step returned a non-finite command {command!r}')
        self.status = status
        return NavigatorOutput(command, status)

    @property
    def replans(self):
        """Return the plug-in's ``replans`` attribute, or 0."""
        return int(getattr(self.navigator, 'replans', 0))

    @property
    def forgets(self):
        """Return the plug-in's ``forgets`` attribute, or 0."""
        return int(getattr(self.navigator, 'forgets', 0))
