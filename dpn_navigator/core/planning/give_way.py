"""
Giving way: step aside for an agent that waits for the robot, so that neither waits for ever.

A polite agent (a P3-AT of the benchmark, a person in a corridor) stops while the robot stands
in its way; the robot waits in front of the agent's mobile cells, or finds no path while the
agent stands by its goal. Neither moves: a mutual wait that only ends at the time limit (the
held-out town run of issue 30: a P3-AT stood by the goal for 120 s, 0.9 m from the waiting
robot). Nav2's default behaviour tree breaks such a wait by backing up 0.3 m, blind; that
frees a wide room, not a corridor, where the agent stops again 1.5 m further on.

`GiveWay` notices the wait (the robot has stood within `STILL_DISTANCE` of one place for
``wait_time`` with an agent within `BLOCKER_RADII` safety radii of it) and looks for a place to
give way from, within ``search_distance`` of the robot on the known map: the nearest, by the
way there, off the agent's way. An agent is the obstacle cells that were mobile within
`AGENT_MEMORY` (an agent that has stood a few seconds is labelled steady: dpn's motion tracks
hold it mobile only while it moves). Off its way means, with the robot's body at the place
(the cells within `PASS_RADII` safety radii of it, where the agent's centre cannot pass):

- the agent still reaches every cell the robot could reach but `CUT_CELLS` (a pocket); and
- it reaches every way out of the searched window (a cell on its edge the robot could reach;
  beyond lies the rest of the map) at most `DETOUR_CELLS` later than with the robot gone. A
  polite agent stops while the robot stands ahead of it on its way, even with room to go
  round: the robot at the mouth of a side room leaves a way through the room, but not one the
  agent takes.

The robot drives there, turns to face the agents (its laser sees half a turn; behind it an
agent's cells expire and the way looks open) and waits while the agent passes: up to
``hold_time``, less once a path to the goal enters no agent's cell (the navigator plans every
retry period); then it plans to its goal again. In a corridor with a side room
behind the robot the place is deep enough in the room; in a street, a step to its side; with
no such place in reach, the robot keeps waiting and looks again after ``wait_time``.

Everything is done on the cells within ``search_distance`` of the robot: 4-connected floods
with numpy over that window, once per wait, not per scan.

"""

import math

import numpy as np

from ..cell_label import blocked_mask, CellLabel

#: The robot stands still while it stays within this distance of where it stopped [m].
STILL_DISTANCE = 0.3

#: Mobile cells within this many safety radii of a robot that stands still are an agent it
#: may wait for.
BLOCKER_RADII = 4.0

#: An agent's centre cannot pass within this many safety radii of the robot's (its body and
#: the robot's, each about one safety radius).
PASS_RADII = 2.0

#: Cells the robot may cut off from the agent at its place besides the pass disc (a pocket).
CUT_CELLS = 4

#: How much later [cells] the agent may reach a way out of the searched window (a cell on its
#: edge the robot could reach) with the robot at its place: the robot is off the agent's way.
DETOUR_CELLS = 2

#: Obstacle cells that were mobile this recently are an agent's [s].
AGENT_MEMORY = 60.0

#: At most this many places are tried, nearest first.
MAX_TRIED = 150

#: The robot has arrived at its place within this distance [m].
ARRIVED = 0.3

#: At its place the robot turns to face the agents (its laser covers half a turn) to within
#: this angle before it judges whether they have gone by [rad].
FACE_TOLERANCE = 0.3


