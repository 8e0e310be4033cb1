"""
Navigators side by side: success per navigator and map, and one navigator against the oracle.

Run as a module on several ``dpn-benchmark`` output folders (one navigator each, as recorded
in their ``run.json``)::

    python -m dpn_navigator.benchmark.compare_report out/dpn out/costmap out/oracle --out out/cmp

It writes ``compare.md`` (success per navigator and wanderer count with failures by reason,
success per map, the subject against every other navigator episode by episode with an exact
sign test, ``subject / reference`` per map and wanderer count, and the pairs where the
subject falls below ``--threshold`` of the reference) and ``compare.png``. Only the episodes
every folder holds are compared (same maps, tasks, wanderer counts and seeds, so the same
wanderers); the report says how many that is.

"""

import argparse
import json
import math
from pathlib import Path

import numpy as np

from .episode_log import read_log, row_key
from .metrics_report import paired_markdown, per_map_markdown, standard_metrics_markdown
from .navigator_overrides import run_label
from .report import cell_stats, group_rows, map_order
from .statistics import sign_test

#: Below this share of the reference's success, a (map, wanderers) pair is a shortfall.
DEFAULT_THRESHOLD = 0.95


def load_runs(folders):
    """
    Read the episode logs of several output folders, keyed by their navigator.

    Parameters
    ----------
    folders : sequence of pathlib.Path
        ``dpn-benchmark`` output folders (``episodes.csv`` and ``run.json``).

    Returns
    -------
    rows_by_navigator : dict of str to list of dict

    Raises
    ------
    ValueError
        If a folder has no log, or two folders hold the same navigator.

    """
    rows_by_navigator = {}
    for folder in folders:
        folder = Path(folder)
        if not (folder / 'episodes.csv').is_file():
            raise ValueError(f'{folder} holds no episodes.csv')
        settings_path = folder / 'run.json'
        name = (run_label(json.loads(settings_path.read_text()), folder.name)
                if settings_path.is_file() else folder.name)
        if name in rows_by_navigator:
            raise ValueError(f'two folders hold the {name} navigator; give one of each')
        rows_by_navigator[name] = read_log(folder / 'episodes.csv')
    return rows_by_navigator


def common_episodes(rows_by_navigator):
    """
    Keep the episodes every navigator ran.

    Returns
    -------
    rows_by_navigator : dict of str to list of dict
        The rows whose key (map, task, wanderers, repetition, seed) every log holds.
    dropped : int
        Rows left out, over every log.

    """
    keys = None
    for rows in rows_by_navigator.values():
        these = {row_key(row) for row in rows}
        keys = these if keys is None else keys & these
    kept = {name: [row for row in rows if row_key(row) in keys]
            for name, rows in rows_by_navigator.items()}
    dropped = sum(len(rows) for rows in rows_by_navigator.values()) - sum(
        len(rows) for rows in kept.values())
    return kept, dropped


def success_rate(rows):
    """Return the success rate of some rows in [0, 1], nan when there are none."""
    return cell_stats(rows).success_rate if rows else math.nan


def ratio_matrix(subject_rows, reference_rows):
    """
    Return ``subject / reference`` success per wanderer count and map.

    Returns
    -------
    ratios : (C, M) ndarray of float
        nan where the reference never succeeded (nothing was possible) or a pair is missing.
    counts : list of int
    maps : list of (str, int or None, str)
        From ``report.map_order`` of the reference rows.

    """
    maps = map_order(reference_rows)
    counts = sorted({row['wanderers'] for row in reference_rows})
    subject = group_rows(subject_rows)
    reference = group_rows(reference_rows)
    ratios = np.full((len(counts), len(maps)), np.nan)
    for i, count in enumerate(counts):
        for j, (name, _, _) in enumerate(maps):
            possible = success_rate(reference.get((name, count), []))
            if possible > 0.0:
                ratios[i, j] = success_rate(subject.get((name, count), [])) / possible
    return ratios, counts, maps


