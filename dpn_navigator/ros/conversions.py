"""
ROS message <-> array and tuple conversion: the one module the nodes convert with.

Pure functions, no node: they take and return messages, numpy arrays and floats, so they are
tested in memory. Array fields use the fast paths (``np.frombuffer`` in,
``array.array(typecode, ndarray.tobytes())`` out).

"""

from array import array
import math

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point, Pose, PoseStamped, Quaternion, Twist
from map_msgs.msg import OccupancyGridUpdate
from nav_msgs.msg import OccupancyGrid, Odometry, Path
import numpy as np
from sensor_msgs.msg import LaserScan
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker

from ..core.cell_label import CellLabel, OCCUPANCY_MOBILE_OBSTACLE, OCCUPANCY_VALUE
from ..core.mapping.map_values import MapValues
from ..core.pose2d import quaternion_yaw
from ..core.scan_polygon import check_pose


def yaw_to_quaternion(yaw):
    """Return the ``Quaternion`` of a rotation by ``yaw`` [rad] about +z."""
    return Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2.0), w=math.cos(yaw / 2.0))


def quaternion_to_yaw(quaternion):
    """
    Return the yaw [rad] of a quaternion: the heading of its x axis projected on the plane.

    Raises
    ------
    ValueError
        When a component is not finite or the quaternion is not of unit length (see
        ``core.pose2d.quaternion_yaw``).

    """
    return quaternion_yaw(quaternion.x, quaternion.y, quaternion.z, quaternion.w)


def stamp_to_seconds(stamp):
    """Return a ``builtin_interfaces/Time`` as seconds [s] (float)."""
    return stamp.sec + stamp.nanosec * 1e-9


