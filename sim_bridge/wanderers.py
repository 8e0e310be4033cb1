"""
Wandering Pioneer 3-ATs: random reachable goals, A* on the ground truth, kinematic motion.

Each wanderer walks from one random goal to the next at its own speed. It plans with
`dpn_navigator.core.astar` (through `clear_paths.plan_path`) on a `ClearanceGrid` of the true
map (cells where a disc of the P3-AT's radius plus a margin fits anywhere) and drives its path
centre to centre: it turns in place until it faces the next waypoint, then moves along the
straight segment, so it never leaves clear cells and never touches a wall. It does not drive
into the Husky: while the Husky is in a corridor ahead of it (up to ``husky_look_ahead``
beyond the Husky's radius) it stops, and likewise for another wanderer close ahead; nor does
it turn its corners into the Husky (``turn_guard``: a P3-AT's box sweeps its circle as it turns
in place, so a polite one holds its heading while that circle and the Husky's are closer than
0.05 m, and counts as stopped). A wanderer that stays stopped longer than its patience picks a
new goal and plans around what blocks it, so none is stuck for long.

**Agent models.** The same walker moves other agents: `WandererConfig` sets their body
(``body``: the P3-AT's URDF, or an upright cylinder of ``radius``, a pedestrian), their speed
range, their acceleration (``max_accel``: 0 changes speed at once, as a P3-AT here does) and
their politeness (``polite``: whether they stop for the Husky ahead; pedestrians do not) and
their reaction to it (``yield_horizon``, below). `AGENT_MODELS` names the presets (``--agents``
of the benchmark).

**Yielding: a velocity obstacle along the path.** An agent with ``yield_horizon`` ``tau`` > 0
walks at the largest speed along its path, at most its walking speed, whose velocity lies
outside the Husky's velocity obstacle truncated at ``tau`` (Fiorini and Shiller 1998, *Motion
planning in dynamic environments using velocity obstacles*, IJRR 17(7); truncated by a time
horizon as in ORCA, van den Berg, Guy, Lin and Manocha 2011, *Reciprocal n-body collision
avoidance*, ISRR): its disc and the Husky's circumscribed disc, ``yield_margin`` apart, do not
meet within ``tau`` if both keep their velocities (the Husky's from its last two positions).
The agent takes the whole avoidance on itself, as towards a robot that does not reciprocate,
but only by its speed (it slows down and stops, it does not step aside: off its path it could
meet a wall); stopped so, it waits out its patience and plans around the Husky, as a stopped
P3-AT does. It does not yield where no speed helps (the Husky drives at it while it stands):
such a contact is the Husky's (``sim_bridge.contacts``). Speeds are searched from the walking
speed down in ``YIELD_SPEED_STEPS`` even steps to ``yield_slowest`` of it; when none of them
yields the agent stands (a person stops rather than creeps: a truncated velocity obstacle alone
lets a walker creep up to a standing obstacle ever slower, never stopping).

Everything here is plain Python + numpy, with no pybullet; the world copies the poses into
the physics engine. All randomness comes from the generator passed in, so a seed fixes the
wanderers' spawn points, speeds, goals and therefore trajectories.

"""

from collections import deque
import copy
import dataclasses
from dataclasses import dataclass
import math
from pathlib import Path

from dpn_navigator.core.pose2d import wrap_angle
import numpy as np

from .clear_paths import block_disc, plan_path, turning_points
from .husky import HUSKY_RADIUS

#: The Pioneer 3-AT model.
P3AT_URDF = Path(__file__).resolve().parent / 'urdf' / 'p3at.urdf'
#: Radius of the circle around a P3-AT's 0.508 m x 0.497 m footprint [m].
P3AT_RADIUS = 0.5 * math.hypot(0.508, 0.497)
#: Gap a polite P3-AT keeps between its circle and the Husky's before it turns in place [m].
TURN_GUARD_GAP = 0.05


