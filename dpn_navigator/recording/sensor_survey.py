"""
What a recording's laser did, and which of the package's parameter files suits it.

``dpn-replay`` surveys every scan it places (`SensorSurvey.add`) and, after the replay, prints
the hints of `SensorSurvey.hints` on stderr; the ``dpn`` node surveys its first scans and logs
them once its laser has moved (`NODE_HINT_SCANS`). The node's defaults are made for an ideal
laser, and real lasers often need one of the package's files:

- the driver writes a beam with no echo as a tiny range (the old Hokuyo driver: 0.000-0.019 m,
  16-47 % of the readings of the leg_tracker recordings): under REP 117 these are invalid, and
  ``no_echo_below_range_min`` reads them as no return;
- the laser stood still the whole time: ``config/dpn_standing_laser.yaml``;
- the laser moved, many beams returned nothing (walls met at a grazing angle) and some returns
  were lost inside surfaces (a real laser's dropouts; an ideal laser in open space has many
  beams with no return but loses none inside a surface): ``config/dpn_real_laser.yaml``. Only
  with ``real_laser_switch`` 0: by default the navigator takes that file's settings itself
  when it sees such a laser on the move (``core.real_laser``).

No rclpy here: a plain survey of numbers, usable in batch runs.

"""

from dataclasses import dataclass, field
import math

import numpy as np

from ..core.real_laser import LaserTravel, lost_returns
from ..core.real_laser import STANDING_DISTANCE  # noqa: F401 (re-exported)
from ..core.settings import settings_of

#: A share of no-echo codes (finite readings below ``range_min``) above this is worth a hint.
NO_ECHO_HINT_SHARE = 0.05
#: A share of readings with no return (``+inf`` or at ``range_max`` and beyond) above this, on
#: a laser that moved, is worth a hint.
NO_RETURN_HINT_SHARE = 0.05
#: A share of such lost returns above this tells a real laser from an ideal one (simulated, on
#: six maps: ideal 0, SICK LMS1xx 0.2 %, UTM-30LX 0.5 %, RPLIDAR A2 1.0 %).
LOST_RETURN_HINT_SHARE = 0.001
#: Scans a running node surveys, its laser having moved, before it logs the hints.
NODE_HINT_SCANS = 100
#: The settings the hints are about: a hint names only what was not changed.
HINTED_SETTINGS = ('no_echo_below_range_min', 'free_burn_in', 'no_return_reach',
                   'real_laser_switch')


def changed_settings(config, names=HINTED_SETTINGS):
    """
    Return the names among ``names`` whose value in ``config`` is not the default.

    Parameters
    ----------
    config : NavigatorConfig
        The node's settings.
    names : sequence of str
        Settings of ``NavigatorConfig``.

    Returns
    -------
    set of str

    """
    defaults = settings_of(type(config))
    return {name for name in names if getattr(config, name) != defaults[name][0]}


@dataclass
class SensorSurvey:
    """
    Counts over the scans of a recording.

    Attributes
    ----------
    readings : int
        Every reading of every scan surveyed.
    no_echo_codes : int
        Finite readings ``0 <= range < range_min``.
    no_returns : int
        Readings ``+inf`` or ``>= range_max`` (REP 117: no return within range).
    lost_returns : int
        Returns lost inside a surface (``core.real_laser.lost_returns``).
    scans : int
    laser_travel : core.real_laser.LaserTravel
        How far the laser came from its first position (`travel`, `standing`).

    """

    readings: int = 0
    no_echo_codes: int = 0
    no_returns: int = 0
    lost_returns: int = 0
    scans: int = 0
    laser_travel: LaserTravel = field(default_factory=LaserTravel)

    def add(self, ranges, range_min, range_max, position):
        """
        Count one scan.

        Parameters
        ----------
        ranges : (L,) array_like of float
            As recorded [m] (REP 117 ``inf``/``NaN`` kept).
        range_min, range_max : float
            [m]
        position : (float, float)
            The laser's position in the map frame [m].

        """
        ranges = np.asarray(ranges, dtype=np.float64)
        with np.errstate(invalid='ignore'):
            self.no_echo_codes += int((np.isfinite(ranges) & (ranges >= 0.0)
                                       & (ranges < range_min)).sum())
            beyond = np.isfinite(ranges) & (ranges >= range_max)
            self.no_returns += int(((ranges == math.inf) | beyond).sum())
        self.lost_returns += lost_returns(ranges, range_min, range_max)
        self.readings += int(ranges.shape[0])
        self.scans += 1
        self.laser_travel.add(position)

    @property
    def travel(self):
        """Return the farthest the laser came from its first position [m]."""
        return self.laser_travel.farthest

    def share(self, count):
        """Return ``count`` over the readings (0 without any)."""
        return count / self.readings if self.readings else 0.0

    @property
    def standing(self):
        """Whether the laser stayed within `STANDING_DISTANCE` of its first position."""
        return self.laser_travel.standing

    def hints(self, values, files=True, standing=True):
        """
        Return the hints for a replay made with the parameter overrides ``values``.

        Parameters
        ----------
        values : dict of str to value
            The dpn node's parameters given (the params file's, and ``paper``'s rule set):
            a hint names only what was not set.
        files : bool
            Whether to name the package's parameter files (not for the paper's rule set).
        standing : bool
            Whether a laser that stood still is worth a hint (not for a running node: its
            robot stands while it waits for a goal).

        Returns
        -------
        list of str
            One line each, without the program's name.

        """
        hints = []
        no_echo = self.share(self.no_echo_codes)
        if no_echo > NO_ECHO_HINT_SHARE and 'no_echo_below_range_min' not in values:
            hints.append(
                f'{100.0 * no_echo:.0f} % of the readings are finite and below range_min, '
                'read as invalid (REP 117); if the driver writes a beam with no echo so (the '
                'old Hokuyo driver), set no_echo_below_range_min: true in a --params-file')
        if files and standing and self.standing and 'free_burn_in' not in values:
            hints.append(
                f'the laser stood still (within {self.travel:.2f} m of its first place): '
                'config/dpn_standing_laser.yaml of the package suits a laser standing still '
                '(range noise, burn-in, a second look; docs/real_data.md)')
        no_return = self.share(self.no_returns)
        lost = self.share(self.lost_returns)
        if (files and not self.standing and self.scans and no_return > NO_RETURN_HINT_SHARE
                and lost > LOST_RETURN_HINT_SHARE and 'no_return_reach' not in values
                and 'real_laser_switch' in values):
            hints.append(
                f'the laser moved {self.travel:.1f} m, {100.0 * no_return:.0f} % of the '
                f'readings returned nothing and {100.0 * lost:.1f} % were returns lost inside '
                'a surface (a real laser): config/dpn_real_laser.yaml of the package suits a '
                'moving robot with a real laser (beams with no return clear nothing; '
                'docs/method.md)')
        return hints
