"""
Turn sweep: a turn in place that would swing the robot's corners into something is not made.

The Husky is a 0.99 m x 0.67 m box that turns in place about its centre, so its corners sweep
the disc of its circumscribed radius (0.6 m). The planner's 0.5 m cells do not keep that disc
clear: its paths run along cell centres, 0.65 m from a wall in the maze's 2 m corridors, and a
wanderer stopped 0.87 m from the robot's centre was hit by a rear corner as the robot turned
towards the next waypoint (u_turn, task 0, 10 wanderers). Before a turn in place is sent, its
sweep is tested against the laser hits kept around the robot, in the map frame.

**Kept hits.** The laser covers only the 180 degrees ahead, so the robot remembers the hits
around it. A hit is kept while it is within reach of the robot and no later scan has seen
through its place (a beam on its bearing that ends farther away); it counts for ``memory``
seconds, and after that only while the grid still labels its cell an obstacle (a wall, or an
object the grid has not yet let go). A wall corner seen before the robot crept past it thus
stays in the sweep however long the robot waits, and a wanderer that drove off out of view
stops counting once its hits are old and the grid has cleared its cell.

**Turn places.** When the follower's turn would touch a kept hit, the robot looks for a place
within ``spot_distance`` from which the turn is clear: a short turn in place towards it (its
sweep clear), a straight drive there (the box, widened by ``margin``, clear of the hits along
the way) and, there, the rest of the turn to the follower's heading (its sweep clear). The
cheapest such place (distance plus the turn towards it, at 0.3 m per radian) is driven to at
``speed``, each step checked again; there the follower's turn is checked once more. Without
such a place the robot waits: a wanderer moves on, and the planner replans when the map
changes. Turning the other way round is no way out: a turn of more than half a turn brings the
box to every orientation, so it meets whatever the short turn meets.

The sweep of a turn by ``angle`` is the footprint at every ``SWEEP_STEP`` of the turn, each
side widened by ``margin``. A hit already within the widened footprint before the turn (beside
a wall the robot stands close to) counts only when the turn would bring it inside the footprint
itself, so that a robot standing close to a wall can still turn away from it.

"""

import math

import numpy as np

from .path_follower import STOP, VelocityCommand
from ..pose2d import wrap_angle
from ..scan_polygon import check_scan

#: Angle between two tested poses of a sweep [rad] (a 0.6 m corner moves 3 cm).
SWEEP_STEP = 0.05
#: Hits farther than this beyond the circumscribed radius and the turn-place distance from the
#: robot are not kept [m].
KEEP_BEYOND = 1.0
#: Of the kept hits closer together than this (in one cell of a lattice of this side), only
#: the newest is kept [m].
KEEP_SPACING = 0.02
#: A kept hit is seen through when a beam on its bearing ends this much farther away [m].
SEE_THROUGH_TOLERANCE = 0.1
#: Turn places are tried at multiples of this distance [m] ...
SPOT_STEP = 0.1
#: ... and of this bearing from the robot's heading [rad], up to ``SPOT_MAX_BEARING``.
SPOT_BEARING_STEP = math.radians(10.0)
SPOT_MAX_BEARING = math.radians(90.0)
#: The turn towards a turn place costs as much as this much more distance per radian [m/rad].
SPOT_TURN_COST = 0.3
#: A turn place is reached this close [m]; the robot drives to it once heading this close to it
#: [rad].
SPOT_REACHED = 0.03
SPOT_HEADING_TOLERANCE = 0.05
#: Turn rate towards a turn place [rad/s], and the gain of the heading correction on the way
#: [1/s].
SPOT_TURN_RATE = 0.6
SPOT_HEADING_GAIN = 2.0


