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
TRAIL_MAX_POINTS = 20000
MARKER_PERIOD = 0.5             # markers at most this often, besides replans [s]
RED, YELLOW, GREEN = (1.0, 0.0, 0.0, 1.0), (1.0, 0.85, 0.0, 1.0), (0.0, 0.8, 0.0, 1.0)


def extend_trail(trail, xy):
    """
    Append a position to the executed path when it is ``TRAIL_STEP`` from the last one.

    Parameters
    ----------
    trail : list of (float, float)
        The executed path [m], changed in place; it keeps the newest ``TRAIL_MAX_POINTS``.
    xy : (float, float)
        The robot's position [m].

    """
    if not trail or math.dist(trail[-1], xy) >= TRAIL_STEP:
        trail.append(tuple(xy))
        del trail[:-TRAIL_MAX_POINTS]


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
        count = len(trail)
        grown = (self._executed is not None and self._executed.action == Marker.ADD
                 and 0 < self._trail_count <= count
                 and count - self._trail_count < TRAIL_MAX_POINTS
                 and trail[self._trail_count - 1] is self._trail_last)
        if grown:
            self._executed.points.extend(
                Point(x=float(x), y=float(y), z=0.05, check_fields=False)
                for x, y in trail[self._trail_count:])
        else:
            self._executed = line_strip_marker(trail, 'executed_path', 1, YELLOW, 0.08, stamp,
                                               frame_id=self.frame_id)
        self._trail_count = count
        self._trail_last = trail[-1] if count else None
