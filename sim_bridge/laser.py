"""
A planar laser range finder simulated with one pybullet ``rayTestBatch`` per scan.

The defaults model the paper's sensor, a 640-beam, 180-degree LRF on the Husky, with the range
limits of Clearpath's simulated SICK LMS1xx (``husky_description``: 0.1 m to 30 m). Ranges
follow REP 117: ``+inf`` where a beam returns nothing within ``range_max``, ``-inf`` where the
return is closer than ``range_min``.

"""

from dataclasses import dataclass
import math
from operator import itemgetter

import numpy as np
import pybullet

from .husky import LASER_HEIGHT, LASER_MOUNT

#: pybullet answers a batch of exactly 16384 rays with nothing, and raises beyond that.
MAX_BEAMS = 16383

# Fields of one rayTestBatch result: (object id, link index, hit fraction, position, normal).
_OBJECT_ID = itemgetter(0)
_HIT_FRACTION = itemgetter(2)


@dataclass(frozen=True)
class LaserConfig:
    """
    Beam layout, range limits, noise and mount of the laser.

    Parameters
    ----------
    n_beams : int
        Number of beams, ``2 <= n_beams <= MAX_BEAMS``.
    angle_min, angle_max : float
        Laser-frame angles of the first and last beam [rad], counter-clockwise from x.
    range_min, range_max : float
        Valid return interval [m], ``0 <= range_min < range_max``.
    noise_std : float
        Standard deviation of zero-mean Gaussian noise added to every return [m]; 0 for
        exact ranges (Clearpath's Gazebo model uses 0.001 m).
    mount : (float, float, float)
        Laser pose on the robot's base frame ``(x, y, yaw)`` [m, m, rad].
    height : float
        Height of the scan plane above the ground [m].
    upside_down : bool
        Mounted upside down (rolled by pi about its x axis): laser-frame angle ``a`` looks
        along base-frame angle ``mount yaw - a``.

    """

    n_beams: int = 640
    angle_min: float = -0.5 * math.pi
    angle_max: float = 0.5 * math.pi
    range_min: float = 0.1
    range_max: float = 30.0
    noise_std: float = 0.0
    mount: tuple = LASER_MOUNT
    height: float = LASER_HEIGHT
    upside_down: bool = False

    def __post_init__(self):
        if isinstance(self.n_beams, bool) or not isinstance(self.n_beams, int) or \
                not 2 <= self.n_beams <= MAX_BEAMS:
            raise ValueError(f'n_beams must be an integer in [2, {MAX_BEAMS}], '
                             f'got {self.n_beams!r}')
        values = (self.angle_min, self.angle_max, self.range_min, self.range_max,
                  self.noise_std, self.height, *self.mount)
        if len(self.mount) != 3 or not all(math.isfinite(v) for v in values):
            raise ValueError('laser angles, ranges, noise, height and mount (x, y, yaw) must '
                             'be finite')
        if not self.angle_min < self.angle_max:
            raise ValueError(f'angle_min {self.angle_min} must be below angle_max '
                             f'{self.angle_max}')
        if not 0.0 <= self.range_min < self.range_max:
            raise ValueError(f'need 0 <= range_min < range_max, got {self.range_min} and '
                             f'{self.range_max}')
        if self.noise_std < 0.0:
            raise ValueError(f'noise_std must be non-negative, got {self.noise_std}')

    @property
    def angle_increment(self):
        """Return the angle between neighbouring beams [rad]."""
        return (self.angle_max - self.angle_min) / (self.n_beams - 1)


@dataclass(frozen=True, eq=False)
class LaserScan:
    """
    One scan, with what a ``sensor_msgs/LaserScan`` needs.

    Attributes
    ----------
    stamp : float
        Simulated time of the scan [s].
    ranges : (n_beams,) ndarray of float32
        Ranges [m], REP 117: ``+inf`` no return, ``-inf`` closer than ``range_min``.
    angle_min, angle_max, angle_increment : float
        Beam angles in the laser frame [rad].
    range_min, range_max : float
        Valid return interval [m].
    pose : (float, float, float)
        The laser's true pose in the map frame at the scan ``(x, y, yaw)`` [m, m, rad].
    hit_body : (n_beams,) ndarray of int64, or None
        Ground truth: the pybullet body id each beam hit, -1 for none (also beyond
        ``range_max``); for measuring, never for the navigator.

    """

    stamp: float
    ranges: np.ndarray
    angle_min: float
    angle_max: float
    angle_increment: float
    range_min: float
    range_max: float
    pose: tuple
    hit_body: np.ndarray = None


class Laser:
    """
    Cast the beams of a `LaserConfig` from a given laser pose.

    Parameters
    ----------
    client : int
        The pybullet physics client.
    config : LaserConfig
        The laser.
    collision_mask : int
        Collision filter mask of the rays: they hit bodies whose collision group shares a bit
        with it. Leave the robot carrying the laser out of it.
    rng : numpy.random.Generator
        Source of the range noise.

    """

    def __init__(self, client, config, collision_mask, rng):
        self.client = client
        self.config = config
        self.collision_mask = int(collision_mask)
        self.rng = rng
        angles = config.angle_min + config.angle_increment * np.arange(config.n_beams)
        self._cos = np.cos(angles)
        # An upside-down laser sweeps clockwise seen from above: its angles are mirrored.
        self._sin = -np.sin(angles) if config.upside_down else np.sin(angles)
        self._from = np.zeros((config.n_beams, 3), dtype=np.float64)
        self._to = np.zeros((config.n_beams, 3), dtype=np.float64)

    def scan(self, laser_pose, stamp):
        """
        Take one scan.

        Parameters
        ----------
        laser_pose : (float, float, float)
            The laser's pose in the map frame ``(x, y, yaw)`` [m, m, rad].
        stamp : float
            Simulated time [s], copied into the scan.

        Returns
        -------
        LaserScan

        Raises
        ------
        RuntimeError
            If pybullet does not return one result per beam.

        """
        cfg = self.config
        x, y, yaw = laser_pose
        c, s = math.cos(yaw), math.sin(yaw)
        n = cfg.n_beams
        self._from[:, 0] = x
        self._from[:, 1] = y
        self._from[:, 2] = cfg.height
        # Beam directions rotated from the laser frame into the map frame.
        self._to[:, 0] = x + cfg.range_max * (c * self._cos - s * self._sin)
        self._to[:, 1] = y + cfg.range_max * (s * self._cos + c * self._sin)
        self._to[:, 2] = cfg.height
        results = pybullet.rayTestBatch(
            self._from, self._to, collisionFilterMask=self.collision_mask,
            physicsClientId=self.client)
        if len(results) != n:
            raise RuntimeError(f'rayTestBatch returned {len(results)} results for {n} rays')
        hit_body = np.fromiter(map(_OBJECT_ID, results), dtype=np.int64, count=n)
        hit = hit_body >= 0
        ranges = cfg.range_max * np.fromiter(map(_HIT_FRACTION, results), dtype=np.float64,
                                             count=n)
        if cfg.noise_std > 0.0:
            ranges += self.rng.normal(0.0, cfg.noise_std, n)
        no_return = ~hit | (ranges >= cfg.range_max)
        ranges[no_return] = math.inf
        hit_body[no_return] = -1
        ranges[hit & (ranges < cfg.range_min)] = -math.inf
        return LaserScan(stamp, ranges.astype(np.float32), cfg.angle_min, cfg.angle_max,
                         cfg.angle_increment, cfg.range_min, cfg.range_max,
                         (float(x), float(y), float(yaw)), hit_body)
