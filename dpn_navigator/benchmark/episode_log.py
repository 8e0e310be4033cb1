"""
The episode log: one CSV row per finished episode, appended as results arrive.

``episodes.csv`` in a run's output folder is the run's only state. A row is written and flushed
as soon as its episode ends, so an interrupted run loses at most the episodes in flight; a
re-run reads the log and skips every episode whose key (map, task, wanderers, repetition, seed)
is already there. A last line cut short by a kill is dropped when the log is reopened.

Columns (`COLUMNS`), per episode:

- ``map``, ``number``, ``family``: the map's index name (or yaml path), index number and family
  (both empty for a bare map_server yaml);
- ``task``, ``wanderers``, ``repetition``, ``seed``: the episode's key;
- ``success`` (1 or 0), ``failure`` (empty, ``collision``, ``no_path`` or ``timeout``);
- ``time`` and ``time_limit`` [s, simulated], ``path_length`` and ``shortest_path`` [m],
  ``replans``, ``forgets``, ``wall_contacts``, ``wanderer_contacts``,
  ``walls_labelled_mobile``, ``ghost_obstacles``: see ``dpn_navigator.benchmark.episode``;
- `DETECTION_COLUMNS`: the map measured as a detector (``dpn_navigator.benchmark.detection``,
  defined in ``docs/detection.md``); a ratio with a zero denominator is an empty field, and
  every one of them is empty for an episode run without the measures;
- `METRIC_COLUMNS` (version 2): the benchmark's own view of the episode
  (``dpn_navigator.benchmark.episode_metrics``): ``goal_distance``, ``end_reason``, ``spl``,
  ``barn_score``, ``time_ratio``, ``path_ratio``, ``min_agent_distance``,
  ``personal_space_time``, ``jerk_rms``, ``angular_jerk_rms``, ``still_time``;
- ``wall_time``: wall-clock seconds the episode took in its worker, and
  ``detection_wall_time``: the part of it spent on the detection measures (the two columns that
  differ between two runs of the same episode).

A log of version 1 (`LEGACY_COLUMNS`: before the metric and the added detection columns,
success as the navigator reported it) still reads, its new columns None; it is not resumed
(`EpisodeLog` refuses it: the rules changed).

"""

import csv
import io
import os

from .detection import DETECTION_FIELDS, DetectionResult
from .episode_metrics import END_REASONS, METRIC_FIELDS

#: The detection measures' columns (`DetectionResult` fields); empty when not measured.
DETECTION_COLUMNS = DETECTION_FIELDS
#: The benchmark's own measures (`EpisodeMetrics` fields); None in a version-1 log.
METRIC_COLUMNS = METRIC_FIELDS
#: The detection columns a version-1 log has (the first 20).
_LEGACY_DETECTION_COLUMNS = DETECTION_COLUMNS[:20]
#: Columns before the detection measures.
_EPISODE_COLUMNS = ('map', 'number', 'family', 'task', 'wanderers', 'repetition', 'seed',
                    'success', 'failure', 'time', 'time_limit', 'path_length', 'shortest_path',
                    'replans', 'forgets', 'wall_contacts', 'wanderer_contacts',
                    'walls_labelled_mobile', 'ghost_obstacles')
#: The log's columns, in file order (version 2).
COLUMNS = (_EPISODE_COLUMNS + METRIC_COLUMNS + DETECTION_COLUMNS
           + ('wall_time', 'detection_wall_time'))
#: The columns of a version-1 log, which `read_log` still reads.
LEGACY_COLUMNS = (_EPISODE_COLUMNS + _LEGACY_DETECTION_COLUMNS
                  + ('wall_time', 'detection_wall_time'))
#: Columns that identify an episode.
KEY_COLUMNS = ('map', 'task', 'wanderers', 'repetition', 'seed')
#: Integer columns (parsed by `read_log`).
INT_COLUMNS = ('task', 'wanderers', 'repetition', 'seed', 'success', 'replans', 'forgets',
               'wall_contacts', 'wanderer_contacts', 'walls_labelled_mobile', 'ghost_obstacles')
#: Float columns (parsed by `read_log`).
FLOAT_COLUMNS = ('time', 'time_limit', 'path_length', 'shortest_path', 'wall_time')
#: Detection columns holding counts (int); the others hold float. Empty fields read as None.
_DETECTION_INT_COLUMNS = tuple(name for name in DETECTION_COLUMNS
                               if DetectionResult.__dataclass_fields__[name].type is int)
#: Values of the ``failure`` column.
FAILURES = ('', 'collision', 'no_path', 'timeout')
#: Metric columns holding text; the others hold float. Empty fields read as None.
_METRIC_TEXT_COLUMNS = ('end_reason',)


def row_key(row):
    """Return a row's episode key ``(map, task, wanderers, repetition, seed)``."""
    return tuple(row[column] for column in KEY_COLUMNS)


