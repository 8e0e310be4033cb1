"""
What the navigator shows of itself: the planned path, the executed path and the goal.

The ``dpn`` node publishes these on ``marker`` (``MarkerArray``) and ``plan``
(``nav_msgs/Path``) through `NavigatorMarkers`, which rebuilds each message only when what it
shows changed and sends them at most every ``marker_min_period`` on replans; the benchmark
writes the same messages into its episode bags on the schedule of `markers_due` (the node's
with ``marker_min_period`` 0).

"""

import math

from geometry_msgs.msg import Point
import numpy as np
from visualization_msgs.msg import Marker, MarkerArray

from .conversions import line_strip_marker, points_to_path, sphere_marker

TRAIL_STEP = 0.05               # executed-path points at least this far apart [m]
# The executed path keeps its newest TRAIL_MAX_POINTS points (1 km at TRAIL_STEP); the node's
# `ExecutedTrail` allocates them all at start (about 2.4 MB), so its memory does not grow.
TRAIL_MAX_POINTS = 20000
TRAIL_HEIGHT = 0.05             # z of the executed path's points [m] (above the map)
MARKER_PERIOD = 0.5             # markers at most this often, besides replans [s]
RED, YELLOW, GREEN = (1.0, 0.0, 0.0, 1.0), (1.0, 0.85, 0.0, 1.0), (0.0, 0.8, 0.0, 1.0)


def extend_trail(trail, xy, max_points=TRAIL_MAX_POINTS):
    """
    Append a position to the executed path when it is ``TRAIL_STEP`` from the last one.

    Parameters
    ----------
    trail : list of (float, float)
        The executed path [m], changed in place; it keeps the newest ``max_points``.
    xy : (float, float)
        The robot's position [m].
    max_points : int
        How many points it keeps.

    """
    if not trail or math.dist(trail[-1], xy) >= TRAIL_STEP:
        trail.append(tuple(xy))
        del trail[:-max_points]


class ExecutedTrail:
    """
    The node's executed path, held as the ``executed_path`` marker's points, allocated once.

    The same rule as `extend_trail` (a point every ``TRAIL_STEP``, the newest ``capacity``
    kept), but every ``geometry_msgs/Point`` it will ever hold is made at construction and
    reused: a full trail moves its oldest point to the end, a reset takes them all back. A
    list of tuples plus a marker point per position grew by about 230 B per 5 cm driven, 5 to
    7 MB an hour of the node's resident memory at 0.3-0.45 m/s until the bound (1 km); this
    keeps it flat from the start (issue 32: the soak's growth).

    Parameters
    ----------
    capacity : int
        Points kept, >= 2.

    Attributes
    ----------
    points : list of geometry_msgs.msg.Point
        The trail in the map frame [m], oldest first, ``z`` `TRAIL_HEIGHT`: the list the
        ``executed_path`` marker of `NavigatorMarkers` publishes (the same object, changed in
        place).

    """

    def __init__(self, capacity=TRAIL_MAX_POINTS):
        capacity = int(capacity)
        if capacity < 2:
            raise ValueError(f'an executed trail keeps at least 2 points, got {capacity}')
        self.capacity = capacity
        self.points = []
        # Each point with float objects of its own, so that the first write of a coordinate
        # replaces one float by another instead of adding one (a shared 0.0 would be).
        self._spare = [Point(x=float(-k), y=float(k), z=TRAIL_HEIGHT, check_fields=False)
                       for k in range(capacity)]

    def __len__(self):
        return len(self.points)

    def __getitem__(self, index):
        """Return the point ``index`` as ``(x, y)`` [m], a slice as a list of them."""
        if isinstance(index, slice):
            return [(point.x, point.y) for point in self.points[index]]
        point = self.points[index]
        return (point.x, point.y)

    def extend(self, xy):
        """
        Append ``xy`` [m] when it lies ``TRAIL_STEP`` or more from the last point.

        Returns
        -------
        appended : bool

        """
        x, y = float(xy[0]), float(xy[1])
        if self.points:
            last = self.points[-1]
            if math.dist((last.x, last.y), (x, y)) < TRAIL_STEP:
                return False
        point = self._spare.pop() if self._spare else self.points.pop(0)
        point.x, point.y = x, y                 # made with check_fields=False: no checks
        self.points.append(point)
        return True

    def reset(self, xy=None):
        """Start the trail over, empty or at ``xy`` [m]; every point goes back to the spares."""
        self._spare.extend(self.points)
        self.points.clear()
        if xy is not None:
            self.extend(xy)


def markers_due(replanned, status_changed, now, last_marker_time):
    """
    Tell whether the markers are due: on a replan, a status change, or ``MARKER_PERIOD`` on.

    Parameters
    ----------
    replanned, status_changed : bool
        What the latest scan did.
    now, last_marker_time : float
        Times of this scan and of the last markers [s]; a jump back in time makes them due.

    """
    return replanned or status_changed or abs(now - last_marker_time) >= MARKER_PERIOD


