"""
Where each recorded scan was taken: the laser's pose in the map plane, from a bag's TF or fixed.

Two ways, as ``dpn-replay --pose`` names them:

- ``tf``: every transform of the bag's ``/tf`` and ``/tf_static`` goes into one `TfBuffer` that
  keeps everything (no cache limit), before the first scan is placed, so that a transform
  logged after its scan (old recordings log odometry late) still counts. A scan is placed at
  ``map_frame -> scan frame`` looked up at the scan's header stamp with tf2's rules (static
  links at all times, dynamic ones interpolated between the samples around the stamp, never
  extrapolated). With no frame ``map`` in the bag, ``odom`` is the map frame.
- ``fixed``: the laser stands at the origin of the map frame, which is the laser's frame.

The 3-D pose is laid into the plane by ``core.frames.laser_plane`` (an upside-down laser's
beams mirrored). A scan that cannot be placed is skipped with its reason counted.

"""

from collections import Counter
from dataclasses import dataclass
import math

import numpy as np

from .bag_reader import fill_tf_buffer
from ..core.frames import TfBuffer, TransformError
from ..core.frames.laser_plane import LaserNotLevelError, planar_laser
from ..core.frames.transform3d import Transform3D
from ..core.scan_polygon import check_scan, scan_points

#: The map frame of ``--pose tf`` when none is named, and its fallback.
DEFAULT_MAP_FRAME = 'map'
FALLBACK_MAP_FRAME = 'odom'
#: Room left around the scans' hits and the laser's positions when the grid is sized [m].
EXTENT_MARGIN = 2.0


class NoTransformsError(ValueError):
    """``--pose tf`` on a bag without usable TF, or without the map frame asked for."""


@dataclass(frozen=True)
class PlacedScan:
    """
    A scan laid into the map plane, ready for ``LabelGrid.update``.

    Attributes
    ----------
    pose : (float, float, float)
        The laser's ``(x, y, yaw)`` in the map frame [m, m, rad].
    ranges : (L,) ndarray of float32
        In the plane's beam order, [m].
    angle_min, angle_increment, angle_max : float
        Plane beam angles relative to ``yaw`` [rad], increment positive.
    range_min, range_max : float
        [m]

    """

    pose: tuple
    ranges: np.ndarray
    angle_min: float
    angle_increment: float
    angle_max: float
    range_min: float
    range_max: float

    def fields(self):
        """Return the keyword arguments of ``LabelGrid.update`` for this scan (no pose)."""
        return {'ranges': self.ranges, 'angle_min': self.angle_min,
                'angle_increment': self.angle_increment, 'angle_max': self.angle_max,
                'range_min': self.range_min, 'range_max': self.range_max}


