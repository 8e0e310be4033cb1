"""
The episode log: one CSV row per finished episode, appended as results arrive.

``episodes.csv`` in a run's output folder is the run's only state. A row is written and flushed
as soon as its episode ends, so an interrupted run loses at most the episodes in flight; a
re-run reads the log and skips every episode whose key (map, task, wanderers, repetition, seed)
is already there. A last line cut short by a kill is dropped when the log is reopened.

The log holds each key once: a log with a key twice is refused when it is read, a row whose key
is there already is refused when it is appended, and an open log is locked (``flock``), so that
a second run into the same folder while one is writing ends with an error instead of running
every episode again. A row is written with one ``write`` call; if that fails (a full disk, a
file-size limit) the file is cut back to its last complete row and the error raised. Text
columns hold no control characters (a NUL, a newline): such a row is refused, when read or
appended.

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
  differ between two runs of the same episode);
- `CONTACT_KIND_COLUMNS` (version 3): ``robot_caused_contacts`` and ``agent_caused_contacts``,
  the wanderer contact events split by who closed the gap (``sim_bridge.contacts``).

A log of version 1 (`LEGACY_COLUMNS`: before the metric and the added detection columns,
success as the navigator reported it) still reads, its new columns None; it is not resumed
(`EpisodeLog` refuses it: the rules changed). A log of version 2 (`VERSION2_COLUMNS`: before
the contact kinds) reads with those None, and is not resumed either (its rows are shorter).

"""

import csv
import errno
import fcntl
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
#: The wanderer contacts by who closed the gap (version 3).
CONTACT_KIND_COLUMNS = ('robot_caused_contacts', 'agent_caused_contacts')
#: The columns of a version-2 log, which `read_log` still reads.
VERSION2_COLUMNS = (_EPISODE_COLUMNS + METRIC_COLUMNS + DETECTION_COLUMNS
                    + ('wall_time', 'detection_wall_time'))
#: The log's columns, in file order (version 3).
COLUMNS = VERSION2_COLUMNS + CONTACT_KIND_COLUMNS
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
#: Free-text columns (checked by `check_text_columns`); ``map`` must not be empty.
TEXT_COLUMNS = ('map', 'family')


def check_text_columns(row):
    """
    Check the free-text columns of a row: no control characters, a ``map``.

    Raises
    ------
    ValueError
        Naming the column and the first bad character.

    """
    for column in TEXT_COLUMNS:
        text = row[column]
        if not isinstance(text, str):
            raise ValueError(f'{column} must be text, got {text!r}')
        bad = next((char for char in text if ord(char) < 32 or ord(char) == 127), None)
        if bad is not None:
            raise ValueError(f'{column} {text!r} holds the control character {bad!r}')
    if not row['map']:
        raise ValueError('map is empty')


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
        If the header is not `COLUMNS`, `VERSION2_COLUMNS` or `LEGACY_COLUMNS` (a log of
        another version or another tool) or a complete row does not parse.

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
    if header not in (COLUMNS, VERSION2_COLUMNS, LEGACY_COLUMNS):
        raise ValueError(f'{os.fspath(path)!r} is not an episode log of this version: its '
                         f'header is {list(header)!r}, expected {list(COLUMNS)}; use another '
                         '--out')
    rows = []
    lines = {}                  # key -> line number
    for line_number, values in _csv_records(reader, path):
        if len(values) != len(header):
            raise ValueError(f'{os.fspath(path)!r} line {line_number}: {len(values)} fields, '
                             f'expected {len(header)}')
        try:
            row = dict.fromkeys(COLUMNS, '')
            row.update(zip(header, values))
            row = _parse_row(row, legacy=header == LEGACY_COLUMNS)
        except ValueError as exc:
            raise ValueError(f'{os.fspath(path)!r} line {line_number}: {exc}') from exc
        key = row_key(row)
        if key in lines:
            raise ValueError(f'{os.fspath(path)!r} line {line_number}: episode {key} is logged '
                             f'already on line {lines[key]}; remove one of the two lines')
        lines[key] = line_number
        rows.append(row)
    return rows


def _is_legacy(path):
    """Tell whether the log at ``path`` has the version-1 header."""
    return _header(path) == LEGACY_COLUMNS


def _header(path):
    """Return the header of the log at ``path`` (empty for an empty file)."""
    with open(path, newline='', encoding='utf-8') as stream:
        return tuple(next(csv.reader(stream), ()))


