"""
The field's standard measures as Markdown tables, with map-stratified 95 % intervals.

For ``summary.md`` (one navigator) and ``compare.md`` (several): success, SPL and the BARN score
with bootstrap intervals (``statistics.stratified_bootstrap``, episodes resampled within each
map), the time and path-length ratios of the successes, the clearance to moving agents and the
time in their personal space, jerk, time standing still and the failures by the benchmark's
reasons (``episode_metrics``); success per map with its interval; paired differences against
one navigator; and the detection measures per episode (distributions, and how many episodes
leave a ratio undefined) beside the pooled ones. Rows of a version-1 log give SPL, the BARN
score and the ratios from their columns, and ``-`` for the measures that need the trajectory.

"""

import math

import numpy as np

from .episode_metrics import barn_score, END_REASONS, REFERENCE_SPEED, spl
from .report import map_order
from .statistics import format_interval, paired_difference, stratified_bootstrap


def _column(rows, name):
    """
    Return a column as float, None as nan.

    SPL, the BARN score and the time and path ratios of a version-1 row (None there) are
    computed from its ``success``, ``time``, ``path_length`` and ``shortest_path``, as
    ``episode_metrics`` defines them.
    """
    values = []
    for row in rows:
        value = row.get(name)
        if value is None and name in _DERIVED and row.get('shortest_path') is not None:
            value = _DERIVED[name](row)
        values.append(math.nan if value is None else float(value))
    return np.array(values)


def _ratio_if_success(row, value):
    """Return ``value`` for a successful episode with a finite ``L``, else None."""
    ok = row['success'] and math.isfinite(row['shortest_path']) and row['shortest_path'] > 0
    return value if ok else None


#: The measures a version-1 row has the inputs of.
_DERIVED = {
    'spl': lambda row: spl(row['success'], row['shortest_path'], row['path_length']),
    'barn_score': lambda row: barn_score(row['success'], row['shortest_path'], row['time']),
    'time_ratio': lambda row: _ratio_if_success(
        row, row['time'] / (row['shortest_path'] / REFERENCE_SPEED) if row['shortest_path']
        else None),
    'path_ratio': lambda row: _ratio_if_success(
        row, row['path_length'] / row['shortest_path'] if row['shortest_path'] else None),
}


def _median(values):
    """Return the median of the finite values as text, ``-`` when there are none."""
    values = values[np.isfinite(values)]
    return f'{np.median(values):.2f}' if values.size else '-'


def standard_metrics_markdown(rows_by_navigator):
    """
    Return the standard-measures table, one line per navigator.

    Parameters
    ----------
    rows_by_navigator : dict of str to list of dict
        Log rows (``episode_log.read_log``) per navigator; non-empty lists.

    Returns
    -------
    text : str

    """
    reasons = [reason for reason in END_REASONS if reason]
    lines = ['## Standard measures, with 95 % intervals', '',
             'Success [%], SPL and BARN score: mean over episodes [map-stratified bootstrap '
             '95 % interval]; time and path ratio: median over the successes (time over the '
             'reference time L / 1 m/s, distance over L); min. distance: median over episodes '
             'with agents of the smallest distance from the robot centre to an agent edge '
             '[m]; personal space: mean seconds with an agent edge within 1.2 m; jerk: median '
             "RMS [m/s^3]; still: mean seconds standing still. Failures by the benchmark's "
             'reasons (docs/benchmark.md).', '',
             '| navigator | episodes | success % | SPL | BARN | time ratio | path ratio | '
             'min. distance | personal space [s] | jerk | still [s] | '
             + ' | '.join(reason.replace('_', ' ') for reason in reasons) + ' |',
             '|---|' + '---:|' * (10 + len(reasons))]
    for name, rows in rows_by_navigator.items():
        maps = [row['map'] for row in rows]
        success = _column(rows, 'success')
        cells = [format_interval(*stratified_bootstrap(success, maps), scale=100.0)]
        for column in ('spl', 'barn_score'):
            cells.append(format_interval(*stratified_bootstrap(_column(rows, column), maps),
                                         digits=3))
        cells += [_median(_column(rows, 'time_ratio')), _median(_column(rows, 'path_ratio')),
                  _median(_column(rows, 'min_agent_distance'))]
        personal = _column(rows, 'personal_space_time')
        cells.append(f'{np.nanmean(personal):.1f}' if np.isfinite(personal).any() else '-')
        cells.append(_median(_column(rows, 'jerk_rms')))
        still = _column(rows, 'still_time')
        cells.append(f'{np.nanmean(still):.1f}' if np.isfinite(still).any() else '-')
        ended = [row.get('end_reason') for row in rows]
        known = any(reason is not None for reason in ended)
        cells += [str(ended.count(reason)) if known else '-' for reason in reasons]
        lines.append(f'| {name} | {len(rows)} | ' + ' | '.join(cells) + ' |')
    return '\n'.join(lines) + '\n'


