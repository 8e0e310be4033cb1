"""
A planar laser range finder simulated with one pybullet ``rayTestBatch`` per scan.

The defaults model the paper's sensor, a 640-beam, 180-degree LRF on the Husky, with the range
limits of Clearpath's simulated SICK LMS1xx (``husky_description``: 0.1 m to 30 m), and no
artefacts: exact ranges, every beam within ``range_max`` returns. Ranges follow REP 117:
``+inf`` where a beam returns nothing within ``range_max``, ``-inf`` where the return is closer
than ``range_min``. The artefacts of real lasers (noise, lost returns, mixed pixels, other error
encodings) are fields of `LaserConfig`, applied by `sim_bridge.laser_artefacts`; named sets of
them, modelled on data sheets, are in `sim_bridge.laser_profiles`.

"""

from dataclasses import dataclass
import math
from operator import itemgetter

import numpy as np
import pybullet

from .husky import LASER_HEIGHT, LASER_MOUNT
from .laser_artefacts import (check_artefacts, dropped_beams, encode_errors, grazing_beams,
                              has_dropout, has_noise, HOKUYO_ERROR_CODES, mix_edge_pixels,
                              noise_std_of)

#: pybullet answers a batch of exactly 16384 rays with nothing, and raises beyond that.
MAX_BEAMS = 16383

# Fields of one rayTestBatch result: (object id, link index, hit fraction, position, normal).
_OBJECT_ID = itemgetter(0)
_HIT_FRACTION = itemgetter(2)
_HIT_NORMAL = itemgetter(4)
#: Slack on "the beams cover a full turn" [rad].
_FULL_TURN_SLACK = 1e-9


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
        exact ranges (Clearpath's Gazebo model uses 0.001 m). The floor of the noise model.
    mount : (float, float, float)
        Laser pose on the robot's base frame ``(x, y, yaw)`` [m, m, rad].
    height : float
        Height of the scan plane above the ground [m].
    upside_down : bool
        Mounted upside down (rolled by pi about its x axis): laser-frame angle ``a`` looks
        along base-frame angle ``mount yaw - a``.
    noise_fraction : float
        The noise standard deviation grows to ``noise_fraction * range`` [1]; 0: off.
    noise_std_far : float
        Noise standard deviation at least this beyond ``far_range`` [m]; 0: off.
    far_range : float
        Where the far band starts [m] (its noise and dropout); ``inf``: no far band.
    dropout : float
        Share of the hits that return nothing, at random [1]; 0: off.
    dropout_far : float
        The same beyond ``far_range`` (the larger of the two applies) [1].
    max_incidence : float
        A beam meeting a surface at more than this from the surface normal returns nothing
        [rad]; ``pi / 2``: off.
    mixed_pixel_probability : float
        Chance that a beam beside a depth jump returns a range between the two surfaces [1];
        0: off.
    mixed_pixel_jump : float
        Smallest depth difference between neighbouring beams that makes a depth edge [m].
    error_encoding : str
        How the driver writes a beam with no valid reading: ``'rep117'`` (``+inf`` no return,
        ``-inf`` too close), ``'nan'`` or ``'tiny_codes'`` (the old Hokuyo driver's codes).
    error_codes : tuple of (float, float)
        The tiny-range codes ``(range [m], weight)`` for ``'tiny_codes'``, each below
        ``range_min``.

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
    noise_fraction: float = 0.0
    noise_std_far: float = 0.0
    far_range: float = math.inf
    dropout: float = 0.0
    dropout_far: float = 0.0
    max_incidence: float = 0.5 * math.pi
    mixed_pixel_probability: float = 0.0
    mixed_pixel_jump: float = 0.15
    error_encoding: str = 'rep117'
    error_codes: tuple = HOKUYO_ERROR_CODES

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
        if not self.angle_min < self.angle_max <= self.angle_min + 2.0 * math.pi + \
                _FULL_TURN_SLACK:
            raise ValueError(f'angle_min {self.angle_min} must be below angle_max '
                             f'{self.angle_max}, by at most a full turn')
        if not 0.0 <= self.range_min < self.range_max:
            raise ValueError(f'need 0 <= range_min < range_max, got {self.range_min} and '
                             f'{self.range_max}')
        if self.noise_std < 0.0:
            raise ValueError(f'noise_std must be non-negative, got {self.noise_std}')
        check_artefacts(self)

    @property
    def angle_increment(self):
        """Return the angle between neighbouring beams [rad]."""
        return (self.angle_max - self.angle_min) / (self.n_beams - 1)

    @property
    def full_turn(self):
        """Return True when the beams cover a full turn (the last one next to the first)."""
        return abs(self.n_beams * self.angle_increment - 2.0 * math.pi) < \
            0.5 * self.angle_increment + _FULL_TURN_SLACK


@dataclass(frozen=True, eq=False)
class LaserScan:
    """
    One scan, with what a ``sensor_msgs/LaserScan`` needs.

    Attributes
    ----------
    stamp : float
        Simulated time of the scan [s].
    ranges : (n_beams,) ndarray of float32
        Ranges [m]. With the default ``error_encoding`` REP 117: ``+inf`` no return, ``-inf``
        closer than ``range_min``; else NaN for both, or the driver's tiny-range codes.
    angle_min, angle_max, angle_increment : float
        Beam angles in the laser frame [rad].
    range_min, range_max : float
        Valid return interval [m].
    pose : (float, float, float)
        The laser's true pose in the map frame at the scan ``(x, y, yaw)`` [m, m, rad].
    hit_body : (n_beams,) ndarray of int64, or None
        Ground truth: the pybullet body id each beam hit, -1 for none (also beyond
        ``range_max``, and where the laser lost the return: grazing incidence, dropout); for
        measuring, never for the navigator.

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
        Source of the artefacts' randomness (noise, dropout, mixed pixels, error codes); a
        laser with none of them on draws nothing from it.

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
        lost = np.zeros(n, dtype=bool)
        if cfg.max_incidence < 0.5 * math.pi:
            normals = np.array(list(map(_HIT_NORMAL, results)), dtype=np.float64).reshape(n, 3)
            directions_x = (self._to[:, 0] - x) / cfg.range_max
            directions_y = (self._to[:, 1] - y) / cfg.range_max
            lost |= hit & grazing_beams(directions_x, directions_y, normals, cfg.max_incidence)
        if cfg.mixed_pixel_probability > 0.0:
            ranges, _ = mix_edge_pixels(ranges, hit & ~lost, cfg.mixed_pixel_probability,
                                        cfg.mixed_pixel_jump, self.rng, wraps=cfg.full_turn)
        if has_noise(cfg):
            ranges += self.rng.normal(0.0, noise_std_of(ranges, cfg), n)
        if has_dropout(cfg):
            lost |= dropped_beams(ranges, hit & ~lost, cfg, self.rng)
        no_return = ~hit | lost | (ranges >= cfg.range_max)
        hit_body[no_return] = -1
        too_close = hit & ~no_return & (ranges < cfg.range_min)
        encode_errors(ranges, no_return, too_close, cfg, self.rng)
        return LaserScan(stamp, ranges.astype(np.float32), cfg.angle_min, cfg.angle_max,
                         cfg.angle_increment, cfg.range_min, cfg.range_max,
                         (float(x), float(y), float(yaw)), hit_body)
