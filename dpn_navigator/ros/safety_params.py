"""
Input limits of the ``dpn`` node: parameters that bound the work one message can cost.

Kept apart from ``dpn_params`` (the navigator's parameters) because they guard the node, not
the method: a scan with more beams than ``max_beams`` is rejected and counted before any work,
so one huge message cannot hold the executor (and the watchdog with it) for seconds.

"""

from dataclasses import dataclass

from rcl_interfaces.msg import IntegerRange, ParameterDescriptor

from ..core.settings import setting, settings_of


@dataclass(frozen=True)
class SafetyParameters:
    """Input limits, read once at start-up; each field carries its setting."""

    # Four times the paper's 640-beam laser, more than a 2-D lidar gives.
    max_beams: int = setting(
        4096, 'beams', 'scans with more beams are rejected and counted before any work',
        1, 1_000_000)


def declare_safety_parameters(node):
    """
    Declare the input-limit parameters of the ``dpn`` node and read them.

    Returns
    -------
    SafetyParameters

    """
    values = {}
    for name, (default, spec) in settings_of(SafetyParameters).items():
        descriptor = ParameterDescriptor(
            description=spec.plain_description(), read_only=True,
            integer_range=[IntegerRange(from_value=spec.low, to_value=spec.high, step=1)])
        values[name] = int(node.declare_parameter(name, default, descriptor).value)
    return SafetyParameters(**values)