def per_map_markdown(rows_by_navigator):
    """Return success [%] per map and navigator with bootstrap 95 % intervals."""
    names = list(rows_by_navigator)
    every = [row for rows in rows_by_navigator.values() for row in rows]
    lines = ['## Success [%] per map, with 95 % intervals', '',
             'Episodes of the map resampled (bootstrap, percentile interval).', '',
             '| map | ' + ' | '.join(names) + ' |', '|---|' + '---:|' * len(names)]
    for key, _, label in map_order(every):
        cells = []
        for name in names:
            success = _column([row for row in rows_by_navigator[name] if row['map'] == key],
                              'success')
            cells.append(format_interval(*stratified_bootstrap(
                success, np.zeros(success.shape[0])), scale=100.0, digits=0))
        lines.append(f'| {label} | ' + ' | '.join(cells) + ' |')
    return '\n'.join(lines) + '\n'


def paired_markdown(rows_by_navigator, subject):
    """
    Return the subject's paired differences against every other navigator, with intervals.

    Rows are paired by episode key; the difference of success [points] and of SPL, mean over
    the common episodes, with a map-stratified bootstrap interval.
    """
    from .episode_log import row_key
    if subject not in rows_by_navigator:
        return ''
    mine = {row_key(row): row for row in rows_by_navigator[subject]}
    lines = [f'## {subject} minus each navigator, paired by episode', '',
             '| against | episodes | success [points] | SPL |', '|---|---:|---:|---:|']
    for name, rows in rows_by_navigator.items():
        if name == subject:
            continue
        pairs = [(mine[row_key(row)], row) for row in rows if row_key(row) in mine]
        if not pairs:
            continue
        maps = [a['map'] for a, _ in pairs]
        cells = []
        for column, scale, digits in (('success', 100.0, 1), ('spl', 1.0, 3)):
            cells.append(format_interval(*paired_difference(
                _column([a for a, _ in pairs], column), _column([b for _, b in pairs], column),
                maps), scale=scale, digits=digits))
        lines.append(f'| {name} | {len(pairs)} | ' + ' | '.join(cells) + ' |')
    return '\n'.join(lines) + '\n'


def detection_distribution_markdown(rows_by_navigator):
    """
    Return the detection measures per episode: medians, quartiles and undefined counts.

    Per navigator and wanderer count (with wanderers): episodes; how many leave the precision
    of visible mobile cells undefined (no mobile cell ever seen); the median [quartiles] of
    the per-episode precision over visible cells and over every cell (ghosts out of view
    counted); the median recall off walls and the pooled recall on the wall belts.
    """
    lines = ['## Detection per episode', '',
             'Per-episode ratios (not pooled): median [25 %, 75 %] over the episodes where '
             'the ratio is defined; "undefined" counts the episodes without a visible mobile '
             'cell (precision undefined, left out of the median, never counted as 1).', '',
             '| navigator | wanderers | episodes | precision undefined | precision, visible | '
             'precision, every cell | recall off walls | recall near walls (pooled) |',
             '|---|---:|---:|---:|---:|---:|---:|---:|']
    for name, rows in rows_by_navigator.items():
        for count in sorted({row['wanderers'] for row in rows if row['wanderers'] > 0}):
            group = [row for row in rows if row['wanderers'] == count]
            if all(row.get('scans') is None for row in group):
                continue
            visible = _column(group, 'mobile_precision')
            near_hits = np.nansum(_column(group, 'wanderer_hit_cells_near_wall'))
            near_mobile = np.nansum(_column(group, 'wanderer_hit_cells_near_wall_mobile'))
            lines.append(
                f'| {name} | {count} | {len(group)} | '
                f'{int(np.count_nonzero(np.isnan(visible)))} | {_quartiles(visible)} | '
                f'{_quartiles(_column(group, "mobile_precision_all"))} | '
                f'{_quartiles(_column(group, "wanderer_hit_recall"))} | '
                + (f'{near_mobile / near_hits:.3f}' if near_hits else '-') + ' |')
    return '\n'.join(lines) + '\n'


def _quartiles(values):
    """Return ``'median [q1, q3]'`` of the finite values, ``-`` when there are none."""
    values = values[np.isfinite(values)]
    if not values.size:
        return '-'
    q1, median, q3 = np.percentile(values, [25.0, 50.0, 75.0])
    return f'{median:.3f} [{q1:.3f}, {q3:.3f}]'
