"""
What ``dpn-replay`` writes: a rosbag2 MCAP bag of maps, scans and markers; a CSV; pictures.

`ReplayOutput` takes, scan by scan, the labelled grid after the scan and writes:

- into the bag ``DIR/replay`` (``recording.bag_writer``): ``/map`` (``nav_msgs/OccupancyGrid``,
  latched QoS as the node publishes it, built by the node's ``conversions.OccupancyGridBuffer``
  with ``map_mobile_value``), stamped with the scan's header stamp to the nanosecond; the scan
  as read on its own topic (``sensor_msgs/LaserScan``, every field as recorded); and
  ``/marker`` (``visualization_msgs/MarkerArray``, the node's ``NavigatorMarkers``: no plan and
  no goal in a replay, the laser's positions as the executed path), on the node's schedule
  (every 0.5 s of scan time). Each message's log time is the scan's stamp. With TF input, the
  bag's transforms too (`ReplayOutput.write_transforms`): ``/tf`` at their stamps and
  ``/tf_static`` once, latched, at the first scan's stamp, so that RViz can show the scans
  over the maps;
- ``DIR/replay.csv``: per scan, the stamp [ns], the cells per label and the label update's
  wall time [ms];
- ``DIR/replay.png``: the final labelled map (``tools.figures``); ``DIR/replay.gif`` when asked
  (one frame per second of scan time, at most ``MAX_FRAMES``).

"""

import csv
from pathlib import Path

import numpy as np

from .bag_writer import BagTopic, BagWriter
from ..core.cell_label import CellLabel, OCCUPANCY_VALUE
from ..ros.conversions import OccupancyGridBuffer
from ..ros.navigator_markers import extend_trail, NavigatorMarkers
from ..ros.qos import LATCHED_QOS, SENSOR_QOS, TF_QOS, TF_STATIC_QOS

BAG_NAME = 'replay'
CSV_NAME = 'replay.csv'
PNG_NAME = 'replay.png'
GIF_NAME = 'replay.gif'
MAP_TOPIC = '/map'
MARKER_TOPIC = '/marker'
TF_TOPIC = '/tf'
TF_STATIC_TOPIC = '/tf_static'
#: Most frames of the GIF; with more seconds of scans, frames are spread evenly.
MAX_FRAMES = 300
#: CSV columns: the stamp, the cells per label, the label update time.
CSV_COLUMNS = ('stamp_ns', *(f'cells_{label.name.lower()}' for label in CellLabel),
               'update_ms')


