"""
A Nav2-faithful reference: the costmap navigator with Nav2 Jazzy's default behaviour tree.

``Nav2Navigator`` plans on a ``CostmapGrid`` as the bare costmap navigator does, and adds what
Nav2 Jazzy's default tree, ``navigate_to_pose_w_replanning_and_recovery.xml``, and its default
parameters (``nav2_bringup/params/nav2_params.yaml``) do around it (sources and the departures
in ``docs/benchmark.md``):

- **Replanning at 1 Hz** (``RateController hz="1.0"`` around ``ComputePathToPose``): a new path
  every second, whatever happened; between plans the robot follows the last one and stops when
  a lethal cell lies on it within `STOP_DISTANCE` (the controller's collision check).
- **NavFn's costs** (``nav2_navfn_planner/src/navfn.cpp``, ``setCostmap``, with
  ``allow_unknown: true``): a free cell costs ``COST_NEUTRAL`` = 50, an unknown one
  ``COST_OBS - 1`` = 253, so entering unknown space costs 253 / 50 = 5.06 times free space
  (`UNKNOWN_EXTRA_COST` on top of A*'s cost of 1 per cell).
- **Planner recovery**: a failed plan clears the global costmap (``ClearEntireCostmap``,
  ``ClearGlobalCostmap-Context``) and plans once more (``RecoveryNode number_of_retries="1"``).
- **Controller recovery**: the progress checker (``SimpleProgressChecker``: 0.5 m within 10 s)
  fails the controller; the first failure clears the local costmap
  (``ClearLocalCostmap-Context``, ``number_of_retries="1"``).
- **The recovery round robin** when either fails again (``RecoveryNode number_of_retries="6"``
  around the whole pipeline): clear both costmaps; spin 1.57 rad; wait 5 s; back up 0.30 m at
  0.15 m/s; in turn, one per failure. After six recoveries the next failure aborts the goal:
  the robot stops for good (status ``NO_PATH``, reason ``aborted``). A spin or back-up whose
  footprint would touch a lethal cell fails at once, and the round robin tries the next
  behaviour, as ``RoundRobin`` does on a failed child.

There is one costmap here (Nav2 has a local and a global one): clearing either clears it.

"""

import enum
import math

import numpy as np

from ...core.cell_label import blocked_mask, CellLabel
from ...core.control.path_follower import follow_path, STOP, VelocityCommand
from ...core.navigator import Navigator, NavigatorOutput, NavigatorStatus, ReplanCause
from ...core.planning.astar_search import astar_checked
from ...core.planning.planning_masks import PlanningMasks, touches_blocked

#: NavFn's cost of a free cell (``COST_NEUTRAL``) and of an unknown one with ``allow_unknown``
#: (``COST_OBS - 1``), nav2_navfn_planner/include/nav2_navfn_planner/navfn.hpp and navfn.cpp.
NAVFN_FREE_COST = 50
NAVFN_UNKNOWN_COST = 253
#: Extra cost of entering an unknown cell on top of A*'s 1 per cell: 253 / 50 - 1.
UNKNOWN_EXTRA_COST = NAVFN_UNKNOWN_COST / NAVFN_FREE_COST - 1.0
#: ``RateController hz`` of the default tree: one plan per second [s].
REPLAN_PERIOD = 1.0
#: ``NavigateRecovery``'s ``number_of_retries``: recoveries before the goal is aborted.
NUMBER_OF_RETRIES = 6
#: The default tree's recovery arguments: ``Spin spin_dist`` [rad], ``Wait wait_duration`` [s],
#: ``BackUp backup_dist`` [m] and ``backup_speed`` [m/s].
SPIN_DISTANCE = 1.57
WAIT_DURATION = 5.0
BACKUP_DISTANCE = 0.30
BACKUP_SPEED = 0.15
#: nav2_params.yaml's behavior_server: ``max_rotational_vel``, ``min_rotational_vel``,
#: ``rotational_acc_lim`` [rad/s, rad/s, rad/s^2], ``simulate_ahead_time`` [s].
MAX_ROTATIONAL_VEL = 1.0
MIN_ROTATIONAL_VEL = 0.4
ROTATIONAL_ACC_LIM = 3.2
SIMULATE_AHEAD_TIME = 2.0
#: The behaviours' ``time_allowance`` (nav2_behaviors default) [s].
TIME_ALLOWANCE = 10.0
#: nav2_params.yaml's progress checker: ``required_movement_radius`` [m] within
#: ``movement_time_allowance`` [s].
REQUIRED_MOVEMENT_RADIUS = 0.5
MOVEMENT_TIME_ALLOWANCE = 10.0
#: Slack of the replanning clock [s]: ten scans of 0.1 s make 1 s, not 0.9999999.
CLOCK_SLACK = 1e-6
#: The controller stops for a lethal cell on its path this close ahead [m].
STOP_DISTANCE = 1.0


