"""
Why the wanderers stand still: stop time by cause, longest stops and wanderer-wanderer jams.

Runs benchmark episodes (``run_episode``, the dpn navigator on its label map, no detection
measures) with the wanderers replaced by `MeasuredWanderers`, a subclass that only records:
every tick each wanderer is classed as

- ``moving``: its position changed;
- ``husky``: stopped because the Husky is ahead (``Wanderers._blocker`` returned it);
- ``wanderer``: stopped because another wanderer is ahead;
- ``wait_goal``: no path, waiting out its patience at a goal (or at its spawn point);
- ``wait_failed``: no path, waiting out its patience after a failed plan;
- ``turning``: turning in place towards its next waypoint (not a stop);
- ``other``: none of these (a zero-length move onto a waypoint).

A stop is a run of ticks in the four stop classes; the longest one per episode is reported.
For a ``wanderer`` stop the corridor width at the place is measured once, when the stop
starts: on the true map, across the line from the stopped wanderer to its blocker, through
their midpoint (free space on both sides, up to ``WIDTH_CAP``). A mutual block is a run of
ticks in which wanderer A is stopped for B and B for A.

Episodes are the benchmark's (``plan_episodes`` with base seed 0, so they match the project's
logs). With ``--arms off,on`` every episode runs twice, with ``WandererConfig()`` and with
``WandererConfig(mutual_yield=True)``, and the tables compare the two.

Not a test: it prints Markdown tables. Run with
``python benchmarks/wanderer_stops.py [--maps ...] [--arms off,on] [--repeats N]``.

"""

import argparse
import dataclasses
import json
import math
import sys
import time

from dpn_navigator.benchmark.episode import run_episode, task_setup
from dpn_navigator.benchmark.protocol import plan_episodes
import numpy as np
from sim_bridge.husky import HUSKY_RADIUS
from sim_bridge.scenario import load_scenario
from sim_bridge.wanderers import WandererConfig, Wanderers
import sim_bridge.world

NARROW_MAPS = ('alleys', 'maze', 'narrow_passages', 'square_spiral', 'tunnel_twisted',
               'tunnel', 'zigzag_narrow', 't_maze')
OPEN_MAPS = ('office', 'campus', 'warehouse')
#: Corridors narrower than this count as passages [m] (the issue's threshold).
NARROW_WIDTH = 2.6
#: Widths are measured up to this far on each side of the midpoint [m].
WIDTH_CAP = 6.0
BLOCKER_STATES = ('mutual', 'moving or turning', 'waiting, no path', 'stopped for another',
                  'other')
CLASSES = ('moving', 'turning', 'husky', 'wanderer', 'wait_goal', 'wait_failed', 'other')
STOP_CLASSES = ('husky', 'wanderer', 'wait_goal', 'wait_failed', 'other')
ARMS = {'off': WandererConfig(), 'on': None}  # 'on' filled in main (needs the option)


def corridor_width(free, geometry, x, y, ux, uy):
    """
    Width of free space across a direction, through a point.

    Parameters
    ----------
    free : (rows, cols) ndarray of bool
        Known-free cells of the true map.
    geometry : GridGeometry
        Its geometry.
    x, y : float
        The point [m].
    ux, uy : float
        Unit direction along the corridor [m/m]; the width is measured across it.

    Returns
    -------
    width : float
        Free length on the line through ``(x, y)`` perpendicular to ``(ux, uy)`` [m], up to
        ``2 * WIDTH_CAP``.

    """
    step = 0.5 * geometry.resolution
    s = np.arange(0.0, WIDTH_CAP + step, step)
    width = 0.0
    for side in (1.0, -1.0):
        px = x - side * uy * s
        py = y + side * ux * s
        rr, cc = geometry.world_to_cell(px, py)
        inside = geometry.contains_cell(rr, cc)
        ok = np.zeros(len(s), dtype=bool)
        ok[inside] = free[rr[inside], cc[inside]]
        blocked = np.flatnonzero(~ok)
        width += float(s[blocked[0]]) if len(blocked) else WIDTH_CAP
    return width