def flood(passable, seeds):
    """
    Return the 4-connected geodesic distance from ``seeds`` through ``passable`` [cells].

    Parameters
    ----------
    passable : (H, W) ndarray of bool
        Cells that may be entered.
    seeds : (H, W) ndarray of bool
        Where the flood starts (distance 0); seeds need not be passable.

    Returns
    -------
    distance : (H, W) ndarray of int32
        Steps from the nearest seed, -1 where not reached.

    """
    passable = np.asarray(passable, dtype=bool)
    seeds = np.asarray(seeds, dtype=bool)
    if passable.shape != seeds.shape or passable.ndim != 2:
        raise ValueError(f'passable and seeds must be equal 2-D shapes, got {passable.shape} '
                         f'and {seeds.shape}')
    distance = np.full(passable.shape, -1, dtype=np.int32)
    reached = seeds.copy()
    distance[reached] = 0
    frontier = reached
    step = 0
    while frontier.any():
        step += 1
        grown = np.zeros_like(frontier)
        grown[1:] |= frontier[:-1]
        grown[:-1] |= frontier[1:]
        grown[:, 1:] |= frontier[:, :-1]
        grown[:, :-1] |= frontier[:, 1:]
        frontier = grown & passable & ~reached
        reached |= frontier
        distance[frontier] = step
    return distance


def _disc(shape, centre, radius_cells):
    """Return the cells of ``shape`` whose centres lie within ``radius_cells`` of ``centre``."""
    rr, cc = np.ogrid[:shape[0], :shape[1]]
    return (rr - centre[0]) ** 2 + (cc - centre[1]) ** 2 <= radius_cells ** 2


def find_place(labels, agents, robot_cell, safety_radius, resolution, search_distance):
    """
    Find where the robot gives way to the agents near it.

    Parameters
    ----------
    labels : (H, W) ndarray of uint8
        The grid's labels (`CellLabel`), usually a window around the robot.
    agents : (H, W) ndarray of bool
        The cells of agents (obstacle cells that were mobile lately).
    robot_cell : (int, int)
        The robot's ``(row, col)`` in ``labels``.
    safety_radius : float
        The safety radius r [m], > 0.
    resolution : float
        Cell side [m], > 0.
    search_distance : float
        Farthest place tried, along the way there [m].

    Returns
    -------
    way : (N, 2) ndarray of int64, or None
        The cells ``(row, col)`` from the robot's to the place, 4-connected, ``N >= 2``; None
        when no agent is near or no place in reach is off its way.

    """
    labels = np.asarray(labels)
    agents = np.asarray(agents, dtype=bool)
    if labels.ndim != 2 or agents.shape != labels.shape:
        raise ValueError(f'labels must be 2-D and agents of its shape, got {labels.shape} and '
                         f'{agents.shape}')
    shape = labels.shape
    row, col = (int(v) for v in robot_cell)
    if not (0 <= row < shape[0] and 0 <= col < shape[1]):
        raise ValueError(f'robot_cell {robot_cell} lies outside labels of shape {shape}')
    near = _disc(shape, (row, col), BLOCKER_RADII * safety_radius / resolution)
    if not (agents & near).any():
        return None
    # The agents near: the blobs of agent cells with a cell near the robot.
    agents = flood(agents, agents & near) >= 0
    free = ~blocked_mask(labels)
    robot = np.zeros(shape, dtype=bool)
    robot[row, col] = True
    # Where the robot can go without coming closer to the agents than a cell, or than it is
    # (it may stand next to them).
    apart = flood(np.ones(shape, dtype=bool), agents)
    keep_off = (apart <= 1) & (apart < apart[row, col])
    way = flood(free & ~agents & ~keep_off, robot)
    reachable = way >= 0
    limit = search_distance / resolution
    pass_cells = PASS_RADII * safety_radius / resolution
    candidates = np.flatnonzero(reachable & (way >= 1) & (way <= limit))
    candidates = candidates[np.argsort(way.ravel()[candidates], kind='stable')][:MAX_TRIED]
    agent_space = free | agents
    exits = reachable & _edge(shape)
    unhindered = flood(agent_space, agents)[exits]
    for index in candidates:
        place = divmod(int(index), shape[1])
        body = _disc(shape, place, pass_cells)
        hindered = flood(agent_space & ~body, agents)
        cut = reachable & ~body & (hindered < 0)
        if np.count_nonzero(cut) > CUT_CELLS or (cut & exits).any():
            continue
        open_exits = ~body[exits]
        if np.all(hindered[exits][open_exits] <= unhindered[open_exits] + DETOUR_CELLS):
            return _way_back(way, place)
    return None


