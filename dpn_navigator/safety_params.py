"""
Input limits of the ``dpn`` node: parameters that bound the work one message can cost.

Kept apart from ``dpn_params`` (the navigator's parameters) because they guard the node, not
the method: a scan with more beams than ``max_beams`` is rejected and counted before any work,
so one huge message cannot hold the executor (and the watchdog with it) for seconds.

"""

from dataclasses import dataclass

from rcl_interfaces.msg import IntegerRange, ParameterDescriptor

#: Default beam limit: four times the 640-beam laser of the paper, more than any 2-D lidar's.
DEFAULT_MAX_BEAMS = 4096


@dataclass(frozen=True)
class SafetyParameters:
    """
    Input limits, read once at start-up.

    Attributes
    ----------
    max_beams : int
        Scans with more ranges than this are rejected.

    """

    max_beams: int


def declare_safety_parameters(node):
    """
    Declare the input-limit parameters of the ``dpn`` node and read them.

    Returns
    -------
    SafetyParameters

    """
    descriptor = ParameterDescriptor(
        description='Scans with more beams than this are rejected and counted [beams].',
        read_only=True,
        integer_range=[IntegerRange(from_value=1, to_value=1_000_000, step=1)])
    max_beams = node.declare_parameter('max_beams', DEFAULT_MAX_BEAMS, descriptor).value
    return SafetyParameters(max_beams=int(max_beams))