class MeasuredWanderers(Wanderers):
    """`Wanderers` that record why each one stands still; behaviour unchanged."""

    last = None   # the instance built last (the episode's)
    scenario = None

    def __init__(self, *args, **kwargs):
        self._rec_blocker = {}
        self._no_path_cause = None
        super().__init__(*args, **kwargs)
        n = len(self.yaws)
        self._no_path_cause = ['wait_goal'] * n
        self.seconds = dict.fromkeys(CLASSES, 0.0)
        self.narrow_wanderer_seconds = 0.0
        self.wide_wanderer_seconds = 0.0
        # Wanderer stops by what the wanderer ahead was doing in that tick [s].
        self.behind = dict.fromkeys(BLOCKER_STATES, 0.0)
        self.longest_stop = 0.0
        self._stop_run = [0.0] * n
        self._ww_width = [None] * n
        self._prev_blocker = [None] * n
        self._mutual_run = {}
        self.mutual_blocks = []
        MeasuredWanderers.last = self

    def _blocker(self, i, ux, uy, husky_xy):
        found = super()._blocker(i, ux, uy, husky_xy)
        if found is not None:
            if found == (husky_xy[0], husky_xy[1], HUSKY_RADIUS):
                self._rec_blocker[i] = -1
            else:
                self._rec_blocker[i] = next(j for j, xy in enumerate(self._xy)
                                            if j != i and xy[0] == found[0]
                                            and xy[1] == found[1])
        return found

    def _new_goal(self, i, husky_xy, blocker):
        found = super()._new_goal(i, husky_xy, blocker)
        if not found and self._no_path_cause is not None:
            self._no_path_cause[i] = 'wait_failed'
        return found

    def _reach_waypoint(self, i):
        super()._reach_waypoint(i)
        if not self._paths[i]:
            self._no_path_cause[i] = 'wait_goal'

    def step(self, dt, husky_xy):
        before_xy = self.positions.copy()
        before_yaw = self.yaws.copy()
        self._rec_blocker = {}
        moved = super().step(dt, husky_xy)
        n = len(before_yaw)
        blocked_by = [-2] * n
        causes = [self._classify(i, before_xy, before_yaw) for i in range(n)]
        for i in range(n):
            cause = causes[i]
            self.seconds[cause] += dt
            if cause in STOP_CLASSES:
                self._stop_run[i] += dt
                self.longest_stop = max(self.longest_stop, self._stop_run[i])
            else:
                self._stop_run[i] = 0.0
            if cause == 'wanderer':
                j = self._rec_blocker[i]
                blocked_by[i] = j
                ahead = causes[j]
                if ahead == 'wanderer' and self._rec_blocker[j] == i:
                    ahead = 'mutual'
                elif ahead in ('moving', 'turning'):
                    ahead = 'moving or turning'
                elif ahead in ('wait_goal', 'wait_failed'):
                    ahead = 'waiting, no path'
                elif ahead in ('husky', 'wanderer'):
                    ahead = 'stopped for another'
                else:
                    ahead = 'other'
                self.behind[ahead] += dt
                if self._prev_blocker[i] != j:
                    self._ww_width[i] = self._width_between(i, j)
                if self._ww_width[i] < NARROW_WIDTH:
                    self.narrow_wanderer_seconds += dt
                else:
                    self.wide_wanderer_seconds += dt
            self._prev_blocker[i] = blocked_by[i]
        for i in range(n):
            j = blocked_by[i]
            if j > i and blocked_by[j] == i:
                self._mutual_run[(i, j)] = self._mutual_run.get((i, j), 0.0) + dt
        for pair in [p for p in self._mutual_run if blocked_by[p[0]] != p[1] or
                     blocked_by[p[1]] != p[0]]:
            self.mutual_blocks.append(self._mutual_run.pop(pair))
        return moved

    def finish(self):
        """Close the mutual blocks still running at the end of the episode."""
        self.mutual_blocks.extend(self._mutual_run.values())
        self._mutual_run = {}

    def _classify(self, i, before_xy, before_yaw):
        if self.positions[i, 0] != before_xy[i, 0] or self.positions[i, 1] != before_xy[i, 1]:
            return 'moving'
        blocker = self._rec_blocker.get(i)
        if blocker is not None:
            return 'husky' if blocker == -1 else 'wanderer'
        if self.yaws[i] != before_yaw[i]:
            return 'turning'
        if not self._paths[i]:
            return self._no_path_cause[i]
        return 'other'

    def _width_between(self, i, j):
        (xi, yi), (xj, yj) = self.positions[i], self.positions[j]
        d = math.hypot(xj - xi, yj - yi)
        scenario = MeasuredWanderers.scenario
        return corridor_width(scenario.free, scenario.geometry, 0.5 * (xi + xj),
                              0.5 * (yi + yj), (xj - xi) / d, (yj - yi) / d)


