"""
Input limits of the ``dpn`` node: parameters that bound the work one message can cost.

Kept apart from ``dpn_params`` (the navigator's parameters) because they guard the node, not
the method: a scan with more beams than ``max_beams`` is rejected and counted before any work,
so one huge message cannot hold the executor (and the watchdog with it) for seconds.

"""

from dataclasses import dataclass

from rcl_interfaces.msg import IntegerRange, ParameterDescriptor

# name: (default, description, (low, high)); all read-only. The default beam limit is four
# times the paper's 640-beam laser, more than a 2-D lidar gives.
INTEGER_PARAMETERS = {
    'max_beams': (4096, 'Scans with more beams than this are rejected and counted [beams].',
                  (1, 1_000_000)),
}


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
    values = {}
    for name, (default, description, (low, high)) in INTEGER_PARAMETERS.items():
        descriptor = ParameterDescriptor(
            description=description, read_only=True,
            integer_range=[IntegerRange(from_value=low, to_value=high, step=1)])
        values[name] = int(node.declare_parameter(name, default, descriptor).value)
    return SafetyParameters(**values)
