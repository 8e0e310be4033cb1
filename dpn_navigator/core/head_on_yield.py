"""
Head-on yield: back off to a passing place when a moving object comes head-on in a corridor.

In a corridor narrower than two robots, a wandering robot that comes the other way closes the
only route, and the robot closes it for the wanderer in turn. Neither planning nor waiting
opens it; one of the two must make room. This module decides when and where the robot does,
on the navigator's map and its motion tracks (``motion_tracks``), with no ROS:

- **Trigger** (`HeadOnYield.encounter`): a followed object, seen within ``SEEN_WITHIN``, that
  concerns the robot (within ``side_clearance`` of its path ahead, or anywhere while it has no
  path) is at most ``trigger_distance`` away along the *route* between the two over known free
  cells, moves towards the robot along it at ``approach_speed`` or more (its velocity from its
  track over at least ``VELOCITY_WINDOW``), and the route runs somewhere through free space
  narrower than ``corridor_width``, wall to wall (``passing_places.corridor_widths``).
- **Passing place** (``passing_places.passing_place``): the known-free cell nearest to the
  robot by a route over known-free cells no longer than ``search_distance``, whose centre lies
  at least ``side_clearance`` from the *corridor line*: the robot's trail behind it (continued
  straight back where the trail is short) and the route to the object. A place beside the
  route must lie in the first half of the way to the object, so that the robot gets there
  first.
- **Yield** (`HeadOnYield.step`): drive there, turn to face the corridor line, watch; leave
  when, after ``WATCH_TIME``, no followed object stands within ``side_clearance`` of the
  junction (the line's point nearest to the place) or comes towards it along the route
  beyond it; or ``wait_max`` after the trigger; or when no passing place can be reached any
  more. The navigator then plans to its goal again.

"""

from dataclasses import dataclass
import math

import numpy as np

from .astar_search import astar
from .cell_label import CellLabel
from .passing_places import corridor_widths, nearest_points, passing_place
from .path_follower import follow_path, STOP, VelocityCommand
from .pose2d import wrap_angle

#: A track counts as live when a scan segment continued it this recently [s].
SEEN_WITHIN = 0.5
#: An object's velocity is estimated over at least this long of its track [s].
VELOCITY_WINDOW = 0.5
#: Track positions older than this are dropped from the velocity estimate [s].
VELOCITY_HISTORY = 1.5
#: At the passing place, watch at least this long before leaving [s].
WATCH_TIME = 1.0
#: At the passing place, the robot faces the corridor line within this angle [rad].
FACE_TOLERANCE = 0.3
#: After an encounter with no passing place, look for one again at most this often [s].
RETRY_PERIOD = 1.0


@dataclass(frozen=True)
class YieldConfig:
    """
    When and where the robot yields; ``corridor_width`` 0 turns the state off.

    Attributes
    ----------
    corridor_width : float
        Yield only where the path to the object runs through free space narrower than this,
        wall to wall, as estimated on the grid (`corridor_widths`) [m]; 0: never.
    trigger_distance : float
        Yield to objects at most this far ahead along the path [m].
    side_clearance : float
        An object this close to the path is on it; a passing place lies at least this far
        from the corridor line; the corridor is clear when no object is this close to the
        line ahead [m].
    search_distance : float
        Longest route to a passing place, and how far back the corridor line reaches [m].
    wait_max : float
        Leave the state at the latest this long after the trigger [s].
    approach_speed : float
        Least speed towards the robot, along the path, of an object yielded to [m/s].

    """

    corridor_width: float = 0.0
    trigger_distance: float = 8.0
    side_clearance: float = 1.5
    search_distance: float = 12.0
    wait_max: float = 30.0
    approach_speed: float = 0.1

    def __post_init__(self):
        for name in ('corridor_width', 'trigger_distance', 'side_clearance', 'search_distance',
                     'wait_max', 'approach_speed'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'yield_{name} must be finite and >= 0, got {value!r}')
        if self.enabled:
            for name in ('trigger_distance', 'side_clearance', 'search_distance', 'wait_max'):
                if getattr(self, name) == 0.0:
                    raise ValueError(f'yield_{name} must be positive when the yield state is '
                                     'on (yield_corridor_width > 0)')

    @property
    def enabled(self):
        """Tell whether the state is on."""
        return self.corridor_width > 0.0


