"""
Needless standstills: spells the robot stands still while a free route to the goal is open.

Issue 31 asks that no episode has the robot stand still for more than 30 s while a free route
exists in the true map and no agent is within 2 m of it. The episode log keeps only the total
time standing still (``still_time``), which counts waiting for an agent that blocks the only
corridor as much as standing in front of an open one. Episodes are deterministic (a rerun
reproduces its row field for field), so this module reruns the episodes of a log whose total
reaches a threshold, records the true state once per scan, and measures:

- **still spells**: runs of scans with the true speeds below ``episode_metrics.STILL_LINEAR``
  and ``STILL_ANGULAR``;
- **needless** scans of a spell, checked every ``period`` seconds: the true map (the reference
  clearance grid of ``episode.shortest_path_length``: 0.25 m cells keeping
  ``HUSKY_HALF_WIDTH`` from walls) holds a route from the robot to the goal, and no agent's
  centre is within ``clearance`` of a point of that route (the shortest one, by A*); a check
  holds until the next;
- the **longest needless spell** [s]: the longest run of needless checks inside one still
  spell, from its first check to the next check that is not needless or the spell's end.

``python -m dpn_navigator.benchmark.standstill LOG_DIR`` prints one line per rerun episode and
says whether each rerun reproduced its logged row (time and success); an episode that did not
is reported, not measured.

"""

import argparse
import json
import math
from pathlib import Path
import sys

import numpy as np

from .episode_metrics import STILL_ANGULAR, STILL_LINEAR

#: No agent's centre within this distance of the route [m] (issue 31).
AGENT_CLEARANCE = 2.0
#: Time between two route checks within a still spell [s].
CHECK_PERIOD = 0.5
#: A robot whose cell is not clear in the reference grid starts its route from the nearest
#: clear cell within this distance [m].
SNAP_DISTANCE = 0.5
#: Episodes standing still at least this long in total are rerun by default [s].
DEFAULT_MIN_STILL = 30.0


