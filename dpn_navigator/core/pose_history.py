"""
Recent robot poses by time: the pose at a scan's stamp, not the latest one.

Odometry arrives at the simulator's tick rate and scans at 10 Hz, over separate topics; by the
time a scan is handled, the latest odometry may be several ticks newer (or older) than the
scan. Placing the scan with that pose turns the robot's own motion into misplaced hits: a yaw
error of 0.05 rad moves a hit 15 m away by 0.75 m, which the label rules would take for an
object that moved. As a TF lookup at the scan's stamp would, this keeps the last poses and
interpolates between the two around a stamp.

"""

from collections import deque
import math

from .pose2d import wrap_angle

#: At most this many poses are kept, whatever their stamps (1 s at 2 kHz): odometry whose
#: stamps barely advance (a stuck clock, a flood) would otherwise fill the span without end.
MAX_KEPT_POSES = 2000


class PoseHistory:
    """
    The last poses of the robot, in time order.

    Parameters
    ----------
    span : float
        How far back poses are kept [s].
    tolerance : float
        How far before the oldest kept pose a stamp may lie and still get it [s].
    extrapolation : float
        How far after the newest kept pose a stamp may lie [s]; the pose there is the newest
        one moved on with its velocity (odometry often arrives a few ticks after a scan).

    """

    def __init__(self, span=1.0, tolerance=0.05, extrapolation=0.2):
        if not (math.isfinite(span) and span > 0.0):
            raise ValueError(f'span must be positive, got {span!r} s')
        if not (math.isfinite(tolerance) and tolerance >= 0.0):
            raise ValueError(f'tolerance must be finite and >= 0, got {tolerance!r} s')
        if not (math.isfinite(extrapolation) and extrapolation >= 0.0):
            raise ValueError(f'extrapolation must be finite and >= 0, got {extrapolation!r} s')
        self.span = float(span)
        self.tolerance = float(tolerance)
        self.extrapolation = float(extrapolation)
        self._poses = deque(maxlen=MAX_KEPT_POSES)
        self._velocity = (0.0, 0.0)

    def __len__(self):
        return len(self._poses)

    @property
    def newest_stamp(self):
        """Return the stamp of the newest kept pose [s], or None when none is kept."""
        return self._poses[-1][0] if self._poses else None

    def add(self, stamp, pose, velocity=(0.0, 0.0)):
        """
        Keep ``pose`` ``(x, y, yaw)`` [m, m, rad] and ``velocity`` ``(v, omega)`` [m/s, rad/s].

        Both taken at ``stamp`` [s].

        A stamp older than the newest kept one (time went back: a restarted simulation)
        starts the history anew; one equal to it replaces that pose (the latest word on that
        instant). At most `MAX_KEPT_POSES` are kept, the oldest dropped first.
        """
        stamp = float(stamp)
        if self._poses and stamp <= self._poses[-1][0]:
            if stamp == self._poses[-1][0]:
                self._poses.pop()
            else:
                self._poses.clear()
        self._poses.append((stamp, tuple(pose)))
        self._velocity = tuple(velocity)
        while self._poses and self._poses[0][0] < stamp - self.span:
            self._poses.popleft()

    def sample_step(self, stamp):
        """
        Return how far apart the two kept poses around ``stamp`` [s] lie (as `pose_at` uses).

        Returns
        -------
        (float, float, float) or None
            ``(duration [s], distance [m], turn [rad])`` between them; zeros when a kept pose
            lies at ``stamp``; None outside the kept poses (no interpolation there).

        """
        stamp = float(stamp)
        if not self._poses or not self._poses[0][0] <= stamp <= self._poses[-1][0]:
            return None
        after_stamp, after = self._poses[-1]
        for before_stamp, before in reversed(self._poses):
            if before_stamp <= stamp:
                break
            after_stamp, after = before_stamp, before
        if before_stamp == stamp:
            return 0.0, 0.0, 0.0
        return (after_stamp - before_stamp, math.dist(before[:2], after[:2]),
                abs(wrap_angle(after[2] - before[2])))

    def pose_at(self, stamp):
        """
        Return the pose at ``stamp`` [s], interpolated between the two kept poses around it.

        Returns
        -------
        pose : (float, float, float) or None
            None when nothing is kept, or the stamp lies more than ``tolerance`` before the
            oldest or more than ``extrapolation`` after the newest kept pose.

        """
        if not self._poses:
            return None
        stamp = float(stamp)
        first_stamp, first_pose = self._poses[0]
        last_stamp, last_pose = self._poses[-1]
        if stamp <= first_stamp:
            return first_pose if first_stamp - stamp <= self.tolerance else None
        if stamp >= last_stamp:
            ahead = stamp - last_stamp
            if ahead == 0.0 or ahead > self.extrapolation:
                return last_pose if ahead == 0.0 else None
            linear, angular = self._velocity
            x, y, yaw = last_pose
            heading = yaw + 0.5 * angular * ahead        # the mean heading over the step
            return (x + linear * ahead * math.cos(heading),
                    y + linear * ahead * math.sin(heading), wrap_angle(yaw + angular * ahead))
        # Scans are recent: look from the newest pose back.
        after_stamp, after = last_stamp, last_pose
        for before_stamp, before in reversed(self._poses):
            if before_stamp <= stamp:
                break
            after_stamp, after = before_stamp, before
        if before_stamp == stamp:
            return before
        t = (stamp - before_stamp) / (after_stamp - before_stamp)
        yaw = before[2] + t * wrap_angle(after[2] - before[2])
        return (before[0] + t * (after[0] - before[0]), before[1] + t * (after[1] - before[1]),
                wrap_angle(yaw))