def _time(stamp_ns):
    from builtin_interfaces.msg import Time
    return Time(sec=stamp_ns // 1_000_000_000, nanosec=stamp_ns % 1_000_000_000)


def laser_scan_message(scan):
    """
    Return a recorded scan as an rclpy ``LaserScan``, every field as read.

    Parameters
    ----------
    scan : ScanRecord
        As read by ``bag_reader``.

    Returns
    -------
    sensor_msgs.msg.LaserScan

    """
    from array import array
    from sensor_msgs.msg import LaserScan
    msg = LaserScan()
    msg.header.stamp = _time(scan.stamp_ns)
    msg.header.frame_id = scan.frame_id
    msg.angle_min = scan.angle_min
    msg.angle_max = scan.angle_max
    msg.angle_increment = scan.angle_increment
    msg.time_increment = scan.time_increment
    msg.scan_time = scan.scan_time
    msg.range_min = scan.range_min
    msg.range_max = scan.range_max
    msg.ranges = array('f', np.asarray(scan.ranges, dtype=np.float32).tobytes())
    msg.intensities = array('f', np.asarray(scan.intensities, dtype=np.float32).tobytes())
    return msg


def scan_topic_name(topic):
    """Return a recorded topic's name as a rosbag2 topic (absolute: ROS 1 names may not be)."""
    return '/' + topic.lstrip('/')


class ReplayOutput:
    """
    Write a replay's outputs into ``out_dir`` (see the module); use as a context manager.

    Parameters
    ----------
    out_dir : pathlib.Path
        Created if missing; ``out_dir / 'replay'`` must not exist.
    grid : LabelGrid
        The grid being replayed into.
    map_frame : str
        ``header.frame_id`` of the maps and markers.
    scan_topic : str
        Topic of the scans in the output bag.
    mobile_value : int
        OccupancyGrid value of mobile cells (the node's ``map_mobile_value``).
    animate : bool
        Also draw ``replay.gif``.
    custom_data : dict, optional
        For the bag's metadata.
    with_transforms : bool
        The bag gets ``/tf`` and ``/tf_static`` (`write_transforms`).

    """

    def __init__(self, out_dir, grid, map_frame, scan_topic, mobile_value, animate=False,
                 custom_data=None, with_transforms=False):
        from nav_msgs.msg import OccupancyGrid
        from sensor_msgs.msg import LaserScan
        from tf2_msgs.msg import TFMessage
        from visualization_msgs.msg import MarkerArray
        self.out_dir = Path(out_dir)
        self.out_dir.mkdir(parents=True, exist_ok=True)
        self.grid = grid
        self.map_frame = map_frame
        self.scan_topic = scan_topic_name(scan_topic)
        self.animate = animate
        topics = [BagTopic(MAP_TOPIC, OccupancyGrid, LATCHED_QOS),
                  BagTopic(self.scan_topic, LaserScan, SENSOR_QOS),
                  BagTopic(MARKER_TOPIC, MarkerArray, LATCHED_QOS)]
        if with_transforms:
            topics += [BagTopic(TF_TOPIC, TFMessage, TF_QOS),
                       BagTopic(TF_STATIC_TOPIC, TFMessage, TF_STATIC_QOS)]
        self.bag = BagWriter(self.out_dir / BAG_NAME, topics, custom_data)
        self._tracker = grid.change_tracker()
        self._map = OccupancyGridBuffer(grid.geometry.shape, mobile_value)
        self._markers = NavigatorMarkers(map_frame)
        self._trail = []
        self._load_time = None
        self._csv_file = open(self.out_dir / CSV_NAME, 'w', newline='')
        self._csv = csv.writer(self._csv_file)
        self._csv.writerow(CSV_COLUMNS)
        self.frames = []            # (stamp [s], picture values, trail) for the GIF
        self._next_frame = None
        self.maps = 0

    def add(self, scan, laser_xy, update_ms):
        """
        Write the map after ``scan``, the scan and (when due) the markers; log the CSV row.

        Parameters
        ----------
        scan : ScanRecord
            The scan just folded into the grid.
        laser_xy : (float, float)
            The laser's position in the map frame [m] (the markers' executed path).
        update_ms : float
            The label update's wall time [ms].

        """
        stamp = _time(scan.stamp_ns)
        if self._load_time is None:
            self._load_time = stamp
        geometry = self.grid.geometry
        rows, cols, _ = self._tracker.take()
        self._map.refresh(self.grid.labels, rows, cols)
        self.bag.write(MAP_TOPIC, self._map.message(
            geometry.resolution, geometry.origin, stamp, frame_id=self.map_frame,
            load_time=self._load_time), scan.stamp_ns)
        self.bag.write(self.scan_topic, laser_scan_message(scan), scan.stamp_ns)
        extend_trail(self._trail, laser_xy)
        seconds = scan.stamp_ns * 1e-9
        if self._markers.due(False, self.maps == 0, seconds):
            markers, _ = self._markers.messages(None, self._trail, None, stamp, seconds)
            self.bag.write(MARKER_TOPIC, markers, scan.stamp_ns)
        counts = np.bincount(self.grid.labels.ravel(), minlength=len(CellLabel))
        self._csv.writerow([scan.stamp_ns, *(int(n) for n in counts[:len(CellLabel)]),
                            f'{update_ms:.3f}'])
        self.maps += 1
        if self.animate and (self._next_frame is None or seconds >= self._next_frame):
            self.frames.append((seconds, self.picture_values(), np.array(self._trail)))
            self._next_frame = seconds + 1.0

    def write_transforms(self, records, static_time_ns):
        """
        Write a bag's transforms: ``/tf`` at their stamps, ``/tf_static`` once.

        Parameters
        ----------
        records : iterable of TransformRecord
            As ``BagReader.transforms`` yields them; the transforms of one recorded message
            (same receive time) go into one ``TFMessage``.
        static_time_ns : int
            Log time and stamp of the one ``/tf_static`` message (the first scan's stamp)
            [ns]; it holds the last static transform of each child frame.

        """
        from geometry_msgs.msg import TransformStamped
        from tf2_msgs.msg import TFMessage

        def stamped(record, stamp_ns):
            msg = TransformStamped()
            msg.header.stamp = _time(stamp_ns)
            msg.header.frame_id = record.parent_frame
            msg.child_frame_id = record.child_frame
            t, q = msg.transform.translation, msg.transform.rotation
            t.x, t.y, t.z = (float(v) for v in record.translation)
            q.x, q.y, q.z, q.w = (float(v) for v in record.rotation)
            return msg

        static = {}
        pending, pending_key = [], None

        def flush():
            if pending:
                self.bag.write(TF_TOPIC, TFMessage(transforms=list(pending)),
                               pending[0].header.stamp.sec * 1_000_000_000
                               + pending[0].header.stamp.nanosec)
                pending.clear()

        for record in records:
            if record.static:
                static[record.child_frame] = record
                continue
            if record.log_time_ns != pending_key:
                flush()
                pending_key = record.log_time_ns
            pending.append(stamped(record, record.stamp_ns))
        flush()
        if static:
            self.bag.write(TF_STATIC_TOPIC, TFMessage(transforms=[
                stamped(record, static_time_ns) for record in static.values()]), static_time_ns)

    def picture_values(self):
        """Return the grid as the OccupancyGrid values the figures draw (mobile 70)."""
        return np.take(OCCUPANCY_VALUE, self.grid.labels)

    def close(self, title):
        """
        Finish the bag and the CSV; draw ``replay.png`` (and ``replay.gif``).

        Parameters
        ----------
        title : str
            Title of the pictures.

        """
        if self._csv_file is None:
            return
        self.bag.close()
        self._csv_file.close()
        self._csv_file = None
        from ..tools import figures
        geometry = self.grid.geometry
        trail = np.array(self._trail) if len(self._trail) >= 2 else None
        figures.save_map_figure(self.out_dir / PNG_NAME, self.picture_values(),
                                geometry.resolution, geometry.origin, executed=trail,
                                title=title)
        if self.animate and self.frames:
            self._save_gif(title)

    def _save_gif(self, title):
        from ..benchmark.animation import save_animation
        from ..benchmark.snapshots import Snapshot
        frames = self.frames
        if len(frames) > MAX_FRAMES:
            keep = np.linspace(0, len(frames) - 1, MAX_FRAMES).round().astype(int)
            frames = [frames[i] for i in keep]
        start = frames[0][0]
        snapshots = [Snapshot(time - start, values, None, trail, np.zeros((0, 2)))
                     for time, values, trail in frames]
        geometry = self.grid.geometry
        save_animation(self.out_dir / GIF_NAME, snapshots, geometry.resolution,
                       geometry.origin, title=title)

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        if self._csv_file is not None:
            self.bag.close()
            self._csv_file.close()
            self._csv_file = None
