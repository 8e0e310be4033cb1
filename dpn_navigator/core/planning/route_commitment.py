"""
Commitment to a route: mobile obstacles priced by distance, and a margin before a switch.

The paper replans whenever a cell of the path turns obstacle and takes the shortest path on
the map as it is. A wanderer 10 m ahead in one of two parallel corridors then sends the robot
to the other, and back when it walks into that one: the robot shuttles between corridors.
`RouteCommitment` changes three things, each with a parameter:

- a mobile cell farther than ``block_distance`` from the robot does not block (it will have
  moved on by the time the robot gets there);
- a mobile cell within it, but farther than `WAIT_STOP_DISTANCE`, costs the expected wait,
  ``wait_time`` plus the time already waited, as a distance at ``speed`` spread over the
  cells a moving object's blob spans along a path (``blob_depth``) (0 ``wait_time``: it
  blocks), so that a detour is taken only when it is shorter than waiting, and the robot
  stops in front of it to wait (`must_wait`); one closer still blocks, as before (a wanderer
  that comes up to a waiting robot is given way to, by a detour if there is one);
- a new plan replaces the current route only when it is cheaper by ``switch_margin``, or
  when the current route is blocked;
- a route left because it was blocked is not taken back for ``block_memory`` seconds: a new
  plan that enters a cell which blocked a route within that time does not replace a current
  route that is open. A P3-AT standing beside the corridor flickers the cell next to it
  between mobile and free from scan to scan; without this memory the robot switched between
  that corridor and a way round 19 times in 30 s, turning back and forth on the spot, and
  never left (seed-0 u_turn, task 0, 9 wanderers). Off by default (the navigator's
  ``route_block_memory`` is 0): on the held-out seed it lost more goals than it won.

"""

import math

import numpy as np

from ..cell_label import blocked_mask, CellLabel

#: The robot stops to wait when a mobile cell on its path is this close ahead, along it [m];
#: mobile cells this close to the robot block.
WAIT_STOP_DISTANCE = 1.0