@dataclass(frozen=True)
class WandererConfig:
    """
    Behaviour of the wanderers.

    Parameters
    ----------
    speed_range : (float, float)
        Each wanderer's walking speed is drawn uniformly from it [m/s].
    max_turn_rate : float
        Turn rate when turning towards a waypoint [rad/s].
    heading_tolerance : float
        Largest heading error at which a wanderer moves forward [rad].
    clearance : float
        Radius kept clear of walls and unknown space around a wanderer's centre [m].
    husky_look_ahead : float
        Stop while the Husky's circle is less than this far ahead [m].
    wanderer_look_ahead : float
        Stop while another wanderer's circle is less than this far ahead [m].
    patience_range : (float, float)
        After stopping this long (drawn uniformly per stop) pick a new goal [s].
    goal_distance_range : (float, float)
        Preferred straight-line distance to a new goal [m].
    spawn_distance : float
        Least distance between a spawn point and the Husky's start [m].
    body : str
        ``'p3at'`` (the Pioneer 3-AT's URDF, `P3AT_RADIUS`) or ``'cylinder'`` (an upright
        cylinder of ``radius``, 1.7 m tall: a pedestrian).
    radius : float
        The cylinder's radius [m] (ignored for a P3-AT, whose circle is `P3AT_RADIUS`).
    polite : bool
        Stop while the Husky is ahead (``husky_look_ahead``); an impolite agent walks on and
        leaves avoiding it to the Husky.
    max_accel : float
        Largest change of walking speed [m/s^2]; 0: at once (starts and stops instantly).
    yield_horizon : float
        Time horizon of the velocity obstacle an agent keeps out of by slowing down [s]; 0:
        no yielding (the agent walks at its speed whatever the Husky does).
    yield_margin : float
        Gap kept between the agent's circle and the Husky's circumscribed circle when
        yielding [m].
    yield_slowest : float
        Slowest speed a yielding agent walks at, as a share of its walking speed, in (0, 1];
        when no speed from its walking speed down to this one yields, it stands.
    turn_guard : bool
        A polite P3-AT does not turn in place while its circle (`P3AT_RADIUS`) comes within
        0.05 m of the Husky's circumscribed one: it holds its heading and counts as stopped
        (before 27 November it turned its box's corners into a standing Husky). Cylinders
        sweep nothing as they turn.
    others : WandererConfig or None
        A second kind of agent in the same crowd: the last ``round(others_share * count)``
        agents behave by it (body, speeds, acceleration, politeness, turning, patience); the
        clearance grid, spawn and goal rules stay this config's, so its ``clearance`` must be
        the larger.
    others_share : float
        Share of the agents of the second kind, in [0, 1].

    """

    speed_range: tuple = (0.3, 0.7)
    max_turn_rate: float = 1.5
    heading_tolerance: float = 0.3
    clearance: float = P3AT_RADIUS + 0.1
    husky_look_ahead: float = 1.5
    wanderer_look_ahead: float = 0.5
    patience_range: tuple = (1.5, 3.0)
    goal_distance_range: tuple = (3.0, 15.0)
    spawn_distance: float = 3.0
    body: str = 'p3at'
    radius: float = P3AT_RADIUS
    polite: bool = True
    max_accel: float = 0.0
    yield_horizon: float = 0.0
    yield_margin: float = 0.05
    yield_slowest: float = 0.5
    turn_guard: bool = True
    others: object = None
    others_share: float = 0.0

    def __post_init__(self):
        if not 0.0 <= self.others_share <= 1.0 or (self.others_share and self.others is None):
            raise ValueError('others_share must lie in [0, 1], and needs others')
        if self.others is not None and self.others.clearance > self.clearance:
            raise ValueError('the second kind of agent needs no more clearance than the first')
        if self.body not in ('p3at', 'cylinder'):
            raise ValueError(f"body must be 'p3at' or 'cylinder', got {self.body!r}")
        if not (math.isfinite(self.radius) and 0.05 <= self.radius <= 2.0):
            raise ValueError(f'radius must lie in [0.05, 2] m, got {self.radius!r}')
        if not (math.isfinite(self.max_accel) and self.max_accel >= 0.0):
            raise ValueError(f'max_accel must be finite and >= 0, got {self.max_accel!r}')
        if not (math.isfinite(self.yield_horizon) and 0.0 <= self.yield_horizon <= 10.0):
            raise ValueError(f'yield_horizon must lie in [0, 10] s, got {self.yield_horizon!r}')
        if not (math.isfinite(self.yield_margin) and 0.0 <= self.yield_margin <= 1.0):
            raise ValueError(f'yield_margin must lie in [0, 1] m, got {self.yield_margin!r}')
        if not (math.isfinite(self.yield_slowest) and 0.0 < self.yield_slowest <= 1.0):
            raise ValueError(f'yield_slowest must lie in (0, 1], got {self.yield_slowest!r}')
        low, high = self.speed_range
        if not (0.0 <= low <= high):
            raise ValueError(f'speed_range must be 0 <= low <= high, got {self.speed_range!r}')

    @property
    def body_radius(self):
        """Return the radius of the circle around the agent's footprint [m]."""
        return P3AT_RADIUS if self.body == 'p3at' else self.radius

    def kinds(self, count):
        """Return the config of each of ``count`` agents: this one, then the others."""
        others = round(self.others_share * count) if self.others is not None else 0
        return [self] * (count - others) + [self.others] * others

    @property
    def largest_radius(self):
        """Return the largest body radius of the kinds of agent [m]."""
        if self.others is None:
            return self.body_radius
        return max(self.body_radius, self.others.body_radius)


