"""
Declare a node's numeric parameters so that ``-p map_width:=25`` works as well as ``25.0``.

rclpy types a parameter by its default: an integer given for a ``double`` parameter would end
in an ``InvalidParameterTypeException`` traceback. Here a number parameter is declared with
dynamic typing, so an integer is accepted and read as a float, and anything else is refused with
a one-line ``ValueError`` that names the parameter, its unit and its range. `declare_setting`
declares any parameter from its ``core.settings.Setting``.

"""

import math

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor


def declare_number(node, name, default, description, bounds=None, read_only=True):
    """
    Declare a floating-point parameter that also takes integers; return its value.

    Parameters
    ----------
    node : rclpy.node.Node
        Node to declare it on.
    name : str
        Parameter name.
    default : float
        Value when none is given.
    description : str
        What it is, with its unit.
    bounds : (float, float) or None
        Inclusive range of allowed values; None allows any value, NaN and infinities too.
    read_only : bool
        Whether it can change after start-up.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        When the given value is not a number or is outside ``bounds``.

    """
    descriptor = ParameterDescriptor(description=description, read_only=read_only,
                                     dynamic_typing=True)
    if bounds is not None:
        descriptor.floating_point_range = [
            FloatingPointRange(from_value=bounds[0], to_value=bounds[1], step=0.0)]
    value = node.declare_parameter(name, float(default), descriptor).value
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f'parameter {name} must be a number ({description}), got {value!r}')
    value = float(value)
    if bounds is not None and not (math.isfinite(value) and bounds[0] <= value <= bounds[1]):
        raise ValueError(f'parameter {name} = {value!r} is outside [{bounds[0]}, {bounds[1]}] '
                         f'({description})')
    return value


def declare_setting(node, name, default, setting):
    """
    Declare a read-only parameter from its setting: description, unit and range; return it.

    Parameters
    ----------
    node : rclpy.node.Node
        The node that declares it.
    name : str
        The parameter's name.
    default : float or int or bool or str
        Its default, which also types it (a float takes integers too, `declare_number`).
    setting : dpn_navigator.core.settings.Setting
        Its unit, range and meaning.

    Returns
    -------
    value : float or int or bool or str

    Raises
    ------
    ValueError
        A number out of its range or not a number (`declare_number`).

    """
    description = setting.plain_description()
    if isinstance(default, float):
        bounds = None if setting.low is None else (setting.low, setting.high)
        return declare_number(node, name, default, description, bounds, read_only=True)
    descriptor = ParameterDescriptor(description=description, read_only=True)
    if isinstance(default, int) and not isinstance(default, bool) and setting.low is not None:
        descriptor.integer_range = [IntegerRange(from_value=setting.low, to_value=setting.high,
                                                 step=1)]
    return node.declare_parameter(name, default, descriptor).value


def refuse_undeclared_parameters(node):
    """
    Make ``node`` refuse every set request that names a parameter it did not declare.

    rclpy's own check (``Node._check_undeclared_parameters``) tests the names with ``any()``
    over a generator: a parameter named ``''`` is falsy and passes as a new parameter, and the
    list of undeclared names it reports has been consumed (``[]``). This check runs first, as a
    pre-set callback, and raises the ``ParameterNotDeclaredException`` rclpy's parameter
    services turn into the refusal's reason, naming every offending parameter, e.g.
    ``['']``.

    Parameters
    ----------
    node : rclpy.node.Node
        A node without ``allow_undeclared_parameters``, its parameters declared.

    """
    from rclpy.exceptions import ParameterNotDeclaredException

    def check_names(parameters):
        undeclared = [parameter.name for parameter in parameters
                      if not parameter.name or not node.has_parameter(parameter.name)]
        if undeclared:
            raise ParameterNotDeclaredException(undeclared)
        return parameters

    node.add_pre_set_parameters_callback(check_names)
