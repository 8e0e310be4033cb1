"""
Tables and figures of an episode log: ``summary.md`` and ``success_rate.png`` (the paper's Fig. 7).

Both group the log's rows by map and wanderer count. Maps are ordered by their index number
(bare map_server maps last, by name). The summary ends with the detection table of
``detection_report``.

"""

from dataclasses import dataclass
import math

import numpy as np

from .detection_report import detection_markdown


@dataclass(frozen=True)
class CellStats:
    """
    Statistics of one group of episodes (one map and wanderer count, or one map).

    Attributes
    ----------
    episodes : int
        How many.
    success_rate : float
        Fraction that succeeded, in [0, 1].
    timeouts, no_paths, collisions : int
        Failures by reason.
    mean_time : float
        Mean simulated time of the successful episodes [s]; nan if none succeeded.
    mean_replans : float
        Mean paths planned per episode.
    wall_contacts, wanderer_contacts : int
        Episodes with at least one contact of each kind.
    robot_caused_contacts, agent_caused_contacts : int or None
        Wanderer contact events the Husky caused (it moved towards the agent) and the agents
        caused (the Husky stood or moved away), summed; None for a log before version 3.
    mean_walls_labelled_mobile, mean_ghost_obstacles : float
        Mean map-quality counts per episode [cells].

    """

    episodes: int
    success_rate: float
    timeouts: int
    no_paths: int
    collisions: int
    mean_time: float
    mean_replans: float
    wall_contacts: int
    wanderer_contacts: int
    robot_caused_contacts: object
    agent_caused_contacts: object
    mean_walls_labelled_mobile: float
    mean_ghost_obstacles: float


def cell_stats(rows):
    """
    Summarise a non-empty group of log rows.

    Parameters
    ----------
    rows : sequence of dict
        Rows as `episode_log.read_log` returns them.

    Returns
    -------
    CellStats

    """
    if not rows:
        raise ValueError('cannot summarise an empty group of episodes')
    success = np.array([row['success'] for row in rows], dtype=bool)
    times = np.array([row['time'] for row in rows], dtype=float)
    failures = [row['failure'] for row in rows]
    return CellStats(
        episodes=len(rows), success_rate=float(success.mean()),
        timeouts=failures.count('timeout'), no_paths=failures.count('no_path'),
        collisions=failures.count('collision'),
        mean_time=float(times[success].mean()) if success.any() else math.nan,
        mean_replans=float(np.mean([row['replans'] for row in rows])),
        wall_contacts=sum(row['wall_contacts'] > 0 for row in rows),
        wanderer_contacts=sum(row['wanderer_contacts'] > 0 for row in rows),
        robot_caused_contacts=_total(rows, 'robot_caused_contacts'),
        agent_caused_contacts=_total(rows, 'agent_caused_contacts'),
        mean_walls_labelled_mobile=float(np.mean([row['walls_labelled_mobile'] for row in rows])),
        mean_ghost_obstacles=float(np.mean([row['ghost_obstacles'] for row in rows])))


def _total(rows, column):
    """Return the sum of a count column, or None when a row lacks it (an older log)."""
    values = [row.get(column) for row in rows]
    return None if any(value is None for value in values) else sum(values)


def _kinds_text(stats):
    """Return the wanderer contact events as ``robot / agent`` ('-' for an older log)."""
    if stats.robot_caused_contacts is None or stats.agent_caused_contacts is None:
        return '-'
    return f'{stats.robot_caused_contacts} / {stats.agent_caused_contacts}'


def map_order(rows):
    """
    Return the maps of the rows as ``(map, number, label)``, ordered by index number.

    ``label`` is ``'<number> <name>'`` for index maps and the file stem for a bare map.
    """
    maps = {}
    for row in rows:
        maps.setdefault(row['map'], row['number'])
    ordered = sorted(maps.items(), key=lambda item: (item[1] is None, item[1] or 0, item[0]))
    labels = []
    for name, number in ordered:
        stem = name.rsplit('/', 1)[-1].rsplit('.', 1)[0]
        labels.append((name, number, stem if number is None else f'{number} {name}'))
    return labels


def group_rows(rows):
    """Group rows by ``(map, wanderers)``; return a dict of lists."""
    groups = {}
    for row in rows:
        groups.setdefault((row['map'], row['wanderers']), []).append(row)
    return groups