#: Speeds tried by a yielding agent: its walking speed times k / YIELD_SPEED_STEPS, k from
#: YIELD_SPEED_STEPS down to 0.
YIELD_SPEED_STEPS = 10

#: People who ignore the Husky: 0.3 m radius (0.25-0.35 m shoulder half-widths), 0.8-1.4 m/s
#: (adults' walking speeds), 1 m/s^2, neither stopping for the Husky nor yielding to it (they
#: walk into it when it stands in their way; a 0.1 m margin from walls).
PEDESTRIANS_IGNORING = WandererConfig(speed_range=(0.8, 1.4), max_turn_rate=3.0,
                                      clearance=0.4, husky_look_ahead=0.0,
                                      wanderer_look_ahead=0.3, body='cylinder', radius=0.3,
                                      polite=False, max_accel=1.0)
#: People as above who yield to the Husky by their speed: a velocity obstacle over 1 s with
#: 0.05 m to spare, walking on at half speed or more, else standing; they do not stop for a
#: Husky merely ahead, only for one they would meet within the second (chosen, not fitted to
#: data: a standing Husky in their way stops them 0.95-1.65 m from its centre).
PEDESTRIANS = dataclasses.replace(PEDESTRIANS_IGNORING, yield_horizon=1.0, yield_margin=0.05,
                                  yield_slowest=0.5)
#: P3-ATs and pedestrians, half and half (the P3-ATs' clearance grid for both).
MIXED = WandererConfig(others=PEDESTRIANS, others_share=0.5)
#: ``--agents`` presets: the wandering P3-ATs (default), pedestrians who yield, pedestrians
#: who ignore the Husky, and P3-ATs with yielding pedestrians.
AGENT_MODELS = {'p3at': WandererConfig(), 'pedestrians': PEDESTRIANS,
                'pedestrians-ignoring': PEDESTRIANS_IGNORING, 'mixed': MIXED}


