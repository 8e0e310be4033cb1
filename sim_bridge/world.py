"""
The simulated world: a scenario's walls, the Husky with its laser, and wandering P3-ATs.

**Kinematic bodies, pybullet for geometry.** The Husky and the wanderers are moved
kinematically: each tick the Husky's pose is integrated exactly from the commanded ``(v, omega)``
(clamped to the Husky's limits and ramped by its acceleration limits), the wanderers' poses come
from their planner, and all of them are written into pybullet with
``resetBasePositionAndOrientation``. pybullet then runs collision detection only
(``performCollisionDetection``, no ``stepSimulation``) and one ``rayTestBatch`` per scan.
The Husky's wheels are not driven through physics because (1) a skid-steer Husky in Bullet
tracks a ``(v, omega)`` command only after tuning of friction, contact stiffness and motor
gains, and its turn rate would depend on them rather than on the navigator under test, which is
what the benchmark must measure; (2) the dynamics step would cost most of the time budget (the
benchmark needs at least 20x real time with ten wanderers and a 640-beam scan at 10 Hz on one
core); and (3) the kinematic world is exactly reproducible from a seed. Contacts are still
detected by Bullet on the real collision shapes: a move that would push the Husky deeper into a
wall or a wanderer is refused (the Husky stops where it was, as a robot held by an obstacle
would), and the contact is counted as an event (`ContactLog`).

**Contacts.** At 1 m/s the Husky moves 2 cm per tick at the default 50 Hz, less than the
thinnest wall (one map cell: 10 cm on back_and_forth, 3 cm on the finest map tried), so it
cannot tunnel through one and no contact is missed. A contact is counted when the pose a tick
proposes penetrates an obstacle, even though the Husky is then held back. The robots' state
lives in this module's arrays and is only written into pybullet, never read back.

**Ticks and scans.** The world advances in fixed ticks of ``1 / physics_rate`` seconds
(`step`); a scan is due every ``physics_rate / scan_rate`` ticks (`scan_due`), which must be a
whole number. `advance` runs ticks up to the next scan and returns it, for batch runs as fast as
possible; a ROS node can instead call `step` from a timer at a real-time factor and publish
`scan` whenever `scan_due`. Simulated time is ``tick / physics_rate`` (`time`).

"""

import math

from dpn_navigator.core.pose2d import compose, wrap_angle
import numpy as np

from .contacts import ContactLog, robot_caused, robot_caused_at_contact
from .free_space import clearance_grid
from .husky import clamp_command, integrate_pose, ramp
from .laser import Laser
from .scene import agent_urdf, RAY_MASK, Scene
from .wanderers import Wanderers
from .world_config import WorldConfig

__all__ = ['wanderer_clearance_grid', 'World', 'WorldConfig']