def run_one(spec, scenario, setup, arm):
    """Run one episode with measured wanderers; return its row (dict)."""
    MeasuredWanderers.scenario = scenario
    sim_bridge.world.Wanderers = MeasuredWanderers
    try:
        started = time.process_time()
        result = run_episode(scenario, spec.task, spec.wanderers, spec.seed,
                             navigator_options={}, detection=False, setup=setup,
                             map_model='labels', wanderer_config=ARMS[arm])
        cpu = time.process_time() - started
    finally:
        sim_bridge.world.Wanderers = Wanderers
    w = MeasuredWanderers.last
    w.finish()
    return {'map': spec.map_key, 'task': spec.task, 'wanderers': spec.wanderers,
            'repetition': spec.repetition, 'seed': spec.seed, 'arm': arm,
            'success': result.success, 'failure': result.failure, 'time': result.time,
            'cpu': round(cpu, 2), 'seconds': w.seconds, 'narrow_ww': w.narrow_wanderer_seconds,
            'wide_ww': w.wide_wanderer_seconds, 'behind': w.behind,
            'longest_stop': w.longest_stop, 'mutual_blocks': w.mutual_blocks,
            'replans': w.replans, 'yields': w.yields, 'goals_reached': w.goals_reached}


def summarise(rows):
    """Aggregate rows of one group: shares of wanderer time [%], stops and mutual blocks."""
    total = sum(sum(r['seconds'].values()) for r in rows)
    share = {c: 100.0 * sum(r['seconds'][c] for r in rows) / total for c in CLASSES}
    ww = sum(r['narrow_ww'] + r['wide_ww'] for r in rows)
    mutual = [d for r in rows for d in r['mutual_blocks']]
    return {
        'episodes': len(rows), 'stopped': sum(share[c] for c in STOP_CLASSES), 'share': share,
        'narrow_ww': 100.0 * sum(r['narrow_ww'] for r in rows) / ww if ww else float('nan'),
        'longest': max(r['longest_stop'] for r in rows),
        'mutual': len(mutual), 'mutual_seconds': sum(mutual),
        'mutual_max': max(mutual, default=0.0),
        'success': sum(r['success'] for r in rows),
        'goals': sum(r['goals_reached'] for r in rows),
        'yields': sum(r.get('yields', 0) for r in rows),
        'behind': {k: 100.0 * sum(r['behind'][k] for r in rows) / total
                   for k in BLOCKER_STATES}}


def groups(rows):
    """Yield ``(label, rows)`` per map, then the narrow and open totals."""
    maps = list(dict.fromkeys(r['map'] for r in rows))
    for name in maps:
        yield name, [r for r in rows if r['map'] == name]
    for label, names in (('**narrow maps**', NARROW_MAPS), ('**open maps**', OPEN_MAPS)):
        chosen = [r for r in rows if r['map'] in names]
        if chosen:
            yield label, chosen


def table(rows):
    """Return the Markdown table of stop causes for one arm."""
    lines = ['| map | eps | stopped % | Husky % | wanderer % | wait at goal % | '
             'wait after failed plan % | turning % | w-w stop in < 2.6 m % | longest stop s | '
             'mutual blocks (n, total s, max s) | dpn success |',
             '|' + '---|' * 12]
    for label, chosen in groups(rows):
        s = summarise(chosen)
        sh = s['share']
        lines.append(
            f"| {label} | {s['episodes']} | {s['stopped']:.1f} | {sh['husky']:.1f} | "
            f"{sh['wanderer']:.1f} | {sh['wait_goal']:.1f} | {sh['wait_failed']:.1f} | "
            f"{sh['turning']:.1f} | {s['narrow_ww']:.0f} | {s['longest']:.1f} | "
            f"{s['mutual']}, {s['mutual_seconds']:.0f}, {s['mutual_max']:.1f} | "
            f"{s['success']}/{s['episodes']} |")
    return '\n'.join(lines)