def paired_outcomes(subject_rows, other_rows):
    """
    Count the episodes one navigator succeeded in and the other did not, per wanderer count.

    Parameters
    ----------
    subject_rows, other_rows : list of dict
        Rows of the same episodes (`common_episodes`); rows whose key the other lacks are
        ignored.

    Returns
    -------
    outcomes : dict
        ``{wanderers: (won, lost)}``: episodes only the subject succeeded in, and episodes
        only the other did, for every wanderer count of the subject's rows.

    """
    other = {row_key(row): row['success'] for row in other_rows}
    outcomes = {}
    for row in subject_rows:
        won, lost = outcomes.get(row['wanderers'], (0, 0))
        key = row_key(row)
        if key in other and row['success'] != other[key]:
            won, lost = (won + 1, lost) if row['success'] else (won, lost + 1)
        outcomes[row['wanderers']] = (won, lost)
    return dict(sorted(outcomes.items()))


def compare_markdown(rows_by_navigator, subject='dpn', reference='oracle',
                     threshold=DEFAULT_THRESHOLD, dropped=0):
    """
    Write the comparison tables.

    Parameters
    ----------
    rows_by_navigator : dict of str to list of dict
        Rows of the same episodes per navigator (`common_episodes`).
    subject, reference : str
        The navigators of the ratio; the ratio tables are left out if either is missing.
    threshold : float
        Shortfall threshold of ``subject / reference``.
    dropped : int
        Rows `common_episodes` left out, to report.

    Returns
    -------
    text : str

    """
    names = list(rows_by_navigator)
    any_rows = next(iter(rows_by_navigator.values()))
    counts = sorted({row['wanderers'] for row in any_rows})
    maps = map_order(any_rows)
    lines = ['# Navigators compared', '',
             f'{len(any_rows)} episodes per navigator ({len(maps)} maps), the same episodes '
             f'for every navigator; {dropped} rows held by some logs only were left out.', '',
             '## Success [%] per navigator and number of wandering robots', '',
             '| navigator | ' + ' | '.join(str(count) for count in counts)
             + ' | all | timeout | no path | collision |',
             '|---|' + '---:|' * (len(counts) + 4)]
    for name in names:
        rows = rows_by_navigator[name]
        cells = [f'{100.0 * success_rate([r for r in rows if r["wanderers"] == count]):.1f}'
                 for count in counts]
        stats = cell_stats(rows)
        lines.append(f'| {name} | ' + ' | '.join(cells) + f' | {100.0 * stats.success_rate:.1f}'
                     f' | {stats.timeouts} | {stats.no_paths} | {stats.collisions} |')
    lines += ['', '## Success [%] per map, all wanderer counts', '',
              '| map | ' + ' | '.join(names) + ' |', '|---|' + '---:|' * len(names)]
    for map_name, _, label in maps:
        cells = [f'{100.0 * success_rate([r for r in rows_by_navigator[name] if r["map"] == map_name]):.0f}'  # noqa: E501
                 for name in names]
        lines.append(f'| {label} | ' + ' | '.join(cells) + ' |')
    if subject in rows_by_navigator and len(names) > 1:
        lines += _paired_lines(rows_by_navigator, subject, counts)
    if subject in rows_by_navigator and reference in rows_by_navigator:
        lines += _ratio_lines(rows_by_navigator[subject], rows_by_navigator[reference],
                              subject, reference, threshold)
    return ('\n'.join(lines) + '\n\n' + standard_metrics_markdown(rows_by_navigator) + '\n'
            + paired_markdown(rows_by_navigator, subject) + '\n'
            + per_map_markdown(rows_by_navigator))


