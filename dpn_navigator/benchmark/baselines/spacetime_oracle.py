"""
The space-time oracle: the true walls, the agents' true future, and a plan in space and time.

The benchmark's upper reference. It knows the walls (an ``OracleGrid`` with no agents on it)
and, through a forecast callable the episode hands it (``World.forecast_wanderers``: a copy of
the deterministic simulation stepped ahead), where every agent will be over the next
`SpaceTimeConfig.horizon` seconds. Every `SpaceTimeConfig.replan_period` it plans with
time-expanded A* (``spacetime_search``) on its grid: waiting is a move, and a cell is blocked
at a time step when an agent's centre will then be within ``R + r`` of the cell's centre (the
bare oracle's inflation). The robot's limits enter as the time a move takes at the follower's
top speed, rounded up to whole steps (a turn in place is not counted: the replanning absorbs
it, and `SpaceTimeConfig.margin` steps of slack around every move absorb the delay).

The agents react to the robot (P3-ATs stop for it, all plan around it when stopped), so their
future depends on the robot's: the forecast places the robot on its last plan (still, before
the first), and the next plan corrects it. The plan is then followed with the navigator's own
path follower: between two waits it follows the plan's cells; during a wait it turns toward
the next cell in place and holds.

The plan keeps cell *centres* ``R + r`` from the agents, but the robot's centre strays from its
cells' centres by up to half a cell's diagonal while it drives, and a turn in place sweeps its
corners round the disc of its circumscribed radius. So every command is checked against where
the agents are now (`SpaceTimeConfig.body_guard`): a turn in place with an agent's body within
that disc, or a drive that brings the robot's box nearer than ``body_margin`` to an agent's
body (``exact_swings``: the box moved without turning; its corners' swing keeps
``turn_margin``; ``close_drives``: a body already within ``body_margin`` keeps ``turn_margin``),
nearer than it is now, is not made: the robot holds (the next plan, at most ``replan_period``
later, takes the agents' new places), or, when the held command is a turn of more than a quarter
turn toward the plan, backs along the plan if that drive passes (``reverse_when_held``). A leg
that ends in a wait is driven to within ``wait_tolerance`` of the wait's cell, where the
forecast places the robot (``exact_waits``).

"""

from dataclasses import dataclass, replace
import math

import numpy as np

from .spacetime_search import spacetime_plan, static_time_to_goal
from ...core.cell_label import blocked_mask
from ...core.control.path_follower import follow_path, STOP, VelocityCommand
from ...core.navigator import Navigator, NavigatorOutput, NavigatorStatus, ReplanCause


#: The body guard tests a turn in place at every this much of it [rad] (a 0.6 m corner moves
#: 3 cm).
TURN_STEP = 0.05