def box_neighbours(points, length, width, margin, beyond):
    """
    Return the points a box can meet when it moves, and the margin each one is kept by.

    Parameters
    ----------
    points : (N, 2) array_like of float
        Points in the box's frame (x forward, y left, origin at its centre) [m].
    length, width : float
        The box's sides along x and y [m].
    margin : float
        Added to each half side [m].
    beyond : float
        How far the box's widened corners move at most [m]: points farther than that beyond
        the widened box's circumscribed circle are left out.

    Returns
    -------
    points : (K, 2) ndarray of float64
        The points outside the box itself and within reach.
    widen : (K,) ndarray of float64
        ``margin`` for the points outside the widened box, 0 for those already within the
        margin (beside a wall the robot stands close to: they count only when the box itself
        would reach them).

    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    half_x, half_y = 0.5 * length, 0.5 * width
    outside_widened = ((np.abs(points[:, 0]) > half_x + margin)
                       | (np.abs(points[:, 1]) > half_y + margin))
    inside_box = (np.abs(points[:, 0]) <= half_x) & (np.abs(points[:, 1]) <= half_y)
    reach = beyond + math.hypot(half_x + margin, half_y + margin)
    keep = ~inside_box & (np.hypot(points[:, 0], points[:, 1]) <= reach)
    return points[keep], np.where(outside_widened[keep], margin, 0.0)


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
    if angle == 0.0:
        return False
    points, widen = box_neighbours(points, length, width, margin, 0.0)
    if not points.shape[0]:
        return False
    half_x, half_y = 0.5 * length, 0.5 * width
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


def seen_through(points, laser_pose, ranges, angle_min, angle_increment, range_min, range_max,
                 tolerance=SEE_THROUGH_TOLERANCE):
    """
    Tell which points a scan sees through: the beam on a point's bearing ends beyond it.

    Parameters
    ----------
    points : (N, 2) ndarray of float64
        Points in the map frame [m].
    laser_pose : (float, float, float)
        The laser's ``(x, y, yaw)`` in the map frame [m, m, rad].
    ranges : (L,) ndarray of float64
        The scan's ranges [m]: NaN or below ``range_min`` is no reading, ``range_max`` or more
        (``inf``) a beam that hit nothing within ``range_max``.
    angle_min, angle_increment : float
        Bearing of the first beam and between beams, in the laser frame [rad]; checked by
        ``scan_polygon.check_scan_angles``.
    range_min, range_max : float
        [m]
    tolerance : float
        How much farther than a point its beam must end [m].

    Returns
    -------
    (N,) ndarray of bool
        True where the nearest beam in bearing ends more than ``tolerance`` beyond the point;
        False for points off the scan's fan and for beams without a reading.

    Raises
    ------
    ValueError
        For a malformed scan (``scan_polygon.check_scan``).

    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    ranges = check_scan(np.asarray(ranges, dtype=np.float64).reshape(-1), angle_min,
                        angle_increment, range_min, range_max)
    if points.shape[0] == 0 or ranges.shape[0] == 0:
        return np.zeros(points.shape[0], dtype=bool)
    x, y, yaw = laser_pose
    dx, dy = points[:, 0] - x, points[:, 1] - y
    offset = np.mod(np.arctan2(dy, dx) - yaw - angle_min, 2.0 * math.pi)
    # The beam index as a float first: bounded on both sides (and NaN, from a NaN point, made
    # off the fan) before the cast, which cannot overflow then.
    beam = np.rint(offset / angle_increment)
    on_fan = (beam >= 0.0) & (beam < ranges.shape[0])
    index = np.where(on_fan, beam, 0.0).astype(np.int64)
    measured = ranges[index]
    no_return = measured >= range_max                          # True for +inf
    reading = no_return | (measured >= range_min)              # False for NaN
    ends = np.where(no_return, range_max, measured)
    return on_fan & reading & (ends > np.hypot(dx, dy) + tolerance)


