"""
What the navigator shows of itself: the planned path, the executed path and the goal.

The ``dpn`` node publishes these on ``marker`` (``MarkerArray``) and ``plan``
(``nav_msgs/Path``), and the benchmark writes the same messages into its episode bags, on the
same schedule (`markers_due`), so a bag looks like the live system.

"""

import math

import numpy as np
from visualization_msgs.msg import MarkerArray

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
