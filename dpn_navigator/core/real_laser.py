"""
Real lasers: the rules that suit them, and how the navigator tells one from an ideal laser.

The default rules are made for an ideal laser: every beam returns from the first surface it
meets, at its exact range, and a beam with no return crossed empty space. A real laser returns
nothing from a wall met at grazing incidence and loses an echo now and then even on a surface
seen squarely; read as empty space, the beams past such a wall show it moving when the robot
later sees it squarely (in the simulator with the UTM-30LX profile, ``dpn``'s defaults take
12-31 % of the walls for moving). `REAL_LASER_SETTINGS` are ``config/dpn_real_laser.yaml``'s
settings (the benchmark's ``dpn_real_laser``): beams with no return clear nothing, edge pixels
are invalid, a hit shows motion only beyond the range noise, and so on (docs/method.md).

`RealLaserSwitch` tells a real laser by **returns lost inside a surface** (`lost_returns`):
runs of one or two beams without a valid reading between two hits that lie within 0.3 m of
each other in range. An ideal laser loses none (0.000 % of the readings on six simulated maps,
open ones included), a real one 0.2-1 % (the simulated SICK LMS1xx, UTM-30LX and RPLIDAR A2)
and the Hokuyos of the real recordings of ``../shared/realdata`` 0.17-0.22 %. Once the laser
has moved (a laser standing still keeps the defaults: the people a standing laser sees walk
where the background returns nothing, and beams that clear nothing would never show their
place empty) and enough scans show such losses, ``Navigator`` takes the real-laser settings
that were left at their defaults (``NavigatorConfig.real_laser_switch``).

No rclpy here.

"""

from dataclasses import fields, replace
import math

import numpy as np

from .settings import settings_of

#: ``config/dpn_real_laser.yaml``: the settings for a moving robot with a real laser (values
#: in the units of ``NavigatorConfig``; docs/real_data.md says how each was chosen).
REAL_LASER_SETTINGS = {
    'no_return_reach': 0.0, 'mixed_pixel_angle': 0.1745, 'spike_angle': 0.1745,
    'veiling_angle': 0.1745, 'range_noise_margin': 0.05, 'range_noise_fraction': 0.03,
    'free_burn_in': 0.5, 'object_min_width': 0.05, 'wall_continuation_angle': 1.0472}
#: Lost returns inside a surface: runs of at most this many beams without a valid reading...
LOST_RETURN_RUN = 2
#: ... between two hits at most this far apart in range [m] (``segment_gap``'s default).
LOST_RETURN_GAP = 0.3
#: A laser that stays within this distance [m] of its first position stands still.
STANDING_DISTANCE = 0.1
#: The switch decides on no fewer scans than this (counted from the first scan)...
SWITCH_MIN_SCANS = 3
#: ... and no fewer returns lost inside a surface than this [beams] (the simulated SICK LMS1xx,
#: 541 beams losing 0.2 % of them, shows that many in about 5 scans; an ideal laser never
#: does). With 10, walls seen at grazing incidence in the SICK's first second turned mobile.
SWITCH_MIN_LOST = 5


def lost_returns(ranges, range_min, range_max):
    """
    Count the returns lost inside a surface in one scan.

    Parameters
    ----------
    ranges : (L,) array_like of float
        As the driver wrote them [m] (REP 117 ``inf``/``NaN`` kept), in beam order.
    range_min, range_max : float
        The valid interval ``[range_min, range_max)`` [m].

    Returns
    -------
    int
        Beams without a valid reading in runs of at most `LOST_RETURN_RUN` between two valid
        hits at most `LOST_RETURN_GAP` apart in range.

    Examples
    --------
    >>> lost_returns([2.0, float('inf'), 2.1, 5.0, float('inf'), float('inf'), float('inf'),
    ...               5.1], 0.1, 30.0)
    1

    """
    ranges = np.asarray(ranges, dtype=np.float64)
    if ranges.ndim != 1:
        raise ValueError(f'ranges must be one-dimensional, got shape {ranges.shape}')
    with np.errstate(invalid='ignore'):
        hits = np.flatnonzero(np.isfinite(ranges) & (ranges >= range_min)
                              & (ranges < range_max))
    if hits.shape[0] < 2:
        return 0
    run = np.diff(hits) - 1
    lone = ((run >= 1) & (run <= LOST_RETURN_RUN)
            & (np.abs(np.diff(ranges[hits])) <= LOST_RETURN_GAP))
    return int(run[lone].sum())


def real_laser_overrides(config):
    """
    Return the real-laser settings that ``config`` left at their defaults and would change.

    Parameters
    ----------
    config : NavigatorConfig
        The navigator's settings now.

    Returns
    -------
    dict of str to float
        Of `REAL_LASER_SETTINGS`, in their order, the names whose value in ``config`` is the
        default of ``type(config)`` and differs from the real-laser value (what a user set
        stays), and that go with ``config``'s other settings and the ones taken before them
        (the burn-in needs the fine free evidence and the ghost expiry, the range noise rule
        the intermittent surfaces: with those off, they are left out).

    """
    defaults = settings_of(type(config))
    names = {item.name for item in fields(config)}
    taken = {}
    for name, value in REAL_LASER_SETTINGS.items():
        if (name not in names or getattr(config, name) != defaults[name][0]
                or getattr(config, name) == value):
            continue
        try:
            replace(config, **taken, **{name: value})
        except ValueError:
            continue
        taken[name] = value
    return taken


