"""
Settings: a configuration field's default, unit, range and meaning, stated once, on the field.

A frozen configuration dataclass of the core (``NavigatorConfig``, ``FollowerConfig``) declares
each user-facing field with `setting`; the ``dpn`` node declares its ROS parameters from these
(``ros/dpn_params.py``), and ``config/dpn.yaml`` and the parameter table of
``docs/ros_reference.md`` are written from them (``tools/parameter_files.py``; a test fails when
either differs).

"""

from dataclasses import dataclass, field, fields, MISSING
import math
import re

#: ``field`` metadata key of a field's `Setting`.
SETTING_KEY = 'setting'
#: Bound of the "any sensible value" ranges (a map's size, its origin) [m].
BIG = 1e6


@dataclass(frozen=True)
class Setting:
    """
    What a configuration value means, besides its default.

    Attributes
    ----------
    unit : str
        Its unit (``'m'``, ``'s'``, ``'m/s'``, ``'hits'``, ...), ``''`` for a flag or a name.
    description : str
        One paragraph, Markdown: what the value does, and which value turns it off.
    low, high : float or int or None
        The values allowed, both included; None: no bound on that side. Flags and names have
        none.

    """

    unit: str
    description: str
    low: object = None
    high: object = None

    def __post_init__(self):
        if not self.description.strip():
            raise ValueError('a setting needs a description')
        if self.low is not None and self.high is not None and not self.low <= self.high:
            raise ValueError(f'setting range {self.low!r} to {self.high!r} is empty')

    def plain_description(self):
        """Return the description without its Markdown links and code marks, with its unit."""
        text = re.sub(r'\s*\(\[[^\]]*\]\([^)]*\)\)', '', self.description)
        text = re.sub(r'\[([^\]]*)\]\([^)]*\)', r'\1', text).replace('`', '')
        text = text.replace('\\*', '*')
        return f'{text} [{self.unit}]' if self.unit else text

    def range_text(self, value):
        """Return the allowed values for the docs: ``'0 to 5'``, ``'any'``, ``'bool'``, ..."""
        if isinstance(value, bool):
            return 'bool'
        if isinstance(value, str):
            return 'string'
        if self.low is None and self.high is None:
            return 'any'
        words = [_number_text(self.low) if self.low is not None else 'any',
                 _number_text(self.high) if self.high is not None else 'any']
        suffix = ' (integer)' if isinstance(value, int) else ''
        return f'{words[0]} to {words[1]}{suffix}'


def _number_text(value):
    """Write a bound as the docs do: ``1e6``, ``-pi``, ``0.01``, ``1000000``."""
    if isinstance(value, int):
        return str(value)
    if abs(abs(value) - math.pi) < 1e-12:
        return '-pi' if value < 0 else 'pi'
    if value != 0 and abs(value) >= 1e5:
        return f'{value:.0e}'.replace('e+0', 'e').replace('e+', 'e')
    return f'{value:g}'


def setting(default, unit, description, low=None, high=None):
    """
    Declare a dataclass field with a default and its `Setting`.

    Parameters
    ----------
    default : float or int or bool or str or dataclasses.MISSING
        The field's default; ``MISSING``: the field has none (it must be given).
    unit, description, low, high
        As `Setting`'s.

    Returns
    -------
    dataclasses.Field
        ``field(default=default)`` with the setting in its metadata.

    """
    metadata = {SETTING_KEY: Setting(unit, description, low, high)}
    if default is MISSING:
        return field(metadata=metadata)
    return field(default=default, metadata=metadata)


def settings_of(config_class):
    """
    Return the fields of ``config_class`` that carry a `Setting`, in declaration order.

    Returns
    -------
    settings : dict
        ``{field name: (default, Setting)}``; ``default`` is ``dataclasses.MISSING`` for a
        field without one.

    """
    found = {}
    for item in fields(config_class):
        if SETTING_KEY in item.metadata:
            found[item.name] = (item.default, item.metadata[SETTING_KEY])
    return found