@dataclass(frozen=True)
class SpaceTimeConfig:
    """
    The space-time oracle's planning.

    Attributes
    ----------
    horizon : float
        How far ahead the agents' true positions are known [s].
    step : float
        The plan's time step [s].
    replan_period : float
        Time between two plans [s].
    margin : int
        Steps of slack: a cell must be free this many steps before and after the robot is in
        it.
    max_expansions : int
        The search's bound on expanded states per plan.
    clearance : float
        Added to ``R + r`` around every agent [m] (the robot's centre strays from its cell's
        centre while it drives the plan); 0.25 was tried against pedestrians and did not help
        (docs/benchmark.md).
    body_guard : bool
        Check each command against the agents' bodies now (module docstring); False: follow
        the plan as it is (the oracle before 27 November, session 13).
    body_margin : float
        Gap the body guard keeps between the robot's box and an agent's body [m].
    guard_lookahead : float
        A drive is checked at where it brings the robot in this long [s].
    exact_turns : bool
        The body guard tests a turn in place by turning the robot's box through it, every
        `TURN_STEP`, against the agents' bodies: it is held when the box comes within
        ``turn_margin`` of an agent's body, nearer than it is now (a turn in place moves no
        centre, so it needs less margin than a drive); False: it refuses every turn in place
        while an agent is within the box's circumscribed circle plus ``body_margin`` (before
        27 November, session 14). That circle held the robot from turning away from a P3-AT
        at its side, which had stopped for it: both stood for the rest of the episode
        (held-out seed 1, back_and_forth 0/3/1 for 183 s, apartment 0/9/1).
    turn_margin : float
        Gap a turn in place keeps from an agent's body with ``exact_turns`` [m].
    exact_swings : bool
        The body guard holds a drive when it brings the box, moved along the drive without
        turning, within ``body_margin`` of an agent's body, or when the box, moved and turned,
        comes within ``turn_margin`` of it, nearer than it is now: the swing of the box's
        corners as it turns needs the margin of a turn in place, not that of a drive. False:
        the box moved and turned is held to ``body_margin`` (before 27 November, session 15).
        That held the robot 0.58 m from its goal while its rear corner would have swung 4 cm
        nearer a P3-AT behind it, which could not turn away from the Husky either: both stood
        for 142 s (held-out seed 1, crossroads 0/2/0).
    close_drives : bool
        A drive that starts with an agent's body already within ``body_margin`` of the box is
        held only when it brings the box within ``turn_margin`` of that body, nearer than it is
        now (the margin of a turn in place). False: it is held by any approach, however small
        (before 28 November, session 16). That held the robot 0.099 m from a P3-AT that had
        stopped for it, its plan passing the P3-AT 1 mm nearer: both stood to the time limit
        (held-out seed 1, l_corridor 1/4/1).
    reverse_when_held : bool
        When the body guard holds a turn in place of more than a quarter turn toward the plan,
        the robot backs along the plan instead: its path follower steers the robot turned
        round, the speed negated, and that drive passes the body guard like any other. False:
        it holds (before 28 November, session 16). The swing of the box's corners cannot pass
        a P3-AT beside it that has stopped for the Husky, and the P3-AT does not move while
        the Husky is there: both stood to the time limit (held-out seed 1, l_corridor 0/8/0,
        the plan leading back past the P3-AT).
    exact_waits : bool
        A leg of the plan that ends in a wait is driven until the robot is within
        ``wait_tolerance`` of the wait's cell centre. False: it ends inside the follower's goal
        tolerance, 0.3 m (before 28 November, session 16). The forecast places the robot at
        the cell's centre: a robot that stopped 0.29 m short of it stood where a P3-AT would
        not pass, while the forecast, with the robot at the centre, had the P3-AT pass; every
        plan waited for it, to the time limit (held-out seed 1, l_corridor 0/8/1).
    wait_tolerance : float
        [m], with ``exact_waits``.
    still_start : bool
        The plan's first entries in the robot's own cell (a wait where it stands) keep its pose,
        not the cell's centre, so that the forecast of the next plan places the robot where it
        stands. False: only the first entry (before 28 November, session 16). A robot standing
        0.1 m from its cell's centre stood where a P3-AT stopped for it, while the forecast,
        with the robot at the centre, had the P3-AT pass; every plan waited for it, to the end
        (held-out seed 1, maze 0/2/0, 0/7/0, l_corridor 2/7/1, narrow_passages 2/8/0).

    """

    horizon: float = 8.0
    step: float = 0.25
    replan_period: float = 1.0
    margin: int = 1
    max_expansions: int = 60_000
    clearance: float = 0.0
    body_guard: bool = True
    body_margin: float = 0.1
    guard_lookahead: float = 0.3
    exact_turns: bool = True
    turn_margin: float = 0.02
    exact_swings: bool = True
    close_drives: bool = True
    reverse_when_held: bool = True
    exact_waits: bool = True
    wait_tolerance: float = 0.1
    still_start: bool = True

    def __post_init__(self):
        for name in ('horizon', 'step', 'replan_period'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be positive and finite, got {value!r}')
        if self.horizon < self.step:
            raise ValueError('horizon must be at least one step')
        for name in ('clearance', 'body_margin', 'guard_lookahead', 'turn_margin',
                     'wait_tolerance'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if not self.wait_tolerance > 0.0:
            raise ValueError(f'wait_tolerance must be positive, got {self.wait_tolerance!r}')
        if self.margin < 0 or self.max_expansions < 1:
            raise ValueError('margin must be >= 0 and max_expansions >= 1')


class SpaceTimeOracle(Navigator):
    """
    A navigator that plans in space and time on the true walls and the agents' true future.

    Parameters
    ----------
    config : NavigatorConfig
    grid : OracleGrid
        The true walls (its agents are never set).
    forecast : callable
        ``forecast(times, husky_xy_at)``: the agents' positions ``(S, K, 2)`` [m] at
        ``times`` [s from now], the robot at ``husky_xy_at(t)`` (``World.forecast_wanderers``).
    reach : float
        ``R + r`` [m]: a cell is blocked while an agent's centre is this close to its centre.
    planning : SpaceTimeConfig, optional

    Attributes
    ----------
    plans : int
        Space-time plans made since the goal was set.
    waits : int
        Decisions taken while the plan waits.

    """

    def __init__(self, config, grid, forecast, reach, planning=None):
        super().__init__(config, grid)
        self.turn_sweep = None            # the walls are known: no turn meets an unseen one
        self.planning = planning if planning is not None else SpaceTimeConfig()
        self._forecast = forecast
        self._reach = float(reach) + self.planning.clearance
        # The agents' body radius R (``reach`` is R + r) and the robot's half length and width.
        self._agent_radius = max(0.0, float(reach) - config.safety_radius)
        self._half_box = (0.5 * config.robot_length, 0.5 * config.robot_width)
        step = self.planning.step
        speed = config.follower.max_linear_speed
        self._straight = max(1, math.ceil(config.resolution / (speed * step) - 1e-9))
        self._diagonal = max(1, math.ceil(config.resolution * math.sqrt(2.0) / (speed * step)
                                          - 1e-9))
        self._steps = max(1, int(round(self.planning.horizon / step)))
        # The follower for a leg that ends in a wait.
        follower = config.follower
        self._to_wait = follower
        if self.planning.exact_waits:
            margin = follower.goal_tolerance - self.planning.wait_tolerance
            self._to_wait = replace(follower, goal_approach_margin=max(
                margin, follower.goal_approach_margin))
        self._walls = blocked_mask(grid.labels)
        self._to_go = None
        self._schedule = None        # (times [s], xy (N, 2) [m]) of the plan being followed
        self._next_plan = -math.inf
        self.plans = 0
        self.waits = 0

    def set_goal(self, x, y):
        """Set the goal [m]; the next step plans (see ``Navigator.set_goal``)."""
        super().set_goal(x, y)
        goal = tuple(int(v) for v in self.grid.geometry.world_to_cell(x, y))
        self._to_go = static_time_to_goal(self._walls, goal, self._straight, self._diagonal)
        self._schedule = None
        self._next_plan = -math.inf
        self.plans = 0
        self.waits = 0

    def _decide(self, stamp, pose, replan_flag):
        if self.goal is None or self.status is NavigatorStatus.GOAL_REACHED:
            return NavigatorOutput(STOP, self.status, self.reason)
        if math.hypot(self.goal[0] - pose[0], self.goal[1] - pose[1]) <= \
                self.config.follower.goal_tolerance:
            self.status = NavigatorStatus.GOAL_REACHED
            self.reason = 'inside the goal tolerance'
            return NavigatorOutput(STOP, self.status, self.reason)
        replanned = False
        if stamp >= self._next_plan:
            self._plan_in_time(stamp, pose)
            self._next_plan = stamp + self.planning.replan_period
            replanned = True
        cause = ReplanCause.OTHER if replanned else ReplanCause.NONE
        if self._schedule is None:
            return NavigatorOutput(STOP, self.status, self.reason, replanned, cause)
        command = self._command(stamp, pose)
        if self.planning.body_guard and command is not STOP and self._held(pose, command):
            back = STOP
            if self.planning.reverse_when_held and command.linear == 0.0 and \
                    abs(command.turn) > 0.5 * math.pi:
                back = self._command(stamp, pose, backwards=True)
                if back is not STOP and self._held(pose, back):
                    back = STOP
            if back is STOP:
                self.waits += 1
            command = back
        return NavigatorOutput(command, self.status, self.reason, replanned, cause)

    def _held(self, pose, command):
        """Tell whether ``command`` would bring the robot's body onto an agent's."""
        agents = np.asarray(self._forecast(np.zeros(1), lambda t: (pose[0], pose[1])),
                            dtype=np.float64)[0]
        if agents.shape[0] == 0:
            return False
        margin = self._agent_radius + self.planning.body_margin
        if command.linear == 0.0:
            if command.angular == 0.0:
                return False
            if self.planning.exact_turns:
                # The box at every TURN_STEP of the turn: held when it comes within
                # ``turn_margin`` of an agent's body, nearer than it is now.
                angle = command.turn if command.turn != 0.0 else \
                    command.angular * self.planning.guard_lookahead
                near = self._agent_radius + self.planning.turn_margin
                now = _box_distance(pose, self._half_box, agents)
                steps = max(1, math.ceil(abs(angle) / TURN_STEP))
                blocked = False
                for yaw in pose[2] + np.linspace(angle / steps, angle, steps):
                    then = _box_distance((pose[0], pose[1], yaw), self._half_box, agents)
                    if np.any((then < near) & (then < now)):
                        blocked = True
                        break
            else:
                # A turn in place sweeps the disc of the circumscribed radius.
                sweep = math.hypot(*self._half_box) + margin
                blocked = bool((np.hypot(agents[:, 0] - pose[0],
                                         agents[:, 1] - pose[1]) < sweep).any())
            return blocked
        now = _box_distance(pose, self._half_box, agents)
        travel = command.linear * self.planning.guard_lookahead
        yaw = pose[2] + 0.5 * command.angular * self.planning.guard_lookahead
        ahead = (pose[0] + travel * math.cos(yaw), pose[1] + travel * math.sin(yaw),
                 pose[2] + command.angular * self.planning.guard_lookahead)
        then = _box_distance(ahead, self._half_box, agents)
        if self.planning.exact_swings:
            moved = _box_distance((ahead[0], ahead[1], pose[2]), self._half_box, agents)
            near = self._agent_radius + self.planning.turn_margin
            # With close_drives, a body already within the margin is held to turn_margin.
            limit = np.where(now < margin, near, margin) if self.planning.close_drives \
                else margin
            blocked = np.any(((moved < limit) & (moved < now)) | ((then < near) & (then < now)))
        else:
            blocked = np.any((then < margin) & (then < now))
        return bool(blocked)

    def _plan_in_time(self, stamp, pose):
        """Forecast the agents, plan in space and time, keep the schedule."""
        geometry = self.grid.geometry
        start = tuple(int(v) for v in geometry.world_to_cell(pose[0], pose[1]))
        goal = tuple(int(v) for v in geometry.world_to_cell(*self.goal))
        self.replans += 1
        self.plans += 1
        if not geometry.contains_cell(*start):
            self._schedule = None
            self._no_path('the robot is outside the map')
            return
        step = self.planning.step
        times = np.arange(self._steps + 1) * step
        previous = self._schedule

        def husky_xy_at(t):
            if previous is None:
                return pose[0], pose[1]
            when, xy = previous
            absolute = stamp + t
            if absolute <= stamp:
                return pose[0], pose[1]
            return (float(np.interp(absolute, when, xy[:, 0])),
                    float(np.interp(absolute, when, xy[:, 1])))

        agents = np.asarray(self._forecast(times, husky_xy_at), dtype=np.float64)
        blocked = self._blocked_over_time(agents)
        plan, _ = spacetime_plan(self._walls, blocked, start, goal, self._to_go,
                                 self._straight, self._diagonal, self.planning.margin,
                                 self.planning.max_expansions)
        if plan is None:
            self._schedule = None
            self._no_path('every plan meets an agent or a wall within the horizon')
            return
        cells = np.array([(r, c) for r, c, _ in plan], dtype=np.int64)
        xs, ys = geometry.cell_to_world(cells[:, 0], cells[:, 1])
        xy = np.column_stack((xs, ys)).astype(np.float64)
        xy[0] = pose[0], pose[1]
        if self.planning.still_start:
            moved = np.flatnonzero(np.any(cells != cells[0], axis=1))
            xy[:moved[0] if moved.size else len(xy)] = pose[0], pose[1]
        if tuple(cells[-1]) == goal:
            xy[-1] = self.goal
        when = stamp + np.array([k for _, _, k in plan], dtype=np.float64) * step
        self._schedule = (when, xy)
        self.path = cells
        self._path_xy = xy
        self.status = NavigatorStatus.ACTIVE
        self.reason = ''

    def _blocked_over_time(self, agents):
        """Return the cells within ``reach`` of an agent at each step, (T + 1, H, W) bool."""
        geometry = self.grid.geometry
        steps, count = agents.shape[:2]
        blocked = np.zeros((steps,) + geometry.shape, dtype=bool)
        if count == 0:
            return blocked
        reach = self._reach
        # Every (step, agent) against the cells of a square stencil around the agent's cell.
        span = int(math.ceil(reach / geometry.resolution)) + 1
        offsets = np.arange(-span, span + 1)
        d_row, d_col = (v.ravel() for v in np.meshgrid(offsets, offsets, indexing='ij'))
        points = agents.reshape(-1, 2)
        row0, col0 = geometry.world_to_cell(points[:, 0], points[:, 1])
        rows = row0[:, None] + d_row[None, :]
        cols = col0[:, None] + d_col[None, :]
        x_centres, y_centres = geometry.cell_to_world(rows, cols)
        near = np.hypot(x_centres - points[:, 0, None], y_centres - points[:, 1, None]) <= reach
        near &= geometry.contains_cell(rows, cols)
        layer = np.repeat(np.arange(steps), count)[:, None] + np.zeros_like(rows)
        blocked[layer[near], rows[near], cols[near]] = True
        return blocked

    def _command(self, stamp, pose, backwards=False):
        """
        Follow the schedule: drive between waits, hold (turned to the next cell) in one.

        ``backwards``: drive the leg in reverse (the follower steers the robot turned round, the
        speed negated); STOP in a wait or when the robot, turned round, would turn in place.
        """
        when, xy = self._schedule
        i = int(np.searchsorted(when, stamp, side='right')) - 1
        i = min(max(i, 0), len(when) - 1)
        same = np.all(np.isclose(xy[1:], xy[:-1]), axis=1)      # entry j waits to j + 1
        config = self.config.follower
        if i < len(when) - 1 and same[i]:
            if backwards:
                return STOP
            self.waits += 1
            anchor = xy[i]
            if math.hypot(anchor[0] - pose[0], anchor[1] - pose[1]) > 0.25:
                return _without_goal(follow_path(pose, xy[i:i + 1], config))
            ahead = np.flatnonzero(~same[i:])
            if ahead.size == 0:
                return STOP
            target = xy[i + ahead[0] + 1]
            turn = follow_path(pose, target[None], config)
            return VelocityCommand(0.0, turn.angular, turn=turn.turn)
        last = len(xy) - 1
        waits_ahead = np.flatnonzero(same[i + 1:])
        if waits_ahead.size:
            last = i + 1 + int(waits_ahead[0])
            config = self._to_wait
        leg = xy[i + 1:last + 1] if last > i else xy[-1:]
        if not backwards:
            return _without_goal(follow_path(pose, leg, config))
        turned = _without_goal(follow_path((pose[0], pose[1], pose[2] + math.pi), leg, config))
        if turned.linear <= 0.0:
            return STOP
        return VelocityCommand(-turned.linear, turned.angular)


def _box_distance(pose, half_box, points):
    """
    Return the distance from each point to the robot's box at ``pose``, 0 inside it.

    Parameters
    ----------
    pose : (float, float, float)
        The robot's centre and heading [m, m, rad].
    half_box : (float, float)
        Half its length and half its width [m].
    points : (K, 2) ndarray of float64
        [m]

    Returns
    -------
    (K,) ndarray of float64 [m]

    """
    dx, dy = points[:, 0] - pose[0], points[:, 1] - pose[1]
    c, s = math.cos(pose[2]), math.sin(pose[2])
    along = np.abs(c * dx + s * dy) - half_box[0]
    across = np.abs(-s * dx + c * dy) - half_box[1]
    return np.hypot(np.maximum(along, 0.0), np.maximum(across, 0.0))


def _without_goal(command):
    """Return a command that holds where a leg of the plan ends (its 'goal' is not the goal)."""
    return STOP if command.goal_reached else command
