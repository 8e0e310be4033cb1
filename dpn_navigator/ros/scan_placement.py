"""
Where a scan was taken: the laser's map-frame pose at the scan's stamp, from TF or odometry.

``pose_source`` chooses, and the node logs the choice:

- ``tf``: the laser's pose is ``map_frame -> <scan frame>`` looked up at the scan's stamp (the
  full 3-D mount: an upside-down laser's beams are mirrored, a laser tilted more than
  ``max_laser_tilt`` refused), the robot's ``map_frame -> base_frame``; goals, plan and goal
  check are in ``map_frame``. Odometry then only feeds the watchdog.
- ``odom``: the odometry pose is taken as the map pose (``map -> odom`` the identity), placed at
  the scan's stamp by interpolating the odometry around it, and the laser at ``laser_x``,
  ``laser_y``, ``laser_yaw`` on it (the behaviour before TF).
- ``auto``: ``tf`` as soon as the TF buffer links ``map_frame`` to the scan's frame, ``odom``
  until then; once TF has placed a scan it stays ``tf`` (a later gap is a counted skip, never a
  silent switch back to odometry). The scans of the first ``auto_wait`` seconds (by their
  stamps) wait for TF instead of falling back at once (dropped, counted, if it does not come):
  a node started a moment before the publisher of the laser's mount would otherwise map its
  first scans with the ``laser_*`` mount. When TF takes over after scans were placed from odometry
  (the node started before the publisher of the laser's mount, or the localiser came up late),
  `ScanPlacer.take_tf_takeover` tells the node once, so that it drops the map those scans made:
  they were placed in the odometry frame with the ``laser_*`` mount, and for a laser mounted
  otherwise (upside down, turned) or a ``map -> odom`` that is not the identity, their walls
  are in the wrong places.

Either way a scan is placed only with data that brackets its stamp: never extrapolated. Nor
interpolated across a long gap while the robot moves: when the two samples of the robot's
motion (``base_frame``'s link to its parent in TF, or two odometry poses) around the scan's
stamp lie more than ``max_gap`` apart and the robot moved between them (more than
`STEP_DISTANCE` or `STEP_TURN`), the scan is a `ScanNotPlaced`. Under load, transforms and
odometry are lost in bursts; a robot that starts or ends a turn inside such a gap is somewhere
else than the straight interpolation says, and a hit 10 m away lands decimetres off (at 4x
real time on 2 busy cores, 80-136 wall cells turned mobile in 2 of 3 runs this way). With
``tf2_ros`` the buffer does not tell which samples a lookup used, so this check is made only
with the node's own buffer and with odometry. A scan
whose pose has not arrived yet waits (`PoseNotYet`); the node drops it, counted, when it has
waited ``transform_timeout``. A scan that cannot be placed at all (older than the kept
odometry, a tilted laser) is a `ScanNotPlaced`.

"""

from dataclasses import dataclass

from .tf_pose_source import planar_pose, TransformUnavailable
from ..core.laser_mount import mirror_scan, planar_laser_pose

POSE_SOURCES = ('auto', 'tf', 'odom')
#: Motion between two samples below which a long gap between them does not matter [m], [rad].
STEP_DISTANCE = 0.01
STEP_TURN = 0.01


class PoseNotYet(Exception):
    """The scan's pose may still arrive: try again later."""


class ScanNotPlaced(Exception):
    """The scan cannot be placed: drop it."""


@dataclass(frozen=True)
class ScanPlacement:
    """
    A scan ready for the navigator.

    Attributes
    ----------
    base_pose : (float, float, float)
        The robot base in the map frame at the scan's stamp [m, m, rad].
    laser_pose : (float, float, float) or None
        The laser in the map frame [m, m, rad]; None: the base pose with the ``laser_*``
        parameters.
    fields : dict
        The scan's arguments for ``Navigator.observe`` (mirrored for an upside-down laser).
    source : str
        ``'tf'`` or ``'odom'``.

    """

    base_pose: tuple
    laser_pose: object
    fields: dict
    source: str