class Recovery(enum.Enum):
    """The default tree's ``RecoveryActions``, in their round-robin order."""

    CLEAR = 'clear costmaps'
    SPIN = 'spin'
    WAIT = 'wait'
    BACKUP = 'back up'


class NavfnMasks(PlanningMasks):
    """
    `PlanningMasks` that add NavFn's cost of unknown cells to A*'s costs.

    Parameters
    ----------
    grid : CostmapGrid
    proximity_cost : float
        As for `PlanningMasks`.
    unknown_cost : float
        Extra cost of entering a ``NON_EXPLORED`` cell [cells].

    """

    def __init__(self, grid, proximity_cost, unknown_cost=UNKNOWN_EXTRA_COST):
        super().__init__(grid, proximity_cost)
        self.unknown_cost = float(unknown_cost)

    def plan(self, start, goal, footprint, cut_corners, extra_cost=None, opened=None):
        """
        Plan as `PlanningMasks.plan` does, unknown cells costing ``unknown_cost`` more.

        ``extra_cost`` and ``opened`` are `PlanningMasks.plan`'s (None with the parts of issue
        31 off, as the reference navigators run).
        """
        blocked = self.blocked.copy()
        if opened is not None:
            blocked &= ~opened
        if blocked[goal]:
            return None
        rows, cols, near = footprint
        blocked[rows, cols] &= ~near
        blocked[start] = False
        cost = np.where(self._grid.labels == CellLabel.NON_EXPLORED, self.unknown_cost, 0.0)
        largest = self.unknown_cost if (cost > 0.0).any() else 0.0
        if self._proximity_cost > 0.0:
            proximity = self._proximity_cost * touches_blocked(blocked)
            cost = cost + proximity
            largest = float(cost.max())
        if extra_cost is not None:
            cost = cost + extra_cost
            largest = float(cost.max())
        cost = np.ascontiguousarray(cost, dtype=np.float64)
        return astar_checked(blocked, start, goal, cost if largest > 0.0 else None, largest,
                             cut_corners)


