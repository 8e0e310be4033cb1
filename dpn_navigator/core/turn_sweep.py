"""
Turn sweep: a turn in place that would swing the robot's corners into something is not made.

The Husky is a 0.99 m x 0.67 m box that turns in place about its centre, so its corners sweep
the disc of its circumscribed radius (0.6 m). The planner's 0.5 m cells do not keep that disc
clear of an object beside the robot: a wanderer stopped 0.87 m from the robot's centre was hit
by a rear corner as the robot turned towards the next waypoint (u_turn, task 0, 10 wanderers).
The laser covers only the 180 degrees ahead, so the hit points of the last ``memory`` seconds
are kept, in the map frame, and before a turn in place is sent its sweep is tested against
them. The follower's turn is kept when its sweep is clear; else the robot creeps straight
ahead when the box moved forward is clear of every kept hit (ahead is where the laser looks),
and waits otherwise (a wanderer moves on; the planner replans once the robot has left its
path). Turning the other way round is no way out: a turn of more than half a turn brings the
box to every orientation, so it meets whatever the short turn meets.

The sweep of a turn by ``angle`` is the footprint at every ``SWEEP_STEP`` of the turn, each
side widened by ``margin``. A hit already within the widened footprint before the turn (beside
a wall the robot stands close to) counts only when the turn would bring it inside the footprint
itself, so that a robot standing close to a wall can still turn away from it.

"""

import math

import numpy as np

from .path_follower import STOP, VelocityCommand

#: Angle between two tested poses of a sweep [rad] (a 0.6 m corner moves 3 cm).
SWEEP_STEP = 0.05
#: Hits farther than this beyond the circumscribed radius from the robot are not kept [m].
KEEP_BEYOND = 1.0


def sweep_hits(points, angle, length, width, margin):
    """
    Tell whether turning a box in place by ``angle`` brings it onto any of ``points``.

    Parameters
    ----------
    points : (N, 2) ndarray of float64
        Points in the box's frame before the turn (x forward, y left, origin at the centre of
        rotation) [m].
    angle : float
        The turn, counter-clockwise positive [rad].
    length, width : float
        The box's sides along x and y [m]; the box is centred on the origin.
    margin : float
        Added to each half side for points outside the widened box before the turn [m].

    Returns
    -------
    bool
        True when some point lies inside the (widened) box at some pose of the turn.

    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    half_x, half_y = 0.5 * length, 0.5 * width
    outside_widened = ((np.abs(points[:, 0]) > half_x + margin)
                       | (np.abs(points[:, 1]) > half_y + margin))
    inside_box = (np.abs(points[:, 0]) <= half_x) & (np.abs(points[:, 1]) <= half_y)
    reach = math.hypot(half_x + margin, half_y + margin)
    keep = ~inside_box & (np.hypot(points[:, 0], points[:, 1]) <= reach)
    if not keep.any() or angle == 0.0:
        return False
    points, widen = points[keep], np.where(outside_widened[keep], margin, 0.0)
    steps = max(1, math.ceil(abs(angle) / SWEEP_STEP))
    thetas = np.linspace(angle / steps, angle, steps)
    cos_t, sin_t = np.cos(thetas)[:, None], np.sin(thetas)[:, None]
    # The points in the box's frame after a turn by theta: rotated by -theta.
    x_turned = cos_t * points[:, 0] + sin_t * points[:, 1]
    y_turned = -sin_t * points[:, 0] + cos_t * points[:, 1]
    inside = (np.abs(x_turned) <= half_x + widen) & (np.abs(y_turned) <= half_y + widen)
    return bool(inside.any())


def advance_hits(points, distance, length, width, margin):
    """
    Tell whether moving a box straight ahead by ``distance`` brings it onto any of ``points``.

    Parameters
    ----------
    points : (N, 2) ndarray of float64
        Points in the box's frame [m], as for `sweep_hits`.
    distance : float
        How far the box moves along +x [m], >= 0.
    length, width, margin : float
        As for `sweep_hits` (here every side is widened).

    Returns
    -------
    bool

    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    half_x, half_y = 0.5 * length + margin, 0.5 * width + margin
    beside = np.abs(points[:, 1]) <= half_y
    ahead = (points[:, 0] > 0.5 * length) & (points[:, 0] <= half_x + distance)
    return bool((beside & ahead).any())