def navigator_markers(path_xy, trail, goal, stamp, frame_id='map'):
    """
    Build the navigator's markers and its plan.

    Parameters
    ----------
    path_xy : (N, 2) ndarray of float or None
        The planned path in ``frame_id`` [m]; None: no plan.
    trail : sequence of (float, float)
        The executed path [m].
    goal : (float, float) or None
        The goal [m].
    stamp : builtin_interfaces.msg.Time
        Stamp of every message.
    frame_id : str
        The map frame.

    Returns
    -------
    markers : MarkerArray
        ``planned_path`` (red), ``executed_path`` (yellow) and, with a goal, ``goal`` (green).
    plan : nav_msgs.msg.Path
        The planned path (no poses when there is no plan).

    """
    path = np.zeros((0, 2)) if path_xy is None else path_xy
    markers = MarkerArray()
    markers.markers.append(line_strip_marker(path, 'planned_path', 0, RED, 0.1, stamp,
                                             frame_id=frame_id))
    markers.markers.append(line_strip_marker(trail, 'executed_path', 1, YELLOW, 0.08, stamp,
                                             frame_id=frame_id))
    if goal is not None:
        markers.markers.append(sphere_marker(goal, 'goal', 2, GREEN, 0.4, stamp,
                                             frame_id=frame_id))
    return markers, points_to_path(path, stamp, frame_id)


class NavigatorMarkers:
    """
    The node's markers and plan: when to send them, and each built once per change.

    Parameters
    ----------
    frame_id : str
        The map frame.
    min_period : float
        Replans and status changes send the markers at most this often [s]; one that comes
        sooner is sent with the first scan after the period. 0: with every one, as
        `markers_due` (they also go out every ``MARKER_PERIOD``).

    """

    def __init__(self, frame_id='map', min_period=0.0):
        self.frame_id = frame_id
        self.min_period = float(min_period)
        self._last_time = -math.inf
        self._pending = False
        self._path = self._goal = self._trail_last = object()    # nothing built yet
        self._planned = self._plan = self._goal_marker = self._executed = None
        self._trail_count = 0

    def due(self, replanned, status_changed, now):
        """
        Tell whether the markers are due after a scan at ``now`` [s].

        Parameters
        ----------
        replanned, status_changed : bool
            What the latest scan did.
        now : float
            Time of this scan [s]; a jump back in time makes them due.

        """
        self._pending = self._pending or replanned or status_changed
        since = abs(now - self._last_time)
        return since >= MARKER_PERIOD or (self._pending and since >= self.min_period)

    def messages(self, path_xy, trail, goal, stamp, now):
        """
        Return the markers and plan of `navigator_markers`, rebuilt where they changed.

        Parameters
        ----------
        path_xy, trail, goal, stamp
            As in `navigator_markers`; ``path_xy`` is the navigator's array, replaced (not
            changed in place) on a new plan, and ``trail`` grows at its end (`extend_trail`).
        now : float
            Time of this scan [s]: the markers count as sent now.

        Returns
        -------
        markers : MarkerArray
        plan : nav_msgs.msg.Path
            The same messages as `navigator_markers` gives, stamped ``stamp``. They are
            rewritten by the next call (the plan's poses are reused): publish them at once.

        """
        self._last_time = now
        self._pending = False
        if path_xy is not self._path:
            self._path = path_xy
            path = np.zeros((0, 2)) if path_xy is None else path_xy
            self._planned = line_strip_marker(path, 'planned_path', 0, RED, 0.1, stamp,
                                              frame_id=self.frame_id)
            self._plan = points_to_path(path, stamp, self.frame_id, reuse=self._plan)
        self._refresh_trail(trail, stamp)
        if goal != self._goal:
            self._goal = goal
            self._goal_marker = (None if goal is None else sphere_marker(
                goal, 'goal', 2, GREEN, 0.4, stamp, frame_id=self.frame_id))
        markers = MarkerArray()
        markers.markers = [self._planned, self._executed]
        if self._goal_marker is not None:
            markers.markers.append(self._goal_marker)
        for marker in markers.markers:
            marker.header.stamp = stamp
        # The poses share the Path's header (points_to_path).
        self._plan.header.stamp = stamp
        return markers, self._plan

    def _refresh_trail(self, trail, stamp):
        """Append the trail's new points to the executed-path marker, or rebuild it."""
        if isinstance(trail, ExecutedTrail):
            self._share_trail(trail, stamp)
            return
        count = len(trail)
        grown = (self._executed is not None and self._executed.action == Marker.ADD
                 and 0 < self._trail_count <= count
                 and count - self._trail_count < TRAIL_MAX_POINTS
                 and trail[self._trail_count - 1] is self._trail_last)
        if grown:
            self._executed.points.extend(
                Point(x=float(x), y=float(y), z=TRAIL_HEIGHT, check_fields=False)
                for x, y in trail[self._trail_count:])
        else:
            self._executed = line_strip_marker(trail, 'executed_path', 1, YELLOW, 0.08, stamp,
                                               frame_id=self.frame_id)
        self._trail_count = count
        self._trail_last = trail[-1] if count else None

    def _share_trail(self, trail, stamp):
        """Make the executed-path marker publish ``trail.points`` itself (built on a change)."""
        add = len(trail) >= 2
        executed = self._executed
        if add and (executed is None or executed.action != Marker.ADD
                    or executed.points is not trail.points):
            executed = line_strip_marker(trail[:2], 'executed_path', 1, YELLOW, 0.08, stamp,
                                         frame_id=self.frame_id)
            executed.points = trail.points
        elif not add and (executed is None or executed.action != Marker.DELETE):
            executed = line_strip_marker((), 'executed_path', 1, YELLOW, 0.08, stamp,
                                         frame_id=self.frame_id)
        self._executed = executed
        self._trail_count = 0                   # a list trail given next is built anew
        self._trail_last = object()
