"""
Configuration of a `sim_bridge.world.World`: rates, robots, seed and models.

A frozen dataclass, validated on construction, so a ROS node can fill it from its parameters
once and a benchmark can vary one field with `dataclasses.replace`.

"""

from dataclasses import dataclass
import math

from .husky import DriveLimits
from .laser import LaserConfig
from .robot_profiles import ROBOT_PROFILES, RobotBody
from .wanderers import WandererConfig


@dataclass(frozen=True)
class WorldConfig:
    """
    Rates, robots, seed and models of a world.

    Parameters
    ----------
    physics_rate : float
        Ticks per simulated second [Hz].
    scan_rate : float
        Scans per simulated second [Hz]; ``physics_rate / scan_rate`` must be a whole number.
    n_wanderers : int
        Number of wandering P3-ATs, 0 to 10 in the paper (more are allowed).
    seed : int
        Seed of every random choice (wanderers, laser noise): same seed, same episode.
    gui : bool
        Open the pybullet GUI instead of running headless (``DIRECT``).
    drive : DriveLimits
        The robot's velocity and acceleration limits (the Husky's by default).
    body : RobotBody
        The robot's body (the Husky's by default; ``robot_profiles``).
    laser : LaserConfig
        The laser.
    wanderer : WandererConfig
        The wanderers' behaviour.
    wall_height : float
        Height of the walls [m].

    """

    physics_rate: float = 50.0
    scan_rate: float = 10.0
    n_wanderers: int = 0
    seed: int = 0
    gui: bool = False
    drive: DriveLimits = DriveLimits()
    body: RobotBody = ROBOT_PROFILES['husky'].body
    laser: LaserConfig = LaserConfig()
    wanderer: WandererConfig = WandererConfig()
    wall_height: float = 1.0

    def __post_init__(self):
        for name in ('physics_rate', 'scan_rate'):
            rate = getattr(self, name)
            if isinstance(rate, bool) or not isinstance(rate, (int, float)) or \
                    not math.isfinite(rate) or rate <= 0.0:
                raise ValueError(f'{name} must be a positive finite number, got {rate!r} Hz')
        ratio = self.physics_rate / self.scan_rate
        if round(ratio) < 1 or abs(ratio - round(ratio)) > 1e-9 * ratio:
            raise ValueError(
                f'scan_rate {self.scan_rate} Hz must divide physics_rate {self.physics_rate} Hz '
                f'a whole number of times (got {ratio:g}); e.g. physics 50 Hz, scans 10 Hz')
        count = self.n_wanderers
        if isinstance(count, bool) or not isinstance(count, int) or count < 0:
            raise ValueError(f'n_wanderers must be a non-negative integer, got {count!r}')
        if not (math.isfinite(self.wall_height) and self.wall_height > 0.0):
            raise ValueError(f'wall_height must be positive, got {self.wall_height!r} m')

    @property
    def ticks_per_scan(self):
        """Return the number of ticks between two scans, ``physics_rate / scan_rate``."""
        return int(round(self.physics_rate / self.scan_rate))