class TurnSweep:
    """
    The kept laser hits around the robot, and the check of a turn in place against them.

    Parameters
    ----------
    memory : float
        How long a scan's hits are kept [s], > 0.
    length, width : float
        The robot's footprint, centred on the base frame's origin [m].
    margin : float
        Clearance a turn keeps from the kept hits [m], >= 0.
    creep_speed : float
        Forward speed when neither turn is clear [m/s], > 0.
    creep_distance : float
        The straight move ahead that must be clear for the robot to creep [m], > 0.

    Attributes
    ----------
    creeps : int
        Steps the robot crept ahead instead of turning, since the last ``reset``.
    waits : int
        Steps the robot waited instead of turning.

    """

    def __init__(self, memory, length, width, margin=0.05, creep_speed=0.2,
                 creep_distance=0.3):
        for name, value in (('memory', memory), ('length', length), ('width', width),
                            ('creep_speed', creep_speed), ('creep_distance', creep_distance)):
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be positive and finite, got {value!r}')
        if not (math.isfinite(margin) and margin >= 0.0):
            raise ValueError(f'margin must be finite and >= 0, got {margin!r}')
        self.memory = memory
        self.length = length
        self.width = width
        self.margin = margin
        self.creep_speed = creep_speed
        self.creep_distance = creep_distance
        self._scans = []                 # (stamp, (N, 2) hits in the map frame [m])
        self.reset()

    def reset(self):
        """Forget the kept hits and zero the counters."""
        self._scans.clear()
        self.creeps = 0
        self.waits = 0

    def add_scan(self, stamp, robot_xy, hits_xy):
        """
        Keep one scan's hits near the robot; drop scans older than ``memory``.

        Parameters
        ----------
        stamp : float or None
            Time of the scan [s]; None keeps only this scan.
        robot_xy : (float, float)
            The robot's position in the map frame [m].
        hits_xy : (N, 2) ndarray of float64
            The scan's hit points in the map frame [m].

        """
        hits_xy = np.asarray(hits_xy, dtype=np.float64).reshape(-1, 2)
        reach = 0.5 * math.hypot(self.length, self.width) + self.margin + KEEP_BEYOND
        near = np.hypot(hits_xy[:, 0] - robot_xy[0], hits_xy[:, 1] - robot_xy[1]) <= reach
        if stamp is None or (self._scans and self._scans[-1][0] is not None
                             and stamp < self._scans[-1][0]):
            self._scans.clear()          # no clock, or time went back: only this scan
        self._scans.append((stamp, hits_xy[near]))
        if stamp is not None:
            self._scans = [(t, h) for t, h in self._scans if stamp - t <= self.memory]

    def _points(self, pose):
        """Return the kept hits in the robot's frame at ``pose`` [m], (N, 2)."""
        if not self._scans:
            return np.empty((0, 2))
        hits = np.concatenate([h for _, h in self._scans])
        x, y, yaw = pose
        dx, dy = hits[:, 0] - x, hits[:, 1] - y
        cos_y, sin_y = math.cos(yaw), math.sin(yaw)
        return np.column_stack((cos_y * dx + sin_y * dy, -sin_y * dx + cos_y * dy))

    def check(self, command, pose):
        """
        Return ``command``, or a safe replacement when it is a turn in place whose sweep hits.

        Parameters
        ----------
        command : VelocityCommand
            The follower's command; only a turn in place (zero linear, non-zero angular,
            with ``turn`` set) is checked.
        pose : (float, float, float)
            The robot's pose in the map frame [m, m, rad].

        Returns
        -------
        VelocityCommand

        """
        if command.linear != 0.0 or command.angular == 0.0 or command.turn == 0.0:
            return command
        points = self._points(pose)
        if not sweep_hits(points, command.turn, self.length, self.width, self.margin):
            return command
        if not advance_hits(points, self.creep_distance, self.length, self.width,
                            self.margin):
            self.creeps += 1
            return VelocityCommand(self.creep_speed, 0.0)
        self.waits += 1
        return STOP
