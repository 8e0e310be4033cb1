"""
Wandering Pioneer 3-ATs: random reachable goals, A* on the ground truth, kinematic motion.

Each wanderer walks from one random goal to the next at its own speed. It plans with
`dpn_navigator.core.astar` (through `clear_paths.plan_path`) on a `ClearanceGrid` of the true
map (cells where a disc of the P3-AT's radius plus a margin fits anywhere) and drives its path
centre to centre: it turns in place until it faces the next waypoint, then moves along the
straight segment, so it never leaves clear cells and never touches a wall. It does not drive
into the Husky: while the Husky is in a corridor ahead of it (up to ``husky_look_ahead``
beyond the Husky's radius) it stops, and likewise for another wanderer close ahead. A
wanderer that stays stopped longer than its patience picks a new goal and plans around what
blocks it, so none is stuck for long.

With ``mutual_yield`` on, two wanderers that stop for each other (typically head-on in a
passage) do not both wait out their patience: the one with the higher index gives way at once.
It takes a new goal it can reach without passing the other and that lies off the other's
remaining path (``yield_path_margin`` away from it); the other keeps its path and starts its
patience afresh. A wanderer already giving way does not give way again (in a knot of three it
waits out its patience as without the option).

Everything here is plain Python + numpy, with no pybullet; the world copies the poses into
the physics engine. All randomness comes from the generator passed in, so a seed fixes the
wanderers' spawn points, speeds, goals and therefore trajectories.

"""

from dataclasses import dataclass
import math
from pathlib import Path

from dpn_navigator.core.pose2d import wrap_angle
import numpy as np

from .clear_paths import block_disc, plan_path, turning_points
from .free_space import label_components
from .husky import HUSKY_RADIUS