class World:
    """
    A pybullet world that runs one episode of a scenario.

    Parameters
    ----------
    scenario : Scenario
        Map (walls are its occupied cells) and tasks.
    config : WorldConfig, optional
        Rates, robots and seed.
    start : (float, float, float), optional
        The Husky's start pose ``(x, y, yaw)`` [m, m, rad]; the first task's start by default.
    wanderer_grid : ClearanceGrid, optional
        The wanderers' `ClearanceGrid` of this scenario for ``config.wanderer.clearance``,
        when the caller has it already (a benchmark worker builds it once per map); built
        here by default. It is only read.

    Attributes
    ----------
    scenario : Scenario
        The scenario; its ``occupied`` grid is the ground truth of the walls.
    config : WorldConfig
        The configuration.
    contacts : ContactLog
        The Husky's contact events with walls and wanderers, and their first times.
    rejected_commands : int
        Velocity commands ignored because they were not finite.
    last_command_accepted : bool
        Whether the latest command was accepted.
    blocked_ticks : int
        Ticks on which an obstacle held the Husky.
    scene : Scene
        The pybullet client and bodies (``scene.client``, ``scene.husky``, ...).

    Raises
    ------
    ValueError
        If there is no start pose, the Husky collides with a wall at it, the wanderers find
        no room to spawn, or ``wanderer_grid`` is for another clearance or map size.

    Examples
    --------
    A batch run, as fast as possible, with the navigator in the loop:

    >>> from sim_bridge.scenario import load_scenario
    >>> with World(load_scenario('back_and_forth'), WorldConfig(n_wanderers=2)) as world:
    ...     scan = world.scan()
    ...     while world.time < 1.0:
    ...         scan = world.advance(0.5, 0.0)  # v, omega from the navigator
    ...     round(world.husky_pose[0], 2), len(scan.ranges)
    (2.46, 640)

    """

    def __init__(self, scenario, config=None, start=None, wanderer_grid=None):
        self.config = config = WorldConfig() if config is None else config
        if start is None:
            if not scenario.tasks:
                raise ValueError(f'scenario {scenario.name!r} has no task: give a start pose')
            start = scenario.tasks[0].start
        x, y, yaw = (float(v) for v in start)
        if not all(math.isfinite(v) for v in (x, y, yaw)):
            raise ValueError(f'start pose must be finite, got {start!r}')
        self.scenario = scenario
        self.contacts = ContactLog()
        self.rejected_commands = 0
        self.blocked_ticks = 0
        self.last_command_accepted = True
        self._dt = 1.0 / config.physics_rate
        self._tick = 0
        self._pose = (x, y, wrap_angle(yaw))
        self._velocity = (0.0, 0.0)
        self._command = (0.0, 0.0)
        self._depth = 0.0
        self._scan = None
        # Wanderers whose ray twin lags behind their body (see `_place_moved_wanderers`).
        self._stale_ray_twins = set()
        self._wanderer_of_body = None
        wander_seed, noise_seed = np.random.SeedSequence(config.seed).spawn(2)
        if wanderer_grid is None:
            grid = wanderer_clearance_grid(scenario, config.wanderer)
        else:
            grid = _checked_wanderer_grid(wanderer_grid, scenario, config.wanderer)
        self._wanderers = Wanderers(grid, config.n_wanderers, (x, y),
                                    np.random.default_rng(wander_seed), config.wanderer,
                                    robot_radius=config.body.radius)
        self.scene = Scene(scenario, config.n_wanderers, config.wall_height, self._dt,
                           config.gui, agent_urdf=[agent_urdf(kind) for kind in
                                                   config.wanderer.kinds(config.n_wanderers)],
                           body=config.body)
        for i in range(config.n_wanderers):
            self._place_wanderer(i)
        self.scene.place(self.scene.husky, self._pose)
        wall, touched, self._depth = self.scene.husky_contacts()
        if wall:
            self.close()
            raise ValueError(f'the Husky collides with a wall at its start pose {self._pose}')
        self.contacts.update(0.0, wall, touched, approached=())  # the Husky stands at its start
        self._laser = Laser(self.scene.client, config.laser, RAY_MASK,
                            np.random.default_rng(noise_seed))

    # -- ground truth -----------------------------------------------------------------------

    @property
    def time(self):
        """Return the simulated time [s]."""
        return self._tick / self.config.physics_rate

    @property
    def tick(self):
        """Return the number of ticks run so far."""
        return self._tick

    @property
    def husky_pose(self):
        """Return the Husky's true pose ``(x, y, yaw)`` in the map frame [m, m, rad]."""
        return self._pose

    @property
    def husky_velocity(self):
        """Return the Husky's true ``(v, omega)`` over the last tick [m/s, rad/s] (0 if held)."""
        return self._velocity

    @property
    def husky_footprint(self):
        """Return the robot's length and width ``(l, w)`` [m] (the Husky's by default)."""
        return (self.config.body.length, self.config.body.width)

    @property
    def laser_pose(self):
        """Return the laser's true pose ``(x, y, yaw)`` in the map frame [m, m, rad]."""
        return compose(self._pose, self.config.laser.mount)

    @property
    def wanderer_positions(self):
        """Return the wanderers' positions, (N, 2) ndarray of float64 [m] (a copy)."""
        return self._wanderers.positions.copy()

    @property
    def wanderer_yaws(self):
        """Return the wanderers' headings, (N,) ndarray of float64 [rad] (a copy)."""
        return self._wanderers.yaws.copy()

    @property
    def wanderer_radius(self):
        """Return the radius of the circle around a wanderer's footprint [m]."""
        return self._wanderers.radius

    def forecast_wanderers(self, times, husky_xy_at):
        """
        Return the wanderers' true future positions, the Husky at ``husky_xy_at(t)``.

        ``times`` [s from now] and ``husky_xy_at`` as for ``Wanderers.forecast``; the world is
        unchanged. Exact while the Husky is where ``husky_xy_at`` puts it (the space-time
        oracle's foresight). Returns a ``(S, K, 2)`` array [m].
        """
        return self._wanderers.forecast(times, self._dt, husky_xy_at)

    def scan_wanderer_beams(self):
        """
        Return which wanderer each beam of the current scan hit (ground truth, for measuring).

        Returns
        -------
        wanderer : (n_beams,) ndarray of int64
            Index of the wanderer (as in `wanderer_positions`) beam ``i`` hit; -1 where it hit a
            wall or returned nothing.

        """
        if self._wanderer_of_body is None:
            bodies = self.scene.wanderer_ray_bodies
            # Indexed by body id; the last entry answers -1 (no hit) with -1.
            self._wanderer_of_body = np.full(max(bodies, default=0) + 2, -1, dtype=np.int64)
            self._wanderer_of_body[bodies] = np.arange(len(bodies))
        hit_body = self.scan().hit_body
        known = hit_body < self._wanderer_of_body.shape[0] - 1
        return np.where(known, self._wanderer_of_body[np.where(known, hit_body, -1)], -1)

    @property
    def occupied(self):
        """Return the walls, (rows, cols) ndarray of bool, row 0 at the bottom."""
        return self.scenario.occupied

    @property
    def scan_due(self):
        """Return True on ticks that fall on the scan rate (tick 0 included)."""
        return self._tick % self.config.ticks_per_scan == 0

    # -- stepping ---------------------------------------------------------------------------

    def set_command(self, v, omega):
        """
        Set the velocity command, clamped to the drive limits.

        Parameters
        ----------
        v, omega : float
            Forward speed [m/s] and turn rate [rad/s].

        Returns
        -------
        accepted : bool
            False when either value is not a finite number: the command is then ignored (the
            previous one stays) and `rejected_commands` grows by one.

        """
        try:
            v, omega = float(v), float(omega)
        except (TypeError, ValueError):
            v = omega = math.nan
        accepted = math.isfinite(v) and math.isfinite(omega)
        if accepted:
            self._command = clamp_command(v, omega, self.config.drive)
        else:
            self.rejected_commands += 1
        self.last_command_accepted = accepted
        return accepted

    @property
    def command(self):
        """Return the command in force ``(v, omega)``, clamped [m/s, rad/s]."""
        return self._command

    def step(self, v, omega):
        """
        Set the command and advance the world by one tick.

        Parameters
        ----------
        v, omega : float
            Velocity command [m/s, rad/s], as for `set_command`.

        Returns
        -------
        accepted : bool
            Whether the command was accepted (see `set_command`).

        """
        accepted = self.set_command(v, omega)
        dt, limits = self._dt, self.config.drive
        lin = ramp(self._velocity[0], self._command[0], limits.max_linear_accel, dt)
        ang = ramp(self._velocity[1], self._command[1], limits.max_angular_accel, dt)
        proposed = integrate_pose(self._pose, lin, ang, dt)
        before = self._wanderers.positions.copy()
        yaws_before = self._wanderers.yaws.copy()
        self._place_moved_wanderers(self._wanderers.step(dt, self._pose[:2]))
        self.scene.place(self.scene.husky, proposed)
        wall, touched, depth = self.scene.husky_contacts()
        self._tick += 1
        self._scan = None
        new = set(touched) - self.contacts.touching_wanderers
        approached = {i for i in new
                      if self._robot_caused(i, proposed, (lin, ang), before, yaws_before)}
        self.contacts.update(self.time, wall, touched, approached)
        if depth > self._depth:
            # Deeper than at the last accepted pose; but a wanderer may have moved into the
            # Husky since, so compare with the penetration where the Husky stands now.
            self.scene.place(self.scene.husky, self._pose)
            self._depth = self.scene.husky_contacts()[2]
            if depth > self._depth:
                # Pushed deeper into an obstacle: the Husky is held where it was.
                self._velocity = (0.0, 0.0)
                self.blocked_ticks += 1
                return accepted
            self.scene.place(self.scene.husky, proposed)
        self._pose = proposed
        self._velocity = (lin, ang)
        self._depth = depth
        return accepted

    def scan(self):
        """
        Return the laser scan at the current tick (taken once per tick, then reused).

        Range noise is drawn at each new scan, so with noise an episode repeats from its seed
        when scans are taken at the same ticks (as ``advance`` and the node do).

        Returns
        -------
        LaserScan
            Ranges and beam layout, stamped with `time`.

        """
        if self._scan is None:
            self._place_ray_twins()
            self._scan = self._laser.scan(self.laser_pose, self.time)
        return self._scan

    def advance(self, v, omega):
        """
        Run ticks with one command up to the next scan and return that scan.

        Parameters
        ----------
        v, omega : float
            Velocity command [m/s, rad/s]; a rejected one is counted once per tick (see
            `last_command_accepted`).

        Returns
        -------
        LaserScan

        """
        self.step(v, omega)
        while not self.scan_due:
            self.step(v, omega)
        return self.scan()

    def close(self):
        """Disconnect from pybullet; the world cannot be stepped afterwards."""
        self.scene.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()

    def _place_wanderer(self, i):
        x, y = self._wanderers.positions[i].tolist()
        self.scene.place_wanderer(i, x, y, float(self._wanderers.yaws[i]))

    def _robot_caused(self, index, pose, velocity, positions_before, yaws_before):
        """
        Tell whether the new contact with wanderer ``index`` is the Husky's doing.

        At pybullet's deepest contact point (``contacts.robot_caused_at_contact``), or, when
        pybullet gives none, by the wanderer's centre (``contacts.robot_caused``).
        """
        dt = self._dt
        position = self._wanderers.positions[index]
        agent_velocity = ((position - positions_before[index]) / dt).tolist()
        contact = self.scene.wanderer_contact(index)
        if contact is None:
            return robot_caused(pose, velocity, *self.husky_footprint, position.tolist(),
                                agent_velocity)
        turned = math.remainder(float(self._wanderers.yaws[index] - yaws_before[index]),
                                2.0 * math.pi)
        return robot_caused_at_contact(pose, velocity, contact[0], contact[1],
                                       position.tolist(), agent_velocity, turned / dt)

    def _place_moved_wanderers(self, moved):
        """
        Move the bodies of the wanderers ``moved`` in pybullet; their ray twins wait for a scan.

        The Husky's contacts are checked on every tick, but rays are cast once per scan, and
        only rays meet the twins: moving a twin once before a scan gives the same scan as
        moving it on every tick, for up to ``ticks_per_scan`` times fewer pybullet calls.
        """
        if not moved:
            return
        positions = self._wanderers.positions.tolist()
        yaws = self._wanderers.yaws.tolist()
        for i in moved:
            self.scene.place_wanderer(i, positions[i][0], positions[i][1], yaws[i],
                                      ray_twin=False)
        self._stale_ray_twins.update(moved)

    def _place_ray_twins(self):
        """Bring the ray twins of the wanderers that moved since the last scan up to date."""
        if not self._stale_ray_twins:
            return
        positions = self._wanderers.positions.tolist()
        yaws = self._wanderers.yaws.tolist()
        for i in sorted(self._stale_ray_twins):
            self.scene.place_wanderer_ray_twin(i, positions[i][0], positions[i][1], yaws[i])
        self._stale_ray_twins.clear()


