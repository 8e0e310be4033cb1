"""
When kept evidence begins a new generation: every so many metres of the laser's travel.

``free_evidence_renewal`` keeps the free evidence in two generations and drops the older one
each time the laser has travelled half the renewal distance; the conservative free space of
the label grid and the fine free evidence count the travel alike, with one `TravelGenerations`
each. No ROS, no kernels.

"""

import math


class TravelGenerations:
    """
    Count the laser's travel and say when a generation ends.

    Parameters
    ----------
    period : float
        Travel per generation [m], > 0 (half of ``free_evidence_renewal``).

    """

    def __init__(self, period):
        self.period = float(period)
        if not (math.isfinite(self.period) and self.period > 0.0):
            raise ValueError(f'period must be finite and > 0, got {period!r} m')
        self.travel = 0.0
        self._last_xy = None

    def step(self, pose):
        """
        Add the travel from the last position to ``pose``; tell whether a generation begins.

        Parameters
        ----------
        pose : (float, float, ...)
            The laser's position in the map frame ``(x, y, ...)`` [m].

        Returns
        -------
        bool
            True when the travel since the current generation began reached ``period``
            (the travel then starts again from 0).

        """
        xy = (float(pose[0]), float(pose[1]))
        if self._last_xy is not None:
            self.travel += math.dist(self._last_xy, xy)
        self._last_xy = xy
        if self.travel < self.period:
            return False
        self.travel = 0.0
        return True

    def reset(self):
        """Forget the travel and the last position."""
        self.travel = 0.0
        self._last_xy = None