def behind_table(rows):
    """Return the Markdown table of wanderer stops by what the wanderer ahead was doing."""
    lines = ['| map | wanderer % | ' + ' | '.join(f'ahead {k} %' for k in BLOCKER_STATES) +
             ' |', '|' + '---|' * (2 + len(BLOCKER_STATES))]
    for label, chosen in groups(rows):
        s = summarise(chosen)
        lines.append(f"| {label} | {s['share']['wanderer']:.1f} | " +
                     ' | '.join(f"{s['behind'][k]:.1f}" for k in BLOCKER_STATES) + ' |')
    return '\n'.join(lines)


def comparison(rows):
    """Return the Markdown table of option on against off, same episodes."""
    off = [r for r in rows if r['arm'] == 'off']
    on = [r for r in rows if r['arm'] == 'on']
    lines = ['| map | eps | stopped % off / on | wanderer % off / on | of which mutual % off / on '
             '| wait (both) % off / on | longest stop s off / on | mutual blocks off / on | '
             'mutual s off / on | yields on | goals reached on/off | dpn success off / on |',
             '|' + '---|' * 12]
    for (label, a), (_, b) in zip(groups(off), groups(on)):
        x, y = summarise(a), summarise(b)
        wait_x = x['share']['wait_goal'] + x['share']['wait_failed']
        wait_y = y['share']['wait_goal'] + y['share']['wait_failed']
        lines.append(
            f"| {label} | {x['episodes']} | {x['stopped']:.1f} / {y['stopped']:.1f} | "
            f"{x['share']['wanderer']:.1f} / {y['share']['wanderer']:.1f} | "
            f"{x['behind']['mutual']:.1f} / {y['behind']['mutual']:.1f} | "
            f"{wait_x:.1f} / {wait_y:.1f} | {x['longest']:.1f} / {y['longest']:.1f} | "
            f"{x['mutual']} / {y['mutual']} | {x['mutual_seconds']:.0f} / "
            f"{y['mutual_seconds']:.0f} | {y['yields']} | {y['goals'] / max(x['goals'], 1):.2f} | "
            f"{x['success']} / {y['success']} |")
    return '\n'.join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[1])
    parser.add_argument('--maps', nargs='+', default=list(NARROW_MAPS + OPEN_MAPS))
    parser.add_argument('--tasks', nargs='+', type=int, default=[0, 1])
    parser.add_argument('--wanderers', nargs='+', type=int, default=[5, 10])
    parser.add_argument('--repeats', type=int, default=1)
    parser.add_argument('--arms', default='off', help='off, on or off,on')
    parser.add_argument('--rows', help='JSON-lines file to write the rows to (or read with '
                        '--table-only)')
    parser.add_argument('--table-only', action='store_true')
    args = parser.parse_args(argv)
    arms = args.arms.split(',')
    if 'on' in arms:
        ARMS['on'] = dataclasses.replace(WandererConfig(), mutual_yield=True)
    rows = []
    if args.table_only:
        with open(args.rows) as f:
            rows = [json.loads(line) for line in f]
    else:
        out = open(args.rows, 'w') if args.rows else None
        specs = plan_episodes(args.maps, args.tasks, args.wanderers, args.repeats, 0)
        cache = {}
        for spec in specs:
            if spec.map_key not in cache:
                cache[spec.map_key] = (load_scenario(spec.map_key), {})
            scenario, setups = cache[spec.map_key]
            if spec.task not in setups:
                grid = next(iter(setups.values())).wanderer_grid if setups else None
                setups[spec.task] = task_setup(scenario, spec.task, grid)
            for arm in arms:
                row = run_one(spec, scenario, setups[spec.task], arm)
                rows.append(row)
                print(f"{row['map']} t{row['task']} w{row['wanderers']} r{row['repetition']} "
                      f"{arm}: success={row['success']} stop={row['longest_stop']:.1f}s "
                      f"cpu={row['cpu']}s", file=sys.stderr, flush=True)
                if out:
                    out.write(json.dumps(row) + '\n')
                    out.flush()
    for arm in arms:
        print(f'\n### Wanderer time by state, arm {arm} (% of wanderer-seconds)\n')
        print(table([r for r in rows if r['arm'] == arm]))
        print(f'\n### Stops for a wanderer by what it was doing, arm {arm} '
              '(% of wanderer-seconds)\n')
        print(behind_table([r for r in rows if r['arm'] == arm]))
    if len(arms) == 2:
        print('\n### Mutual yield on against off, same episodes\n')
        print(comparison(rows))


if __name__ == '__main__':
    main()
