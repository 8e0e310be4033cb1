"""
Odometry that drifts and a localiser that corrects it: the world's ``odom`` and ``map -> odom``.

Real wheel odometry integrates wheel turns: a wrong wheel radius scales the distance, a wrong
track width scales the turns, uneven tyres or floor add a turn per metre driven, and slip adds
noise. `DriftingOdometry` integrates the true motion of each tick with those errors, so that the
odometry pose (in the ``odom`` frame) wanders away from the true pose (in the ``map`` frame) the
way a real robot's does. `Localiser` plays AMCL or slam_toolbox: it publishes ``map -> odom``,
the correction that puts the odometry pose back on the true pose, exactly or with a fixed error,
refreshed at a rate (between refreshes the last correction holds, as AMCL republishes it).

No ROS, no pybullet: poses are ``(x, y, yaw)`` [m, m, rad] tuples.

"""

from dataclasses import dataclass
import math

from dpn_navigator.core.pose2d import compose, wrap_angle
import numpy as np


@dataclass(frozen=True)
class DriftConfig:
    """
    Errors of the simulated wheel odometry; all zero: the odometry is the true pose.

    Parameters
    ----------
    scale : float
        Relative error of the distance driven (0.02: 2 % too long).
    yaw_scale : float
        Relative error of the turns (0.01: turns read 1 % too large).
    yaw_per_metre : float
        Heading error added per metre driven [rad/m] (a slowly curving straight line).
    noise : float
        Standard deviation of the distance and heading noise per square root of metre driven
        [m/sqrt(m) and rad/sqrt(m)].

    """

    scale: float = 0.0
    yaw_scale: float = 0.0
    yaw_per_metre: float = 0.0
    noise: float = 0.0

    def __post_init__(self):
        values = (self.scale, self.yaw_scale, self.yaw_per_metre, self.noise)
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f'odometry drift values must be finite, got {values}')
        if not (-0.5 < self.scale < 0.5 and -0.5 < self.yaw_scale < 0.5):
            raise ValueError('odometry scale and yaw scale errors must lie in (-0.5, 0.5), got '
                             f'{self.scale} and {self.yaw_scale}')
        if self.noise < 0.0:
            raise ValueError(f'odometry noise must be non-negative, got {self.noise}')

    @property
    def drifts(self):
        """Return whether any error is set."""
        return any(v != 0.0 for v in (self.scale, self.yaw_scale, self.yaw_per_metre,
                                      self.noise))


def relative_motion(before, after):
    """
    Return the motion from pose ``before`` to ``after`` in ``before``'s frame.

    Returns
    -------
    (float, float, float)
        ``(dx, dy, dyaw)`` [m, m, rad]: forward, left, turn.

    """
    dx, dy = after[0] - before[0], after[1] - before[1]
    c, s = math.cos(before[2]), math.sin(before[2])
    return (c * dx + s * dy, -s * dx + c * dy, wrap_angle(after[2] - before[2]))


class DriftingOdometry:
    """
    Integrate the true motion of each tick with the errors of a `DriftConfig`.

    Parameters
    ----------
    config : DriftConfig
    start : (float, float, float)
        The true start pose; the odometry starts there too (``map -> odom`` the identity at
        the start, as a localiser initialised at the true pose has it).
    seed : int
        Seed of the noise.

    """

    def __init__(self, config, start, seed=0):
        self.config = config
        self._true = tuple(float(v) for v in start)
        self.pose = self._true
        self.distance = 0.0
        self._rng = np.random.default_rng(seed)

    def update(self, true_pose):
        """
        Advance to the true pose of the next tick; return the odometry pose.

        Returns
        -------
        (float, float, float)
            The odometry's base pose in the ``odom`` frame [m, m, rad].

        """
        true_pose = tuple(float(v) for v in true_pose)
        cfg = self.config
        if not cfg.drifts:
            self._true = self.pose = true_pose
            return self.pose
        dx, dy, dyaw = relative_motion(self._true, true_pose)
        self._true = true_pose
        step = math.hypot(dx, dy)
        self.distance += step
        scale = 1.0 + cfg.scale
        dyaw_odom = dyaw * (1.0 + cfg.yaw_scale) + cfg.yaw_per_metre * step
        if cfg.noise > 0.0 and step > 0.0:
            sigma = cfg.noise * math.sqrt(step)
            scale += self._rng.normal(0.0, sigma) / step
            dyaw_odom += self._rng.normal(0.0, sigma)
        self.pose = compose(self.pose, (scale * dx, scale * dy, dyaw_odom))
        return self.pose


@dataclass(frozen=True)
class LocaliserConfig:
    """
    How the simulated localiser publishes ``map -> odom``.

    Parameters
    ----------
    error_xy : float
        Position error of its estimate [m], along a direction fixed by the seed.
    error_yaw : float
        Heading error of its estimate [rad].
    rate : float
        Refreshes of the correction per simulated second [Hz]; 0: every tick (exact tracking).

    """

    error_xy: float = 0.0
    error_yaw: float = 0.0
    rate: float = 0.0

    def __post_init__(self):
        values = (self.error_xy, self.error_yaw, self.rate)
        if not all(math.isfinite(v) for v in values) or self.error_xy < 0.0 or self.rate < 0.0:
            raise ValueError('localiser error_xy and rate must be finite and >= 0, error_yaw '
                             f'finite; got {values}')


class Localiser:
    """
    The correction ``map -> odom`` a localiser publishes: true pose composed with odom^-1.

    Parameters
    ----------
    config : LocaliserConfig
    seed : int
        Seed of the direction of the position error.

    """

    def __init__(self, config, seed=0):
        self.config = config
        direction = np.random.default_rng(seed).uniform(-math.pi, math.pi)
        self._error = (config.error_xy * math.cos(direction),
                       config.error_xy * math.sin(direction), config.error_yaw)
        self._next_time = -math.inf
        self.odom_in_map = (0.0, 0.0, 0.0)

    def update(self, time, true_pose, odom_pose):
        """
        Return ``map -> odom`` (the odom frame's pose in the map frame) at ``time`` [s].

        Refreshed from the true and the odometry pose when a refresh is due, else the last one.
        """
        if self.config.rate <= 0.0 or time >= self._next_time:
            estimate = compose(true_pose, self._error)
            self.odom_in_map = compose(estimate, inverse_pose(odom_pose))
            if self.config.rate > 0.0:
                self._next_time = time + 1.0 / self.config.rate
        return self.odom_in_map


def inverse_pose(pose):
    """
    Return the inverse of a planar pose: where frame A is seen from frame B, given B in A.

    Parameters
    ----------
    pose : (float, float, float)
        ``(x, y, yaw)`` of frame B in frame A [m, m, rad].

    Returns
    -------
    (float, float, float)
        ``(x, y, yaw)`` of frame A in frame B, so that ``compose(pose, inverse) == (0, 0, 0)``.

    """
    x, y, yaw = pose
    cos_yaw, sin_yaw = math.cos(yaw), math.sin(yaw)
    return (-cos_yaw * x - sin_yaw * y, sin_yaw * x - cos_yaw * y, wrap_angle(-yaw))
