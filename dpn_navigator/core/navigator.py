"""
The dynamic planner navigator without ROS: grid update, replanning and path following per scan.

Per scan the navigator folds the scan into its ``LabelGrid``, decides whether to replan (the
grid's replan flag, no path yet, a blocked cell ahead on the path, the robot off its path, or a
new goal), plans with A* on the partly known grid (non-explored counts as free) and turns the
path into a velocity command. The ROS node and the batch benchmark both drive this object.

"""

from dataclasses import dataclass, field
import enum
import math
import time

import numpy as np

from .cell_label import blocked_mask, CellLabel
from .control.path_follower import follow_path, FollowerConfig, STOP, VelocityCommand
from .control.turn_sweep import TurnSweep
from .mapping.label_grid import LabelGrid, LabelRule, warm_up_label_update
from .planning.astar_search import warm_up_astar
from .planning.planning_masks import PlanningMasks, touches_blocked  # noqa: F401 (re-exported)
from .planning.planning_masks import warm_up_planning_masks
from .pose2d import compose
from .scan_polygon import check_pose, scan_points


#: Forgetting unseen obstacles keeps those within this many safety radii of the robot.
FORGET_KEEP_RADII = 2.0


class NavigatorStatus(enum.Enum):
    """What the navigator is doing."""

    IDLE = 'idle'                    # no goal
    ACTIVE = 'active'                # following a path to the goal
    GOAL_REACHED = 'goal_reached'    # inside the goal tolerance; stays until a new goal
    NO_PATH = 'no_path'              # no path on the current map; retried as the map changes


class ReplanCause(enum.Enum):
    """Why a step planned a path."""

    NONE = ''                        # no planning in this step
    FLAG = 'flag'                    # the grid's replan flag: a path cell turned obstacle
    NO_PATH_RETRY = 'no_path_retry'  # a retry while there was no path
    OTHER = 'other'                  # no path yet (new goal), a blocked cell ahead, off the path