class Nav2Navigator(Navigator):
    """
    The costmap navigator run by Nav2 Jazzy's default behaviour tree (see the module).

    Parameters
    ----------
    config : NavigatorConfig
    grid : CostmapGrid
        The costmap (``reset`` is ``ClearEntireCostmap``).

    Attributes
    ----------
    recoveries : int
        Recoveries run since the goal was set.
    clears : int
        Times the costmap was cleared (context clears and the recovery's).
    aborted : bool
        The goal was aborted after `NUMBER_OF_RETRIES` recoveries.

    """

    def __init__(self, config, grid):
        super().__init__(config, grid)
        self._masks = NavfnMasks(self.grid, config.obstacle_proximity_cost)
        half_length, half_width = config.robot_length / 2.0, config.robot_width / 2.0
        self._footprint_box = (half_length, half_width)
        self._reset_tree()

    def _reset_tree(self):
        self.recoveries = 0
        self.clears = 0
        self.aborted = False
        self._next_plan = -math.inf
        self._behaviour = None
        self._round_robin = 0
        self._controller_failed = False
        self._progress = None
        self._spin_yaw = None

    def set_goal(self, x, y):
        """Set a new goal (``GoalUpdated``: the tree starts over)."""
        super().set_goal(x, y)
        self._reset_tree()

    def _decide(self, stamp, pose, replan_flag):
        if self.goal is None or self.status is NavigatorStatus.GOAL_REACHED:
            return NavigatorOutput(STOP, self.status, self.reason)
        if self.aborted:
            return NavigatorOutput(STOP, self.status, self.reason)
        if self._behaviour is not None:
            command = self._run_behaviour(stamp, pose)
            if command is not None:
                return NavigatorOutput(command, NavigatorStatus.ACTIVE,
                                       f'recovery: {self._behaviour[0].value}')
        replanned = False
        cause = ReplanCause.NONE
        if stamp >= self._next_plan - CLOCK_SLACK:
            self._next_plan = stamp + REPLAN_PERIOD
            cause = ReplanCause.FLAG if replan_flag else ReplanCause.OTHER
            replanned = True
            if not self._plan_with_context_clear(pose):
                return self._fail(stamp, pose, replanned, cause)
        if self.path is None:
            return NavigatorOutput(STOP, self.status, self.reason, replanned, cause)
        if self._progress_failed(stamp, pose):
            if self._controller_failed:
                return self._fail(stamp, pose, replanned, cause)
            self._controller_failed = True          # ClearLocalCostmap-Context, then retry
            self._clear()
            self._progress = (stamp, pose[:2])
        command = follow_path(pose, self._path_xy, self.config.follower)
        if command.goal_reached:
            self.status = NavigatorStatus.GOAL_REACHED
            self.reason = 'inside the goal tolerance'
            return NavigatorOutput(STOP, self.status, self.reason, replanned, cause)
        if self._blocked_ahead(pose):
            return NavigatorOutput(STOP, self.status, 'a lethal cell on the path ahead',
                                   replanned, cause)
        if self.turn_sweep is not None:
            command = self.turn_sweep.check(command, pose, self._obstacle_at)
        return NavigatorOutput(command, self.status, self.reason, replanned, cause)

    def _plan_with_context_clear(self, pose):
        """Plan; on failure clear the costmap and plan once more. Tell whether a path came."""
        self._plan(pose)
        if self.path is None:
            self._clear()
            self._plan(pose, count=False)          # the same replan: counted once
        return self.path is not None

    def _clear(self):
        """Clear the costmap entirely (``ClearEntireCostmap``)."""
        self.grid.reset()
        self.clears += 1

    def _fail(self, stamp, pose, replanned, cause):
        """Run the next recovery after a failure of the pipeline, or abort after the last."""
        if self.recoveries >= NUMBER_OF_RETRIES:
            self.aborted = True
            self.path = None
            self._path_xy = None
            self.status = NavigatorStatus.NO_PATH
            self.reason = f'aborted after {NUMBER_OF_RETRIES} recoveries'
            return NavigatorOutput(STOP, self.status, self.reason, replanned, cause)
        self.recoveries += 1
        self._controller_failed = False
        self._progress = None
        self.status = NavigatorStatus.ACTIVE
        self.reason = 'recovering'
        self._start_next_behaviour(stamp, pose)
        command = self._run_behaviour(stamp, pose) if self._behaviour is not None else None
        return NavigatorOutput(command or STOP, self.status, self.reason, replanned, cause)

    def _start_next_behaviour(self, stamp, pose):
        """Start the round robin's next behaviour that does not fail at once."""
        order = list(Recovery)
        for _ in range(len(order)):
            behaviour = order[self._round_robin % len(order)]
            self._round_robin += 1
            if behaviour is Recovery.CLEAR:
                self._clear()
                self._behaviour = None
                self._next_plan = -math.inf
                return
            if behaviour is Recovery.SPIN and self._footprint_hits(pose, spin=True):
                continue
            if behaviour is Recovery.BACKUP and self._footprint_hits(pose, spin=False):
                continue
            self._behaviour = (behaviour, stamp, tuple(pose))
            self._spin_yaw = None
            return
        self._behaviour = None

    def _run_behaviour(self, stamp, pose):
        """Return the running behaviour's command, or None when it has ended (then replan)."""
        behaviour, started, start_pose = self._behaviour
        elapsed = stamp - started
        done = elapsed >= TIME_ALLOWANCE
        command = STOP
        if behaviour is Recovery.WAIT:
            done = done or elapsed >= WAIT_DURATION
        elif behaviour is Recovery.SPIN:
            turned = self._turned(pose)
            remaining = SPIN_DISTANCE - turned
            if remaining <= 0.0 or self._footprint_hits(pose, spin=True):
                done = True
            else:
                speed = min(max(math.sqrt(2.0 * ROTATIONAL_ACC_LIM * remaining),
                                MIN_ROTATIONAL_VEL), MAX_ROTATIONAL_VEL)
                command = VelocityCommand(0.0, speed)
        elif behaviour is Recovery.BACKUP:
            moved = math.dist(pose[:2], start_pose[:2])
            if moved >= BACKUP_DISTANCE or self._footprint_hits(pose, spin=False):
                done = True
            else:
                command = VelocityCommand(-BACKUP_SPEED, 0.0)
        if done:
            self._behaviour = None
            self._next_plan = -math.inf
            self._spin_yaw = None
            return None
        return command

    def _turned(self, pose):
        """Return the heading turned since the spin began [rad], counter-clockwise."""
        last, total = self._spin_yaw or (pose[2], 0.0)
        total += math.remainder(pose[2] - last, math.tau)
        self._spin_yaw = (pose[2], total)
        return total

    def _progress_failed(self, stamp, pose):
        """``SimpleProgressChecker``: tell whether the robot kept within 0.5 m for 10 s."""
        if self._progress is None or math.dist(pose[:2], self._progress[1]) > \
                REQUIRED_MOVEMENT_RADIUS:
            self._progress = (stamp, tuple(pose[:2]))
            return False
        return stamp - self._progress[0] > MOVEMENT_TIME_ALLOWANCE

    def _blocked_ahead(self, pose):
        """Tell whether a blocked cell lies on the path within `STOP_DISTANCE` ahead."""
        distance = np.hypot(self._path_xy[:, 0] - pose[0], self._path_xy[:, 1] - pose[1])
        closest = int(np.argmin(distance))
        ahead = self.path[closest + 1:]
        steps = np.hypot(*np.diff(self._path_xy[closest:], axis=0).T)
        near = np.cumsum(steps) <= STOP_DISTANCE
        if not near.any():
            return False
        cells = ahead[near]
        return bool(blocked_mask(self.grid.labels[cells[:, 0], cells[:, 1]]).any())

    def _footprint_hits(self, pose, spin):
        """
        Tell whether the footprint would touch a lethal layer cell in the next 2 s.

        As the behaviours' collision check (``simulate_ahead_time``): the rectangle of
        ``robot_length`` x ``robot_width`` at the poses a spin (or back-up) reaches within
        `SIMULATE_AHEAD_TIME`, against the obstacle layer's lethal cells.
        """
        half_length, half_width = self._footprint_box
        reach = math.hypot(half_length, half_width) + BACKUP_SPEED * SIMULATE_AHEAD_TIME
        geometry = self.grid.layer_geometry
        rows, cols = geometry.cell_window(pose[0] - reach, pose[0] + reach, pose[1] - reach,
                                          pose[1] + reach)
        lethal = self.grid.lethal[rows, cols]
        if not lethal.any():
            return False
        rr, cc = np.nonzero(lethal)
        x, y = geometry.cell_to_world(rr + rows.start, cc + cols.start)
        if spin:
            headings = pose[2] + np.linspace(0.0, min(SPIN_DISTANCE, MAX_ROTATIONAL_VEL
                                                      * SIMULATE_AHEAD_TIME), 16)
            offsets = [(0.0, heading) for heading in headings]
        else:
            offsets = [(-d, pose[2]) for d in np.linspace(0.0, BACKUP_DISTANCE, 7)]
        for shift, heading in offsets:
            cx = pose[0] + shift * math.cos(pose[2])
            cy = pose[1] + shift * math.sin(pose[2])
            dx, dy = x - cx, y - cy
            along = dx * math.cos(heading) + dy * math.sin(heading)
            across = -dx * math.sin(heading) + dy * math.cos(heading)
            if ((np.abs(along) < half_length) & (np.abs(across) < half_width)).any():
                return True
        return False