def _csv_records(reader, path):
    """Yield ``(first line number, values)`` per CSV record; raise ValueError for a bad one."""
    while True:
        first_line = reader.line_num + 1
        try:
            values = next(reader)
        except StopIteration:
            return
        except csv.Error as exc:
            raise ValueError(f'{os.fspath(path)!r} line {first_line}: {exc}') from exc
        yield first_line, values


def _parse_row(row, legacy=False):
    """
    Convert one row's strings to the column types; raise ValueError when one does not fit.

    A version-1 row (``legacy``) has None in every column it lacks.
    """
    check_text_columns(row)
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
    for column in CONTACT_KIND_COLUMNS:
        row[column] = int(row[column]) if row[column] else None
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
    An episode log open for appending, locked against a second writer.

    Use as a context manager. Opening creates the file with its header, or drops a cut-short
    last line of an existing one, so that the next row starts on a line of its own.

    Parameters
    ----------
    path : str or os.PathLike
        ``episodes.csv``; its folder must exist.

    Raises
    ------
    ValueError
        If an existing file is not a log of this version or holds a key twice (see
        `read_log`), is of version 1 (read, never resumed), or another process has it open
        (another run into the same folder).
    OSError
        If the file cannot be created, read or written.

    """

    def __init__(self, path):
        self.path = path
        self._fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_APPEND | os.O_CLOEXEC, 0o644)
        try:
            try:
                fcntl.flock(self._fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as exc:
                if exc.errno not in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                    raise
                raise ValueError(
                    f'{os.fspath(path)!r} is being written by another run (a second '
                    'dpn-benchmark into the same --out): wait for it to end, then run the '
                    'command again to resume, or use another --out') from exc
            self.rows = read_log(path)
            if _is_legacy(path):
                raise ValueError(
                    f'{os.fspath(path)!r} is a version-1 episode log (success as the navigator '
                    'reported it, the time limit from its own speed): it reads, but a run with '
                    'the current rules needs another --out')
            if _header(path) == VERSION2_COLUMNS:
                raise ValueError(
                    f'{os.fspath(path)!r} is a version-2 episode log (before the contacts by '
                    'who closed the gap): it reads, but a run needs another --out')
            with open(path, 'rb') as stream:
                data = stream.read()
            keep = data.rfind(b'\n') + 1
            if keep < len(data):
                os.ftruncate(self._fd, keep)
            if keep == 0:
                self._write_line(COLUMNS)
        except BaseException:
            os.close(self._fd)
            raise
        self._keys = {row_key(row) for row in self.rows}

    def done_keys(self):
        """Return the keys of the episodes in the log, as in `row_key`."""
        return set(self._keys)

    def _write_line(self, values):
        """Write one CSV line with one ``write``; on failure cut the file back and raise."""
        text = io.StringIO()
        csv.writer(text, lineterminator='\n').writerow(values)
        data = text.getvalue().encode('utf-8')
        size = os.fstat(self._fd).st_size
        try:
            written = 0
            while written < len(data):
                written += os.write(self._fd, data[written:])
        except OSError as exc:
            try:
                os.ftruncate(self._fd, size)
            except OSError:
                pass
            if exc.filename is None:
                raise type(exc)(exc.errno, exc.strerror or str(exc), os.fspath(self.path)) \
                    from exc
            raise

    def append(self, row):
        """
        Write one episode's row to the operating system (one ``write`` call).

        Parameters
        ----------
        row : dict
            Every column of `COLUMNS`; ``success`` as bool or 0/1, ``number`` int or None.

        Raises
        ------
        ValueError
            If the row's key is in the log already or a text column holds a control
            character; nothing is written then.
        OSError
            If the write fails (a full disk, a file-size limit); the log then ends with its
            last complete row.

        """
        check_text_columns(row)
        values = []
        for column in COLUMNS:
            value = row[column]
            if column == 'success':
                value = int(bool(value))
            elif value is None:
                value = ''
            values.append(value)
        parsed = dict(zip(COLUMNS, values))
        key = row_key(parsed)
        if key in self._keys:
            raise ValueError(f'episode {key} is in {os.fspath(self.path)!r} already')
        self._write_line(values)
        parsed['success'] = int(parsed['success'])
        parsed['number'] = row['number']
        self.rows.append(parsed)
        self._keys.add(key)

    def close(self):
        """Close the file (and release its lock)."""
        if self._fd is not None:
            fd, self._fd = self._fd, None
            os.close(fd)

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()