class ScanPlacer:
    """
    Place scans with TF or odometry (see the module).

    Parameters
    ----------
    mode : str
        ``'auto'``, ``'tf'`` or ``'odom'``.
    map_frame, base_frame : str
        Frame ids.
    tf_lookup : FallbackTfLookup or Tf2RosLookup or None
        The TF buffer; None only with ``mode='odom'``.
    history : PoseHistory
        The odometry poses, kept with no extrapolation.
    max_tilt : float
        Largest tilt of the laser from level or upside down [rad].
    on_source : callable, optional
        Called with the source (``'tf'`` or ``'odom'``) when the first scan is placed with it.
    auto_wait : float
        With ``mode='auto'``: how long after the first scan's stamp [s] scans wait for TF
        (`PoseNotYet`) before odometry is used.
    max_gap : float
        Longest step [s] between the two samples of the robot's motion a scan's pose is
        interpolated across while the robot moves (see the module); 0: no limit.

    """

    def __init__(self, mode, map_frame, base_frame, tf_lookup, history, max_tilt,
                 on_source=None, auto_wait=0.0, max_gap=0.0):
        if mode not in POSE_SOURCES:
            raise ValueError(f"pose_source must be one of {', '.join(POSE_SOURCES)}; got "
                             f'{mode!r}')
        if mode != 'odom' and tf_lookup is None:
            raise ValueError(f'pose_source {mode!r} needs a TF buffer')
        if not auto_wait >= 0.0:
            raise ValueError(f'auto_wait must be >= 0 s; got {auto_wait!r}')
        if not max_gap >= 0.0:
            raise ValueError(f'max_gap must be >= 0 s; got {max_gap!r}')
        self.max_gap = float(max_gap)
        self.gap_skips = 0                     # scans refused for a long interpolation
        self.mode = mode
        self.map_frame = map_frame
        self.base_frame = base_frame
        self.tf = tf_lookup
        self.history = history
        self.max_tilt = max_tilt
        self.on_source = on_source
        self.source = 'tf' if mode == 'tf' else None
        self.placed_from_odometry = 0          # scans placed from odometry before TF
        self._takeover = False
        self.auto_wait_ns = int(round(auto_wait * 1e9))
        self._first_stamp_ns = None
        self._announced = set()

    def _use(self, source):
        self.source = source
        if source not in self._announced:
            self._announced.add(source)
            if self.on_source is not None:
                self.on_source(source)

    def place(self, frame_id, stamp_ns, fields):
        """
        Return the `ScanPlacement` of a scan taken in ``frame_id`` at ``stamp_ns`` [ns].

        Raises
        ------
        PoseNotYet
            Its transform or odometry has not arrived yet.
        ScanNotPlaced
            It cannot be placed (older than the kept odometry, a tilted laser).

        """
        if self.mode == 'odom':
            return self._place_with_odometry(stamp_ns, fields)
        if self.source != 'tf' and self.tf.connected(self.map_frame, frame_id):
            self._takeover = self.source == 'odom'
            self.source = 'tf'
        if self.source == 'tf':
            return self._place_with_tf(frame_id, stamp_ns, fields)
        if self.source is None:
            if self._first_stamp_ns is None:
                self._first_stamp_ns = stamp_ns
            if stamp_ns - self._first_stamp_ns < self.auto_wait_ns:
                raise PoseNotYet(f'no transform {self.map_frame} -> {frame_id} yet; waiting '
                                 f'{self.auto_wait_ns * 1e-9:g} s for TF before odometry')
        return self._place_with_odometry(stamp_ns, fields)

    def _place_with_tf(self, frame_id, stamp_ns, fields):
        try:
            laser_rotation, laser_translation = self.tf.lookup(self.map_frame, frame_id,
                                                               stamp_ns)
            base = planar_pose(*self.tf.lookup(self.map_frame, self.base_frame, stamp_ns))
        except TransformUnavailable as error:
            raise PoseNotYet(f'no transform {self.map_frame} -> {frame_id} at the stamp of '
                             f'the scan yet: {error}') from None
        self._check_step(self.tf.sample_step(self.base_frame, stamp_ns))
        try:
            laser, mirrored = planar_laser_pose(laser_rotation, laser_translation,
                                                self.max_tilt)
        except ValueError as error:
            raise ScanNotPlaced(f'frame {frame_id!r}: {error}') from None
        if mirrored:
            ranges, angle_min, angle_increment, angle_max = mirror_scan(
                fields['ranges'], fields['angle_min'], fields['angle_increment'])
            fields = dict(fields, ranges=ranges, angle_min=angle_min,
                          angle_increment=angle_increment, angle_max=angle_max)
        self._use('tf')
        return ScanPlacement(base, laser, fields, 'tf')

    def _place_with_odometry(self, stamp_ns, fields):
        # As stamp_to_seconds computes the odometry's stamps, so that equal stamps stay equal.
        sec, nanosec = divmod(int(stamp_ns), 1_000_000_000)
        stamp = sec + nanosec * 1e-9
        pose = self.history.pose_at(stamp)
        if pose is None:
            newest = self.history.newest_stamp
            if newest is None or stamp > newest:
                raise PoseNotYet('no odometry at or after the stamp of the scan yet')
            raise ScanNotPlaced(f'the scan (stamp {stamp:.3f} s) is older than the kept '
                                f'odometry')
        self._check_step(self.history.sample_step(stamp))
        self._use('odom')
        if self.mode == 'auto':
            self.placed_from_odometry += 1
        return ScanPlacement(pose, None, fields, 'odom')

    def _check_step(self, step):
        """Raise `ScanNotPlaced` when the pose is interpolated across a long moving step."""
        if step is None or self.max_gap <= 0.0:
            return
        duration, distance, turn = step
        if duration > self.max_gap and (distance > STEP_DISTANCE or turn > STEP_TURN):
            self.gap_skips += 1
            raise ScanNotPlaced(f"its pose lies between two samples of the robot's motion "
                                f'{duration:.3f} s apart (max_pose_gap {self.max_gap:g} s) in '
                                f'which it moved {distance:.3f} m and turned {turn:.3f} rad')

    def take_tf_takeover(self):
        """
        Return True once after TF took over from odometry (``auto``), else False.

        The scans placed from odometry until then (`placed_from_odometry`) were placed in the
        odometry frame with the ``laser_*`` mount; the caller drops what they mapped.
        """
        takeover, self._takeover = self._takeover, False
        return takeover

    def robot_pose(self, odometry_pose):
        """
        Return the robot base's latest pose in the map frame, or None when there is none yet.

        With TF, the latest ``map_frame -> base_frame``; else ``odometry_pose``.
        """
        if self.source != 'tf':
            return odometry_pose
        try:
            return planar_pose(*self.tf.lookup(self.map_frame, self.base_frame, 0))
        except TransformUnavailable:
            return None