def read_log(path):
    """
    Read an episode log.

    Parameters
    ----------
    path : str or os.PathLike
        ``episodes.csv``; a missing or empty file reads as no rows.

    Returns
    -------
    rows : list of dict
        One per complete line, with `INT_COLUMNS` as int, `FLOAT_COLUMNS` as float and
        ``number`` as int or None, the detection columns as int or float, or None where empty.
        A last line without its newline (cut short) is left out.

    Raises
    ------
    ValueError
        If the header is neither `COLUMNS` nor `LEGACY_COLUMNS` (a log of another version or
        another tool) or a complete row does not parse.

    """
    try:
        with open(path, newline='', encoding='utf-8') as stream:
            text = stream.read()
    except FileNotFoundError:
        return []
    if not text:
        return []
    complete = text[:text.rfind('\n') + 1]
    reader = csv.reader(io.StringIO(complete))
    header = tuple(next(reader, None) or ())
    if header != COLUMNS and header != LEGACY_COLUMNS:
        raise ValueError(f'{os.fspath(path)!r} is not an episode log of this version: its '
                         f'header is {list(header)!r}, expected {list(COLUMNS)}; use another '
                         '--out')
    rows = []
    for line_number, values in enumerate(reader, start=2):
        if len(values) != len(header):
            raise ValueError(f'{os.fspath(path)!r} line {line_number}: {len(values)} fields, '
                             f'expected {len(header)}')
        try:
            row = dict.fromkeys(COLUMNS, '')
            row.update(zip(header, values))
            rows.append(_parse_row(row, legacy=header == LEGACY_COLUMNS))
        except ValueError as exc:
            raise ValueError(f'{os.fspath(path)!r} line {line_number}: {exc}') from exc
    return rows


def _is_legacy(path):
    """Tell whether the log at ``path`` has the version-1 header."""
    with open(path, newline='', encoding='utf-8') as stream:
        return tuple(next(csv.reader(stream), ())) == LEGACY_COLUMNS


def _parse_row(row, legacy=False):
    """
    Convert one row's strings to the column types; raise ValueError when one does not fit.

    A version-1 row (``legacy``) has None in every column it lacks.
    """
    for column in INT_COLUMNS:
        row[column] = int(row[column])
    for column in FLOAT_COLUMNS:
        row[column] = float(row[column])
    row['number'] = int(row['number']) if row['number'] else None
    for column in DETECTION_COLUMNS + ('detection_wall_time',):
        text = row[column]
        if not text:
            row[column] = None
        elif column in _DETECTION_INT_COLUMNS:
            row[column] = int(text)
        else:
            row[column] = float(text)
    for column in METRIC_COLUMNS:
        text = row[column]
        if column in _METRIC_TEXT_COLUMNS:
            row[column] = None if legacy else text
        else:
            row[column] = float(text) if text else None
    if row['end_reason'] not in END_REASONS + (None,):
        raise ValueError(f'bad end_reason {row["end_reason"]!r}')
    if row['success'] not in (0, 1) or row['failure'] not in FAILURES:
        raise ValueError(f'bad success/failure {row["success"]!r}/{row["failure"]!r}')
    return row


class EpisodeLog:
    """
    An episode log open for appending.

    Use as a context manager. Opening creates the file with its header, or drops a cut-short
    last line of an existing one, so that the next row starts on a line of its own.

    Parameters
    ----------
    path : str or os.PathLike
        ``episodes.csv``; its folder must exist.

    Raises
    ------
    ValueError
        If an existing file is not a log of this version (see `read_log`), or of version 1
        (read, never resumed).

    """

    def __init__(self, path):
        self.path = path
        self.rows = read_log(path)
        if os.path.isfile(path) and _is_legacy(path):
            raise ValueError(f'{os.fspath(path)!r} is a version-1 episode log (success as the '
                             'navigator reported it, the time limit from its own speed): '
                             'it reads, but a run with the current rules needs another --out')
        with open(path, 'a+b') as stream:
            stream.seek(0)
            data = stream.read()
            keep = data.rfind(b'\n') + 1
            if keep < len(data):
                stream.truncate(keep)
        self._stream = open(path, 'a', newline='', encoding='utf-8')
        self._writer = csv.writer(self._stream, lineterminator='\n')
        if self._stream.tell() == 0:
            self._writer.writerow(COLUMNS)
            self._stream.flush()

    def done_keys(self):
        """Return the keys of the episodes in the log, as in `row_key`."""
        return {row_key(row) for row in self.rows}

    def append(self, row):
        """
        Write one episode's row and flush it to the operating system.

        Parameters
        ----------
        row : dict
            Every column of `COLUMNS`; ``success`` as bool or 0/1, ``number`` int or None.

        """
        values = []
        for column in COLUMNS:
            value = row[column]
            if column == 'success':
                value = int(bool(value))
            elif value is None:
                value = ''
            values.append(value)
        self._writer.writerow(values)
        self._stream.flush()
        parsed = dict(zip(COLUMNS, values))
        parsed['success'] = int(parsed['success'])
        parsed['number'] = row['number']
        self.rows.append(parsed)

    def close(self):
        """Close the file."""
        self._stream.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()