def take_real_laser_settings(config, grid):
    """
    Switch ``grid`` to the real-laser settings and start its map again.

    The grid takes the new label rule (``LabelGrid.switch_rule``) and forgets everything
    (``LabelGrid.reset``): what the scans so far showed was read with the ideal-laser rules,
    whose beams with no return showed space empty past walls the laser did not return from,
    and whose mixed pixels stand as obstacles in empty space. The next scans go in with the
    new rule.

    Parameters
    ----------
    config : NavigatorConfig
        The settings in use.
    grid : LabelGrid
        The grid built with them.

    Returns
    -------
    config : NavigatorConfig
        With `real_laser_overrides` taken.
    overrides : dict of str to float
        The settings taken.

    """
    overrides = real_laser_overrides(config)
    config = replace(config, **overrides)
    grid.switch_rule(config.label_rule())
    grid.reset()
    return config, overrides


def real_laser_switch_for(config, grid):
    """
    Return the `RealLaserSwitch` for ``config`` and ``grid``, or None when there is none to make.

    None when ``config.real_laser_switch`` is 0, the grid cannot switch its rule (only the
    ``LabelGrid`` can), or no real-laser setting would change (`real_laser_overrides`).

    """
    if (config.real_laser_switch == 0.0 or not hasattr(grid, 'switch_rule')
            or not real_laser_overrides(config)):
        return None
    return RealLaserSwitch(config.real_laser_switch)


class LaserTravel:
    """
    How far a laser came from its first position.

    Attributes
    ----------
    first_xy : (float, float) or None
        The first position given [m] (map frame); None before any.
    farthest : float
        The farthest the laser came from it [m].

    """

    def __init__(self):
        self.first_xy = None
        self.farthest = 0.0

    def add(self, xy):
        """Take the laser's position ``xy`` [m]; return `farthest`."""
        x, y = float(xy[0]), float(xy[1])
        if self.first_xy is None:
            self.first_xy = (x, y)
        self.farthest = max(self.farthest, math.hypot(x - self.first_xy[0],
                                                      y - self.first_xy[1]))
        return self.farthest

    @property
    def standing(self):
        """Whether positions were given and all lie within `STANDING_DISTANCE` of the first."""
        return self.first_xy is not None and self.farthest <= STANDING_DISTANCE


class RealLaserSwitch:
    """
    Watches the scans for a real laser on the move.

    Parameters
    ----------
    lost_share : float
        The share of the readings lost inside a surface (`lost_returns`) above which the
        laser is a real one, in (0, 1].

    Attributes
    ----------
    scans, readings, lost : int
        Scans and readings watched, and the returns lost inside a surface among them.
    switched_at : float or None
        The stamp of the scan that showed a real laser [s] (0.0 for a scan without a stamp);
        None until then. The switch watches nothing more after it.

    """

    def __init__(self, lost_share):
        lost_share = float(lost_share)
        if not (math.isfinite(lost_share) and 0.0 < lost_share <= 1.0):
            raise ValueError(f'lost_share must be in (0, 1], got {lost_share!r}')
        self.lost_share = lost_share
        self.scans = 0
        self.readings = 0
        self.lost = 0
        self.switched_at = None
        self._travel = LaserTravel()

    @property
    def travel(self):
        """Return the farthest the laser came from its first position [m]."""
        return self._travel.farthest

    @property
    def share(self):
        """Return the share of the readings watched lost inside a surface (0 without any)."""
        return self.lost / self.readings if self.readings else 0.0

    def watch(self, laser_xy, ranges, range_min, range_max, stamp=None):
        """
        Watch one scan; return True when it is the scan that shows a real laser on the move.

        Parameters
        ----------
        laser_xy : (float, float)
            The laser's position in the map frame [m].
        ranges : (L,) array_like of float
            As the driver wrote them [m].
        range_min, range_max : float
            [m]
        stamp : float, optional
            The scan's time [s].

        Returns
        -------
        bool
            True once: when the laser has moved more than `STANDING_DISTANCE`, at least
            `SWITCH_MIN_SCANS` scans were watched, and at least `SWITCH_MIN_LOST` and more than
            ``lost_share`` of their readings were lost inside a surface.

        """
        if self.switched_at is not None:
            return False
        ranges = np.asarray(ranges, dtype=np.float64)
        self.lost += lost_returns(ranges, range_min, range_max)
        self.readings += int(ranges.shape[0])
        self.scans += 1
        self._travel.add(laser_xy)
        if (not self._travel.standing and self.scans >= SWITCH_MIN_SCANS
                and self.lost >= SWITCH_MIN_LOST and self.share > self.lost_share):
            self.switched_at = 0.0 if stamp is None else float(stamp)
            return True
        return False

    def describe(self, overrides, elapsed):
        """
        Return one line on the switch, for a log or a note.

        Parameters
        ----------
        overrides : dict of str to float
            The settings taken (`real_laser_overrides` before the switch).
        elapsed : float
            Time from the first scan to the first scan read with them [s].

        """
        taken = ', '.join(f'{name} {value:g}' for name, value in overrides.items())
        return (f'a real laser: once it moved, {100.0 * self.share:.2f} % of its readings were '
                'returns lost inside a surface (an ideal laser loses none); from '
                f'{elapsed:.1f} s on, the settings of config/dpn_real_laser.yaml left at their '
                f'defaults are taken ({taken}) and the map starts again; '
                'real_laser_switch: 0 keeps the settings given')
