"""
``dpn-benchmark --set NAME=VALUE``: a built-in navigator with some of its settings changed.

An ablation (one rule off, one time longer) is a navigator that differs from a built-in one in
a few ``NavigatorConfig`` settings. `parse_overrides` reads them from the command line, with
the setting's type and range (``core.settings``), and checks the whole configuration as the
navigator would build it, so that a wrong name or value ends the run before its first
episode. The overrides go into the log's ``run.json`` (a log holds one configuration) and
into its label (`run_label`), which the reports (``compare_report``, ``detection_report``)
key their columns by: ``dpn [give_way_time=15]`` beside ``dpn``.

"""

import math

#: Settings the scenario fixes for each episode (its size), not to be set by hand.
SCENARIO_SETTINGS = ('width', 'height')

_TRUE = ('true', '1', 'yes', 'on')
_FALSE = ('false', '0', 'no', 'off')


def _value(name, text, default):
    """Return ``text`` read as the type of ``name``'s default; ValueError when it is not."""
    if isinstance(default, bool):
        if text.lower() in _TRUE:
            return True
        if text.lower() in _FALSE:
            return False
        raise ValueError(f'--set {name}: expected true or false, got {text!r}')
    if isinstance(default, int):
        try:
            return int(text)
        except ValueError:
            raise ValueError(f'--set {name}: expected an integer, got {text!r}') from None
    if isinstance(default, float):
        try:
            value = float(text)
        except ValueError:
            raise ValueError(f'--set {name}: expected a number, got {text!r}') from None
        if not math.isfinite(value):
            raise ValueError(f'--set {name}: expected a finite number, got {text!r}')
        return value
    return text


def parse_overrides(pairs, base_options=None):
    """
    Read ``NAME=VALUE`` pairs into ``NavigatorConfig`` overrides.

    Parameters
    ----------
    pairs : sequence of str
        ``NAME=VALUE``, NAME a setting of ``NavigatorConfig`` (``docs/ros_reference.md``
        lists them under the same names as the node's parameters) other than the scenario's
        ``width`` and ``height``; a name given twice takes its last value.
    base_options : dict, optional
        The built-in navigator's overrides (``protocol.NAVIGATORS[name]``) these go on top
        of, for the check of the whole configuration.

    Returns
    -------
    dict of str to object
        Setting name to value, typed as the setting.

    Raises
    ------
    ValueError
        For a pair without ``=``, an unknown or fixed name, a value of the wrong type, out of
        the setting's range, or one the navigator's configuration refuses.

    """
    from ..core.navigator import NavigatorConfig     # not for the reports, which need the label
    from ..core.settings import settings_of
    settings = settings_of(NavigatorConfig)
    overrides = {}
    for pair in pairs:
        name, equals, text = pair.partition('=')
        name = name.strip()
        if not equals or not name:
            raise ValueError(f'--set takes NAME=VALUE, got {pair!r}')
        if name in SCENARIO_SETTINGS:
            raise ValueError(f'--set {name}: the scenario sets it')
        if name not in settings:
            raise ValueError(f'--set {name}: NavigatorConfig has no such setting (the names '
                             'are those of docs/ros_reference.md)')
        default, setting = settings[name]
        value = _value(name, text.strip(), default)
        if not isinstance(value, (bool, str)):
            if setting.low is not None and value < setting.low:
                raise ValueError(f'--set {name}: {value!r} is below its least value, '
                                 f'{setting.low}')
            if setting.high is not None and value > setting.high:
                raise ValueError(f'--set {name}: {value!r} is above its greatest value, '
                                 f'{setting.high}')
        overrides[name] = value
    options = {**(base_options or {}), **overrides}
    try:
        NavigatorConfig(width=10.0, height=10.0, **options).label_rule()
    except (TypeError, ValueError) as error:
        raise ValueError(f'--set: {error}') from None
    return overrides


def run_label(settings, default=''):
    """
    Return the label of a log from its ``run.json`` settings.

    ``dpn`` for a built-in navigator as it is, ``dpn [give_way_time=15.0]`` with overrides
    (``settings['settings']``, sorted by name); ``default`` when no navigator is recorded.
    """
    name = settings.get('navigator', default)
    overrides = settings.get('settings')
    if overrides:
        name += ' [' + ', '.join(f'{key}={overrides[key]}' for key in sorted(overrides)) + ']'
    return name