def _paired_lines(rows_by_navigator, subject, counts):
    """Return the episode-by-episode table of ``subject`` against the others as Markdown."""
    lines = ['', f'## {subject} against each navigator, episode by episode', '',
             f'won / lost: episodes only {subject} succeeded in / only the other did. p: exact '
             'two-sided sign test on those episodes (small p: the difference is not chance).',
             '', '| against | ' + ' | '.join(str(count) for count in counts) + ' | all | p |',
             '|---|' + '---:|' * (len(counts) + 2)]
    for name, rows in rows_by_navigator.items():
        if name == subject:
            continue
        outcomes = paired_outcomes(rows_by_navigator[subject], rows)
        won = sum(pair[0] for pair in outcomes.values())
        lost = sum(pair[1] for pair in outcomes.values())
        cells = ['{} / {}'.format(*outcomes.get(count, (0, 0))) for count in counts]
        lines.append(f'| {name} | ' + ' | '.join(cells)
                     + f' | **{won} / {lost}** | {sign_test(won, lost):.2g} |')
    return lines


def _ratio_lines(subject_rows, reference_rows, subject, reference, threshold):
    """Return the ratio table and the shortfall list as Markdown lines."""
    ratios, counts, maps = ratio_matrix(subject_rows, reference_rows)
    subject_groups = group_rows(subject_rows)
    reference_groups = group_rows(reference_rows)
    overall = success_rate(subject_rows) / success_rate(reference_rows)
    lines = ['', f'## {subject} / {reference} success per map and wanderer count', '',
             f'Overall {subject} / {reference}: {overall:.3f}. "-": {reference} never '
             'succeeded there. all: every wanderer count of the map pooled.', '',
             '| map | ' + ' | '.join(str(count) for count in counts) + ' | all |',
             '|---|' + '---:|' * (len(counts) + 1)]
    for j, (name, _, label) in enumerate(maps):
        possible = success_rate([row for row in reference_rows if row['map'] == name])
        pooled = (success_rate([row for row in subject_rows if row['map'] == name]) / possible
                  if possible > 0.0 else math.nan)
        lines.append(f'| {label} | ' + ' | '.join(
            '-' if np.isnan(ratios[i, j]) else f'{ratios[i, j]:.2f}'
            for i in range(len(counts))) + (' | -' if np.isnan(pooled) else f' | {pooled:.2f}')
            + ' |')
    short = [(maps[j], counts[i]) for i, j in zip(*np.nonzero(ratios < threshold))]
    lines += ['', f'## Where {subject} is below {100.0 * threshold:.0f} % of {reference}', '']
    if not short:
        lines.append('Nowhere.')
    else:
        lines += [f'| map | wanderers | {subject} % | {reference} % | {subject} failures |',
                  '|---|---:|---:|---:|---|']
        for (name, _, label), count in sorted(short, key=lambda pair: (pair[0][1] or 0,
                                                                       pair[1])):
            rows = subject_groups[(name, count)]
            failures = ', '.join(sorted({row['failure'] for row in rows if row['failure']}))
            lines.append(
                f'| {label} | {count} | {100.0 * success_rate(rows):.0f} | '
                f'{100.0 * success_rate(reference_groups[(name, count)]):.0f} | {failures} |')
    return lines


