"""
The benchmark's data safety: write failures end in one line and exit 2, nothing lost or doubled.

The episode log holds each episode once (refused twice when read, appended or written by two
runs at once), refuses control characters in its text columns and is cut back to its last
complete row when a write fails; summaries and figures are written whole or not at all; a bag
folder cut short by a kill is replaced on resume. A full disk is simulated by a file-size limit
(``RLIMIT_FSIZE``) on a real ``dpn-benchmark`` process, and by a ``write`` that raises
``ENOSPC``.
"""

import errno
import os
import resource
import subprocess

from dpn_navigator.benchmark import cli
from dpn_navigator.benchmark.episode_bag import episode_bag_name
from dpn_navigator.benchmark.episode_log import COLUMNS, EpisodeLog, read_log
from dpn_navigator.benchmark.output_files import (os_error_line, write_file_atomically,
                                                  write_text_atomically)
from dpn_navigator.benchmark.protocol import plan_episodes
from dpn_navigator.benchmark.runner import check_bag_folders, is_partial_bag
from dpn_navigator.recording.bag_writer import BagPathError
from dpn_navigator.tools.demo import installed_executable
import pytest

#: One short episode (about 5 s): back_and_forth, task 0, no wanderers.
ONE_EPISODE = ['--maps', 'back_and_forth', '--tasks', '0', '--wanderers', '0', '--repeats',
               '1', '--no-detection', '--no-progress', '--workers', '1']


def row(map_key='back_and_forth', task=0, **changes):
    """Return a log row of every column (numbers made up, in their types)."""
    values = dict.fromkeys(COLUMNS, None)
    values.update(map=map_key, number=3, family='corridors', task=task, wanderers=0,
                  repetition=0, seed=7, success=True, failure='', time=12.5, time_limit=100.0,
                  path_length=9.0, shortest_path=8.0, replans=1, forgets=0, wall_contacts=0,
                  wanderer_contacts=0, walls_labelled_mobile=0, ghost_obstacles=0,
                  wall_time=1.5)
    values.update(changes)
    return values


def test_a_key_is_appended_once(tmp_path):
    path = tmp_path / 'episodes.csv'
    with EpisodeLog(path) as log:
        log.append(row())
        with pytest.raises(ValueError, match='is in .* already'):
            log.append(row(time=99.0))
        log.append(row(task=1))
    assert [r['task'] for r in read_log(path)] == [0, 1]


def test_a_log_with_a_key_twice_is_refused(tmp_path):
    path = tmp_path / 'episodes.csv'
    with EpisodeLog(path) as log:
        log.append(row())
    lines = path.read_text().splitlines(keepends=True)
    path.write_text(''.join(lines + lines[1:]))
    with pytest.raises(ValueError, match=r'line 3: episode .* logged already on line 2'):
        read_log(path)
    with pytest.raises(ValueError, match='logged already'):
        EpisodeLog(path)


@pytest.mark.parametrize('column, text', [('map', 'back\0and_forth'), ('map', 'a\nb'),
                                          ('family', 'x\ry'), ('map', '')])
def test_text_columns_refuse_control_characters(tmp_path, column, text):
    path = tmp_path / 'episodes.csv'
    with EpisodeLog(path) as log:
        with pytest.raises(ValueError, match=f'{column}'):
            log.append(row(**{column: text}))
        log.append(row())
    assert len(read_log(path)) == 1
    # The same text written into the file by hand is refused when read.
    good = path.read_text()
    if column == 'family':
        path.write_text(good.replace(',corridors,', f',{text},'))
    elif text:
        path.write_text(good.replace('back_and_forth', f'"{text}"'))
    else:
        path.write_text(good.replace('back_and_forth', ''))
    with pytest.raises(ValueError, match='line 2'):
        read_log(path)


def test_a_second_writer_is_refused_while_the_first_holds_the_log(tmp_path):
    path = tmp_path / 'episodes.csv'
    with EpisodeLog(path) as log:
        log.append(row())
        with pytest.raises(ValueError, match='being written by another run'):
            EpisodeLog(path)
    with EpisodeLog(path) as log:                       # free again
        assert log.done_keys() == {('back_and_forth', 0, 0, 0, 7)}