def still_spells(times, velocities):
    """
    Return the spells of standing still, as index ranges of the recorded scans.

    Parameters
    ----------
    times : (T,) array_like of float
        Scan times [s], increasing.
    velocities : (T, 2) array_like of float
        True ``(v, omega)`` [m/s, rad/s] at each scan.

    Returns
    -------
    list of (int, int)
        ``(first, end)``: scans ``first .. end - 1`` are still, the spell lasting
        ``times[end] - times[first]`` (to the last scan for a spell at the end).

    """
    velocities = np.asarray(velocities, dtype=np.float64).reshape(-1, 2)
    still = ((np.abs(velocities[:, 0]) < STILL_LINEAR)
             & (np.abs(velocities[:, 1]) < STILL_ANGULAR))
    edges = np.diff(np.concatenate(([0], still.astype(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return list(zip(starts.tolist(), ends.tolist()))


class RouteCheck:
    """
    The true map's routes to a goal, from the reference clearance grid.

    Parameters
    ----------
    clear : (rows, cols) ndarray of bool
        Cells where the robot fits (``ClearanceGrid.clear``).
    geometry : dpn_navigator.core.grid_geometry.GridGeometry
        Their grid.
    goal : (float, float)
        The goal [m], map frame.

    """

    def __init__(self, clear, geometry, goal):
        self.clear = np.asarray(clear, dtype=bool)
        self.geometry = geometry
        self.goal_cell = self._cell(goal)

    @classmethod
    def of_scenario(cls, scenario, goal):
        """Build the check on a scenario's reference clearance grid (``shortest_path_length``)."""
        from sim_bridge.free_space import clearance_grid
        from .episode import HUSKY_HALF_WIDTH, REFERENCE_CELL
        grid = clearance_grid(scenario.free, scenario.geometry, HUSKY_HALF_WIDTH,
                              cell_size=REFERENCE_CELL)
        return cls(grid.clear, grid.geometry, goal)

    def _cell(self, xy):
        """Return the clear cell at ``xy`` or the nearest within `SNAP_DISTANCE`, or None."""
        row, col = (int(v) for v in self.geometry.world_to_cell(float(xy[0]), float(xy[1])))
        reach = int(math.ceil(SNAP_DISTANCE / self.geometry.resolution))
        rows, cols = self.clear.shape
        r0, r1 = max(0, row - reach), min(rows, row + reach + 1)
        c0, c1 = max(0, col - reach), min(cols, col + reach + 1)
        if r0 >= r1 or c0 >= c1:
            return None
        window_r, window_c = np.nonzero(self.clear[r0:r1, c0:c1])
        if window_r.shape[0] == 0:
            return None
        distance = np.hypot(window_r + r0 - row, window_c + c0 - col)
        best = int(np.argmin(distance))
        if distance[best] * self.geometry.resolution > SNAP_DISTANCE:
            return None
        return int(window_r[best] + r0), int(window_c[best] + c0)

    def route(self, xy):
        """
        Return the shortest true route from ``xy`` to the goal, or None when there is none.

        Returns
        -------
        (K, 2) ndarray of float64 or None
            The route's cell centres [m], map frame, from the robot's cell to the goal's.

        """
        from ..core.planning.astar_search import astar
        start = self._cell(xy)
        if start is None or self.goal_cell is None:
            return None
        path = astar(~self.clear, start, self.goal_cell)
        if path is None:
            return None
        path = np.asarray(path)
        x, y = self.geometry.cell_to_world(path[:, 0], path[:, 1])
        return np.column_stack((x, y))


def longest_needless_standstill(times, poses, velocities, agent_xy, route_check,
                                clearance=AGENT_CLEARANCE, period=CHECK_PERIOD):
    """
    Return the longest spell standing still while an open route to the goal existed.

    Parameters
    ----------
    times : (T,) array_like of float
        Scan times [s], increasing.
    poses : (T, 3) array_like of float
        True base poses ``(x, y, yaw)`` [m, m, rad].
    velocities : (T, 2) array_like of float
        True ``(v, omega)`` [m/s, rad/s].
    agent_xy : sequence of (K, 2) array_like of float
        The agents' true centres at each scan [m] (K may be 0).
    route_check : object
        ``route_check.route(xy)`` returns the true route from ``xy`` as (K, 2) points [m], or
        None (`RouteCheck`).
    clearance : float
        An agent's centre within this distance of a route point closes the route [m].
    period : float
        Time between two checks within a spell [s], > 0.

    Returns
    -------
    longest_still : float
        The longest still spell [s].
    longest_needless : float
        Its needless part's longest run [s] (see the module's docstring).

    """
    times = np.asarray(times, dtype=np.float64).reshape(-1)
    poses = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    if not period > 0.0:
        raise ValueError(f'period must be positive, got {period!r}')
    longest_still = longest_needless = 0.0
    for first, end in still_spells(times, velocities):
        stop = times[min(end, times.shape[0] - 1)]
        longest_still = max(longest_still, float(stop - times[first]))
        checks, next_check = [], -math.inf
        for index in range(first, end):
            if times[index] >= next_check:
                checks.append((times[index], _open(route_check, poses[index, :2],
                                                   agent_xy[index], clearance)))
                next_check = times[index] + period
        run_start = None
        for (time, needless) in checks + [(stop, False)]:
            if needless and run_start is None:
                run_start = time
            elif not needless and run_start is not None:
                longest_needless = max(longest_needless, float(time - run_start))
                run_start = None
    return longest_still, longest_needless


def _open(route_check, xy, agents, clearance):
    """Tell whether a route from ``xy`` exists with no agent centre within ``clearance``."""
    route = route_check.route(xy)
    if route is None:
        return False
    agents = np.asarray(agents, dtype=np.float64).reshape(-1, 2)
    if agents.shape[0] == 0:
        return True
    dx = route[:, None, 0] - agents[None, :, 0]
    dy = route[:, None, 1] - agents[None, :, 1]
    return bool(np.hypot(dx, dy).min() > clearance)


def rerun(row, navigator, episode_options=None, index=None):
    """
    Rerun one logged episode and measure its standstills.

    Parameters
    ----------
    row : dict
        A row of ``episode_log.read_log``.
    navigator : str
        A name of ``protocol.NAVIGATORS``, or a plug-in's ``'package.module:Class'`` (the
        log's ``run.json``).
    episode_options : dict, optional
        As ``runner.run_spec``'s.
    index : str, optional
        The scenario index.

    Returns
    -------
    dict
        ``reproduced`` (the rerun's time and success are the row's), ``time``, ``success``,
        ``longest_still`` and ``longest_needless`` [s].

    """
    from .episode import run_episode
    from .protocol import MAP_MODELS, NAVIGATORS
    from .runner import _scenario, _task_setup, episode_keywords
    scenario = _scenario(row['map'], index)
    options = dict(episode_options or {})
    agents = options.get('agents', 'p3at')
    goal = scenario.tasks[row['task']].goal
    recorded = {'times': [], 'poses': [], 'velocities': [], 'agents': []}

    def recorder(world, _navigator):
        recorded['times'].append(world.time)
        recorded['poses'].append(tuple(world.husky_pose))
        recorded['velocities'].append(tuple(world.husky_velocity))
        recorded['agents'].append(np.asarray(world.wanderer_positions,
                                             dtype=np.float64).reshape(-1, 2))

    if navigator not in NAVIGATORS:
        options['navigator_class'] = navigator              # a plug-in, 'package.module:Class'
    result = run_episode(scenario, row['task'], row['wanderers'], row['seed'],
                         navigator_options=NAVIGATORS.get(navigator, {}), detection=False,
                         setup=_task_setup(row['map'], index, row['task'], agents),
                         recorder=recorder, map_model=MAP_MODELS.get(navigator, 'labels'),
                         **episode_keywords(options))
    success = int(result.success)
    reproduced = (math.isclose(result.time, row['time'], abs_tol=1e-6)
                  and success == row['success'])
    still, needless = longest_needless_standstill(
        recorded['times'], recorded['poses'], recorded['velocities'], recorded['agents'],
        RouteCheck.of_scenario(scenario, goal))
    return {'reproduced': reproduced, 'time': result.time, 'success': success,
            'longest_still': still, 'longest_needless': needless}


def main(argv=None):
    """Rerun a log's long standstills and print their longest needless spells."""
    from .episode_log import read_log
    parser = argparse.ArgumentParser(
        prog='python -m dpn_navigator.benchmark.standstill',
        description='Rerun the episodes of a benchmark log that stood still at least '
                    '--min-still seconds in total, and print the longest spell standing still '
                    'while the true map held a route to the goal with no agent within 2 m.')
    parser.add_argument('log_dir', help='a dpn-benchmark output folder (episodes.csv, run.json)')
    parser.add_argument('--min-still', type=float, default=DEFAULT_MIN_STILL, metavar='S',
                        help='rerun episodes whose still_time is at least this [s] '
                             f'(default {DEFAULT_MIN_STILL:g})')
    parser.add_argument('--navigator', help="the log's navigator (default: run.json's)")
    args = parser.parse_args(argv)
    folder = Path(args.log_dir)
    rows = read_log(folder / 'episodes.csv')
    run = {}
    if (folder / 'run.json').is_file():
        run = json.loads((folder / 'run.json').read_text(encoding='utf-8'))
    navigator = args.navigator or run.get('navigator')
    if navigator is None:
        parser.error(f'{folder}/run.json names no navigator; give --navigator')
    options = {key: run[key] for key in ('agents', 'laser', 'pose_noise') if run.get(key)}
    chosen = [row for row in rows if (row.get('still_time') or 0.0) >= args.min_still]
    print(f'{len(chosen)} of {len(rows)} episodes stood still >= {args.min_still:g} s in total')
    print('map task wanderers repetition | success time still_total | longest_still '
          'longest_needless | reproduced')
    worst = 0.0
    for row in chosen:
        got = rerun(row, navigator, options)
        print(f"{row['map']} {row['task']} {row['wanderers']} {row['repetition']} | "
              f"{row['success']} {row['time']:.1f} {row['still_time']:.1f} | "
              f"{got['longest_still']:.1f} {got['longest_needless']:.1f} | "
              f"{'yes' if got['reproduced'] else 'NO'}", flush=True)
        if got['reproduced']:
            worst = max(worst, got['longest_needless'])
    print(f'longest needless standstill: {worst:.1f} s')
    return 0


if __name__ == '__main__':
    sys.exit(main())
