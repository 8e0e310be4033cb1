"""
The numpy parts of the ``dpn`` node that compiled or incremental code replaced, kept as twins.

``NumpyOccupancyGridBuffer`` is ``OccupancyGridBuffer`` of commit 60fa892: every update
converts the whole box the grid's change tracker gives (``np.take``) and compares it with the
values sent before. ``NumpyPlanningMasks`` is ``PlanningMasks`` of that commit: every plan
recomputes ``blocked`` over the box changed since the last plan and the cost one cell wider.
`eager_observe` is ``Navigator.observe`` of that commit: the turn sweep takes a scan's hits at
once, before the node publishes the map. ``FreshMarkers`` builds the markers and the plan anew
each time they go out, the plan with ``points_to_path`` of that commit.
`numpy_node` swaps these parts into a ``DpnNode``, so a test can run it beside the node as it
is on the same scans and compare what the two publish.

"""

from array import array

from dpn_navigator.core.cell_label import blocked_mask
from dpn_navigator.core.planning.planning_masks import _grown, PlanningMasks
from dpn_navigator.core.pose2d import compose
from dpn_navigator.core.scan_polygon import check_pose, scan_points
from dpn_navigator.ros.conversions import (line_strip_marker, occupancy_values,
                                           OccupancyGridBuffer, sphere_marker, yaw_to_quaternion)
from dpn_navigator.ros.navigator_markers import GREEN, NavigatorMarkers, RED, YELLOW
from geometry_msgs.msg import PoseStamped
from map_msgs.msg import OccupancyGridUpdate
from nav_msgs.msg import Path
import numpy as np
from visualization_msgs.msg import MarkerArray


class NumpyOccupancyGridBuffer(OccupancyGridBuffer):
    """``OccupancyGridBuffer`` converting and comparing whole boxes with numpy."""

    def __init__(self, shape, mobile_value):
        super().__init__(shape, mobile_value)
        self._values = occupancy_values(mobile_value)

    def refresh(self, labels, rows, cols):
        self._grid_values[rows, cols] = np.take(self._values, labels[rows, cols])

    def update_message(self, labels, rows, cols, stamp, frame_id='map'):
        fresh = np.take(self._values, labels[rows, cols])
        changed = fresh != self._grid_values[rows, cols]
        changed_rows = np.flatnonzero(changed.any(axis=1))
        if changed_rows.size == 0:
            return None
        changed_cols = np.flatnonzero(changed.any(axis=0))
        self._grid_values[rows, cols] = fresh
        row_lo, row_hi = rows.start + changed_rows[0], rows.start + changed_rows[-1] + 1
        col_lo, col_hi = cols.start + changed_cols[0], cols.start + changed_cols[-1] + 1
        msg = OccupancyGridUpdate()
        msg.header.stamp = stamp
        msg.header.frame_id = frame_id
        msg.x, msg.y = int(col_lo), int(row_lo)
        msg.width, msg.height = int(col_hi - col_lo), int(row_hi - row_lo)
        msg.data = array('b', self._grid_values[row_lo:row_hi, col_lo:col_hi].tobytes())
        return msg


def numpy_node(node):
    """Swap the numpy twins into a freshly built ``DpnNode`` (before its first scan)."""
    navigator = node.navigator
    node.map_buffer = NumpyOccupancyGridBuffer(navigator.grid.geometry.shape,
                                               node.params.map_mobile_value)
    navigator._masks = NumpyPlanningMasks(navigator.grid, navigator.config.obstacle_proximity_cost)
    navigator.observe = lambda *args, **kwargs: eager_observe(navigator, *args, **kwargs)
    node.markers = FreshMarkers(node.params.map_frame, node.params.marker_min_period)
    return node


class NumpyPlanningMasks(PlanningMasks):
    """``PlanningMasks`` refreshing the whole changed box with numpy, as in commit 60fa892."""

    def refresh(self):
        rows, cols, whole = self._changes.take()
        if rows.start == rows.stop or cols.start == cols.stop:
            return
        self.blocked[rows, cols] = blocked_mask(self._grid.labels[rows, cols])
        if self.cost is not None:
            self._recost(*_grown(rows, cols, self.blocked.shape))


def eager_observe(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
                  angle_max=None, stamp=None, defer_evidence=False, laser_pose=None):
    """
    Fold one scan into ``self`` (a ``Navigator``) and its turn sweep at once.

    The free evidence too: ``defer_evidence`` is taken and ignored, as nothing was deferred
    then. ``laser_pose`` (from TF) replaces the base pose composed with the laser offset.
    """
    pose = check_pose(pose)
    laser_pose = (compose(pose, self.config.laser_offset) if laser_pose is None
                  else check_pose(laser_pose))
    if self.config.map_growth_step > 0.0:       # issue 29: the map grows as the node's does
        self._grow_for_scan(pose, laser_pose, ranges, angle_min, angle_increment, range_min,
                            range_max)
    replan = self.grid.update(laser_pose, ranges, angle_min, angle_increment, range_min,
                              range_max, self.config.safety_radius, path=self.path,
                              angle_max=angle_max, stamp=stamp)
    self._replan_requested |= replan
    self._remember_scan(stamp)      # issue 31's bookkeeping: hits confirming cells, dead ends
    self._last_scan = (laser_pose, np.array(ranges, dtype=np.float64), angle_min,
                       angle_increment, range_min, range_max, angle_max, stamp)
    if self.turn_sweep is not None:
        points = scan_points(laser_pose, self._last_scan[1], angle_min, angle_increment,
                             range_min, range_max)
        self.turn_sweep.add_scan(
            stamp, pose[:2], np.column_stack((points.hits_x, points.hits_y)),
            view=(laser_pose, self._last_scan[1], angle_min, angle_increment, range_min,
                  range_max))


def points_to_path(points_xy, stamp, frame_id='map'):
    """Build a ``Path`` through the points, each pose facing the next one, pose by pose."""
    points = np.asarray(points_xy, dtype=float).reshape(-1, 2)
    msg = Path()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    headings = np.arctan2(*np.diff(points, axis=0)[:, ::-1].T) if len(points) > 1 else []
    for index, (x, y) in enumerate(points.tolist()):
        pose = PoseStamped()
        pose.header = msg.header
        pose.pose.position.x, pose.pose.position.y = x, y
        yaw = headings[min(index, len(headings) - 1)] if len(headings) else 0.0
        pose.pose.orientation = yaw_to_quaternion(float(yaw))
        msg.poses.append(pose)
    return msg


class FreshMarkers(NavigatorMarkers):
    """``NavigatorMarkers`` on the same schedule, building every message anew."""

    def messages(self, path_xy, trail, goal, stamp, now):
        self._last_time = now
        self._pending = False
        path = np.zeros((0, 2)) if path_xy is None else path_xy
        markers = MarkerArray()
        markers.markers.append(line_strip_marker(path, 'planned_path', 0, RED, 0.1, stamp,
                                                 frame_id=self.frame_id))
        markers.markers.append(line_strip_marker(trail, 'executed_path', 1, YELLOW, 0.08,
                                                 stamp, frame_id=self.frame_id))
        if goal is not None:
            markers.markers.append(sphere_marker(goal, 'goal', 2, GREEN, 0.4, stamp,
                                                 frame_id=self.frame_id))
        return markers, points_to_path(path, stamp, self.frame_id)
