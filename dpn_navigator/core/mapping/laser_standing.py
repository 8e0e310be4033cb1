"""
Whether the laser stands still: for beams with no return, which show space empty only then.

A beam with no return says that nothing echoed, not that nothing is there: a wall seen at
grazing incidence, or a dark one, returns nothing. From a laser that stands still the same
wall stays at the same incidence, so reading such a beam as empty space costs nothing but a
wall that never shows; from a laser that moves, the wall turns towards it and its next echo
lands in space the laser has seen empty, where it looks like motion. ``LabelRule``'s
``no_return_standing_distance`` and ``no_return_standing_time`` use `LaserStanding` to let
beams with no return clear space only while the laser stands, and to drop the free
evidence when it starts to move. No ROS, no kernels.

"""

import math


class LaserStanding:
    """
    Follow the laser's position and say whether it stands still.

    The laser stands when it has stayed within ``distance`` of one place (the anchor, where
    it came to rest) for at least ``time``. A position farther than ``distance`` from the
    anchor makes it move, and becomes the new anchor.

    Parameters
    ----------
    distance : float
        Radius of the place the laser may wander in and still stand [m], > 0: the pose's
        noise (a localiser's jitter), well below the distance it drives in ``time``.
    time : float
        How long the laser must stay at a place before it stands [s], >= 0.

    """

    def __init__(self, distance, time):
        self.distance = float(distance)
        self.time = float(time)
        if not (math.isfinite(self.distance) and self.distance > 0.0):
            raise ValueError(f'distance must be finite and > 0, got {distance!r} m')
        if not (math.isfinite(self.time) and self.time >= 0.0):
            raise ValueError(f'time must be finite and >= 0, got {time!r} s')
        self.standing = False
        self._anchor = None          # (x, y) [m] of the place, or None before a first pose
        self._since = -math.inf      # when the laser came to the anchor [s]

    def step(self, pose, stamp):
        """
        Take the laser's position at ``stamp``; return whether it started to move.

        Parameters
        ----------
        pose : (float, float, ...)
            The laser's position in the map frame ``(x, y, ...)`` [m].
        stamp : float
            The time of the pose [s], any clock. When time goes back (a bag played again)
            the laser counts as having come to its place then.

        Returns
        -------
        bool
            True when the laser stood before this pose and moves now (``standing`` is then
            False). ``standing`` holds the state after this pose.

        """
        xy = (float(pose[0]), float(pose[1]))
        stamp = float(stamp)
        if self._anchor is None or math.dist(self._anchor, xy) > self.distance:
            started = self.standing
            self._anchor = xy
            self._since = stamp
            self.standing = False
            return started
        if stamp < self._since:
            self._since = stamp
        self.standing = stamp - self._since >= self.time
        return False

    def reset(self):
        """Forget the place: the next pose is a new one, and the laser does not stand."""
        self.standing = False
        self._anchor = None
        self._since = -math.inf