class Wanderers:
    """
    The wandering robots' state and behaviour.

    Parameters
    ----------
    grid : ClearanceGrid
        Clear cells for a circle of ``config.clearance``, from the true map.
    count : int
        Number of wanderers, 0 or more.
    husky_xy : (float, float)
        The Husky's start position [m]; wanderers spawn ``config.spawn_distance`` away.
    rng : numpy.random.Generator
        Source of all randomness.
    config : WandererConfig
        Behaviour.
    robot_radius : float
        Radius of the circle around the robot's footprint [m] (the Husky's by default), which
        polite wanderers keep clear of.

    Attributes
    ----------
    positions : (count, 2) ndarray of float64
        Map-frame positions [m]; read-only for callers.
    yaws : (count,) ndarray of float64
        Headings [rad].
    speeds : (count,) ndarray of float64
        Walking speeds [m/s].
    goals_reached, replans : int
        Goals reached, and new goals picked because a wanderer was blocked or had no path.

    """

    radius = P3AT_RADIUS

    def __init__(self, grid, count, husky_xy, rng, config=WandererConfig(),
                 robot_radius=HUSKY_RADIUS):
        self.robot_radius = float(robot_radius)
        if isinstance(count, bool) or not isinstance(count, int) or count < 0:
            raise ValueError(f'count must be a non-negative integer, got {count!r}')
        self.radius = config.largest_radius
        self.grid = grid
        self.config = config
        self.rng = rng
        self.positions = np.zeros((count, 2), dtype=np.float64)
        self.yaws = np.zeros(count, dtype=np.float64)
        # Each agent's kind of agent (all `config` without a second kind).
        self._kinds = config.kinds(count)
        self.radii = [kind.body_radius for kind in self._kinds]
        if config.others is None:
            self.speeds = rng.uniform(*config.speed_range, count)
        else:
            unit = rng.uniform(0.0, 1.0, count)
            self.speeds = np.array([kind.speed_range[0] + u * (kind.speed_range[1]
                                                               - kind.speed_range[0])
                                    for kind, u in zip(self._kinds, unit)])
        self.goals_reached = 0
        self.replans = 0
        self._blocked = ~grid.clear
        # During a step the state lives in plain floats, much cheaper than numpy scalars; the
        # arrays are brought up to date at its end.
        self._xy = []
        self._yaw = []
        self._speeds = self.speeds.tolist()
        # The speed each walks at now, below its walking speed while it speeds up [m/s].
        self._speed_now = [0.0 if kind.max_accel > 0.0 else s
                           for kind, s in zip(self._kinds, self._speeds)]
        # A circle blocks while its centre is ahead by at most `reach` and beside the line of
        # travel by less than `side`: Husky first, then other wanderers [m], per agent.
        self._husky_reach = [kind.husky_look_ahead + self.robot_radius + r
                             for kind, r in zip(self._kinds, self.radii)]
        self._husky_side = [self.robot_radius + r + 0.1 for r in self.radii]
        # The Husky's position at the last step, for its velocity (None before the first).
        self._husky_last = None
        self._husky_velocity = (0.0, 0.0)
        self._paths = [[] for _ in range(count)]
        # Last waypoint reached, a clear cell (where a new path starts if need be).
        self._anchors = [None] * count
        # Whether the first leg of the path is the short move to the centre of the wanderer's
        # own cell, which needs no look-out.
        self._centring = [False] * count
        # Time stopped (or without a path), and how long to bear it before a new goal [s].
        self._stopped = [0.0] * count
        self._patience = [0.0] * count
        self._spawn(husky_xy)

    def _spawn(self, husky_xy):
        rr, cc = np.nonzero(self.grid.clear)
        labels = self.grid.labels[rr, cc]
        # Only components with room to wander (50 cells, or the largest one) are candidates.
        sizes = np.bincount(labels, minlength=1)
        roomy = (sizes[labels] >= 50) | (labels == int(np.argmax(sizes)))
        xs, ys = self.grid.geometry.cell_to_world(rr, cc)
        ok = roomy & (np.hypot(xs - husky_xy[0], ys - husky_xy[1]) >= self.config.spawn_distance)
        apart = 2.0 * self.radius + 0.5
        for i in range(len(self.yaws)):
            candidates = np.flatnonzero(ok)
            if len(candidates) == 0:
                raise ValueError(
                    f'no room to spawn wanderer {i + 1} of {len(self.yaws)}: the map has too '
                    'little clear space away from the Husky and the other wanderers')
            k = int(candidates[self.rng.integers(len(candidates))])
            self.positions[i] = xs[k], ys[k]
            self.yaws[i] = self.rng.uniform(-math.pi, math.pi)
            self._anchors[i] = (int(rr[k]), int(cc[k]))
            ok &= np.hypot(xs - xs[k], ys - ys[k]) >= apart

    def step(self, dt, husky_xy):
        """
        Advance every wanderer by one time step.

        Parameters
        ----------
        dt : float
            Time step [s].
        husky_xy : (float, float)
            The Husky's position [m].

        Returns
        -------
        moved : list of int
            Indices of the wanderers whose pose changed.

        """
        moved = []
        hx, hy = float(husky_xy[0]), float(husky_xy[1])
        if self._husky_last is not None:
            self._husky_velocity = ((hx - self._husky_last[0]) / dt,
                                    (hy - self._husky_last[1]) / dt)
        self._husky_last = (hx, hy)
        self._xy = self.positions.tolist()
        self._yaw = self.yaws.tolist()
        for i in range(len(self._yaw)):
            if not self._paths[i]:
                # Without a path (at a goal, or after a failed plan) wait out the patience.
                self._stopped[i] += dt
                if self._stopped[i] < self._patience[i] or \
                        not self._new_goal(i, husky_xy, None):
                    continue
            if self._advance(i, dt, husky_xy):
                moved.append(i)
        if self._yaw:
            self.positions[:] = self._xy
            self.yaws[:] = self._yaw
        return moved

    def forecast(self, times, dt, husky_xy_at):
        """
        Return where the wanderers will be, stepping a copy of them; this object is unchanged.

        The simulation is deterministic: a copy of the state and of the random generator
        steps exactly as the wanderers will, as long as the Husky is where ``husky_xy_at``
        says (they stop for it and plan around it).

        Parameters
        ----------
        times : (S,) array_like of float
            Non-decreasing times from now [s], ``>= 0``.
        dt : float
            The world's time step [s] (``1 / physics_rate``), positive.
        husky_xy_at : callable
            ``husky_xy_at(t)`` is the Husky's position ``(x, y)`` [m] at ``t`` seconds from
            now.

        Returns
        -------
        positions : (S, count, 2) ndarray of float64
            The positions at each time, rounded down to a whole number of steps [m].

        """
        times = np.asarray(times, dtype=np.float64).reshape(-1)
        if not (dt > 0.0 and math.isfinite(dt)):
            raise ValueError(f'dt must be positive and finite, got {dt!r}')
        if times.size and (times[0] < 0.0 or np.any(np.diff(times) < 0.0)):
            raise ValueError('times must be non-decreasing and >= 0')
        twin = self._twin()
        out = np.empty((times.size, len(self.yaws), 2))
        ticks = np.floor(times / dt + 1e-9).astype(np.int64)
        tick = 0
        for s, wanted in enumerate(ticks):
            while tick < wanted:
                twin.step(dt, husky_xy_at(tick * dt))
                tick += 1
            out[s] = twin.positions
        return out

    def _twin(self):
        """Return a copy that steps independently (the grids shared, read-only)."""
        twin = copy.copy(self)
        twin.rng = copy.deepcopy(self.rng)
        twin.positions = self.positions.copy()
        twin.yaws = self.yaws.copy()
        twin.speeds = self.speeds.copy()
        for name in ('_speeds', '_speed_now', '_anchors', '_centring', '_stopped', '_patience'):
            setattr(twin, name, list(getattr(self, name)))
        twin._paths = [list(path) for path in self._paths]
        twin._xy, twin._yaw = [], []
        return twin

    def _advance(self, i, dt, husky_xy):
        """Turn and move wanderer ``i`` along its path; return True when it moved."""
        x, y = self._xy[i]
        tx, ty = self._paths[i][0]
        dx, dy = tx - x, ty - y
        dist = math.hypot(dx, dy)
        if dist < 1e-9:
            self._reach_waypoint(i)
            return False
        yaw = self._yaw[i]
        kind = self._kinds[i]
        max_turn = kind.max_turn_rate * dt
        err = wrap_angle(math.atan2(dy, dx) - yaw)
        turn = min(max(err, -max_turn), max_turn)
        if (turn != 0.0 and kind.turn_guard and kind.polite and kind.body == 'p3at'
                and math.hypot(husky_xy[0] - x, husky_xy[1] - y)
                < self.robot_radius + P3AT_RADIUS + TURN_GUARD_GAP):
            # Its corners would sweep into the Husky: hold, as stopped for it.
            self._stopped[i] += dt
            if self._stopped[i] >= self._patience[i]:
                self._new_goal(i, husky_xy, (husky_xy[0], husky_xy[1], self.robot_radius))
            return False
        self._yaw[i] = wrap_angle(yaw + turn)
        if abs(err - turn) > kind.heading_tolerance:
            return turn != 0.0
        ux, uy = dx / dist, dy / dist
        blocker = None if self._centring[i] else self._blocker(i, ux, uy, husky_xy)
        speed = self._speeds[i]
        if blocker is None and kind.yield_horizon > 0.0 and not self._centring[i]:
            speed = self._yield_speed(i, ux, uy, speed, husky_xy)
            if speed <= 0.0:
                blocker = husky_xy[0], husky_xy[1], self.robot_radius
        accel = kind.max_accel
        if blocker is not None:
            self._stopped[i] += dt
            if accel > 0.0:
                self._speed_now[i] = 0.0
            if self._stopped[i] >= self._patience[i]:
                self._new_goal(i, husky_xy, blocker)
            return turn != 0.0
        self._stopped[i] = 0.0
        if accel > 0.0:
            speed = self._speed_now[i] = min(speed, self._speed_now[i] + accel * dt)
        step = min(speed * dt, dist)
        if step >= dist:
            self._xy[i] = [tx, ty]
            self._reach_waypoint(i)
        else:
            self._xy[i] = [x + step * ux, y + step * uy]
        return True

    def _blocker(self, i, ux, uy, husky_xy):
        """Return the circle ``(x, y, r)`` ahead that stops wanderer ``i``, or None."""
        x, y = self._xy[i]
        hx, hy = husky_xy
        rx, ry = hx - x, hy - y
        along = rx * ux + ry * uy
        kind = self._kinds[i]
        if (kind.polite and 0.0 < along <= self._husky_reach[i]
                and abs(rx * uy - ry * ux) < self._husky_side[i]):
            return hx, hy, self.robot_radius
        radii = self.radii
        r = radii[i]
        look = kind.wanderer_look_ahead
        for j, (ox, oy) in enumerate(self._xy):
            rx, ry = ox - x, oy - y
            along = rx * ux + ry * uy  # 0 for wanderer i itself
            if (0.0 < along <= look + r + radii[j] and abs(rx * uy - ry * ux) < r + radii[j] + 0.1
                    and j != i):
                return ox, oy, radii[j]
        return None

    def _yield_speed(self, i, ux, uy, speed, husky_xy):
        """
        Return the largest speed along ``(ux, uy)``, at most ``speed``, that yields.

        A speed yields when agent ``i`` moving at it and the Husky at its velocity keep their
        circles (plus ``yield_margin``) apart for ``yield_horizon`` seconds, or, when they
        overlap already, do not close in. 0 when none of the speeds tried (down to
        ``yield_slowest`` of ``speed``) does [m/s].
        """
        kind = self._kinds[i]
        x, y = self._xy[i]
        px, py = husky_xy[0] - x, husky_xy[1] - y  # the Husky, from the agent
        hvx, hvy = self._husky_velocity
        reach = self.radii[i] + self.robot_radius + kind.yield_margin
        tau = kind.yield_horizon
        if math.hypot(px, py) > reach + (math.hypot(hvx, hvy) + speed) * tau:
            return speed  # too far apart to meet within the horizon
        slowest = kind.yield_slowest * speed - 1e-12
        for k in range(YIELD_SPEED_STEPS, 0, -1):
            s = speed * k / YIELD_SPEED_STEPS
            if s < slowest:
                break
            if _keeps_apart(px, py, hvx - s * ux, hvy - s * uy, reach, tau):
                return s
        return 0.0

    def _reach_waypoint(self, i):
        tx, ty = self._paths[i].pop(0)
        self._anchors[i] = self.grid.cell_of(tx, ty)
        self._centring[i] = False
        if not self._paths[i]:
            self.goals_reached += 1

    def _new_goal(self, i, husky_xy, blocker):
        """
        Pick a random reachable goal for wanderer ``i`` and plan a path to it.

        When ``blocker`` (a circle ``(x, y, r)``) is given, the wanderer was stopped: the plan
        also avoids the Husky's circle and ``blocker``. Returns True when a path was found.

        The path starts at the centre of the clear cell the wanderer stands in: a move inside
        one clear cell is always safe. (Standing exactly on a corner of a diagonal step, the
        cell found may not be clear; the path then starts at the last waypoint reached, back
        along the segment the wanderer is on.)

        """
        cfg = self._kinds[i]
        self._stopped[i] = 0.0
        self._patience[i] = self.rng.uniform(*cfg.patience_range)
        anchor = self.grid.cell_of(*self._xy[i])
        own_cell = anchor is not None and bool(self.grid.clear[anchor])
        if not own_cell:
            anchor = self._anchors[i]
        blocked = self._blocked
        if blocker is not None:
            blocked = blocked.copy()
            for cx, cy, radius in ((husky_xy[0], husky_xy[1], self.robot_radius), blocker):
                block_disc(blocked, self.grid.geometry, cx, cy, radius + cfg.clearance)
            if cfg.yield_horizon > 0.0:
                # Its own cell stays open: a yielding agent may stand nearer the Husky than
                # the disc (it stops 0.95 m from the Husky's centre at the least) and must be
                # able to walk away. (P3-ATs keep the rule they were published with.)
                blocked[anchor] = False
        if blocker is not None and cfg.yield_horizon > 0.0:
            # A yielding agent stopped by the Husky turns back rather than wait for a way past
            # it: its goal is drawn among the cells it can reach around the Husky, so that a
            # corridor the two meet in is freed.
            blocked = blocked | ~_reachable(blocked, anchor)
        goal = self._pick_goal(anchor, blocked)
        path = None if goal is None else plan_path(self.grid.geometry, blocked, anchor, goal)
        if blocker is not None or path is None:
            self.replans += 1
        if path is None:
            self._paths[i] = []  # wait out the new patience, then try another goal
            return False
        self._paths[i] = [self.grid.centre(*cell) for cell in turning_points(path)]
        self._centring[i] = own_cell
        return True

    def _pick_goal(self, anchor, blocked):
        """
        Draw a goal cell in the anchor's component, preferably ``goal_distance_range`` away.

        The preferred cells all lie in the square window of half side ``hi`` around the
        anchor's centre, so only that window is searched; the draw is the same as over the whole
        grid (same candidates in the same row-major order, one ``rng.integers`` call). Only when
        the window holds no preferred cell does the whole grid come in, for the fallback: any
        other cell of the component.
        """
        lo, hi = self.config.goal_distance_range
        ax, ay = self.grid.centre(*anchor)
        rows, cols = self.grid.geometry.cell_window(ax - hi, ax + hi, ay - hi, ay + hi)
        goal = self._draw_goal(anchor, blocked, rows, cols, lambda dist: (dist >= lo) &
                               (dist <= hi))
        if goal is None:
            whole = slice(0, self.grid.clear.shape[0]), slice(0, self.grid.clear.shape[1])
            goal = self._draw_goal(anchor, blocked, *whole, lambda dist: dist > 0.0)
        return goal

    def _draw_goal(self, anchor, blocked, rows, cols, wanted):
        """Draw one cell of the anchor's component in a window where ``wanted(dist)``."""
        label = self.grid.labels[anchor]
        rr, cc = np.nonzero((self.grid.labels[rows, cols] == label) & ~blocked[rows, cols])
        rr += rows.start
        cc += cols.start
        xs, ys = self.grid.geometry.cell_to_world(rr, cc)
        ax, ay = self.grid.centre(*anchor)
        pool = np.flatnonzero(wanted(np.hypot(xs - ax, ys - ay)))
        if len(pool) == 0:
            return None
        k = int(pool[self.rng.integers(len(pool))])
        return int(rr[k]), int(cc[k])