class ScanPoses:
    """
    Places scans in the map frame (see the module).

    Parameters
    ----------
    mode : {'tf', 'fixed'}
    bag : BagReader, optional
        The open bag whose TF is read (``tf`` only).
    map_frame : str, optional
        ``tf``: the map frame; None for ``map``, falling back to ``odom``. ``fixed``: ignored.

    Attributes
    ----------
    map_frame : str or None
        ``tf``: the frame the scans are placed in. ``fixed``: None until the first scan,
        then that scan's frame.
    skipped : collections.Counter
        Scans not placed, by reason.
    transforms : int
        Transforms read from the bag (``tf``).
    refused_transforms : int
        Transforms the buffer refused (malformed, a second parent, a loop).

    Raises
    ------
    NoTransformsError
        ``tf``: the bag has no TF, or no frame ``map_frame`` (nor ``odom`` when none was
        named).
    ValueError
        For another mode.

    """

    def __init__(self, mode, bag=None, map_frame=None):
        if mode not in ('tf', 'fixed'):
            raise ValueError(f"pose mode must be 'tf' or 'fixed', got {mode!r}")
        self.mode = mode
        self.skipped = Counter()
        self.transforms = self.refused_transforms = 0
        self.buffer = None
        self.map_frame = None
        if mode == 'fixed':
            return
        self.buffer = TfBuffer(cache_duration_ns=None)
        self.transforms, self.refused_transforms, reasons = fill_tf_buffer(bag, self.buffer)
        if self.transforms == 0:
            why = f' ({reasons[0]})' if reasons else ''
            raise NoTransformsError(
                f'no TF in {bag.path}: no transforms on /tf or /tf_static{why}; use --pose '
                'fixed for a laser standing still')
        frames = self.buffer.frames
        if map_frame is not None:
            if map_frame not in frames:
                raise NoTransformsError(f'no frame {map_frame!r} in the TF of {bag.path} '
                                        f'(frames: {", ".join(sorted(frames))})')
            self.map_frame = map_frame
        elif DEFAULT_MAP_FRAME in frames:
            self.map_frame = DEFAULT_MAP_FRAME
        elif FALLBACK_MAP_FRAME in frames:
            self.map_frame = FALLBACK_MAP_FRAME
        else:
            raise NoTransformsError(
                f'no frame {DEFAULT_MAP_FRAME!r} or {FALLBACK_MAP_FRAME!r} in the TF of '
                f'{bag.path} (frames: {", ".join(sorted(frames))}); name one with --map-frame')

    def laser_pose(self, scan):
        """
        Return the 3-D pose of a scan's laser in the map frame, or None (counted) if unknown.

        Parameters
        ----------
        scan : ScanRecord
            As read by ``bag_reader``.

        Returns
        -------
        Transform3D or None

        """
        frame = scan.frame_id.lstrip('/')
        if self.mode == 'fixed':
            if self.map_frame is None:
                self.map_frame = frame or 'laser'
            return Transform3D.identity()
        if not frame:
            self.skipped['scan without frame_id'] += 1
            return None
        if scan.stamp_ns < 0:
            self.skipped['negative scan stamp'] += 1
            return None
        try:
            # A stamp of 0 is the time 0 here (a simulation's first scan), not tf2's "latest".
            return self.buffer.lookup(self.map_frame, frame, scan.stamp_ns, zero_is_latest=False)
        except TransformError as error:
            self.skipped[f'no transform {self.map_frame} -> {frame}: '
                         f'{type(error).__name__}'] += 1
            return None

    def place(self, scan):
        """
        Lay a scan into the map plane at its laser's pose.

        Parameters
        ----------
        scan : ScanRecord
            As read by ``bag_reader``.

        Returns
        -------
        PlacedScan or None
            None when the scan is skipped: no pose, a malformed scan, or a laser tilted out
            of the plane (each reason counted in `skipped`).

        """
        laser_in_map = self.laser_pose(scan)
        if laser_in_map is None:
            return None
        try:
            # The node's checks (angle_max against the beam count too); a driver counting its
            # beams clockwise (negative increment) is checked as if counted the other way.
            sign = -1.0 if scan.angle_increment < 0.0 else 1.0
            check_scan(scan.ranges, sign * scan.angle_min, sign * scan.angle_increment,
                       scan.range_min, scan.range_max, sign * scan.angle_max)
            plane = planar_laser(laser_in_map, scan.angle_min, scan.angle_increment,
                                 len(scan.ranges))
        except LaserNotLevelError:
            self.skipped['laser not level'] += 1
            return None
        except ValueError as error:
            self.skipped[f'malformed scan: {str(error).split(",")[0]}'] += 1
            return None
        return PlacedScan(plane.pose, np.ascontiguousarray(plane.ranges(scan.ranges)),
                          plane.angle_min, plane.angle_increment, plane.angle_max,
                          scan.range_min, scan.range_max)


def scan_extent(placed):
    """
    Return the box of a placed scan's laser position and hits.

    Parameters
    ----------
    placed : PlacedScan
        A scan laid into the plane.

    Returns
    -------
    (float, float, float, float)
        ``(x_min, x_max, y_min, y_max)`` in the map frame [m].

    """
    ranges = np.asarray(placed.ranges, dtype=np.float64)
    points = scan_points(placed.pose, ranges, placed.angle_min, placed.angle_increment,
                         placed.range_min, placed.range_max)
    xs = np.append(points.hits_x, placed.pose[0])
    ys = np.append(points.hits_y, placed.pose[1])
    return float(xs.min()), float(xs.max()), float(ys.min()), float(ys.max())


def merge_extents(a, b):
    """Return the box holding two ``(x_min, x_max, y_min, y_max)`` boxes (either may be None)."""
    if a is None:
        return b
    if b is None:
        return a
    return (min(a[0], b[0]), max(a[1], b[1]), min(a[2], b[2]), max(a[3], b[3]))


def grid_box(extent, resolution, given=None, margin=EXTENT_MARGIN):
    """
    Return the grid's size and origin: from the scans' extent, unless given.

    Parameters
    ----------
    extent : (float, float, float, float)
        ``(x_min, x_max, y_min, y_max)`` of the hits and laser positions [m].
    resolution : float
        Cell side [m]; the computed origin and size are whole cells.
    given : dict, optional
        Any of ``width``, ``height``, ``origin_x``, ``origin_y`` [m] set by the user: kept as
        they are. A missing size covers the extent from the origin (plus the margin); a
        missing origin centres the extent in the size.
    margin : float, optional
        Room around the extent [m].

    Returns
    -------
    (float, float, (float, float))
        ``width``, ``height`` [m] and ``origin`` [m].

    """
    given = given or {}
    x_min, x_max, y_min, y_max = extent
    box = {}
    for axis, low, high in (('x', x_min, x_max), ('y', y_min, y_max)):
        size_key = 'width' if axis == 'x' else 'height'
        origin_key = f'origin_{axis}'
        size, origin = given.get(size_key), given.get(origin_key)
        if origin is None and size is None:
            origin = math.floor((low - margin) / resolution) * resolution
            size = math.ceil((high + margin - origin) / resolution) * resolution
        elif origin is None:
            origin = math.floor(((low + high) / 2.0 - size / 2.0) / resolution) * resolution
        elif size is None:
            size = max(resolution, math.ceil((high + margin - origin) / resolution) * resolution)
        box[size_key], box[origin_key] = float(size), float(origin)
    return box['width'], box['height'], (box['origin_x'], box['origin_y'])