def summary_markdown(rows, title='dpn benchmark', navigator='dpn'):
    """
    Write the summary of an episode log as Markdown.

    Parameters
    ----------
    rows : sequence of dict
        Rows as `episode_log.read_log` returns them.
    title : str
        The first heading.
    navigator : str
        The navigator variant, for the detection table.

    Returns
    -------
    text : str
        A success-rate table (map x wanderer count, in %), then per map and wanderer count:
        episodes, success, failures by reason, mean time of successes, mean replans, episodes
        with contacts and mean label errors; the standard measures with 95 % intervals and
        success per map with its interval (``metrics_report``); then the detection table per
        wanderer count, pooled and per episode.

    """
    maps = map_order(rows)
    groups = group_rows(rows)
    counts = sorted({row['wanderers'] for row in rows})
    overall = cell_stats(rows) if rows else None
    lines = [f'# {title}', '']
    if overall is None:
        return '\n'.join(lines + ['No episodes yet.', ''])
    lines += [f'{overall.episodes} episodes on {len(maps)} maps; success '
              f'{100.0 * overall.success_rate:.1f} %, timeouts {overall.timeouts}, no path '
              f'{overall.no_paths}, collisions {overall.collisions}; wanderer contact events '
              f'robot-caused / agent-caused {_kinds_text(overall)}.', '',
              '## Success rate [%] per map and number of wandering robots', '',
              '| map | ' + ' | '.join(f'{count}' for count in counts) + ' | all |',
              '|---|' + '---:|' * (len(counts) + 1)]
    for name, _, label in maps:
        cells = []
        for count in counts:
            group = groups.get((name, count))
            cells.append(f'{100.0 * cell_stats(group).success_rate:.0f}' if group else '')
        every = [row for row in rows if row['map'] == name]
        cells.append(f'{100.0 * cell_stats(every).success_rate:.0f}')
        lines.append(f'| {label} | ' + ' | '.join(cells) + ' |')
    per_count = [cell_stats([row for row in rows if row['wanderers'] == count])
                 for count in counts]
    totals = [f'{100.0 * stats.success_rate:.0f}' for stats in per_count]
    lines.append('| **all** | ' + ' | '.join(totals) + f' | {100.0 * overall.success_rate:.0f} |')
    lines += ['', '## Details per map and number of wandering robots', '',
              'time: mean simulated time of the successful episodes; contacts: episodes with '
              'a wall / wanderer contact; label errors: mean cells per episode of wall cells '
              'labelled mobile / ghost obstacles at the end; wanderer events robot / agent: '
              'contact events with agents that the Husky caused (it moved towards the agent) '
              '/ that the agent caused (the Husky stood or moved away).', '',
              '| map | wanderers | episodes | success % | timeout | no path | collision | '
              'time [s] | replans | contacts wall / wanderer | wanderer events robot / agent '
              '| label errors |',
              '|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|']
    for name, _, label in maps:
        for count in counts:
            group = groups.get((name, count))
            if not group:
                continue
            stats = cell_stats(group)
            time_text = '-' if math.isnan(stats.mean_time) else f'{stats.mean_time:.1f}'
            lines.append(
                f'| {label} | {count} | {stats.episodes} | {100.0 * stats.success_rate:.0f} | '
                f'{stats.timeouts} | {stats.no_paths} | {stats.collisions} | {time_text} | '
                f'{stats.mean_replans:.1f} | {stats.wall_contacts} / '
                f'{stats.wanderer_contacts} | {_kinds_text(stats)} | '
                f'{stats.mean_walls_labelled_mobile:.1f} / '
                f'{stats.mean_ghost_obstacles:.1f} |')
    from .metrics_report import (detection_distribution_markdown, per_map_markdown,
                                 standard_metrics_markdown)
    by_navigator = {navigator: rows}
    return ('\n'.join(lines) + '\n\n' + standard_metrics_markdown(by_navigator) + '\n'
            + per_map_markdown(by_navigator) + '\n' + detection_markdown(by_navigator)
            + '\n' + detection_distribution_markdown(by_navigator))


def success_matrix(rows):
    """
    Return the success rate per wanderer count and map.

    Returns
    -------
    rates : (C, M) ndarray of float
        Success rate in [0, 1]; nan where a pair has no episode.
    counts : list of int
        The wanderer counts (rows of ``rates``).
    maps : list of (str, int or None, str)
        From `map_order` (columns of ``rates``).

    """
    maps = map_order(rows)
    counts = sorted({row['wanderers'] for row in rows})
    groups = group_rows(rows)
    rates = np.full((len(counts), len(maps)), np.nan)
    for i, count in enumerate(counts):
        for j, (name, _, _) in enumerate(maps):
            group = groups.get((name, count))
            if group:
                rates[i, j] = cell_stats(group).success_rate
    return rates, counts, maps


def save_success_figure(path, rows, title='Success rate per map'):
    """
    Draw the success rate per map (the paper's Fig. 7) into a PNG file.

    The top panel shows each map's success rate over all its episodes as bars; the bottom one
    is a heatmap with one row per wanderer count, annotated in %.

    Parameters
    ----------
    path : str or os.PathLike
        The PNG to write.
    rows : sequence of dict
        Rows as `episode_log.read_log` returns them; at least one.
    title : str
        Figure title.

    """
    from ..tools import figures  # selects the Agg backend before pyplot is imported
    pyplot = figures.pyplot
    if not rows:
        raise ValueError('no episodes to draw')
    rates, counts, maps = success_matrix(rows)
    overall = [cell_stats([row for row in rows if row['map'] == name]).success_rate
               for name, _, _ in maps]
    width = max(8.0, 0.38 * len(maps) + 2.0)
    figure, (bars, heat) = pyplot.subplots(
        2, 1, figsize=(width, 3.0 + 0.35 * len(counts) + 2.2), sharex=True,
        gridspec_kw={'height_ratios': [2.0, max(1.0, 0.25 * len(counts))]})
    positions = np.arange(len(maps))
    bars.bar(positions, 100.0 * np.asarray(overall), color='#4c72b0')
    bars.axhline(90.0, color='#999999', linewidth=0.8, linestyle='--')
    bars.set_ylim(0.0, 100.0)
    bars.set_ylabel('success [%]')
    bars.set_title(title)
    image = heat.imshow(100.0 * rates, aspect='auto', cmap='RdYlGn', vmin=0.0, vmax=100.0,
                        interpolation='nearest')
    for i in range(len(counts)):
        for j in range(len(maps)):
            if not np.isnan(rates[i, j]):
                heat.text(j, i, f'{100.0 * rates[i, j]:.0f}', ha='center', va='center',
                          fontsize=6)
    heat.set_yticks(np.arange(len(counts)), [str(count) for count in counts])
    heat.set_ylabel('wanderers')
    heat.set_xticks(positions, [label for _, _, label in maps], rotation=90, fontsize=7)
    figure.colorbar(image, ax=[bars, heat], fraction=0.02, pad=0.01, label='success [%]')
    figure.savefig(path, dpi=110, bbox_inches='tight')
    pyplot.close(figure)