@dataclass(frozen=True)
class Encounter:
    """
    A moving object coming head-on in a narrow corridor.

    Attributes
    ----------
    track_id : int
        Its track's number (``MotionTracks.ids``).
    position, velocity : (float, float)
        Where it is [m] and how it moves [m/s], map frame.
    distance : float
        How far it is along the route [m].
    width : float
        The narrowest width of the corridor along the route [m].
    line_xy : (M, 2) ndarray of float64
        The corridor line [m]: the trail behind the robot, then the route.
    behind : int
        How many of the line's points are the trail behind the robot.
    reachable : (M,) ndarray of bool
        The line points beside which a passing place may lie: all but those of the route
        beyond half the way to the object.
    route_xy : (K, 2) ndarray of float64
        The route from the robot to the object over known free cells [m]: what must be clear
        of objects to leave the passing place.

    """

    track_id: int
    position: tuple
    velocity: tuple
    distance: float
    width: float
    line_xy: np.ndarray
    behind: int
    reachable: np.ndarray
    route_xy: np.ndarray


@dataclass(frozen=True)
class YieldStep:
    """
    One step of the yield state.

    Attributes
    ----------
    command : VelocityCommand
    route : (K, 2) ndarray of int64 or None
        A new route to a passing place, when this step planned one.
    done : bool
        The state is over: the navigator plans to its goal.
    reason : str
        What the robot does, for people.

    """

    command: VelocityCommand
    route: object = None
    done: bool = False
    reason: str = ''