def seconds_to_time(seconds):
    """Return a ``builtin_interfaces/Time`` for a time in seconds [s] (nanoseconds rounded)."""
    nanoseconds = int(round(seconds * 1e9))
    return Time(sec=nanoseconds // 1_000_000_000, nanosec=nanoseconds % 1_000_000_000)


def odometry_to_pose(msg):
    """
    Read the planar pose of an ``Odometry`` message.

    Returns
    -------
    (float, float, float)
        ``(x, y, yaw)`` of the child frame in the header's frame [m, m, rad].

    Raises
    ------
    ValueError
        When the position or orientation is not finite, the orientation not a unit
        quaternion, or the position beyond any map (``core.scan_polygon.check_pose``).

    """
    position = msg.pose.pose.position
    if not (math.isfinite(position.x) and math.isfinite(position.y)):
        raise ValueError('odometry position is not finite')
    return check_pose((position.x, position.y, quaternion_to_yaw(msg.pose.pose.orientation)),
                      'odometry pose')


def pose_to_odometry(pose, velocity, stamp, frame_id='map', child_frame_id='base_link'):
    """
    Build an ``Odometry`` message from a planar pose and velocity.

    Parameters
    ----------
    pose : (float, float, float)
        ``(x, y, yaw)`` [m, m, rad] of ``child_frame_id`` in ``frame_id``.
    velocity : (float, float)
        Forward speed [m/s] and turn rate [rad/s] in the child frame.
    stamp : builtin_interfaces.msg.Time
        Header stamp.
    frame_id, child_frame_id : str
        Frames of the pose and of the body.

    """
    msg = Odometry()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.child_frame_id = child_frame_id
    msg.pose.pose = Pose(position=Point(x=float(pose[0]), y=float(pose[1]), z=0.0),
                         orientation=yaw_to_quaternion(float(pose[2])))
    msg.twist.twist.linear.x = float(velocity[0])
    msg.twist.twist.angular.z = float(velocity[1])
    return msg


def laser_scan_fields(msg):
    """
    Read a ``LaserScan`` into the arguments of ``LabelGrid.update`` and ``Navigator.step``.

    Returns
    -------
    dict
        ``ranges`` ((L,) float32 ndarray, a read-only view of the message's buffer, [m]),
        ``angle_min``, ``angle_increment``, ``angle_max`` [rad], ``range_min``, ``range_max``
        [m]. Validation is left to the core, which raises ``ValueError``.

    """
    return {
        'ranges': np.frombuffer(msg.ranges, dtype=np.float32),
        'angle_min': msg.angle_min,
        'angle_increment': msg.angle_increment,
        'angle_max': msg.angle_max,
        'range_min': msg.range_min,
        'range_max': msg.range_max,
    }


def make_laser_scan(ranges, angle_min, angle_increment, range_min, range_max, stamp,
                    frame_id='laser', scan_time=0.0):
    """
    Build a ``LaserScan`` message.

    Parameters
    ----------
    ranges : (L,) array_like of float
        Ranges [m], REP 117.
    angle_min, angle_increment : float
        [rad]; ``angle_max`` is set to ``angle_min + (L - 1) * angle_increment``.
    range_min, range_max : float
        [m]
    stamp : builtin_interfaces.msg.Time
        Header stamp.
    frame_id : str
        The laser's frame.
    scan_time : float
        Time between scans [s].

    """
    ranges = np.asarray(ranges, dtype=np.float32)
    msg = LaserScan()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.angle_min = float(angle_min)
    msg.angle_increment = float(angle_increment)
    msg.angle_max = float(angle_min + (ranges.shape[0] - 1) * angle_increment)
    msg.range_min = float(range_min)
    msg.range_max = float(range_max)
    msg.scan_time = float(scan_time)
    msg.ranges = array('f', ranges.tobytes())
    return msg


def occupancy_values(mobile_value=OCCUPANCY_MOBILE_OBSTACLE):
    """
    Return the OccupancyGrid value of each label, ``OCCUPANCY_VALUE`` with ``mobile_value``.

    Parameters
    ----------
    mobile_value : int
        Value of mobile-obstacle cells, 1 to 100.

    Returns
    -------
    values : (4,) ndarray of int8

    Raises
    ------
    ValueError
        When ``mobile_value`` is not in 1..100.

    """
    if mobile_value == OCCUPANCY_MOBILE_OBSTACLE:
        return OCCUPANCY_VALUE
    if not 1 <= mobile_value <= 100:
        raise ValueError(f'mobile_value must be in 1..100, got {mobile_value!r}')
    values = OCCUPANCY_VALUE.copy()
    values[CellLabel.MOBILE_OBSTACLE] = mobile_value
    return values


def _occupancy_grid(shape, resolution, origin, stamp, frame_id, load_time, data):
    """Build an ``OccupancyGrid`` around ``data`` (an ``array('b')``, not copied)."""
    msg = OccupancyGrid()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.info.map_load_time = stamp if load_time is None else load_time
    msg.info.resolution = float(resolution)
    msg.info.height, msg.info.width = (int(n) for n in shape)
    msg.info.origin.position.x = float(origin[0])
    msg.info.origin.position.y = float(origin[1])
    msg.info.origin.orientation.w = 1.0
    msg.data = data
    return msg


def labels_to_occupancy_grid(labels, resolution, origin, stamp, frame_id='map',
                             load_time=None, mobile_value=OCCUPANCY_MOBILE_OBSTACLE):
    """
    Build an ``OccupancyGrid`` from cell labels.

    Parameters
    ----------
    labels : (H, W) ndarray of uint8
        ``CellLabel`` values, row 0 at the origin's y.
    resolution : float
        Cell side [m].
    origin : (float, float)
        Map-frame position of cell (0, 0)'s lower-left corner [m].
    stamp : builtin_interfaces.msg.Time
        Header stamp.
    frame_id : str
        The map's frame.
    load_time : builtin_interfaces.msg.Time or None
        ``info.map_load_time``: when the map was started; None: ``stamp``.
    mobile_value : int
        Value of mobile-obstacle cells, 1 to 100.

    Returns
    -------
    OccupancyGrid
        ``data`` holds -1, 0, 100 or ``mobile_value`` per cell (``OCCUPANCY_VALUE``),
        row-major.

    Raises
    ------
    ValueError
        When ``mobile_value`` is not in 1..100.

    """
    values = occupancy_values(mobile_value)
    return _occupancy_grid(labels.shape, resolution, origin, stamp, frame_id, load_time,
                           array('b', np.take(values, labels).tobytes()))


class OccupancyGridBuffer:
    """
    The data of a published ``OccupancyGrid``, rewritten only where the labels changed.

    Converting the whole grid for every map costs about 1 ns per cell (5 ms at 2000 x 2000);
    this keeps one ``array('b')`` of the values and rewrites, inside the box a ``ChangeTracker``
    of the grid says changed, the cells whose labels changed (``core.map_values.MapValues``).
    Every message it builds shares that array, so a message is good until the next `refresh`
    (publish it at once, as a node does).

    Parameters
    ----------
    shape : (int, int)
        The grid's ``(rows, cols)``.
    mobile_value : int
        Value of mobile-obstacle cells, 1 to 100.

    Raises
    ------
    ValueError
        When ``mobile_value`` is not in 1..100.

    """

    def __init__(self, shape, mobile_value=OCCUPANCY_MOBILE_OBSTACLE):
        self._shape = tuple(int(n) for n in shape)
        self._data = array('b', bytes(self._shape[0] * self._shape[1]))
        self._grid_values = np.frombuffer(self._data, dtype=np.int8).reshape(self._shape)
        self._map_values = MapValues(self._grid_values, occupancy_values(mobile_value))

    @property
    def shape(self):
        """Return the grid's ``(rows, cols)`` the buffer holds."""
        return self._shape

    def refresh(self, labels, rows, cols):
        """
        Rewrite the values of ``labels[rows, cols]``.

        Parameters
        ----------
        labels : (H, W) ndarray of uint8
            The grid's labels, of the buffer's shape.
        rows, cols : slice
            The box that changed since the last refresh (may be empty).

        """
        self._map_values.refresh(labels, rows, cols)

    def message(self, resolution, origin, stamp, frame_id='map', load_time=None):
        """
        Return an ``OccupancyGrid`` of the buffer's values (shared, not copied).

        Parameters are those of `labels_to_occupancy_grid`.

        """
        return _occupancy_grid(self._shape, resolution, origin, stamp, frame_id, load_time,
                               self._data)

    def update_message(self, labels, rows, cols, stamp, frame_id='map'):
        """
        Rewrite ``labels[rows, cols]`` and return the cells whose values changed, as an update.

        The ``map_msgs/OccupancyGridUpdate`` that Nav2's costmaps publish on ``<map>_updates``
        between full maps (RViz's Map display reads it): the smallest box of cells holding every
        value that changed since the last `refresh` or update (the box ``rows, cols`` may be
        wider: it is the scan's window). Applied in order to the last full map
        (`apply_occupancy_grid_update`), the updates give the buffer's values.

        Parameters
        ----------
        labels : (H, W) ndarray of uint8
            The grid's labels, of the buffer's shape.
        rows, cols : slice
            The box that changed since the last refresh or update (may be empty).
        stamp : builtin_interfaces.msg.Time
            Header stamp.
        frame_id : str
            Header frame, the map's.

        Returns
        -------
        OccupancyGridUpdate or None
            None when no value changed. ``x``, ``y`` are the box's first column and row
            [cells], ``data`` its values row by row (row 0 at the map origin's y).

        """
        changed_rows, changed_cols = self._map_values.refresh(labels, rows, cols)
        if changed_rows.stop <= changed_rows.start:
            return None
        msg = OccupancyGridUpdate()
        msg.header.stamp = stamp
        msg.header.frame_id = frame_id
        msg.x, msg.y = changed_cols.start, changed_rows.start
        msg.width = changed_cols.stop - changed_cols.start
        msg.height = changed_rows.stop - changed_rows.start
        msg.data = array('b', self._grid_values[changed_rows, changed_cols].tobytes())
        return msg


def apply_occupancy_grid_update(values, msg):
    """
    Write an ``OccupancyGridUpdate`` into a map's values, in place.

    Parameters
    ----------
    values : (H, W) ndarray of int8
        The map's values (e.g. `occupancy_grid_values` of a copy of the last full map).
    msg : map_msgs.msg.OccupancyGridUpdate
        A box of cells: ``x``, ``y`` its first column and row, ``data`` row by row.

    Raises
    ------
    ValueError
        When the box does not lie inside the map or ``data`` does not fill it.

    """
    rows, cols = values.shape
    if not (0 <= msg.x and 0 <= msg.y and msg.x + msg.width <= cols
            and msg.y + msg.height <= rows):
        raise ValueError(f'update box at ({msg.x}, {msg.y}) of {msg.width}x{msg.height} cells '
                         f'outside a map of {cols}x{rows}')
    if len(msg.data) != msg.width * msg.height:
        raise ValueError(f'update of {msg.width}x{msg.height} cells with {len(msg.data)} values')
    values[msg.y:msg.y + msg.height, msg.x:msg.x + msg.width] = np.frombuffer(
        msg.data, dtype=np.int8).reshape(msg.height, msg.width)


def occupancy_grid_values(msg):
    """Return the ``data`` of an ``OccupancyGrid`` as an (height, width) int8 ndarray view."""
    return np.frombuffer(msg.data, dtype=np.int8).reshape(msg.info.height, msg.info.width)


def velocity_to_twist(linear, angular):
    """Build a ``Twist`` for a differential-drive base: ``linear.x`` [m/s], ``angular.z``."""
    msg = Twist()
    msg.linear.x = float(linear)
    msg.angular.z = float(angular)
    return msg


def twist_to_velocity(msg):
    """
    Read ``(linear.x, angular.z)`` from a ``Twist``.

    Raises
    ------
    ValueError
        When either is not finite.

    """
    linear, angular = msg.linear.x, msg.angular.z
    if not (math.isfinite(linear) and math.isfinite(angular)):
        raise ValueError(f'non-finite velocity command ({linear!r}, {angular!r})')
    return linear, angular


def line_strip_marker(points_xy, namespace, marker_id, rgba, width, stamp, frame_id='map'):
    """
    Build a ``LINE_STRIP`` marker through map-frame points.

    Parameters
    ----------
    points_xy : (N, 2) array_like of float
        The points [m]; fewer than 2 gives a ``DELETE`` marker.
    namespace, marker_id : str, int
        The marker's identity in RViz.
    rgba : (float, float, float, float)
        Colour, each in [0, 1].
    width : float
        Line width [m].
    stamp : builtin_interfaces.msg.Time
        Header stamp.
    frame_id : str
        Frame of the points.

    """
    marker = Marker()
    marker.header.stamp = stamp
    marker.header.frame_id = frame_id
    marker.ns = namespace
    marker.id = marker_id
    points_xy = np.asarray(points_xy, dtype=np.float64).reshape(-1, 2)
    if points_xy.shape[0] < 2:
        marker.action = Marker.DELETE
        return marker
    marker.type = Marker.LINE_STRIP
    marker.action = Marker.ADD
    marker.pose.orientation.w = 1.0
    marker.scale.x = float(width)
    marker.color = ColorRGBA(r=rgba[0], g=rgba[1], b=rgba[2], a=rgba[3])
    # Plain floats from tolist(): the field checks (a third of the time on a long path) can go.
    marker.points = [Point(x=x, y=y, z=0.05, check_fields=False)
                     for x, y in points_xy.tolist()]
    return marker


def sphere_marker(xy, namespace, marker_id, rgba, diameter, stamp, frame_id='map'):
    """Build a ``SPHERE`` marker at a map-frame point ``xy`` [m] with ``diameter`` [m]."""
    marker = Marker()
    marker.header.stamp = stamp
    marker.header.frame_id = frame_id
    marker.ns = namespace
    marker.id = marker_id
    marker.type = Marker.SPHERE
    marker.action = Marker.ADD
    marker.pose.position = Point(x=float(xy[0]), y=float(xy[1]), z=0.1)
    marker.pose.orientation.w = 1.0
    marker.scale.x = marker.scale.y = marker.scale.z = float(diameter)
    marker.color = ColorRGBA(r=rgba[0], g=rgba[1], b=rgba[2], a=rgba[3])
    return marker


def marker_points(marker):
    """Return a marker's points as an (N, 2) float64 ndarray [m]."""
    return np.array([(p.x, p.y) for p in marker.points], dtype=np.float64).reshape(-1, 2)


def points_to_path(points_xy, stamp, frame_id='map', reuse=None):
    """
    Build a ``nav_msgs/Path`` through planar points, each pose facing the next point.

    Parameters
    ----------
    points_xy : (N, 2) array_like of float
        Waypoints in ``frame_id`` [m]; N may be 0 (an empty path: no plan).
    stamp : builtin_interfaces.msg.Time
        Stamp of the header and of every pose.
    frame_id : str
        Frame of the points.
    reuse : Path, optional
        A path this function returned before, rewritten in place and returned (its poses
        kept as far as they go: building a pose costs about five times as much as rewriting
        one). The earlier message then changes: for a caller that publishes each at once.

    Returns
    -------
    Path

    """
    points = np.asarray(points_xy, dtype=float).reshape(-1, 2)
    msg = Path() if reuse is None else reuse
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    headings = (np.arctan2(*np.diff(points, axis=0)[:, ::-1].T).tolist() if len(points) > 1
                else [])
    # The last pose faces as the one before it; a lone pose faces along x.
    yaws = headings + headings[-1:] if headings else [0.0] * len(points)
    poses = msg.poses
    del poses[len(points):]
    for index, ((x, y), yaw) in enumerate(zip(points.tolist(), yaws)):
        if index < len(poses):
            pose = poses[index].pose
            pose.position.x, pose.position.y = x, y
            pose.orientation.z, pose.orientation.w = math.sin(yaw / 2.0), math.cos(yaw / 2.0)
            continue
        pose = PoseStamped()
        pose.header = msg.header
        pose.pose.position.x, pose.pose.position.y = x, y
        pose.pose.orientation = yaw_to_quaternion(yaw)
        poses.append(pose)
    return msg
