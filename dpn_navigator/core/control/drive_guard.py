"""
Drive guard: a drive along an arc that would bring the robot's box onto a kept hit is not made.

The planner keeps the path's cells ``footprint_radius`` (0.6 m) from obstacle cells, but on
0.5 m cells the Husky's 0.99 m x 0.67 m box can still reach a body the path passes: on
held-out seed 1 (narrow_passages, task 1, 2 wanderers, repetition 0) the robot curved around
a P3-AT standing 0.95 m ahead and its front corner struck it at 0.79 m between centres. The
turn sweep (``turn_sweep``) guards only turns in place. Before a command that drives forward is
sent, the drive guard follows the box along the command's arc (constant linear and angular
speed) for ``distance`` metres of travel and tests it against the laser hits the turn sweep
keeps around the robot, in the map frame.

**The arc clear:** the command is sent as it is.

**The arc blocked:** the robot slows to ``speed`` and steers along the clear arc whose
curvature is nearest the command's, among curvatures from straight to ``MAX_CURVATURE`` either
way; it thus slides past the body on the side the path wants. With no clear arc (the body
stands right across the front), it turns in place by ``TURN_STEP`` the way the command turns,
at ``TURN_RATE``, when that turn's sweep (``turn_sweep.sweep_hits``) is clear, and the arcs are
tried again from the new heading; else it stops: the planner replans when the map changes, and
a wanderer moves on.

As for the sweep, a hit already within the box widened by ``margin`` before the drive (beside a
wall the robot stands close to) counts only when the drive would bring it inside the box
itself, and a hit inside the box (its own body, a misreading) does not count.

"""

import math

import numpy as np

from .path_follower import STOP, VelocityCommand
from .turn_sweep import box_neighbours, sweep_hits

#: Travel between two tested poses of an arc [m].
ARC_STEP = 0.05
#: Curvatures tried when the command's arc is blocked: up to this either way [1/m] ...
MAX_CURVATURE = 4.0
#: ... in this many steps from straight to each side.
CURVATURE_STEPS = 16
#: With no clear arc, the turn in place tried [rad], and its rate [rad/s].
TURN_STEP = 0.3
TURN_RATE = 0.6


def arc_poses(curvature, distance, step=ARC_STEP):
    """
    Return the poses of a box driven ``distance`` along an arc, in its frame before the drive.

    Parameters
    ----------
    curvature : float
        Turn per metre of travel, counter-clockwise positive [1/m]; 0 drives straight.
    distance : float
        Travel [m], > 0.
    step : float
        Travel between two poses [m], > 0.

    Returns
    -------
    (K, 3) ndarray of float64
        ``(x, y, yaw)`` [m, m, rad] at each step, the last at ``distance``; the start excluded.

    """
    steps = max(1, math.ceil(distance / step))
    travel = np.linspace(distance / steps, distance, steps)
    yaw = curvature * travel
    if abs(curvature) < 1e-9:
        return np.column_stack((travel, np.zeros(steps), np.zeros(steps)))
    return np.column_stack((np.sin(yaw) / curvature, (1.0 - np.cos(yaw)) / curvature, yaw))


def arc_hits(points, curvature, distance, length, width, margin):
    """
    Tell whether driving a box along an arc brings it onto any of ``points``.

    Parameters
    ----------
    points : (N, 2) ndarray of float64
        Points in the box's frame before the drive (x forward, y left, origin at the box's
        centre) [m].
    curvature : float
        [1/m], as for `arc_poses`.
    distance : float
        Travel [m], > 0.
    length, width : float
        The box's sides along x and y [m], centred on the origin.
    margin : float
        Added to each half side for points outside the widened box before the drive [m].

    Returns
    -------
    bool
        True when some point lies inside the (widened) box at some pose of the drive.

    """
    points, widen = box_neighbours(points, length, width, margin, distance)
    if not points.shape[0]:
        return False
    half_x, half_y = 0.5 * length, 0.5 * width
    poses = arc_poses(curvature, distance)
    cos_t, sin_t = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
    dx = points[None, :, 0] - poses[:, 0:1]
    dy = points[None, :, 1] - poses[:, 1:2]
    # The points in the box's frame at each pose: moved, then rotated by -yaw.
    x_moved = cos_t * dx + sin_t * dy
    y_moved = -sin_t * dx + cos_t * dy
    inside = (np.abs(x_moved) <= half_x + widen) & (np.abs(y_moved) <= half_y + widen)
    return bool(inside.any())