class HeadOnYield:
    """
    The head-on yield state of the navigator: when to yield, where to, and when to leave.

    Parameters
    ----------
    config : YieldConfig
    geometry : GridGeometry
        The navigator's grid.
    safety_radius : float
        f1's ``r`` [m].
    follower : FollowerConfig
        The navigator's path follower, to drive to the passing place.

    Attributes
    ----------
    active : bool
        Whether the robot is yielding.
    count : int
        Yields started since the last `reset`.

    """

    def __init__(self, config, geometry, safety_radius, follower):
        self.config = config
        self.geometry = geometry
        self.safety_radius = safety_radius
        self.follower = follower
        self._trail = []
        self._history = {}
        self.reset()

    def reset(self):
        """Leave the state and forget the yields counted (a new goal)."""
        self.active = False
        self.count = 0
        self._encounter = None
        self._route = None
        self._route_xy = None
        self._phase = ''
        self._started = 0.0
        self._watch_since = 0.0
        self._watch_xy = None
        self._clear_xy = None
        self._next_search = -math.inf

    # -- what the robot sees ------------------------------------------------------------

    def observe(self, stamp, pose, tracks):
        """
        Keep the robot's trail and the followed objects' recent positions.

        Parameters
        ----------
        stamp : float
            [s]
        pose : (float, float, float)
            Robot base ``(x, y, yaw)`` [m, m, rad].
        tracks : MotionTracks or None
            The grid's tracks; None when the map follows no objects (nothing is yielded to).

        """
        xy = (float(pose[0]), float(pose[1]))
        if not self._trail or math.dist(self._trail[-1], xy) >= 0.5 * self.geometry.resolution:
            self._trail.append(xy)
            length = 0.0
            for k in range(len(self._trail) - 1, 0, -1):
                length += math.dist(self._trail[k], self._trail[k - 1])
                if length > self.config.search_distance:
                    del self._trail[:k - 1]
                    break
        if tracks is None:
            self._history.clear()
            return
        live = {}
        for track_id, position, seen in zip(tracks.ids.tolist(), tracks.positions.tolist(),
                                            tracks.last_seen.tolist()):
            samples = self._history.get(track_id, [])
            if not samples or seen > samples[-1][0]:
                samples = samples + [(seen, position[0], position[1])]
            live[track_id] = [s for s in samples if s[0] >= stamp - VELOCITY_HISTORY]
        self._history = live

    def velocities(self, stamp):
        """
        Return the live tracks with a velocity: ``{track id: (x, y, vx, vy)}`` [m, m/s].

        A track is live when continued within ``SEEN_WITHIN``; its velocity is the change of
        position over its kept samples, when they span at least ``VELOCITY_WINDOW``.
        """
        moving = {}
        for track_id, samples in self._history.items():
            first, last = samples[0], samples[-1]
            span = last[0] - first[0]
            if last[0] >= stamp - SEEN_WITHIN and span >= VELOCITY_WINDOW:
                moving[track_id] = (last[1], last[2], (last[1] - first[1]) / span,
                                    (last[2] - first[2]) / span)
        return moving

    # -- the decision ----------------------------------------------------------------------

    def encounter(self, stamp, pose, labels, path_xy, no_path, footprint):
        """
        Find the nearest object coming head-on through a narrow corridor.

        An object concerns the robot when it stands within ``side_clearance`` of the path ahead
        (up to ``trigger_distance`` along it), or whenever the robot has no path (it may be
        what closes the way). The corridor is the route between the two over known free cells
        (explored, or mobile: the object's own cells), found with A*: the object must be at
        most ``trigger_distance`` along it and move towards the robot along it, and the route
        must run somewhere through free space narrower than ``corridor_width``.

        Parameters
        ----------
        stamp : float
            [s]
        pose : (float, float, float)
            Robot base [m, m, rad].
        labels : (H, W) ndarray of uint8
            The grid's labels.
        path_xy : (N, 2) ndarray of float64 or None
            The path to the goal [m].
        no_path : bool
            Whether the robot has no path to its goal.
        footprint : (slice, slice, ndarray of bool)
            The navigator's window around the robot and the cells of it the robot stands on
            (passable whatever their label).

        Returns
        -------
        Encounter or None

        """
        config = self.config
        moving = self.velocities(stamp)
        if not moving or (path_xy is None and not no_path):
            return None
        geometry = self.geometry
        concerned = {}
        for track_id, (x, y, vx, vy) in moving.items():
            if math.hypot(x - pose[0], y - pose[1]) > config.trigger_distance:
                continue
            if path_xy is not None and not no_path:
                to_robot = np.hypot(path_xy[:, 0] - pose[0], path_xy[:, 1] - pose[1])
                ahead_xy = path_xy[int(np.argmin(to_robot)):]
                arc = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(ahead_xy, axis=0).T))))
                distance, _ = nearest_points(np.array([x]), np.array([y]),
                                             ahead_xy[arc <= config.trigger_distance])
                if distance[0] > config.side_clearance:
                    continue
            concerned[track_id] = (x, y, vx, vy)
        if not concerned:
            return None
        blocked = self._known_blocked(labels, footprint)
        start = tuple(int(v) for v in geometry.world_to_cell(pose[0], pose[1]))
        best = None
        for track_id, (x, y, vx, vy) in concerned.items():
            goal = tuple(int(v) for v in geometry.world_to_cell(x, y))
            if not (geometry.contains_cell(*start) and geometry.contains_cell(*goal)):
                continue
            saved = blocked[goal]
            blocked[goal] = False
            cells = astar(blocked, start, goal, cut_corners=False)
            blocked[goal] = saved
            if cells is None or len(cells) < 2:
                continue
            route = np.array(cells, dtype=np.int64)
            route_x, route_y = geometry.cell_to_world(route[:, 0], route[:, 1])
            route_xy = np.column_stack((route_x, route_y))
            arc = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(route_xy, axis=0).T))))
            if arc[-1] > config.trigger_distance or (best is not None and arc[-1] >= best[0]):
                continue
            tangent = route_xy[-1] - route_xy[max(0, route_xy.shape[0] - 3)]
            tangent /= max(float(np.hypot(*tangent)), 1e-9)
            if -(vx * tangent[0] + vy * tangent[1]) < config.approach_speed:
                continue
            widths = corridor_widths(labels == CellLabel.STEADY_OBSTACLE, route,
                                     geometry.resolution, self.safety_radius,
                                     config.corridor_width)
            if widths.min() >= config.corridor_width:
                continue
            best = (float(arc[-1]), track_id, (x, y), (vx, vy), float(widths.min()), route_xy,
                    arc)
        if best is None:
            return None
        distance, track_id, position, velocity, width, route_xy, arc = best
        back = self._line_behind(pose, route_xy, labels == CellLabel.STEADY_OBSTACLE)
        line = np.vstack((back, route_xy))
        reachable = np.concatenate((np.ones(back.shape[0], dtype=bool),
                                    arc <= 0.5 * distance))
        return Encounter(track_id, position, velocity, distance, width, line, back.shape[0],
                         reachable, route_xy)

    def _known_blocked(self, labels, footprint):
        """Return the cells the robot may not drive through: all but known free and its own."""
        blocked = ~((labels == CellLabel.EXPLORED) | (labels == CellLabel.MOBILE_OBSTACLE))
        rows, cols, near = footprint
        blocked[rows, cols] &= ~near
        return blocked

    def _line_behind(self, pose, route_xy, steady):
        """
        Return the corridor line behind the robot [m]: its trail, continued straight back.

        The trail (positions every half cell, up to ``search_distance``) ends at the robot;
        where it is shorter, the line goes on straight from its oldest point, away from the
        object, until a wall cell or the grid's edge.
        """
        trail = np.array(self._trail + [(float(pose[0]), float(pose[1]))])
        length = float(np.hypot(*np.diff(trail, axis=0).T).sum()) if trail.shape[0] > 1 else 0.0
        missing = self.config.search_distance - length
        if missing <= 0.0:
            return trail
        if length > 0.0:
            tail = trail[0] - trail[min(trail.shape[0] - 1, 2)]
        else:
            tail = route_xy[0] - route_xy[min(route_xy.shape[0] - 1, 2)]
        norm = float(np.hypot(*tail))
        if norm == 0.0:
            return trail
        step = 0.5 * self.geometry.resolution
        offsets = step * np.arange(1, math.ceil(missing / step) + 1)
        points = trail[0] + offsets[:, None] * (tail / norm)
        rr, cc = self.geometry.world_to_cell(points[:, 0], points[:, 1])
        inside = self.geometry.contains_cell(rr, cc)
        stop = ~inside
        stop[inside] = steady[rr[inside], cc[inside]]
        if stop.any():
            points = points[:int(np.argmax(stop))]
        return np.vstack((points[::-1], trail))

    def _search(self, pose, labels, footprint):
        """Plan a route to a passing place for the current encounter; None if none."""
        encounter = self._encounter
        geometry = self.geometry
        passable = labels == CellLabel.EXPLORED
        rows, cols, near = footprint
        passable[rows, cols] |= near
        start = tuple(int(v) for v in geometry.world_to_cell(pose[0], pose[1]))
        reach = self.config.search_distance + geometry.resolution
        window_rows, window_cols = geometry.cell_window(pose[0] - reach, pose[0] + reach,
                                                        pose[1] - reach, pose[1] + reach)
        x_centres, y_centres = geometry.window_centres(window_rows, window_cols)
        x, y = np.meshgrid(x_centres, y_centres)
        distance, index = nearest_points(x.ravel(), y.ravel(), encounter.line_xy)
        candidate = np.zeros(geometry.shape, dtype=bool)
        candidate[window_rows, window_cols] = (
            (distance >= self.config.side_clearance)
            & encounter.reachable[index]).reshape(x.shape)
        candidate &= passable
        return passing_place(passable, candidate, start, geometry.resolution,
                             self.config.search_distance)

    def start(self, stamp, pose, labels, path_xy, no_path, footprint):
        """
        Start yielding when an object comes head-on and a passing place is in reach.

        Parameters
        ----------
        stamp, pose, labels, path_xy, no_path, footprint
            As for `encounter`.

        Returns
        -------
        route : (K, 2) ndarray of int64 or None
            Cells to the passing place; None when the robot does not yield.

        """
        if self.active or stamp < self._next_search:
            return None
        encounter = self.encounter(stamp, pose, labels, path_xy, no_path, footprint)
        if encounter is None:
            return None
        self._encounter = encounter
        route = self._search(pose, labels, footprint)
        if route is None:
            self._next_search = stamp + RETRY_PERIOD
            self._encounter = None
            return None
        self.active = True
        self.count += 1
        self._started = stamp
        self._phase = 'going'
        self._set_route(route)
        return route

    def _set_route(self, route):
        """
        Follow ``route`` to a passing place; face the line where it is nearest to the place.

        The corridor is clear when no object is near the route from that point on towards the
        object (all of it when the place lies beside the trail behind the robot): one that
        went past the place, away from the robot's way, no longer keeps it waiting.
        """
        encounter = self._encounter
        x, y = self.geometry.cell_to_world(route[:, 0], route[:, 1])
        self._route = route
        self._route_xy = np.column_stack((x, y))
        _, index = nearest_points(self._route_xy[-1:, 0], self._route_xy[-1:, 1],
                                  encounter.line_xy)
        junction = int(index[0])
        self._watch_xy = encounter.line_xy[junction]
        self._clear_xy = encounter.route_xy[max(0, junction - encounter.behind):]

    def step(self, stamp, pose, labels, footprint):
        """
        Drive to the passing place, face the corridor, watch, and tell when to leave.

        Parameters
        ----------
        stamp, pose, labels, footprint
            As for `encounter` (time [s], robot base [m, m, rad], the grid's labels, the
            robot's own cells).

        Returns
        -------
        YieldStep

        """
        if stamp - self._started >= self.config.wait_max:
            return self._leave('waited yield_wait_max')
        if self._phase == 'going':
            new_route = None
            if self._route_blocked(pose, labels, footprint):
                new_route = self._search(pose, labels, footprint)
                if new_route is None:
                    return self._leave('no passing place in reach any more')
                self._set_route(new_route)
            command = follow_path(pose, self._route_xy, self.follower)
            if not command.goal_reached:
                return YieldStep(command, new_route, reason='yielding: going to a passing place')
            self._phase = 'facing'
        if self._phase == 'facing':
            error = wrap_angle(math.atan2(self._watch_xy[1] - pose[1],
                                          self._watch_xy[0] - pose[0]) - pose[2])
            if abs(error) > FACE_TOLERANCE:
                angular = float(np.clip(self.follower.heading_gain * error,
                                        -self.follower.max_angular_speed,
                                        self.follower.max_angular_speed))
                return YieldStep(VelocityCommand(0.0, angular, turn=error),
                                 reason='yielding: facing the corridor')
            self._phase = 'watching'
            self._watch_since = stamp
        if stamp - self._watch_since >= WATCH_TIME and self._corridor_clear(stamp):
            return self._leave('')
        return YieldStep(STOP, reason='yielding: letting a moving obstacle pass')

    def _leave(self, reason):
        self.active = False
        self._phase = ''
        self._encounter = None
        return YieldStep(STOP, done=True, reason=reason)

    def _route_blocked(self, pose, labels, footprint):
        """Tell whether a cell of the route ahead of the robot is an obstacle."""
        distance = np.hypot(self._route_xy[:, 0] - pose[0], self._route_xy[:, 1] - pose[1])
        ahead = self._route[int(np.argmin(distance)):]
        blocked = labels[ahead[:, 0], ahead[:, 1]] >= CellLabel.STEADY_OBSTACLE
        rows, cols, near = footprint
        inside = ((ahead[:, 0] >= rows.start) & (ahead[:, 0] < rows.stop)
                  & (ahead[:, 1] >= cols.start) & (ahead[:, 1] < cols.stop))
        blocked[inside] &= ~near[ahead[inside, 0] - rows.start, ahead[inside, 1] - cols.start]
        return bool(blocked.any())

    def _corridor_clear(self, stamp):
        """
        Tell whether no object holds the robot at its passing place any more.

        A live track holds it while it is within ``side_clearance`` of the route from the
        junction on and comes towards the junction at ``approach_speed`` or more (or has no
        velocity yet), or stands within ``side_clearance`` of the junction itself. One that
        stopped or turned away on the route is left to the planner, as without the state.
        """
        moving = self.velocities(stamp)
        junction = self._watch_xy
        for track_id, samples in self._history.items():
            seen, x, y = samples[-1]
            if seen < stamp - SEEN_WITHIN:
                continue
            to_junction = np.array([junction[0] - x, junction[1] - y])
            gap = float(np.hypot(*to_junction))
            if gap < self.config.side_clearance:
                return False
            distance, _ = nearest_points(np.array([x]), np.array([y]), self._clear_xy)
            if distance[0] >= self.config.side_clearance:
                continue
            if track_id not in moving:
                return False
            vx, vy = moving[track_id][2:]
            if (vx * to_junction[0] + vy * to_junction[1]) / gap >= self.config.approach_speed:
                return False
        return True