#: The Pioneer 3-AT model.
P3AT_URDF = Path(__file__).resolve().parent / 'urdf' / 'p3at.urdf'
#: Radius of the circle around a P3-AT's 0.508 m x 0.497 m footprint [m].
P3AT_RADIUS = 0.5 * math.hypot(0.508, 0.497)


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
    mutual_yield : bool
        When two wanderers stop for each other, the one with the higher index gives way at
        once (see the module's notes). Off by default: every seeded world then moves exactly
        as it did before the option existed.
    yield_path_margin : float
        Least distance from the goal of a wanderer giving way to the remaining path of the one
        it gives way to [m]; with ``mutual_yield`` only.

    Raises
    ------
    ValueError
        For a ``mutual_yield`` that is not a bool or a ``yield_path_margin`` that is not a
        finite number of 0 or more.

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
    mutual_yield: bool = False
    yield_path_margin: float = 1.0

    def __post_init__(self):
        if not isinstance(self.mutual_yield, bool):
            raise ValueError(f'mutual_yield must be True or False, got {self.mutual_yield!r}')
        margin = self.yield_path_margin
        if isinstance(margin, bool) or not isinstance(margin, (int, float)) or \
                not math.isfinite(margin) or margin < 0.0:
            raise ValueError(f'yield_path_margin must be a finite distance of 0 m or more, got '
                             f'{margin!r}')


def distance_to_polyline(xs, ys, points):
    """
    Distance from points to a polyline.

    Parameters
    ----------
    xs, ys : (K,) ndarray of float64
        The points [m].
    points : (S + 1, 2) ndarray of float64
        The polyline's vertices [m], one or more (a single vertex is a point).

    Returns
    -------
    distance : (K,) ndarray of float64
        Distance from each point to the nearest point of the polyline [m].

    Examples
    --------
    >>> distance_to_polyline(np.array([1.0, 3.0]), np.array([1.0, 0.0]),
    ...                      np.array([[0.0, 0.0], [2.0, 0.0]])).tolist()
    [1.0, 1.0]

    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if len(points) == 0:
        raise ValueError('the polyline needs one vertex or more')
    start = points[:-1] if len(points) > 1 else points
    end = points[1:] if len(points) > 1 else points
    ex, ey = (end - start).T                                  # (S,) segment vectors
    px = np.asarray(xs, dtype=np.float64)[:, np.newaxis] - start[:, 0]   # (K, S)
    py = np.asarray(ys, dtype=np.float64)[:, np.newaxis] - start[:, 1]
    length2 = ex * ex + ey * ey
    along = np.clip((px * ex + py * ey) / np.where(length2 > 0.0, length2, 1.0), 0.0, 1.0)
    return np.hypot(px - along * ex, py - along * ey).min(axis=1, initial=np.inf)


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
    yields : int
        Times a wanderer gave way to another (``WandererConfig.mutual_yield``); counted in
        ``replans`` too.

    """

    radius = P3AT_RADIUS

    def __init__(self, grid, count, husky_xy, rng, config=WandererConfig()):
        if isinstance(count, bool) or not isinstance(count, int) or count < 0:
            raise ValueError(f'count must be a non-negative integer, got {count!r}')
        self.grid = grid
        self.config = config
        self.rng = rng
        self.positions = np.zeros((count, 2), dtype=np.float64)
        self.yaws = np.zeros(count, dtype=np.float64)
        self.speeds = rng.uniform(*config.speed_range, count)
        self.goals_reached = 0
        self.replans = 0
        self.yields = 0
        self._blocked = ~grid.clear
        # During a step the state lives in plain floats, much cheaper than numpy scalars; the
        # arrays are brought up to date at its end.
        self._xy = []
        self._yaw = []
        self._speeds = self.speeds.tolist()
        # A circle blocks while its centre is ahead by at most `reach` and beside the line of
        # travel by less than `side`: Husky first, then other wanderers [m].
        r = self.radius
        self._husky_reach = config.husky_look_ahead + HUSKY_RADIUS + r
        self._husky_side = HUSKY_RADIUS + r + 0.1
        self._wanderer_reach = config.wanderer_look_ahead + r + r
        self._wanderer_side = r + r + 0.1
        self._paths = [[] for _ in range(count)]
        # Last waypoint reached, a clear cell (where a new path starts if need be).
        self._anchors = [None] * count
        # Whether the first leg of the path is the short move to the centre of the wanderer's
        # own cell, which needs no look-out.
        self._centring = [False] * count
        # Time stopped (or without a path), and how long to bear it before a new goal [s].
        self._stopped = [0.0] * count
        self._patience = [0.0] * count
        # The wanderer each one stopped for at its last look-out (-1: none or the Husky), and
        # the one each is giving way to (-1: none); with `mutual_yield` only.
        self._stopped_for = [-1] * count
        self._giving_way_to = [-1] * count
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
        max_turn = self.config.max_turn_rate * dt
        err = wrap_angle(math.atan2(dy, dx) - yaw)
        turn = min(max(err, -max_turn), max_turn)
        self._yaw[i] = wrap_angle(yaw + turn)
        if abs(err - turn) > self.config.heading_tolerance:
            return turn != 0.0
        ux, uy = dx / dist, dy / dist
        blocker = None if self._centring[i] else self._blocker(i, ux, uy, husky_xy)
        if blocker is not None:
            if self.config.mutual_yield and self._yield_to(i, blocker, husky_xy):
                return turn != 0.0
            self._stopped[i] += dt
            if self._stopped[i] >= self._patience[i]:
                self._new_goal(i, husky_xy, blocker)
            return turn != 0.0
        self._stopped[i] = 0.0
        self._stopped_for[i] = -1
        step = min(self._speeds[i] * dt, dist)
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
        if 0.0 < along <= self._husky_reach and abs(rx * uy - ry * ux) < self._husky_side:
            return hx, hy, HUSKY_RADIUS
        reach, side = self._wanderer_reach, self._wanderer_side
        for j, (ox, oy) in enumerate(self._xy):
            rx, ry = ox - x, oy - y
            along = rx * ux + ry * uy  # 0 for wanderer i itself
            if 0.0 < along <= reach and abs(rx * uy - ry * ux) < side and j != i:
                return ox, oy, self.radius
        return None

    def _yield_to(self, i, blocker, husky_xy):
        """
        Apply `mutual_yield` to wanderer ``i`` stopped for ``blocker``; True when it gave way.

        Wanderer ``i`` gives way when ``blocker`` is wanderer ``j`` with a lower index that
        stopped for ``i`` at its own last look-out (``j`` itself gives way to ``i`` on its own
        turn when the indices are the other way round), unless ``i`` is already giving way:
        then it waits out its patience as without the option, so that three or more in a knot
        cannot pass the turn round for ever. ``j`` starts its patience afresh.
        """
        j = self._wanderer_at(blocker)
        self._stopped_for[i] = j
        if j < 0:
            return False
        if self._stopped_for[j] != i or j > i or self._giving_way_to[i] >= 0:
            return False
        if not self._give_way(i, j, husky_xy):
            return False
        self._stopped[j] = 0.0
        self._stopped_for[i] = -1
        return True

    def _wanderer_at(self, blocker):
        """Return the index of the wanderer whose circle is ``blocker``, or -1 (the Husky)."""
        if blocker[2] != self.radius:
            return -1
        for j, (ox, oy) in enumerate(self._xy):
            if ox == blocker[0] and oy == blocker[1]:
                return j
        return -1

    def _give_way(self, i, j, husky_xy):
        """
        Send wanderer ``i`` to a goal off wanderer ``j``'s way; return True when it has a path.

        The goal lies in the window of `_pick_goal`, in the part of it ``i`` reaches without
        passing ``j`` or the Husky (their circles blocked as for a stopped wanderer), and at
        least ``yield_path_margin`` from ``j``'s remaining path; preferably
        ``goal_distance_range`` away. When there is none, nothing changes.
        """
        cfg = self.config
        anchor = self.grid.cell_of(*self._xy[i])
        own_cell = anchor is not None and bool(self.grid.clear[anchor])
        if not own_cell:
            anchor = self._anchors[i]
        blocked = self._blocked.copy()
        geometry = self.grid.geometry
        for cx, cy, radius in ((husky_xy[0], husky_xy[1], HUSKY_RADIUS),
                               (*self._xy[j], self.radius)):
            block_disc(blocked, geometry, cx, cy, radius + cfg.clearance)
        if blocked[anchor]:
            return False
        lo, hi = cfg.goal_distance_range
        ax, ay = self.grid.centre(*anchor)
        rows, cols = geometry.cell_window(ax - hi, ax + hi, ay - hi, ay + hi)
        components, _ = label_components(~blocked[rows, cols])
        reachable = components == components[anchor[0] - rows.start, anchor[1] - cols.start]
        rr, cc = np.nonzero(reachable)
        rr += rows.start
        cc += cols.start
        xs, ys = geometry.cell_to_world(rr, cc)
        path_j = np.array([self._xy[j]] + self._paths[j], dtype=np.float64)
        off_way = distance_to_polyline(xs, ys, path_j) >= cfg.yield_path_margin
        rr, cc, xs, ys = rr[off_way], cc[off_way], xs[off_way], ys[off_way]
        dist = np.hypot(xs - ax, ys - ay)
        pool = np.flatnonzero((dist >= lo) & (dist <= hi))
        if len(pool) == 0:
            pool = np.flatnonzero(dist > 0.0)
        if len(pool) == 0:
            return False
        k = int(pool[self.rng.integers(len(pool))])
        path = plan_path(geometry, blocked, anchor, (int(rr[k]), int(cc[k])))
        if path is None:
            return False
        self._paths[i] = [self.grid.centre(*cell) for cell in turning_points(path)]
        self._centring[i] = own_cell
        self._stopped[i] = 0.0
        self._patience[i] = self.rng.uniform(*cfg.patience_range)
        self._giving_way_to[i] = j
        self.replans += 1
        self.yields += 1
        return True

    def _reach_waypoint(self, i):
        tx, ty = self._paths[i].pop(0)
        self._anchors[i] = self.grid.cell_of(tx, ty)
        self._centring[i] = False
        if not self._paths[i]:
            self.goals_reached += 1
            self._stopped_for[i] = -1
            self._giving_way_to[i] = -1

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
        cfg = self.config
        self._stopped[i] = 0.0
        self._stopped_for[i] = -1
        self._giving_way_to[i] = -1
        self._patience[i] = self.rng.uniform(*cfg.patience_range)
        anchor = self.grid.cell_of(*self._xy[i])
        own_cell = anchor is not None and bool(self.grid.clear[anchor])
        if not own_cell:
            anchor = self._anchors[i]
        blocked = self._blocked
        if blocker is not None:
            blocked = blocked.copy()
            for cx, cy, radius in ((husky_xy[0], husky_xy[1], HUSKY_RADIUS), blocker):
                block_disc(blocked, self.grid.geometry, cx, cy, radius + cfg.clearance)
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
