"""
The detection table and figure of episode logs: the map as a detector per wanderer count.

Ratios are pooled: the counts of every scan of every episode in a group are summed and divided
once, so an episode weighs by how much it saw, and an episode where a ratio is undefined (no
visible mobile cell, no hit on a wanderer) adds nothing to it. Ghost means are weighted by scans.
Rows without detection measures (``scans`` empty) are left out.

Run as a module to compare navigators from several output folders::

    python -m dpn_navigator.benchmark.detection_report out/dpn out/paper --out out/detection

"""

import argparse
from dataclasses import dataclass
import json
from pathlib import Path

import numpy as np

from .detection import ratio, REPLAN_CLASSES
from .episode_log import read_log
from .navigator_overrides import run_label
from .protocol import MAP_MODELS


@dataclass(frozen=True)
class DetectionStats:
    """
    Pooled detection measures of a group of episodes (see ``docs/detection.md``).

    Attributes
    ----------
    episodes, scans : int
        Episodes with measures, and their scans.
    precision, recall, wall_mobile_share : float or None
        Pooled ratios; None when undefined (zero denominator).
    mobile_ghosts, steady_ghosts : float or None
        Ghost cells per scan, mean over every scan.
    mobile_ghost_scans, steady_ghost_scans : float or None
        Share of scans with a ghost of the label.
    mobile_ghosts_end, steady_ghosts_end : float
        Ghost cells at the end, mean per episode.
    replans : dict of str to float
        Mean paths planned per episode, by cause (`detection.REPLAN_CLASSES`).
    cost_share : float or None
        Wall-clock time of the measures over the episodes' wall-clock time.

    """

    episodes: int
    scans: int
    precision: object
    recall: object
    wall_mobile_share: object
    mobile_ghosts: object
    steady_ghosts: object
    mobile_ghost_scans: object
    steady_ghost_scans: object
    mobile_ghosts_end: float
    steady_ghosts_end: float
    replans: dict
    cost_share: object


def detection_stats(rows):
    """
    Pool the detection measures of some log rows.

    Parameters
    ----------
    rows : sequence of dict
        Rows as ``episode_log.read_log`` returns them.

    Returns
    -------
    DetectionStats or None
        None when no row carries detection measures.

    """
    rows = [row for row in rows if row.get('scans') is not None]
    if not rows:
        return None

    def total(column):
        return sum(row[column] for row in rows)

    def scan_weighted(column):
        return ratio(sum(row[column] * row['scans'] for row in rows if row[column] is not None),
                     total('scans'))

    wall_time = total('wall_time')
    return DetectionStats(
        episodes=len(rows), scans=total('scans'),
        precision=ratio(total('mobile_visible_true'), total('mobile_visible')),
        recall=ratio(total('wanderer_hit_cells_mobile'), total('wanderer_hit_cells')),
        wall_mobile_share=ratio(total('wall_cells_ever_mobile'), total('wall_cells_seen')),
        mobile_ghosts=scan_weighted('mobile_ghosts_mean'),
        steady_ghosts=scan_weighted('steady_ghosts_mean'),
        mobile_ghost_scans=scan_weighted('mobile_ghost_scan_share'),
        steady_ghost_scans=scan_weighted('steady_ghost_scan_share'),
        mobile_ghosts_end=total('mobile_ghosts_end') / len(rows),
        steady_ghosts_end=total('steady_ghosts_end') / len(rows),
        replans={cause: total(f'replans_{cause}') / len(rows) for cause in REPLAN_CLASSES},
        cost_share=ratio(sum(row['detection_wall_time'] or 0.0 for row in rows), wall_time))


def has_mobile_label(navigator):
    """
    Tell whether a navigator's map has a mobile-obstacle label (``protocol.MAP_MODELS``).

    The costmap has one obstacle class (lethal), so its precision, recall, walls-mobile share
    and mobile ghosts are not defined (``n/a``); its ghosts are all obstacle (steady) ghosts.

    Parameters
    ----------
    navigator : str
        A ``--navigator`` name, optionally followed by `` (folder)``.

    """
    return MAP_MODELS.get(navigator.split(' (')[0], 'labels') == 'labels'


def _number(value, digits=2, scale=1.0):
    """Format a value that may be undefined (None) as ``-``."""
    return '-' if value is None else f'{scale * value:.{digits}f}'