class DriveGuard:
    """
    The check of a forward drive against the kept laser hits.

    Parameters
    ----------
    distance : float
        Travel along the command's arc that must be clear [m], > 0.
    length, width : float
        The robot's footprint, centred on the base frame's origin [m], > 0.
    margin : float
        Clearance kept from the hits [m], >= 0.
    speed : float
        Forward speed along a steered arc [m/s], > 0.
    max_angular_speed : float
        Turn rate limit [rad/s], > 0: a steered arc that needs more is not tried.

    Attributes
    ----------
    steered : int
        Steps sent along another arc than the command's, since the last ``reset``.
    turned : int
        Steps turned in place because no arc was clear.
    stopped : int
        Steps stopped because no arc and no turn in place was clear.

    """

    def __init__(self, distance, length, width, margin=0.05, speed=0.2,
                 max_angular_speed=math.inf):
        for name, value in (('distance', distance), ('length', length), ('width', width),
                            ('speed', speed)):
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be positive and finite, got {value!r}')
        if not (math.isfinite(margin) and margin >= 0.0):
            raise ValueError(f'margin must be finite and >= 0, got {margin!r}')
        if not max_angular_speed > 0.0:
            raise ValueError(f'max_angular_speed must be positive, got {max_angular_speed!r}')
        self.distance = distance
        self.length = length
        self.width = width
        self.margin = margin
        self.speed = speed
        self.max_angular_speed = max_angular_speed
        sides = np.linspace(0.0, MAX_CURVATURE, CURVATURE_STEPS + 1)
        self._curvatures = np.concatenate((-sides[:0:-1], sides))
        self.reset()

    @property
    def reach(self):
        """Return how far from the robot's centre a hit can matter [m]."""
        return self.distance + math.hypot(0.5 * self.length + self.margin,
                                          0.5 * self.width + self.margin)

    def reset(self):
        """Zero the counters."""
        self.steered = 0
        self.turned = 0
        self.stopped = 0

    def check(self, command, points):
        """
        Return ``command``, or a safe replacement when its arc brings the box onto a point.

        Parameters
        ----------
        command : VelocityCommand
            The command; only one with a positive linear speed is checked.
        points : (N, 2) ndarray of float64
            The kept hits in the robot's frame [m] (``TurnSweep.points``).

        Returns
        -------
        VelocityCommand
            ``command``; or a drive at ``speed`` along the nearest clear arc; or a turn in place
            the way the command turns; or ``STOP``.

        """
        if not command.linear > 0.0:
            return command
        wanted = command.angular / command.linear
        if not arc_hits(points, wanted, self.distance, self.length, self.width, self.margin):
            return command
        order = np.argsort(np.abs(self._curvatures - wanted), kind='stable')
        speed = min(self.speed, command.linear)
        for curvature in self._curvatures[order]:
            if abs(curvature * speed) > self.max_angular_speed:
                continue
            if not arc_hits(points, curvature, self.distance, self.length, self.width,
                            self.margin):
                self.steered += 1
                return VelocityCommand(speed, float(curvature * speed))
        if command.angular != 0.0:
            turn = math.copysign(TURN_STEP, command.angular)
            if not sweep_hits(points, turn, self.length, self.width, self.margin):
                self.turned += 1
                rate = min(TURN_RATE, self.max_angular_speed)
                return VelocityCommand(0.0, math.copysign(rate, turn), turn=turn)
        self.stopped += 1
        return STOP
