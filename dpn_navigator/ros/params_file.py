"""
The ``dpn`` node's parameters from a ROS 2 parameter file, without running the node.

`node_values` reads a params YAML (``<node>: ros__parameters: {...}``, as ``--params-file``
takes) and returns the values meant for one node: those under ``/**`` first, then under a key
naming the node (``dpn``, ``/dpn``, ``/**/dpn``, ``/<namespace>/dpn``), which win.
`dpn_parameters` turns such values into the node's ``DpnParameters`` and ``SafetyParameters``
exactly as the node does: a short-lived rclpy node named ``dpn`` gets them as parameter
overrides and declares its parameters with ``dpn_params.declare_parameters`` (same types,
ranges and checks), then is destroyed. Tools that run the core on recorded data
(``dpn-replay``) use it, so that a params file means the same to them as to the node.

"""

from pathlib import Path

import yaml

from .dpn_params import declare_parameters, PARAMETERS
from .safety_params import declare_safety_parameters, SafetyParameters
from ..core.settings import settings_of

#: Parameters every rclpy node has; not unknown to the dpn node.
_BUILTIN_PARAMETERS = frozenset({'use_sim_time', 'start_type_description_service'})


class ParamsFileError(ValueError):
    """A params file cannot be read, or its values are not valid ``dpn`` parameters."""


def known_parameters():
    """Return the names of the ``dpn`` node's parameters, a frozenset."""
    return frozenset({p.name for p in PARAMETERS} | set(settings_of(SafetyParameters))
                     | _BUILTIN_PARAMETERS)


def _flatten(values, prefix=''):
    """Return nested parameter dicts as ``{'a.b': value}`` (ROS 2 parameter names)."""
    flat = {}
    for key, value in values.items():
        name = f'{prefix}{key}'
        if isinstance(value, dict):
            flat.update(_flatten(value, f'{name}.'))
        else:
            flat[name] = value
    return flat


def _names_node(key, node_name):
    """Tell whether a params-file key addresses the node ``node_name``."""
    parts = [part for part in str(key).split('/') if part]
    return bool(parts) and parts[-1] == node_name


def node_values(path, node_name='dpn'):
    """
    Return the parameter values a params file gives the node ``node_name``.

    Parameters
    ----------
    path : str or os.PathLike
        A ROS 2 params YAML.
    node_name : str
        The node's name (not its namespace).

    Returns
    -------
    dict of str to object
        Parameter name to value; ``/**`` entries overridden by the node's own.

    Raises
    ------
    ParamsFileError
        When the file cannot be read, is not YAML, or has no ``ros__parameters`` for the node.

    """
    path = Path(path)
    try:
        document = yaml.safe_load(path.read_text())
    except OSError as error:
        raise ParamsFileError(f'cannot read the params file {path}: '
                              f'{error.strerror or error}') from error
    except yaml.YAMLError as error:
        raise ParamsFileError(f'the params file {path} is not valid YAML: '
                              f'{str(error).splitlines()[0]}') from error
    if not isinstance(document, dict):
        raise ParamsFileError(f'the params file {path} holds no node keys '
                              "(expected '<node>: ros__parameters: ...')")
    wildcard, own = {}, {}
    found = False
    for key, body in document.items():
        if str(key) in ('/**', '**'):
            target = wildcard
        elif _names_node(key, node_name):
            target = own
        else:
            continue
        if not isinstance(body, dict) or not isinstance(body.get('ros__parameters'), dict):
            raise ParamsFileError(f'the params file {path}: key {key!r} has no '
                                  "'ros__parameters:' mapping")
        target.update(_flatten(body['ros__parameters']))
        found = True
    if not found:
        raise ParamsFileError(f'the params file {path} has no parameters for the node '
                              f"{node_name!r} (keys: {', '.join(map(str, document))}; expected "
                              f"'{node_name}', '/**/{node_name}' or '/**')")
    return {**wildcard, **own}


def dpn_parameters(values):
    """
    Build the ``dpn`` node's parameters from values, as the node declares and checks them.

    Parameters
    ----------
    values : dict of str to object
        Parameter overrides (`node_values`); names the node does not know are ignored, as
        the node ignores them.

    Returns
    -------
    (DpnParameters, SafetyParameters)

    Raises
    ------
    ParamsFileError
        When a value has the wrong type or is out of range, or the values do not make a
        valid configuration (the node's one-line message).

    """
    import rclpy
    from rclpy.context import Context
    from rclpy.node import Node
    from rclpy.parameter import Parameter
    context = Context()
    rclpy.init(args=[], context=context)
    try:
        overrides = [Parameter(name, value=value) for name, value in values.items()
                     if name in known_parameters()]
        node = Node('dpn', context=context, parameter_overrides=overrides,
                    use_global_arguments=False, enable_rosout=False,
                    start_parameter_services=False)
        try:
            return declare_parameters(node), declare_safety_parameters(node)
        finally:
            node.destroy_node()
    except Exception as error:     # ValueError, rclpy's parameter exceptions, TypeError
        message = str(error).strip().splitlines()[0] if str(error).strip() else repr(error)
        raise ParamsFileError(message) from error
    finally:
        rclpy.try_shutdown(context=context)