def test_a_failed_append_leaves_the_last_complete_row(tmp_path, monkeypatch):
    path = tmp_path / 'episodes.csv'
    with EpisodeLog(path) as log:
        log.append(row())
        real_write = os.write

        def full_disk(fd, data):
            if fd == log._fd:
                real_write(fd, data[:len(data) // 2])       # half a row, then the disk is full
                raise OSError(errno.ENOSPC, 'No space left on device')
            return real_write(fd, data)

        monkeypatch.setattr(os, 'write', full_disk)
        with pytest.raises(OSError, match='No space left') as caught:
            log.append(row(task=1))
        monkeypatch.undo()
        assert caught.value.filename == os.fspath(path)
        assert os_error_line(caught.value) == (f"cannot write '{path}': No space left on "
                                               'device')
        log.append(row(task=2))
    assert [r['task'] for r in read_log(path)] == [0, 2]


def test_a_file_is_written_whole_or_not_at_all(tmp_path):
    path = tmp_path / 'summary.md'
    write_text_atomically(path, 'old\n')

    def half_then_full(temporary):
        temporary.write_text('half')
        raise OSError(errno.ENOSPC, 'No space left on device')

    with pytest.raises(OSError) as caught:
        write_file_atomically(path, half_then_full)
    assert caught.value.filename == os.fspath(path)
    assert path.read_text() == 'old\n'
    assert sorted(p.name for p in tmp_path.iterdir()) == ['summary.md']


def test_a_partial_bag_is_replaced_and_a_complete_one_refused(tmp_path):
    first, second = plan_episodes(('back_and_forth',), (0, 1), (0,), 1, 0)
    partial = tmp_path / episode_bag_name(first)
    partial.mkdir()
    (partial / f'{partial.name}_0.mcap').write_bytes(b'\x89MCAP0\r\n')     # cut short
    assert is_partial_bag(partial)
    assert check_bag_folders([first, second], tmp_path) == [partial]
    assert not partial.exists()
    complete = tmp_path / episode_bag_name(second)
    complete.mkdir()
    (complete / f'{complete.name}_0.mcap').write_bytes(b'')
    (complete / 'metadata.yaml').write_text('rosbag2_bagfile_information: {}\n')
    assert not is_partial_bag(complete)
    with pytest.raises(BagPathError, match='exists already'):
        check_bag_folders([first, second], tmp_path)
    empty = tmp_path / 'empty'
    empty.mkdir()
    assert not is_partial_bag(empty)
    other = tmp_path / 'notes'
    other.mkdir()
    (other / 'notes.txt').write_text('mine')
    assert not is_partial_bag(other) and not is_partial_bag(tmp_path / 'missing')


@pytest.mark.parametrize('where', ['file', 'under_a_file'])
def test_an_out_that_is_no_folder_ends_in_one_line(tmp_path, capsys, where):
    (tmp_path / 'file').write_text('')
    out = tmp_path / 'file' if where == 'file' else tmp_path / 'file' / 'out'
    with pytest.raises(SystemExit) as caught:
        cli.main([*ONE_EPISODE, '--out', str(out)])
    assert caught.value.code == 2
    err = capsys.readouterr().err
    assert err.count('\n') == 1 and err.startswith('dpn-benchmark: error: cannot write'), err


def test_a_second_run_into_a_folder_being_written_is_refused(tmp_path, capsys):
    with EpisodeLog(tmp_path / 'episodes.csv'):
        with pytest.raises(SystemExit) as caught:
            cli.main([*ONE_EPISODE, '--out', str(tmp_path)])
    assert caught.value.code == 2
    err = capsys.readouterr().err
    assert err.count('\n') == 1 and 'being written by another run' in err, err


def benchmark_with_file_size_limit(out, limit):
    """Run the installed dpn-benchmark on one episode, its files limited to ``limit`` bytes."""
    def set_limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    command = [str(installed_executable('dpn_navigator', 'dpn-benchmark')), *ONE_EPISODE,
               '--out', str(out)]
    return subprocess.run(command, capture_output=True, text=True, timeout=300, check=False,
                          preexec_fn=None if limit is None else set_limit)


def error_lines(done):
    return [line for line in done.stderr.splitlines() if 'pybullet build time' not in line]


@pytest.mark.slow
def test_a_file_size_limit_ends_in_one_line_and_the_rerun_loses_nothing(tmp_path):
    # 1. The limit stops the episode's row: exit 2, one line, the log without a partial row.
    header = len(','.join(COLUMNS)) + 1
    row_limit = benchmark_with_file_size_limit(tmp_path, header + 60)
    assert row_limit.returncode == 2, row_limit.stderr
    assert len(error_lines(row_limit)) == 1, row_limit.stderr
    assert 'File too large' in row_limit.stderr and 'episodes.csv' in row_limit.stderr
    assert read_log(tmp_path / 'episodes.csv') == []
    assert len((tmp_path / 'episodes.csv').read_bytes()) == header
    # 2. The row fits, the summary does not: exit 2, the row kept, no half summary.
    # One row is about 300 bytes; a report (summary.md, success_rate.png) is larger.
    summary_limit = benchmark_with_file_size_limit(tmp_path, header + 400)
    assert summary_limit.returncode == 2, summary_limit.stderr
    assert len(error_lines(summary_limit)) == 1, summary_limit.stderr
    failed = 'summary.md' if 'summary.md' in summary_limit.stderr else 'success_rate.png'
    assert f"{failed}': File too large" in summary_limit.stderr, summary_limit.stderr
    assert len(read_log(tmp_path / 'episodes.csv')) == 1
    # No half file: the report that failed is not there, nor any temporary file.
    names = sorted(p.name for p in tmp_path.iterdir())
    assert failed not in names and not any('.tmp' in name for name in names), names
    assert len((tmp_path / 'episodes.csv').read_bytes()) <= header + 400
    # 3. Without the limit the same command resumes: nothing run twice, the reports written.
    done = benchmark_with_file_size_limit(tmp_path, None)
    assert done.returncode == 0, done.stderr
    assert 'ran 0 episodes (1 already logged)' in done.stdout
    assert len(read_log(tmp_path / 'episodes.csv')) == 1
    assert (tmp_path / 'summary.md').stat().st_size > 450