def _edge(shape):
    """Return the cells on the edge of an array of ``shape`` (beyond lies the rest of the map)."""
    edge = np.zeros(shape, dtype=bool)
    edge[[0, -1], :] = True
    edge[:, [0, -1]] = True
    return edge


def _way_back(way, place):
    """Return the cells from distance 0 of ``way`` to ``place``, each one step apart."""
    cells = [place]
    row, col = place
    while way[row, col] > 0:
        step = way[row, col] - 1
        for d_row, d_col in ((-1, 0), (1, 0), (0, -1), (0, 1)):
            r, c = row + d_row, col + d_col
            if 0 <= r < way.shape[0] and 0 <= c < way.shape[1] and way[r, c] == step:
                row, col = r, c
                break
        cells.append((row, col))
    return np.array(cells[::-1], dtype=np.int64)


class GiveWay:
    """
    When to give way to a waiting agent, and the way to the place it is given from.

    Parameters
    ----------
    shape : (int, int)
        The grid's ``(rows, cols)``.
    wait_time : float
        Standing still this long near an agent starts a search for a place [s], > 0.
    search_distance : float
        Farthest place, along the way there [m], > 0.
    hold_time : float
        Longest wait at the place [s], >= 0.

    Attributes
    ----------
    last_mobile : (rows, cols) ndarray of float64
        When each cell was last seen mobile [s], -inf for never.
    way_xy : (N, 2) ndarray of float64, or None
        The way to the place in the map frame [m] while giving way.
    agents_xy : (float, float) or None
        The centre of the agents' cells when the way was found [m].
    given : int
        How many times the robot went to give way.
    held_since : float or None
        When the robot arrived at the place [s].

    """

    def __init__(self, shape, wait_time, search_distance, hold_time):
        for name, value in (('wait_time', wait_time), ('search_distance', search_distance)):
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be positive, got {value!r}')
        if not (math.isfinite(hold_time) and hold_time >= 0.0):
            raise ValueError(f'hold_time must be finite and >= 0, got {hold_time!r}')
        self.last_mobile = np.full(shape, -math.inf)
        self.wait_time = float(wait_time)
        self.search_distance = float(search_distance)
        self.hold_time = float(hold_time)
        self.given = 0
        self.reset()

    def reset(self):
        """Forget the wait and any way (a new goal, or the way given up)."""
        self.way_xy = None
        self.agents_xy = None
        self.held_since = None
        self._still_at = None
        self._still_since = None
        self._started = None

    def grow(self, growth, shape):
        """Follow the grid as it grows (``map_growth.GridGrowth``) to ``shape``."""
        self.last_mobile = growth.embed(self.last_mobile, shape, -math.inf)

    @property
    def nbytes(self):
        """Bytes held by the per-cell array."""
        return self.last_mobile.nbytes

    def observe(self, labels, window, stamp):
        """Record the mobile cells of one update's ``window`` (its row and column slices first)."""
        rows, cols = window[0], window[1]
        self.last_mobile[rows, cols][labels[rows, cols] == CellLabel.MOBILE_OBSTACLE] = stamp

    @property
    def active(self):
        """Tell whether the robot is driving to the place or waiting there."""
        return self.way_xy is not None

    def note(self, stamp, robot_xy):
        """Record the robot's position ``robot_xy`` [m] at ``stamp`` [s]."""
        if self._still_at is None or math.dist(self._still_at, robot_xy) > STILL_DISTANCE:
            self._still_at = (float(robot_xy[0]), float(robot_xy[1]))
            self._still_since = float(stamp)

    def due(self, stamp):
        """Tell whether the robot has stood still for ``wait_time``."""
        return (not self.active and self._still_since is not None
                and stamp - self._still_since >= self.wait_time)

    def agents(self, labels, stamp):
        """Return the agents' cells: obstacles now, mobile within `AGENT_MEMORY` of ``stamp``."""
        return blocked_mask(labels) & (self.last_mobile >= stamp - AGENT_MEMORY)

    def start(self, grid, robot_xy, safety_radius, stamp):
        """
        Look for a place to give way from; True when found (then `way_xy` is set).

        Not found, the wait counts again from ``stamp``.

        Parameters
        ----------
        grid : LabelGrid
            The navigator's grid (its ``labels`` and ``geometry``).
        robot_xy : (float, float)
            The robot in the map frame [m].
        safety_radius : float
            The safety radius r [m].
        stamp : float
            Now [s].

        """
        geometry = grid.geometry
        reach = self.search_distance + BLOCKER_RADII * safety_radius
        rows, cols = geometry.cell_window(robot_xy[0] - reach, robot_xy[0] + reach,
                                          robot_xy[1] - reach, robot_xy[1] + reach)
        cell = geometry.world_to_cell(robot_xy[0], robot_xy[1])
        self._still_since = float(stamp)
        if not geometry.contains_cell(*cell):
            return False
        window = grid.labels[rows, cols]
        agents = blocked_mask(window) & (self.last_mobile[rows, cols] >= stamp - AGENT_MEMORY)
        local = (int(cell[0]) - rows.start, int(cell[1]) - cols.start)
        way = find_place(window, agents, local, safety_radius, geometry.resolution,
                         self.search_distance)
        if way is None:
            return False
        x, y = geometry.cell_to_world(way[:, 0] + rows.start, way[:, 1] + cols.start)
        self.way_xy = np.column_stack((x, y)).astype(np.float64)
        seen = np.argwhere(agents)
        ax, ay = geometry.cell_to_world(seen[:, 0] + rows.start, seen[:, 1] + cols.start)
        self.agents_xy = (float(np.mean(ax)), float(np.mean(ay)))
        self._started = float(stamp)
        self.given += 1
        return True

    def arrived(self, stamp, robot_xy):
        """Tell whether the robot is at the place; the hold starts when it first is."""
        if self.held_since is None and math.dist(robot_xy, self.way_xy[-1]) <= ARRIVED:
            self.held_since = float(stamp)
        return self.held_since is not None

    def facing_error(self, pose):
        """Return the turn [rad] that faces the robot at ``pose`` towards the agents."""
        bearing = math.atan2(self.agents_xy[1] - pose[1], self.agents_xy[0] - pose[0])
        return math.remainder(bearing - pose[2], 2.0 * math.pi)

    def done(self, stamp):
        """Tell whether the robot has waited ``hold_time`` at the place."""
        return self.held_since is not None and stamp - self.held_since >= self.hold_time

    def crosses_agents(self, cells, labels, stamp):
        """
        Tell whether a path enters an agent's cell now (one planned through at a wait's cost).

        Parameters
        ----------
        cells : (N, 2) ndarray of int
            The path's ``(row, col)`` cells.
        labels : (rows, cols) ndarray of uint8
            The grid's labels.
        stamp : float
            Now [s].

        """
        cells = np.asarray(cells, dtype=np.int64)
        rr, cc = cells[:, 0], cells[:, 1]
        return bool((blocked_mask(labels[rr, cc])
                     & (self.last_mobile[rr, cc] >= stamp - AGENT_MEMORY)).any())

    def given_up(self, stamp, grid, robot_xy, speed):
        """
        Tell whether the drive to the place is to be given up.

        It is when a cell of the way ahead of the robot (at ``robot_xy`` [m]) is an obstacle
        now, or when the drive has taken longer than ``wait_time`` plus twice the way's
        length at ``speed`` [m/s].
        """
        length = float(np.hypot(*np.diff(self.way_xy, axis=0).T).sum())
        if stamp - self._started > self.wait_time + 2.0 * length / speed:
            return True
        geometry = grid.geometry
        distance = np.hypot(self.way_xy[:, 0] - robot_xy[0], self.way_xy[:, 1] - robot_xy[1])
        closest = int(np.argmin(distance))
        ahead = self.way_xy[closest + 1:]
        rr, cc = geometry.world_to_cell(ahead[:, 0], ahead[:, 1])
        inside = geometry.contains_cell(rr, cc)
        return bool(blocked_mask(grid.labels[rr[inside], cc[inside]]).any())