@dataclass(frozen=True)
class NavigatorConfig:
    """
    Everything the navigator needs to know before the first scan.

    Attributes
    ----------
    width, height : float
        Size of the environment, ``W x H`` [m].
    origin : (float, float)
        Map-frame position of the environment's lower-left corner [m].
    resolution : float
        Grid cell side [m]; the paper uses 0.5.
    safety_radius : float
        f1's ``r`` [m]; the default is the Husky's circumscribed radius, ~0.6 m.
    footprint_radius : float
        Cells whose centre is this close to the robot are planned through even when labelled
        as obstacles: the robot stands on them, so whatever was seen there has moved [m].
    laser_offset : (float, float, float)
        Laser pose on the robot base ``(x, y, yaw)`` [m, m, rad].
    max_path_deviation : float
        Replan when the robot is farther than this from its path [m].
    obstacle_proximity_cost : float
        Extra A* cost of entering a free cell that touches an obstacle cell (8-neighbourhood)
        [cells]. It keeps the path a cell off obstacles where there is room, so that corner
        cutting and turning in place do not bring the Husky's corners to a wall; narrow
        corridors, where every cell touches one, are planned as before. 0 plans the paper's
        plain shortest paths.
    no_path_retry_period : float
        While there is no path, plan again at most this often [s].
    forget_obstacles_after : float
        After this long with no path [s], the mobile-obstacle cells that the latest scan does
        not see are forgotten (set back to explored, which they were before something moved
        into them) and the robot plans again; after as long again with still no path, every
        obstacle cell out of view (steady too, as a wanderer first seen in unexplored space is
        labelled steady) goes back to non-explored. The cells the scan sees are labelled again
        at once, and those within ``FORGET_KEEP_RADII`` safety radii (1.2 m) of the robot are
        kept. Without it, a wanderer that blocked a corridor and then left it out of the
        laser's view (behind the robot, round a corner) would block it for good. 0 turns it
        off: the paper's navigator.
    free_evidence_radius : float
        Conservative free space [m]: explored -> mobile obstacle only for cells once surely
        seen free (their disc of this radius inside one scan's polygon), else a steady
        obstacle; see ``LabelRule``. 0: the paper's FSM.
    moving_object_size : float
        Object-level relabelling [m]: the steady cells of a scan segment's hits within this
        distance of a hit in surely-free space become mobile; see ``LabelRule``. 0: off.
    evidence_margin : float
        A hit shows motion only within ``free_evidence_radius`` minus this of a cell surely
        seen free [m]; see ``LabelRule``.
    segment_gap : float
        Consecutive hits farther apart than this belong to different objects [m].
    object_min_hits : int
        Thin things [hits]: a scan segment of fewer hits shows no motion and is not followed
        (a post thinner than the beam spacing slips between the beams); see ``LabelRule``.
        0: off.
    fine_evidence_resolution, fine_evidence_radius, fine_evidence_range : float
        Fine free evidence [m]: a hit also shows motion when its cell of a grid this fine was
        once surely seen free with this radius, within this range of the laser; see
        ``LabelRule``. Resolution and radius 0: off.
    mobile_expiry : float
        Ghost expiry [s]: mobile cells unconfirmed by any hit for this long and out of view go
        back to explored; see ``LabelRule``. 0: off.
    track_confirm_time : float
        Motion tracks [s]: a compact, free-standing scan segment near an object seen to move
        is that object while motion was seen within this long; see ``LabelRule``. 0: off.
    track_still_distance : float
        Still objects [m]: a compact segment this close to where a compact free-standing one
        stood 0.8-1.5 s ago is not seen to move by the places left empty near it, nor
        continues a track that never moved; see ``LabelRule``. 0: off.
    track_exclusive : bool
        Exclusive tracks: one scan segment per track and scan; see ``LabelRule``.
    trail_distance : float
        Trails [m]: out-of-view mobile cells whose object the scan sees at least this far away
        go back to explored; see ``LabelRule``. 0: off.
    object_memory : float
        Object memory [s]: steady cells of small objects (scan segments up to 1 m, 3 hits or
        more) that no longer segment has hit are forgotten after this long without a hit, out
        of view; see ``LabelRule``. 0: off.
    object_memory_short_segments : bool
        Short segments in the object memory: steady cells that only segments of one or two
        hits have hit (a wanderer glimpsed far off) are forgotten too; see ``LabelRule``.
    robot_length, robot_width : float
        The robot's footprint, centred on the base frame's origin [m]; the Husky A200 with
        bumpers.
    turn_sweep_memory : float
        Turn sweep [s]: a turn in place is tested against the laser hits kept around the robot,
        and replaced by a move to a place where it is clear, or held, when the robot's corners
        would sweep into one; a kept hit counts for this long, and after that while the grid
        labels its cell an obstacle; see ``turn_sweep``. 0: off (the follower's turn is sent
        as it is; the paper).
    turn_sweep_margin : float
        Clearance the turn sweep keeps from the kept hits [m].
    turn_sweep_spot_distance : float
        Farthest place the turn sweep moves the robot to for a blocked turn [m]; 0: it waits.
    follower : FollowerConfig
        Speed limits and gains of the path follower.

    """

    width: float
    height: float
    origin: tuple = (0.0, 0.0)
    resolution: float = 0.5
    safety_radius: float = 0.6
    footprint_radius: float = 0.35
    laser_offset: tuple = (0.0, 0.0, 0.0)
    max_path_deviation: float = 1.0
    obstacle_proximity_cost: float = 1.0
    no_path_retry_period: float = 0.5
    forget_obstacles_after: float = 10.0
    free_evidence_radius: float = 0.6
    moving_object_size: float = 0.7
    evidence_margin: float = 0.15
    segment_gap: float = 0.3
    object_min_hits: int = 3
    fine_evidence_resolution: float = 0.1
    fine_evidence_radius: float = 0.2
    fine_evidence_range: float = 20.0
    mobile_expiry: float = 3.0
    track_confirm_time: float = 5.0
    track_still_distance: float = 0.08
    track_exclusive: bool = True
    trail_distance: float = 1.2
    object_memory: float = 5.0
    object_memory_short_segments: bool = True
    robot_length: float = 0.99
    robot_width: float = 0.67
    turn_sweep_memory: float = 2.0
    turn_sweep_margin: float = 0.05
    turn_sweep_spot_distance: float = 0.6
    follower: FollowerConfig = field(default_factory=FollowerConfig)

    def __post_init__(self):
        for name in ('safety_radius', 'footprint_radius', 'no_path_retry_period',
                     'obstacle_proximity_cost', 'forget_obstacles_after', 'turn_sweep_memory',
                     'turn_sweep_margin', 'turn_sweep_spot_distance'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if not (math.isfinite(self.max_path_deviation) and self.max_path_deviation > 0.0):
            raise ValueError(
                f'max_path_deviation must be positive, got {self.max_path_deviation!r}')
        for name in ('robot_length', 'robot_width'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be positive and finite, got {value!r}')
        check_pose(self.laser_offset, 'laser_offset')
        self.label_rule()                        # validates the label rule's fields

    def label_rule(self):
        """Return the grid's ``LabelRule`` from the label fields of this configuration."""
        return LabelRule(free_evidence_radius=self.free_evidence_radius,
                         moving_object_size=self.moving_object_size,
                         evidence_margin=self.evidence_margin, segment_gap=self.segment_gap,
                         object_min_hits=self.object_min_hits,
                         fine_evidence_resolution=self.fine_evidence_resolution,
                         fine_evidence_radius=self.fine_evidence_radius,
                         fine_evidence_range=self.fine_evidence_range,
                         mobile_expiry=self.mobile_expiry,
                         track_confirm_time=self.track_confirm_time,
                         track_still_distance=self.track_still_distance,
                         track_exclusive=self.track_exclusive,
                         trail_distance=self.trail_distance,
                         object_memory=self.object_memory,
                         object_memory_short_segments=self.object_memory_short_segments)


@dataclass(frozen=True)
class NavigatorOutput:
    """
    The result of one navigator step.

    Attributes
    ----------
    command : VelocityCommand
        What to send to the base.
    status : NavigatorStatus
    reason : str
        Why the status is what it is, for people (empty when active).
    replanned : bool
        True when this step computed a new path.
    replan_cause : ReplanCause
        Why it did (``ReplanCause.NONE`` when it did not); the flag wins over a stale path.

    """

    command: VelocityCommand
    status: NavigatorStatus
    reason: str = ''
    replanned: bool = False
    replan_cause: ReplanCause = ReplanCause.NONE


class Navigator:
    """
    Map, plan and follow toward a goal in an unknown environment with moving obstacles.

    Parameters
    ----------
    config : NavigatorConfig
    grid : LabelGrid-like, optional
        The map to plan on, in place of the ``LabelGrid`` built from ``config``: any object
        with ``LabelGrid``'s ``geometry``, ``labels``, ``last_window`` and ``update`` (the
        benchmark's reference navigators: ``CostmapGrid``, ``OracleGrid``), and optionally
        ``settle`` (then its ``update`` takes ``defer_evidence``).

    Attributes
    ----------
    grid : LabelGrid
        The labelled occupancy grid built from the scans.
    path : (N, 2) ndarray of int64, or None
        The planned path as ``(row, col)`` cells, start to goal.
    goal : (float, float) or None
        The goal in the map frame [m].
    status : NavigatorStatus
    replans : int
        How many paths have been planned since the goal was set.
    forgets : int
        How many times unseen obstacles were forgotten since the goal was set (see
        ``NavigatorConfig.forget_obstacles_after``).

    """

    def __init__(self, config, grid=None):
        self.config = config
        self.grid = grid if grid is not None else LabelGrid(
            config.width, config.height, config.resolution, config.origin, config.label_rule())
        self._settles = callable(getattr(self.grid, 'settle', None))
        self._masks = PlanningMasks(self.grid, config.obstacle_proximity_cost)
        self.path = None
        self.goal = None
        self.status = NavigatorStatus.IDLE
        self.reason = 'no goal'
        self.replans = 0
        self.forgets = 0
        self._path_xy = None
        self._next_retry = -math.inf
        self._replan_requested = False
        self._no_path_since = None
        self._spell_forgets = 0
        self._last_scan = None
        self._unswept_pose = None                # robot pose of a scan the turn sweep lacks
        self._last_stamp = None
        self.turn_sweep = None if config.turn_sweep_memory == 0.0 else TurnSweep(
            config.turn_sweep_memory, config.robot_length, config.robot_width,
            config.turn_sweep_margin, spot_distance=config.turn_sweep_spot_distance)

    def set_goal(self, x, y):
        """
        Set a new goal [m] in the map frame; the next step plans a path to it.

        Raises
        ------
        ValueError
            When the goal is not finite or lies outside the map.

        """
        x, y, _ = check_pose((x, y, 0.0), 'goal')      # finite, within MAX_POSE_COORDINATE
        rr, cc = self.grid.geometry.world_to_cell(x, y)
        if not self.grid.geometry.contains_cell(rr, cc):
            raise ValueError(f'goal ({x:.2f}, {y:.2f}) m is outside the map')
        self.goal = (x, y)
        self.path = None
        self._path_xy = None
        self.status = NavigatorStatus.ACTIVE
        self.reason = ''
        self.replans = 0
        self.forgets = 0
        self._next_retry = -math.inf
        self._no_path_since = None
        self._spell_forgets = 0

    def clear_goal(self):
        """Drop the goal; the robot stops."""
        self.goal = None
        self.path = None
        self._path_xy = None
        self.status = NavigatorStatus.IDLE
        self.reason = 'no goal'

    def step(self, stamp, pose, ranges, angle_min, angle_increment, range_min, range_max,
             angle_max=None):
        """
        Fold one scan into the map and decide the next velocity command.

        The same as ``observe`` followed by ``decide``.

        Parameters
        ----------
        stamp : float
            Time of the scan [s], any monotonic clock (simulated time in the simulator).
        pose : (float, float, float)
            Robot base ``(x, y, yaw)`` in the map frame when the scan was taken [m, m, rad].
        ranges, angle_min, angle_increment, range_min, range_max, angle_max
            The laser scan, as for ``LabelGrid.update``.

        Returns
        -------
        NavigatorOutput

        Raises
        ------
        ValueError
            For a malformed scan or pose; the navigator's state is then unchanged.

        """
        self.observe(pose, ranges, angle_min, angle_increment, range_min, range_max, angle_max,
                     stamp=stamp)
        return self.decide(stamp, pose)

    def observe(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
                angle_max=None, stamp=None, defer_evidence=False):
        """
        Fold one scan into the map; the next ``decide`` replans if the scan asks for it.

        Split from ``decide`` so that a caller can publish the map before planning. The turn
        sweep takes the scan's hits at the next ``decide`` (or ``observe``), for the same
        reason; it only reads them there.

        Parameters
        ----------
        pose, ranges, angle_min, angle_increment, range_min, range_max, angle_max
            As for ``step``.
        stamp : float, optional
            Time of the scan [s]; needed when ``mobile_expiry`` is on.
        defer_evidence : bool
            Leave the free evidence of the scan for `settle` (``LabelGrid.update``), so that
            the map is ready sooner; the map and the plans are the same. Ignored by a grid
            without ``settle``.

        Raises
        ------
        ValueError
            For a malformed scan or pose; the navigator's state is then unchanged.

        """
        pose = check_pose(pose)
        laser_pose = compose(pose, self.config.laser_offset)
        deferring = {'defer_evidence': True} if defer_evidence and self._settles else {}
        replan = self.grid.update(laser_pose, ranges, angle_min, angle_increment, range_min,
                                  range_max, self.config.safety_radius, path=self.path,
                                  angle_max=angle_max, stamp=stamp, **deferring)
        self._sweep_last_scan()
        self._replan_requested |= replan
        self._last_scan = (laser_pose, np.array(ranges, dtype=np.float64), angle_min,
                           angle_increment, range_min, range_max, angle_max, stamp)
        self._unswept_pose = pose if self.turn_sweep is not None else None

    def settle(self):
        """Finish what the last ``observe`` with ``defer_evidence`` left for later."""
        if self._settles:
            self.grid.settle()

    def _sweep_last_scan(self):
        """Give the turn sweep the hits of the last scan observed, once."""
        if self._unswept_pose is None:
            return
        laser_pose, ranges, angle_min, angle_increment, range_min, range_max, _, stamp = \
            self._last_scan
        points = scan_points(laser_pose, ranges, angle_min, angle_increment, range_min,
                             range_max)
        self.turn_sweep.add_scan(
            stamp, self._unswept_pose[:2], np.column_stack((points.hits_x, points.hits_y)),
            view=(laser_pose, ranges, angle_min, angle_increment, range_min, range_max))
        self._unswept_pose = None

    def decide(self, stamp, pose):
        """
        Plan if needed and compute the velocity command for the robot at ``pose``.

        Parameters
        ----------
        stamp : float
            Current time [s].
        pose : (float, float, float)
            Robot base ``(x, y, yaw)`` in the map frame [m, m, rad].

        Returns
        -------
        NavigatorOutput

        """
        pose = check_pose(pose)
        self._sweep_last_scan()
        self._follow_clock(stamp)
        replan, self._replan_requested = self._replan_requested, False
        return self._decide(stamp, pose, replan)

    def _follow_clock(self, stamp):
        """
        Restart the no-path retry and forget timers when time goes backwards.

        Simulated time jumps back when the simulator restarts; a retry time or a no-path start
        kept from the old clock would hold the navigator without a plan until the new clock
        caught up with it.
        """
        if self._last_stamp is not None and stamp < self._last_stamp:
            self._next_retry = -math.inf
            if self._no_path_since is not None:
                self._no_path_since = stamp
        self._last_stamp = stamp

    def _decide(self, stamp, pose, replan_flag):
        if self.goal is None:
            return NavigatorOutput(STOP, self.status, self.reason)
        if self.status is NavigatorStatus.GOAL_REACHED:
            return NavigatorOutput(STOP, self.status, self.reason)
        replanned = False
        cause = ReplanCause.NONE
        if replan_flag or self._path_is_stale(pose):
            if self.path is None and stamp < self._next_retry:
                return NavigatorOutput(STOP, self.status, self.reason)
            if self.path is None and self.status is NavigatorStatus.NO_PATH:
                cause = ReplanCause.NO_PATH_RETRY
            else:
                cause = ReplanCause.FLAG if replan_flag else ReplanCause.OTHER
            if self.path is None and self._forget_is_due(stamp):
                self._forget_unseen_obstacles(pose)
                self._no_path_since = stamp
            replanned = self._plan(pose)
            if self.path is None:
                self._next_retry = stamp + self.config.no_path_retry_period
                if self._no_path_since is None:
                    self._no_path_since = stamp
                return NavigatorOutput(STOP, self.status, self.reason, replanned, cause)
            self._no_path_since = None
            self._spell_forgets = 0
        command = follow_path(pose, self._path_xy, self.config.follower)
        if command.goal_reached:
            self.status = NavigatorStatus.GOAL_REACHED
            self.reason = 'inside the goal tolerance'
            return NavigatorOutput(STOP, self.status, self.reason, replanned, cause)
        if self.turn_sweep is not None:
            command = self.turn_sweep.check(command, pose, self._obstacle_at)
        return NavigatorOutput(command, self.status, self.reason, replanned, cause)

    def _path_is_stale(self, pose):
        """Tell whether there is no path, a cell ahead on it is blocked, or the robot left it."""
        if self.path is None:
            return True
        distance = np.hypot(self._path_xy[:, 0] - pose[0], self._path_xy[:, 1] - pose[1])
        closest = int(np.argmin(distance))
        if distance[closest] > self.config.max_path_deviation:
            return True
        ahead = self.path[closest + 1:]
        return bool(blocked_mask(self.grid.labels[ahead[:, 0], ahead[:, 1]]).any())

    def _plan(self, pose):
        """Plan from the robot's cell to the goal's; set path, status and reason."""
        geometry = self.grid.geometry
        start = tuple(int(v) for v in geometry.world_to_cell(pose[0], pose[1]))
        goal = tuple(int(v) for v in geometry.world_to_cell(*self.goal))
        self.replans += 1
        if not geometry.contains_cell(*start):
            return self._no_path('the robot is outside the map')
        self._masks.refresh()
        if self._masks.blocked[goal]:
            return self._no_path('the goal cell is an obstacle')
        # No diagonal past a blocked cell: r equals the Husky's circumscribed radius, so the
        # half-cell a cut corner saves would bring the robot's corners to the wall.
        cells = self._masks.plan(start, goal, self._footprint(pose), cut_corners=False)
        if cells is None:
            return self._no_path('no path to the goal on the current map')
        self.path = np.array(cells, dtype=np.int64)
        path_x, path_y = geometry.cell_to_world(self.path[:, 0], self.path[:, 1])
        self._path_xy = np.column_stack((path_x, path_y))
        self._path_xy[-1] = self.goal                  # aim at the goal itself, not its cell
        self.status = NavigatorStatus.ACTIVE
        self.reason = ''
        return True

    def _forget_is_due(self, stamp):
        """Tell whether there has been no path for ``forget_obstacles_after`` seconds."""
        after = self.config.forget_obstacles_after
        return (after > 0.0 and self._no_path_since is not None
                and stamp - self._no_path_since >= after and self._last_scan is not None)

    def _forget_unseen_obstacles(self, pose):
        """
        Forget obstacle cells, then fold the latest scan in again.

        The first time in a spell without a path, mobile obstacles go back to explored; after
        that, every obstacle cell goes back to non-explored. Cells within
        ``FORGET_KEEP_RADII`` safety radii of the robot are kept: the robot may have to turn in
        place beside them before the laser sees them again.
        """
        self.settle()                   # the deferred evidence reads the labels as they were
        labels = self.grid.labels
        geometry = self.grid.geometry
        keep = FORGET_KEEP_RADII * self.config.safety_radius
        rows, cols = geometry.cell_window(pose[0] - keep, pose[0] + keep, pose[1] - keep,
                                          pose[1] + keep)
        x_centres, y_centres = geometry.window_centres(rows, cols)
        near = np.hypot(x_centres[None, :] - pose[0], y_centres[:, None] - pose[1]) <= keep
        kept = labels[rows, cols].copy()
        if self._spell_forgets == 0:
            labels[labels == CellLabel.MOBILE_OBSTACLE] = CellLabel.EXPLORED
        else:
            labels[blocked_mask(labels)] = CellLabel.NON_EXPLORED
        labels[rows, cols] = np.where(near, kept, labels[rows, cols])
        self.grid.labels_changed()
        laser_pose, ranges, angle_min, angle_increment, range_min, range_max, angle_max, \
            stamp = self._last_scan
        self.grid.update(laser_pose, ranges, angle_min, angle_increment, range_min, range_max,
                         self.config.safety_radius, angle_max=angle_max, stamp=stamp)
        self.forgets += 1
        self._spell_forgets += 1

    def _no_path(self, reason):
        self.path = None
        self._path_xy = None
        self.status = NavigatorStatus.NO_PATH
        self.reason = reason
        return True

    def _obstacle_at(self, xy):
        """Tell which map-frame points (N, 2) [m] lie on cells the grid holds as obstacles."""
        geometry = self.grid.geometry
        rr, cc = geometry.world_to_cell(xy[:, 0], xy[:, 1])
        inside = geometry.contains_cell(rr, cc)
        obstacle = np.zeros(xy.shape[0], dtype=bool)
        obstacle[inside] = blocked_mask(self.grid.labels[rr[inside], cc[inside]])
        return obstacle

    def _footprint(self, pose):
        """Return the window around the robot and its cells within ``footprint_radius``."""
        geometry = self.grid.geometry
        radius = self.config.footprint_radius
        rows, cols = geometry.cell_window(pose[0] - radius, pose[0] + radius,
                                          pose[1] - radius, pose[1] + radius)
        x_centres, y_centres = geometry.window_centres(rows, cols)
        near = np.hypot(x_centres[None, :] - pose[0], y_centres[:, None] - pose[1]) <= radius
        return rows, cols, near

    @property
    def path_xy(self):
        """Return the planned path in the map frame, (N, 2) float64 [m], or None."""
        return self._path_xy


def warm_up_navigator():
    """
    Compile (or load from the cache) the kernels a `Navigator` on a ``LabelGrid`` runs.

    The label update (every rule part), the planning masks and A*; a process calls it once at
    start, so that its first scan does not wait for them.

    Returns
    -------
    seconds : float
        Wall time it took [s]: the compile time with an empty cache, the load time with a
        warm one, nearly 0 when the kernels were ready already.

    """
    started = time.perf_counter()
    warm_up_label_update()
    warm_up_planning_masks()
    warm_up_astar()
    return time.perf_counter() - started