def _keeps_apart(px, py, wx, wy, reach, horizon):
    """
    Tell whether ``p + w t`` stays at least ``reach`` from the origin for t in [0, horizon].

    ``p`` is the relative position [m] and ``w`` the relative velocity [m/s]; when
    ``|p| < reach`` already, whether the two do not close in (``p . w >= 0``).
    """
    closing = px * wx + py * wy
    if px * px + py * py < reach * reach:
        return closing >= 0.0
    ww = wx * wx + wy * wy
    if closing >= 0.0 or ww == 0.0:
        return True  # moving apart (or not at all): the distance only grows
    t = min(-closing / ww, horizon)
    return math.hypot(px + wx * t, py + wy * t) >= reach


def _reachable(blocked, start):
    """
    Return the cells 8-connected to ``start`` through unblocked cells, (H, W) bool.

    ``blocked`` is (H, W) bool; ``start`` a cell ``(row, col)`` (reachable even if blocked).
    """
    rows, cols = blocked.shape
    seen = np.zeros_like(blocked, dtype=bool)
    seen[start] = True
    queue = deque([start])
    while queue:
        r, c = queue.popleft()
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                nr, nc = r + dr, c + dc
                if 0 <= nr < rows and 0 <= nc < cols and not seen[nr, nc] \
                        and not blocked[nr, nc]:
                    seen[nr, nc] = True
                    queue.append((nr, nc))
    return seen