def find_turn_place(points, turn, length, width, margin, max_distance):
    """
    Find a place near the robot from which a turn in place to the same heading is clear.

    A place is a point at a multiple of ``SPOT_STEP`` up to ``max_distance`` ahead, on a bearing
    a multiple of ``SPOT_BEARING_STEP`` within ``SPOT_MAX_BEARING`` of the heading. It is
    reachable when the turn towards it misses the points (`sweep_hits`) and so does the straight
    drive there (`advance_hits`); it serves when, there, the rest of the turn (to the heading
    ``turn`` from the robot's now, the short way round) misses them too.

    Parameters
    ----------
    points : (N, 2) ndarray of float64
        Points in the robot's frame [m], as for `sweep_hits`.
    turn : float
        The turn in place wanted from here [rad].
    length, width, margin : float
        As for `sweep_hits` [m].
    max_distance : float
        Farthest place tried [m].

    Returns
    -------
    (float, float) or None
        The cheapest place that serves, in the robot's frame [m] (cost: its distance plus
        ``SPOT_TURN_COST`` times the turn towards it), or None.

    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    steps = int(math.floor(max_distance / SPOT_STEP + 1e-9))
    bearing_steps = int(math.floor(SPOT_MAX_BEARING / SPOT_BEARING_STEP + 1e-9))
    bearings = SPOT_BEARING_STEP * np.arange(-bearing_steps, bearing_steps + 1)
    candidates = sorted(((k * SPOT_STEP + SPOT_TURN_COST * abs(b), k * SPOT_STEP, b)
                         for k in range(1, steps + 1) for b in bearings))
    turn_clear = {}
    drive_blocked = {}                 # bearing -> shortest blocked distance
    for _, distance, bearing in candidates:
        if bearing not in turn_clear:
            turn_clear[bearing] = not sweep_hits(points, bearing, length, width, margin)
        if not turn_clear[bearing] or distance >= drive_blocked.get(bearing, math.inf):
            continue
        cos_b, sin_b = math.cos(bearing), math.sin(bearing)
        # The points in the frame of the robot turned by the bearing, then moved ahead.
        turned = np.column_stack((cos_b * points[:, 0] + sin_b * points[:, 1],
                                  -sin_b * points[:, 0] + cos_b * points[:, 1]))
        if advance_hits(turned, distance, length, width, margin):
            drive_blocked[bearing] = distance
            continue
        there = turned - np.array([distance, 0.0])
        if not sweep_hits(there, wrap_angle(turn - bearing), length, width, margin):
            return distance * cos_b, distance * sin_b
    return None


class TurnSweep:
    """
    The kept laser hits around the robot, and the check of a turn in place against them.

    Parameters
    ----------
    memory : float
        How long every kept hit counts [s], > 0; after that a hit counts only while the grid
        holds its cell as an obstacle (``check``'s ``obstacle``).
    length, width : float
        The robot's footprint, centred on the base frame's origin [m].
    margin : float
        Clearance a turn, and the drive to a turn place, keeps from the kept hits [m], >= 0.
    speed : float
        Forward speed on the way to a turn place [m/s], > 0.
    spot_distance : float
        Farthest turn place tried [m], >= 0; 0: none, the robot waits.
    min_reach : float
        Hits are kept at least this far from the robot [m] (the drive guard's ``reach``).

    Attributes
    ----------
    held : int
        Steps whose turn in place was not sent, since the last ``reset``.
    spots : int
        Turn places chosen.
    waits : int
        Steps the robot waited (no turn place).

    """

    def __init__(self, memory, length, width, margin=0.05, speed=0.2, spot_distance=0.6,
                 min_reach=0.0):
        for name, value in (('memory', memory), ('length', length), ('width', width),
                            ('speed', speed)):
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be positive and finite, got {value!r}')
        for name, value in (('margin', margin), ('spot_distance', spot_distance)):
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        self.memory = memory
        self.length = length
        self.width = width
        self.margin = margin
        self.speed = speed
        self.spot_distance = spot_distance
        self.reach = max(0.5 * math.hypot(length, width) + margin + spot_distance + KEEP_BEYOND,
                         min_reach)
        self.reset()

    def reset(self):
        """Forget the kept hits and the turn place, and zero the counters."""
        self._xy = np.empty((0, 2))           # kept hits in the map frame [m]
        self._stamps = np.empty(0)            # their scans' stamps [s]
        self._now = None
        self._spot = None                     # the turn place, map frame [m]
        self._driving = False                 # heading for it, driving there
        self.held = 0
        self.spots = 0
        self.waits = 0

    @property
    def kept(self):
        """Return the kept hits in the map frame, (N, 2) float64 [m]."""
        return self._xy

    def add_scan(self, stamp, robot_xy, hits_xy, view=None):
        """
        Keep one scan's hits near the robot; drop the kept hits out of reach or seen through.

        Parameters
        ----------
        stamp : float or None
            Time of the scan [s]; None (no clock) keeps only this scan, as does a stamp older
            than the last one (the clock restarted).
        robot_xy : (float, float)
            The robot's position in the map frame [m].
        hits_xy : (N, 2) ndarray of float64
            The scan's hit points in the map frame [m].
        view : tuple, optional
            ``(laser_pose, ranges, angle_min, angle_increment, range_min, range_max)`` of the
            scan, as for `seen_through`: the kept hits it sees through are dropped.

        """
        hits_xy = np.asarray(hits_xy, dtype=np.float64).reshape(-1, 2)
        if stamp is None or (self._now is not None and stamp < self._now):
            self._xy, self._stamps = np.empty((0, 2)), np.empty(0)
        keep = np.hypot(self._xy[:, 0] - robot_xy[0],
                        self._xy[:, 1] - robot_xy[1]) <= self.reach
        if view is not None:
            keep &= ~seen_through(self._xy, *view)
        near = np.hypot(hits_xy[:, 0] - robot_xy[0], hits_xy[:, 1] - robot_xy[1]) <= self.reach
        self._now = stamp
        xy = np.concatenate((self._xy[keep], hits_xy[near]))
        stamps = np.concatenate((self._stamps[keep],
                                 np.full(int(near.sum()), 0.0 if stamp is None else stamp)))
        # One hit per lattice cell: the newest, the last one in the arrays.
        cells = np.floor(xy / KEEP_SPACING).astype(np.int64)
        key = cells[:, 0] * (1 << 32) + cells[:, 1]
        _, last = np.unique(key[::-1], return_index=True)
        newest = np.sort(xy.shape[0] - 1 - last)
        self._xy, self._stamps = xy[newest], stamps[newest]

    def points(self, pose, obstacle=None, within=None):
        """
        Return the kept hits that count, in the robot's frame at ``pose`` [m], (N, 2).

        ``pose`` and ``obstacle`` are as for `check`; ``within`` [m], if given, leaves out the
        hits farther than that from the robot (the grid is not asked about them).
        """
        hits, stamps = self._xy, self._stamps
        if within is not None:
            near = np.hypot(hits[:, 0] - pose[0], hits[:, 1] - pose[1]) <= within
            hits, stamps = hits[near], stamps[near]
        if self._now is not None:
            old = self._now - stamps > self.memory
            if old.any():
                count = ~old
                if obstacle is not None:
                    count[old] = np.asarray(obstacle(hits[old]), dtype=bool)
                hits = hits[count]
        x, y, yaw = pose
        dx, dy = hits[:, 0] - x, hits[:, 1] - y
        cos_y, sin_y = math.cos(yaw), math.sin(yaw)
        return np.column_stack((cos_y * dx + sin_y * dy, -sin_y * dx + cos_y * dy))

    def check(self, command, pose, obstacle=None):
        """
        Return ``command``, or a safe replacement when it is a turn in place whose sweep hits.

        Parameters
        ----------
        command : VelocityCommand
            The follower's command; only a turn in place (zero linear, non-zero angular,
            with ``turn`` set) is checked.
        pose : (float, float, float)
            The robot's pose in the map frame [m, m, rad].
        obstacle : callable, optional
            ``obstacle(xy)`` for (N, 2) map-frame points [m]: (N,) bool, whether the grid holds
            each point's cell as an obstacle; the kept hits older than ``memory`` count only
            there. None: they do not count.

        Returns
        -------
        VelocityCommand
            ``command``; or a step towards a turn place (a slow turn in place towards it, or a
            drive ahead); or ``STOP``.

        """
        if command.linear != 0.0 or command.angular == 0.0 or command.turn == 0.0:
            self._spot, self._driving = None, False
            return command
        points = self.points(pose, obstacle)
        if not sweep_hits(points, command.turn, self.length, self.width, self.margin):
            self._spot, self._driving = None, False
            return command
        self.held += 1
        if self._spot is not None:
            step = self._towards_spot(points, pose)
            if step is not None:
                return step
            self._spot = None
        self._driving = False
        if self.spot_distance > 0.0:
            spot = find_turn_place(points, command.turn, self.length, self.width, self.margin,
                                   self.spot_distance)
            if spot is not None:
                x, y, yaw = pose
                cos_y, sin_y = math.cos(yaw), math.sin(yaw)
                self._spot = (x + cos_y * spot[0] - sin_y * spot[1],
                              y + sin_y * spot[0] + cos_y * spot[1])
                self.spots += 1
                step = self._towards_spot(points, pose)
                if step is not None:
                    return step
                self._spot = None
        self.waits += 1
        return STOP

    def _towards_spot(self, points, pose):
        """Return the next step to the turn place, or None when it is reached or blocked."""
        x, y, yaw = pose
        dx, dy = self._spot[0] - x, self._spot[1] - y
        ahead = math.cos(yaw) * dx + math.sin(yaw) * dy
        left = -math.sin(yaw) * dx + math.cos(yaw) * dy
        distance = math.hypot(ahead, left)
        bearing = math.atan2(left, ahead)
        if self._driving:
            if ahead <= SPOT_REACHED:
                return None                            # there (abreast of it)
        elif distance <= SPOT_REACHED:
            return None
        elif abs(bearing) > SPOT_HEADING_TOLERANCE:
            if sweep_hits(points, bearing, self.length, self.width, self.margin):
                return None
            rate = min(SPOT_TURN_RATE, SPOT_HEADING_GAIN * abs(bearing))
            return VelocityCommand(0.0, math.copysign(rate, bearing))
        if advance_hits(points, ahead, self.length, self.width, self.margin):
            return None
        self._driving = True
        angular = float(np.clip(SPOT_HEADING_GAIN * bearing, -SPOT_TURN_RATE, SPOT_TURN_RATE))
        return VelocityCommand(min(self.speed, ahead), angular)
