"""
Looking up a named profile (a robot's, a laser's) with an error that lists the known names.

No ROS, no pybullet.

"""


def named_profile(profiles, kind, name):
    """
    Return ``profiles[name]``.

    Parameters
    ----------
    profiles : dict
        The known profiles by name.
    kind : str
        What they are, for the error (``'robot profile'``).
    name : object
        The name asked for.

    Raises
    ------
    ValueError
        For an unknown (or unhashable) name, listing the known ones.

    """
    try:
        return profiles[name]
    except (KeyError, TypeError):
        raise ValueError(f'unknown {kind} {name!r}: choose one of '
                         f'{", ".join(profiles)}') from None