def detection_markdown(rows_by_navigator):
    """
    Write the detection table: one line per navigator and wanderer count.

    Parameters
    ----------
    rows_by_navigator : dict of str to sequence of dict
        Log rows per navigator name.

    Returns
    -------
    text : str
        A Markdown section; says so when no row carries measures.

    """
    lines = ['## Detection per navigator and number of wandering robots', '',
             'Definitions in docs/detection.md. precision / recall: pooled over every scan; '
             'walls mobile: wall cells ever labelled mobile with no wanderer near, over wall '
             'cells seen; ghosts: obstacle cells no wall or wanderer explains, mean per scan '
             '(share of scans with any); replans: mean per episode by cause; cost: share of '
             'episode wall time spent measuring. "-": undefined (nothing to count); "n/a": '
             'the map has no mobile label (costmap: its lethal cells are its obstacles, '
             'counted as steady).', '',
             '| navigator | wanderers | episodes | precision | recall | walls mobile % | '
             'mobile ghosts / scan (scans %) | steady ghosts / scan (scans %) | ghosts at end '
             'mobile / steady | replans wall / wanderer / no-path retry / other | cost % |',
             '|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|']
    measured = False
    for navigator, rows in rows_by_navigator.items():
        for count in sorted({row['wanderers'] for row in rows}):
            stats = detection_stats([row for row in rows if row['wanderers'] == count])
            if stats is None:
                continue
            measured = True
            replans = ' / '.join(f'{stats.replans[cause]:.1f}' for cause in REPLAN_CLASSES)
            if has_mobile_label(navigator):
                mobile = (f'{_number(stats.precision)} | {_number(stats.recall)} | '
                          f'{_number(stats.wall_mobile_share, 1, 100.0)} | '
                          f'{_number(stats.mobile_ghosts, 1)} '
                          f'({_number(stats.mobile_ghost_scans, 0, 100.0)})')
                mobile_end = f'{stats.mobile_ghosts_end:.1f}'
            else:
                mobile, mobile_end = 'n/a | n/a | n/a | n/a', 'n/a'
            lines.append(
                f'| {navigator} | {count} | {stats.episodes} | {mobile} | '
                f'{_number(stats.steady_ghosts, 1)} '
                f'({_number(stats.steady_ghost_scans, 0, 100.0)}) | '
                f'{mobile_end} / {stats.steady_ghosts_end:.1f} | {replans} | '
                f'{_number(stats.cost_share, 1, 100.0)} |')
    if not measured:
        lines[2:] = ['No episode with detection measures.']
    return '\n'.join(lines) + '\n'


def save_detection_figure(path, rows_by_navigator, title='Detection against wanderer count'):
    """
    Plot precision, recall, walls mobile and ghosts per scan against the wanderer count.

    Parameters
    ----------
    path : str or os.PathLike
        The PNG to write.
    rows_by_navigator : dict of str to sequence of dict
        Log rows per navigator name; at least one with detection measures.
    title : str
        Figure title.

    """
    from ..tools import figures  # selects the Agg backend before pyplot is imported
    pyplot = figures.pyplot
    curves = {}
    for navigator, rows in rows_by_navigator.items():
        counts = sorted({row['wanderers'] for row in rows})
        stats = [(count, detection_stats([row for row in rows if row['wanderers'] == count]))
                 for count in counts]
        stats = [(count, s) for count, s in stats if s is not None]
        if stats:
            curves[navigator] = stats
    if not curves:
        raise ValueError('no episodes with detection measures to draw')
    figure, (ratios, ghosts) = pyplot.subplots(1, 2, figsize=(10.0, 3.8))
    colours = ('#4c72b0', '#dd8452', '#55a868', '#c44e52', '#8172b3')
    for (navigator, stats), colour in zip(curves.items(), colours):
        counts = [count for count, _ in stats]

        def series(name, stats=stats):
            return np.array([np.nan if getattr(s, name) is None else getattr(s, name)
                             for _, s in stats], dtype=float)
        if has_mobile_label(navigator):
            ratios.plot(counts, series('precision'), 'o-', color=colour,
                        label=f'{navigator}: precision')
            ratios.plot(counts, series('recall'), 's--', color=colour,
                        label=f'{navigator}: recall')
            ratios.plot(counts, series('wall_mobile_share'), '^:', color=colour,
                        label=f'{navigator}: walls mobile')
            ghosts.plot(counts, series('mobile_ghosts'), 'o-', color=colour,
                        label=f'{navigator}: mobile')
            ghosts.plot(counts, series('steady_ghosts'), 's--', color=colour,
                        label=f'{navigator}: steady')
        else:
            ghosts.plot(counts, series('steady_ghosts'), 's--', color=colour,
                        label=f'{navigator}: lethal')
    every_count = sorted({count for stats in curves.values() for count, _ in stats})
    for axes in (ratios, ghosts):
        axes.set_xticks(every_count)
    ratios.set_ylim(0.0, 1.0)
    ratios.set_xlabel('wanderers')
    ratios.set_ylabel('share')
    ratios.set_title('mobile label: precision, recall on wanderer hits, walls ever mobile',
                     fontsize=9)
    ghosts.set_xlabel('wanderers')
    ghosts.set_ylabel('ghost cells per scan')
    ghosts.set_ylim(bottom=0.0)
    ghosts.set_title('obstacle cells no wall or wanderer explains', fontsize=9)
    for axes in (ratios, ghosts):
        axes.grid(alpha=0.3)
        if axes.get_legend_handles_labels()[0]:      # none on the left for a costmap alone
            axes.legend(fontsize=7)
    figure.suptitle(title)
    figure.savefig(path, dpi=110, bbox_inches='tight')
    pyplot.close(figure)


def main(argv=None):
    """Write ``detection.md`` and ``detection.png`` for several benchmark output folders."""
    parser = argparse.ArgumentParser(
        prog='python -m dpn_navigator.benchmark.detection_report',
        description='Compare the detection measures of several dpn-benchmark output folders.')
    parser.add_argument('folders', nargs='+', type=Path,
                        help='output folders of dpn-benchmark (episodes.csv, run.json)')
    parser.add_argument('--out', type=Path, required=True, help='folder for the table and plot')
    args = parser.parse_args(argv)
    rows_by_navigator = {}
    for folder in args.folders:
        settings = json.loads((folder / 'run.json').read_text())
        name = run_label(settings, folder.name)
        if name in rows_by_navigator:
            name = f'{name} ({folder})'
        rows_by_navigator[name] = read_log(folder / 'episodes.csv')
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / 'detection.md').write_text(detection_markdown(rows_by_navigator))
    save_detection_figure(args.out / 'detection.png', rows_by_navigator)
    print(f'wrote {args.out / "detection.md"} and {args.out / "detection.png"}')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