def wanderer_clearance_grid(scenario, wanderer_config):
    """
    Build the `ClearanceGrid` the wanderers of a scenario plan on.

    Parameters
    ----------
    scenario : Scenario
        The map.
    wanderer_config : WandererConfig
        Its ``clearance`` [m] is the radius kept clear.

    Returns
    -------
    ClearanceGrid
        Built with the default coarse cell size of `sim_bridge.free_space`; its arrays are
        read-only, so that one grid can serve many episodes.

    """
    grid = clearance_grid(scenario.free, scenario.geometry, wanderer_config.clearance)
    grid.clear.setflags(write=False)
    grid.labels.setflags(write=False)
    return grid


def _checked_wanderer_grid(grid, scenario, wanderer_config):
    """Return ``grid`` if it can be the wanderers' grid of ``scenario``; else raise."""
    if grid.clearance != wanderer_config.clearance:
        raise ValueError(f'wanderer_grid was built for a clearance of {grid.clearance} m, the '
                         f'wanderers keep {wanderer_config.clearance} m')
    geometry = scenario.geometry
    coarse = (-(-geometry.shape[0] // grid.factor), -(-geometry.shape[1] // grid.factor))
    if grid.clear.shape != coarse or grid.geometry.origin != geometry.origin or \
            not math.isclose(grid.geometry.resolution, grid.factor * geometry.resolution):
        raise ValueError("wanderer_grid is not a grid of this scenario's map: build it with "
                         'wanderer_clearance_grid(scenario, config.wanderer)')
    return grid
