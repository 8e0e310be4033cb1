"""
A benchmark episode as a rosbag2 MCAP bag: what the two nodes would have published.

`EpisodeBagRecorder` is a ``recorder`` for `run_episode`. The lockstep episode has no ROS
process, so at every scan it builds the messages the ``pybullet_world`` and ``dpn`` nodes
publish, with the same conversion functions they use, and writes them at the simulated time of
the scan. It only reads the world and the navigator, so an episode's result is the same with or
without it (a test checks).

What the bag holds, by topic (names as the nodes publish them in the default namespace):

- ``/clock``, ``/compabot/scan``, ``/compabot/odom``, ``/tf`` (``map -> odom`` and
  ``odom -> base_link``), ``/compabot/odom_real``, ``/compabot/map`` and
  ``/compabot/sim/wanderers`` (the wanderers' true positions): once per scan, 10 Hz. The world
  node publishes ``/clock``, ``odom`` and ``/tf`` at every physics tick (50 Hz); the lockstep
  episode advances scan by scan, and the bag keeps the scan rate.
- ``/tf_static`` (``base_link -> laser``): once, at the start.
- ``/compabot/marker`` and ``/compabot/plan``: when the dpn node would publish them, on a
  replan, a status change or every 0.5 s (`navigator_markers.markers_due`).

"""

import math
from pathlib import Path

from rosgraph_msgs.msg import Clock
from sim_bridge.robot_frames import FrameNames, laser_mount_transforms, robot_transforms
from sim_bridge.wanderer_markers import wanderer_markers

from ..recording.bag_writer import BagWriter
from ..recording.recorded_topics import episode_topics, node_topic
from ..ros.conversions import (labels_to_occupancy_grid, make_laser_scan, pose_to_odometry,
                               seconds_to_time)
from ..ros.names import TF_STATIC_TOPIC, TF_TOPIC
from ..ros.navigator_markers import extend_trail, markers_due, navigator_markers


def episode_bag_name(spec):
    """
    Return the bag folder name of an episode, e.g. ``maze_task0_w5_r0_seed1234``.

    Parameters
    ----------
    spec : EpisodeSpec
        The episode; a map given as a yaml path is named by the file's stem.

    """
    name = Path(spec.map_key).stem if spec.map_key.endswith(('.yaml', '.yml')) else spec.map_key
    return f'{name}_task{spec.task}_w{spec.wanderers}_r{spec.repetition}_seed{spec.seed}'


class EpisodeBagRecorder:
    """
    Record an episode into a bag: call it as ``recorder(world, navigator)`` once per scan.

    Use as a context manager, or call `close` at the end: the bag is complete (with its
    ``metadata.yaml``) only then.

    Parameters
    ----------
    path : str or os.PathLike
        The bag folder to create; must not exist.
    description : dict of str to str, optional
        Written into the metadata's ``custom_data`` (scenario, task, wanderers, seed, ...).

    Raises
    ------
    dpn_navigator.recording.bag_writer.BagPathError
        When ``path`` exists or cannot be written.

    """

    def __init__(self, path, description=None):
        self.writer = BagWriter(path, episode_topics(), custom_data=description)
        self.frames = FrameNames()
        self.trail = []
        self._map_load_time = None
        self._last_marker_time = -math.inf
        self._last_replans = None
        self._last_status = None

    @property
    def path(self):
        """Return the bag folder (pathlib.Path)."""
        return self.writer.path

    def __call__(self, world, navigator):
        """Write what the nodes would publish at this scan."""
        write = self.writer.write
        frames = self.frames
        now = world.time
        time_ns = round(now * 1e9)
        stamp = seconds_to_time(now)
        pose, velocity = world.husky_pose, world.husky_velocity
        if self._map_load_time is None:
            self._map_load_time = stamp
            write(TF_STATIC_TOPIC, laser_mount_transforms(
                frames, world.config.laser.mount, world.config.laser.height, stamp), time_ns)
        write('/clock', Clock(clock=stamp), time_ns)
        write(TF_TOPIC, robot_transforms(frames, pose, pose, stamp), time_ns)
        write(node_topic('odom'), pose_to_odometry(
            pose, velocity, stamp, frame_id=frames.odom, child_frame_id=frames.base), time_ns)
        scan = world.scan()     # the scan of this tick, which the navigator has just seen
        write(node_topic('scan'), make_laser_scan(
            scan.ranges, scan.angle_min, scan.angle_increment, scan.range_min, scan.range_max,
            seconds_to_time(scan.stamp), frame_id=frames.laser,
            scan_time=1.0 / world.config.scan_rate), time_ns)
        geometry = navigator.grid.geometry
        write(node_topic('map'), labels_to_occupancy_grid(
            navigator.grid.labels, geometry.resolution, geometry.origin, stamp,
            frame_id=frames.map, load_time=self._map_load_time), time_ns)
        write(node_topic('odom_real'), pose_to_odometry(
            pose, velocity, stamp, frame_id=frames.map, child_frame_id=frames.base), time_ns)
        write(node_topic('sim/wanderers'), wanderer_markers(
            world.wanderer_positions, world.wanderer_radius, stamp, frames.map), time_ns)
        if navigator.goal is not None:
            extend_trail(self.trail, (float(pose[0]), float(pose[1])))
        replanned = self._last_replans is not None and navigator.replans != self._last_replans
        status_changed = navigator.status is not self._last_status
        if markers_due(replanned, status_changed, now, self._last_marker_time):
            markers, plan = navigator_markers(navigator.path_xy, self.trail, navigator.goal,
                                              stamp, frames.map)
            write(node_topic('marker'), markers, time_ns)
            write(node_topic('plan'), plan, time_ns)
            self._last_marker_time = now
        self._last_replans = navigator.replans
        self._last_status = navigator.status

    def close(self):
        """Finish the bag (its MCAP file and ``metadata.yaml``)."""
        self.writer.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()
