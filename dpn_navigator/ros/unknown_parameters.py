"""
Parameters given to a node at start that it does not declare: warned about once, with a hint.

A parameter from a params file (``--params-file``, a launch file's ``parameters=``), ``-p`` or
``parameter_overrides`` that the node never declares is kept by rclpy as an override and never
read: a misspelt ``max_vel_X`` would silently leave ``max_vel_x`` at its default. After the
node has declared everything, `warn_unknown_parameters` names each such parameter once with the
closest declared name (``difflib``), and the node counts them in its status
(``unknown_parameters``).

"""

import difflib

#: How alike a declared name must be to be offered as the hint (difflib's ratio, 0 to 1).
HINT_CUTOFF = 0.6


def unknown_parameter_names(node):
    """
    Return the parameters given to ``node`` at start that it has not declared, sorted.

    Parameters
    ----------
    node : rclpy.node.Node
        A node without ``allow_undeclared_parameters``, its parameters declared.

    Returns
    -------
    list of str

    """
    # rclpy keeps the start-up values (global arguments, the node's params file entries and
    # ``parameter_overrides``) in this dict and has no public accessor for it.
    given = getattr(node, '_parameter_overrides', {}) or {}
    return sorted(name for name in given if not node.has_parameter(name))


def closest_parameter(name, known):
    """
    Return the declared name closest to ``name`` (difflib), or None when none is alike.

    Parameters
    ----------
    name : str
        The unknown name.
    known : iterable of str
        The declared names.

    Returns
    -------
    str or None

    """
    matches = difflib.get_close_matches(name, sorted(known), n=1, cutoff=HINT_CUTOFF)
    return matches[0] if matches else None


def warn_unknown_parameters(node):
    """
    Warn once per parameter given to ``node`` that it does not declare; return their names.

    Each warning names the parameter and, when one is alike, the closest declared name
    (``did you mean max_vel_x?``).

    Parameters
    ----------
    node : rclpy.node.Node
        The node, after it declared its parameters.

    Returns
    -------
    list of str
        The unknown names, sorted.

    """
    unknown = unknown_parameter_names(node)
    if not unknown:
        return unknown
    known = node.list_parameters([], 0).names
    for name in unknown:
        hint = closest_parameter(name, known)
        node.get_logger().warning(
            f'unknown parameter {name!r} ignored (the node does not declare it)'
            + (f': did you mean {hint!r}?' if hint else ''))
    return unknown