def save_compare_figure(path, rows_by_navigator, subject='dpn', reference='oracle'):
    """
    Draw success per map for every navigator, and ``subject / reference`` per map and count.

    Parameters
    ----------
    path : str or os.PathLike
        The PNG to write.
    rows_by_navigator : dict of str to list of dict
        Rows of the same episodes per navigator; at least one navigator with rows.
    subject, reference : str
        The ratio panel is drawn when both are present.

    """
    from ..tools import figures  # selects the Agg backend before pyplot is imported
    pyplot = figures.pyplot
    names = [name for name, rows in rows_by_navigator.items() if rows]
    if not names:
        raise ValueError('no episodes to draw')
    maps = map_order(rows_by_navigator[names[0]])
    with_ratio = subject in names and reference in names
    figure, axes = pyplot.subplots(
        2 if with_ratio else 1, 1, figsize=(max(8.0, 0.3 * len(maps) + 2.0), 6.0
                                            if with_ratio else 3.2),
        sharex=True, squeeze=False, gridspec_kw={'height_ratios': [2.0, 1.0]}
        if with_ratio else None)
    bars = axes[0, 0]
    positions = np.arange(len(maps))
    width = 0.8 / len(names)
    colours = ('#4c72b0', '#dd8452', '#55a868', '#c44e52', '#8172b3')
    for k, (name, colour) in enumerate(zip(names, colours)):
        rates = [success_rate([r for r in rows_by_navigator[name] if r['map'] == map_name])
                 for map_name, _, _ in maps]
        bars.bar(positions - 0.4 + (k + 0.5) * width, 100.0 * np.asarray(rates), width,
                 color=colour, label=name)
    bars.set_ylim(0.0, 100.0)
    bars.set_ylabel('success [%]')
    bars.legend(fontsize=7, ncol=len(names), loc='lower left', bbox_to_anchor=(0.0, 1.02))
    bars.set_title('Success per map, all wanderer counts', fontsize=9, loc='right')
    if with_ratio:
        ratios, counts, ratio_maps = ratio_matrix(rows_by_navigator[subject],
                                                  rows_by_navigator[reference])
        heat = axes[1, 0]
        colours_map = pyplot.get_cmap('RdYlGn').with_extremes(bad='#d9d9d9')
        image = heat.imshow(np.ma.masked_invalid(ratios), aspect='auto', cmap=colours_map,
                            vmin=0.5, vmax=1.0, interpolation='nearest')
        for i in range(len(counts)):
            for j in range(len(ratio_maps)):
                text = '-' if np.isnan(ratios[i, j]) else f'{ratios[i, j]:.1f}'
                heat.text(j, i, text, ha='center', va='center', fontsize=6)
        heat.set_yticks(np.arange(len(counts)), [str(count) for count in counts])
        heat.set_ylabel('wanderers')
        heat.set_title(f'{subject} / {reference} success (grey: {reference} never succeeded)',
                       fontsize=9)
        figure.colorbar(image, ax=heat, fraction=0.02, pad=0.01)
    axes[-1, 0].set_xticks(positions, [label for _, _, label in maps], rotation=90, fontsize=7)
    figure.savefig(path, dpi=80, bbox_inches='tight')
    pyplot.close(figure)


def main(argv=None):
    """Write ``compare.md`` and ``compare.png`` for several benchmark output folders."""
    parser = argparse.ArgumentParser(
        prog='python -m dpn_navigator.benchmark.compare_report',
        description='Compare the success of navigators from several dpn-benchmark output '
                    'folders, on the episodes they all ran.')
    parser.add_argument('folders', nargs='+', type=Path,
                        help='output folders of dpn-benchmark, one navigator each')
    parser.add_argument('--out', type=Path, required=True, help='folder for the table and plot')
    parser.add_argument('--subject', default='dpn', help='navigator of the ratio (%(default)s)')
    parser.add_argument('--reference', default='oracle',
                        help='navigator the ratio divides by (%(default)s)')
    parser.add_argument('--threshold', type=float, default=DEFAULT_THRESHOLD,
                        help='shortfall below this share of the reference (%(default)s)')
    args = parser.parse_args(argv)
    try:
        rows_by_navigator, dropped = common_episodes(load_runs(args.folders))
    except ValueError as exc:
        parser.exit(2, f'compare_report: error: {exc}\n')
    if not any(rows_by_navigator.values()):
        parser.exit(2, 'compare_report: error: the folders share no episode\n')
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / 'compare.md').write_text(compare_markdown(
        rows_by_navigator, args.subject, args.reference, args.threshold, dropped))
    save_compare_figure(args.out / 'compare.png', rows_by_navigator, args.subject,
                        args.reference)
    print(f'wrote {args.out / "compare.md"} and {args.out / "compare.png"}')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