class RouteCommitment:
    """
    How mobile obstacles weigh on a plan, and whether a new plan replaces the route.

    Parameters
    ----------
    block_distance : float
        Mobile cells farther than this from the robot are planned through for free [m], > 0.
    switch_margin : float
        A new route must be cheaper than the current one by this [m], >= 0.
    wait_time : float
        The expected wait for a mobile obstacle within ``block_distance`` [s], >= 0; 0: those
        block.
    speed : float
        Speed that turns a wait into a distance [m/s], > 0.
    resolution : float
        Cell side [m], > 0.
    blob_depth : float
        How deep a moving object's blob of mobile cells is along a path crossing it [m]
        (its body and the safety radius on both sides), > 0; the wait is spread over it.
    block_memory : float
        How long the cells that blocked a route keep a new plan through them from replacing an
        open route [s], >= 0; 0: not at all.

    Attributes
    ----------
    waited : float
        How long the robot has been waiting in front of a mobile obstacle [s].
    switches : int
        How many times a replan changed the route for one cheaper by the margin.
    kept : int
        How many replans kept the current route.
    held_back : int
        How many new plans were refused for entering a cell that blocked a route within
        ``block_memory``.

    """

    def __init__(self, block_distance, switch_margin, wait_time, speed, resolution,
                 blob_depth=1.7, block_memory=0.0):
        if not (math.isfinite(block_distance) and block_distance > 0.0):
            raise ValueError(f'block_distance must be positive, got {block_distance!r}')
        for name, value in (('switch_margin', switch_margin), ('wait_time', wait_time),
                            ('block_memory', block_memory)):
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name} must be finite and >= 0, got {value!r}')
        if not (speed > 0.0 and resolution > 0.0 and blob_depth > 0.0):
            raise ValueError('speed, resolution and blob_depth must be positive')
        self.block_distance = float(block_distance)
        self.switch_margin = float(switch_margin)
        self.wait_time = float(wait_time)
        self.speed = float(speed)
        self.resolution = float(resolution)
        self.blob_depth = float(blob_depth)
        self.block_memory = float(block_memory)
        self.waited = 0.0
        self.switches = 0
        self.kept = 0
        self.held_back = 0
        self._waiting_since = None
        self._blockers_xy = np.empty((0, 2))   # centres of cells that blocked a route [m]
        self._blocker_stamps = np.empty(0)     # when each did [s]

    def reset(self):
        """Forget the wait and the cells that blocked a route (a new goal)."""
        self.waited = 0.0
        self._waiting_since = None
        self._blockers_xy = np.empty((0, 2))
        self._blocker_stamps = np.empty(0)

    def note_blockers(self, cells_xy, stamp):
        """
        Remember the cells that blocked the route being left (``block_memory`` > 0).

        Parameters
        ----------
        cells_xy : (N, 2) array_like of float
            The blocked cells' centres in the map frame [m].
        stamp : float
            Now [s].

        """
        if self.block_memory == 0.0:
            return
        cells_xy = np.asarray(cells_xy, dtype=np.float64).reshape(-1, 2)
        recent = self._recent(stamp)
        self._blockers_xy = np.concatenate((self._blockers_xy[recent], cells_xy))
        self._blocker_stamps = np.concatenate((self._blocker_stamps[recent],
                                               np.full(cells_xy.shape[0], float(stamp))))

    def enters_blocker(self, cells_xy, stamp):
        """
        Tell whether a plan enters a cell that blocked a route within ``block_memory``.

        Parameters
        ----------
        cells_xy : (N, 2) array_like of float
            The plan's cell centres in the map frame [m], the robot's cell first (not
            counted: the robot is in it).
        stamp : float
            Now [s].

        """
        recent = self._recent(stamp)
        if not recent.any():
            return False
        cells_xy = np.asarray(cells_xy, dtype=np.float64).reshape(-1, 2)[1:]
        blockers = self._blockers_xy[recent]
        # Cell centres: the same cell lies well within a quarter of a cell.
        same = (np.abs(cells_xy[:, None, :] - blockers[None, :, :])
                < 0.25 * self.resolution).all(axis=2)
        return bool(same.any())

    def _recent(self, stamp):
        """Mark the remembered blockers noted within ``block_memory`` before ``stamp``."""
        stamps = self._blocker_stamps
        return (stamps >= stamp - self.block_memory) & (stamps <= stamp)

    def mobile_terms(self, labels, geometry, robot_xy):
        """
        Return which mobile cells A* may enter, and what entering each costs.

        Parameters
        ----------
        labels : (rows, cols) ndarray of uint8
            The grid's labels.
        geometry : GridGeometry
            The grid's geometry.
        robot_xy : (float, float)
            The robot in the map frame [m].

        Returns
        -------
        opened : (rows, cols) ndarray of bool
            Mobile cells planned through: the far ones, and when waiting is on, the near ones
            farther than `WAIT_STOP_DISTANCE` from the robot.
        cost : (rows, cols) ndarray of float64
            The wait on the near opened cells [cells], 0 elsewhere: the wait's distance
            divided by the cells of a blob's depth.

        """
        mobile = labels == CellLabel.MOBILE_OBSTACLE
        near = mobile & self._near(geometry, labels.shape, robot_xy, self.block_distance)
        cost = np.zeros(labels.shape)
        if self.wait_time > 0.0:
            wait_cells = (self.wait_time + self.waited) * self.speed / self.resolution
            cost[near] = wait_cells / max(1.0, self.blob_depth / self.resolution)
            return mobile & ~self._near(geometry, labels.shape, robot_xy,
                                        WAIT_STOP_DISTANCE), cost
        return mobile & ~near, cost

    def opens(self, labels, cells_xy, robot_xy):
        """
        Tell which of some cells `mobile_terms` opens, from their labels and centres.

        Parameters
        ----------
        labels : (N,) ndarray of uint8
            The cells' labels.
        cells_xy : (N, 2) ndarray of float
            Their centres in the map frame [m].
        robot_xy : (float, float)
            The robot [m].

        Returns
        -------
        opened : (N,) ndarray of bool

        """
        mobile = labels == CellLabel.MOBILE_OBSTACLE
        distance = np.hypot(cells_xy[:, 0] - robot_xy[0], cells_xy[:, 1] - robot_xy[1])
        if self.wait_time > 0.0:
            return mobile & (distance > WAIT_STOP_DISTANCE)
        return mobile & (distance > self.block_distance)

    @staticmethod
    def _near(geometry, shape, robot_xy, reach):
        """Mark the cells whose centre lies within ``reach`` [m] of the robot."""
        near = np.zeros(shape, dtype=bool)
        rows, cols = geometry.cell_window(robot_xy[0] - reach, robot_xy[0] + reach,
                                          robot_xy[1] - reach, robot_xy[1] + reach)
        x_centres, y_centres = geometry.window_centres(rows, cols)
        near[rows, cols] = np.hypot(x_centres[None, :] - robot_xy[0],
                                    y_centres[:, None] - robot_xy[1]) <= reach
        return near

    def route_cost(self, path, blocked, cell_cost):
        """
        Return what A* would charge for ``path``, or inf when a cell after its first is blocked.

        Parameters
        ----------
        path : (N, 2) ndarray of int
            ``(row, col)`` cells, each an 8-neighbour of the one before.
        blocked : (rows, cols) ndarray of bool
            Cells A* may not enter.
        cell_cost : (rows, cols) ndarray of float64, or None
            Extra cost of entering each cell [cells].

        Returns
        -------
        cost : float
            Steps (1 and sqrt 2) plus the extra cost of every cell entered [cells].

        """
        if path.shape[0] < 2:
            return 0.0
        entered = path[1:]
        if blocked[entered[:, 0], entered[:, 1]].any():
            return math.inf
        steps = np.abs(np.diff(path, axis=0)).sum(axis=1)
        cost = float(np.where(steps == 2, math.sqrt(2.0), 1.0).sum())
        if cell_cost is not None:
            cost += float(cell_cost[entered[:, 0], entered[:, 1]].sum())
        return cost

    def keep_current(self, current_cost, new_cost, margin=None, count=True):
        """
        Tell whether the current route stays, and count the decision.

        Parameters
        ----------
        current_cost, new_cost : float
            The two routes' costs from `route_cost` [cells] (inf: blocked).
        margin : float, optional
            How much cheaper the new route must be [m] (default ``switch_margin``).
        count : bool
            Count the decision in ``kept`` or ``switches`` (not for a route review).

        Returns
        -------
        keep : bool
            True unless the new route is cheaper by the margin.

        """
        margin = self.switch_margin if margin is None else margin
        keep = math.isfinite(current_cost) and (
            new_cost > current_cost - margin / self.resolution)
        if count and keep:
            self.kept += 1
        elif count:
            self.switches += 1
        return keep

    def must_wait(self, path, path_xy, closest, labels, stamp):
        """
        Tell whether a mobile cell on the path lies within `WAIT_STOP_DISTANCE` ahead.

        Also keeps ``waited``: the time since the robot started waiting, 0 when it does not.

        Parameters
        ----------
        path : (N, 2) ndarray of int
            The path's ``(row, col)`` cells.
        path_xy : (N, 2) ndarray of float
            The path's cells in the map frame [m].
        closest : int
            Index of the path point closest to the robot.
        labels : (rows, cols) ndarray of uint8
            The grid's labels.
        stamp : float
            Now [s].

        Returns
        -------
        wait : bool

        """
        ahead = path[closest + 1:]
        wait = False
        if ahead.shape[0]:
            along = np.cumsum(np.hypot(*np.diff(path_xy[closest:], axis=0).T))
            close = ahead[along <= WAIT_STOP_DISTANCE]
            wait = bool((labels[close[:, 0], close[:, 1]] == CellLabel.MOBILE_OBSTACLE).any())
        if not wait:
            self._waiting_since = None
            self.waited = 0.0
        elif self._waiting_since is None:
            self._waiting_since = stamp
        else:
            self.waited = max(0.0, stamp - self._waiting_since)
        return wait

    @staticmethod
    def effective_blocked(labels, opened):
        """Return ``blocked_mask(labels)`` without the ``opened`` cells."""
        return blocked_mask(labels) & ~opened
