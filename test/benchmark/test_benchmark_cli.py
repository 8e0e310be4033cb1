"""
The installed ``dpn-benchmark`` on the smoke profile, 2 maps: CSV schema, determinism, resume.

Each run is a process of its own, started from the executable ``ros2 run dpn_navigator
dpn-benchmark`` resolves. Episodes are deterministic for a seed, so two runs of the same
protocol must log the same rows, whatever the number of workers or the backend (local processes
or Ray); only ``wall_time`` and ``detection_wall_time`` may differ.

"""

import math
import os
import shutil
import subprocess

from dpn_navigator.benchmark.episode_log import (COLUMNS, DETECTION_COLUMNS, FAILURES,
                                                 read_log, row_key)
from dpn_navigator.benchmark.protocol import plan_episodes, PROFILES
from dpn_navigator.tools.demo import installed_executable
import pytest

#: The smoke profile on two maps: 1 task, 0/5/10 wanderers, 1 repetition, so 6 episodes.
SMOKE_MAPS = ('back_and_forth', 'tunnel')
SMOKE = ['--profile', 'smoke', '--maps', *SMOKE_MAPS, '--no-progress']


def benchmark(*args, timeout=600):
    """Run the installed dpn-benchmark; return the finished process (output captured)."""
    executable = installed_executable('dpn_navigator', 'dpn-benchmark')
    env = dict(os.environ, RAY_USAGE_STATS_ENABLED='0')
    return subprocess.run([str(executable), *args], capture_output=True, text=True,
                          timeout=timeout, env=env, check=False)


def without_wall_time(rows):
    """Return the rows sorted by key, without the two columns that may differ between runs."""
    return sorted(({k: v for k, v in row.items() if k not in ('wall_time', 'detection_wall_time')}
                   for row in rows), key=lambda row: tuple(map(str, row_key(row))))


@pytest.fixture(scope='module')
def smoke_run(tmp_path_factory):
    """Run the smoke profile on two workers; return the output folder and the process."""
    out = tmp_path_factory.mktemp('smoke')
    done = benchmark(*SMOKE, '--workers', '2', '--out', str(out))
    assert done.returncode == 0, done.stderr
    return out, done


@pytest.mark.slow
def test_smoke_run_logs_every_episode_with_the_schema(smoke_run):
    out, done = smoke_run
    smoke = PROFILES['smoke']
    specs = plan_episodes(SMOKE_MAPS, smoke.tasks, smoke.wanderers, smoke.repeats, 0)
    header = (out / 'episodes.csv').read_text().splitlines()[0]
    assert header == ','.join(COLUMNS)
    rows = read_log(out / 'episodes.csv')
    assert sorted(row_key(row) for row in rows) == sorted(spec.key for spec in specs)
    for row in rows:
        assert row['failure'] in FAILURES
        assert row['success'] == (row['failure'] == '')
        assert row['family'] and row['number'] in (3, 27)
        assert 0.0 < row['time'] <= row['time_limit'] + 0.11
        assert math.isfinite(row['shortest_path']) and row['shortest_path'] > 5.0
        assert row['time_limit'] == pytest.approx(30.0 + 3.0 * row['shortest_path'], abs=0.01)
        assert row['replans'] >= 1 and row['wall_time'] > 0.0
        assert min(row['wall_contacts'], row['wanderer_contacts'], row['path_length'],
                   row['walls_labelled_mobile'], row['ghost_obstacles']) >= 0
        # The detection measures are on: every scan measured, every plan given a cause.
        assert row['scans'] >= 10 * row['time'] and 0.0 < row['detection_wall_time']
        assert sum(row[f'replans_{cause}'] for cause in
                   ('wall', 'wanderer', 'no_path_retry', 'other')) == row['replans']
        assert (row['wanderer_hit_recall'] is None) == (row['wanderers'] == 0)
    # Without wanderers, nothing can stop the robot on these maps.
    assert all(row['success'] for row in rows if row['wanderers'] == 0)
    assert 'ran 6 episodes (0 already logged)' in done.stdout
    assert 'episodes per hour' in done.stdout
    summary = (out / 'summary.md').read_text()
    assert '| 3 back_and_forth |' in summary and '| 27 tunnel |' in summary
    assert (out / 'success_rate.png').read_bytes()[:4] == b'\x89PNG'
    assert '| dpn | 10 | 2 |' in summary                   # the detection table
    assert (out / 'detection.png').read_bytes()[:4] == b'\x89PNG'


@pytest.mark.slow
def test_same_seed_same_rows_on_one_worker(smoke_run, tmp_path):
    out, _ = smoke_run
    done = benchmark(*SMOKE, '--workers', '1', '--out', str(tmp_path))
    assert done.returncode == 0, done.stderr
    assert without_wall_time(read_log(tmp_path / 'episodes.csv')) == \
        without_wall_time(read_log(out / 'episodes.csv'))


@pytest.mark.slow
def test_a_rerun_resumes_where_the_log_ends(smoke_run, tmp_path):
    out, _ = smoke_run
    shutil.copy(out / 'episodes.csv', tmp_path / 'episodes.csv')
    lines = (tmp_path / 'episodes.csv').read_text().splitlines(keepends=True)
    # Two episodes lost, and a third cut short in the middle of its line, as by a kill.
    (tmp_path / 'episodes.csv').write_text(''.join(lines[:-2]) + lines[-2][:20])
    done = benchmark(*SMOKE, '--workers', '2', '--out', str(tmp_path))
    assert done.returncode == 0, done.stderr
    assert 'ran 2 episodes (4 already logged)' in done.stdout
    resumed = read_log(tmp_path / 'episodes.csv')
    assert resumed[:4] == read_log(out / 'episodes.csv')[:4]     # untouched, wall_time too
    assert without_wall_time(resumed) == without_wall_time(read_log(out / 'episodes.csv'))
    again = benchmark(*SMOKE, '--out', str(tmp_path))
    assert again.returncode == 0 and 'ran 0 episodes (6 already logged)' in again.stdout


@pytest.mark.slow
def test_ray_backend_logs_the_same_rows(smoke_run, tmp_path):
    pytest.importorskip('ray', reason='the Ray backend is optional: requirements-ray.txt')
    out, _ = smoke_run
    done = benchmark('--profile', 'smoke', '--maps', 'back_and_forth', '--wanderers', '0', '5',
                     '--ray-address', 'local', '--no-progress', '--out', str(tmp_path))
    assert done.returncode == 0, done.stderr
    expected = [row for row in read_log(out / 'episodes.csv')
                if row['map'] == 'back_and_forth' and row['wanderers'] in (0, 5)]
    assert without_wall_time(read_log(tmp_path / 'episodes.csv')) == \
        without_wall_time(expected)


def test_without_detection_the_same_episode_logs_the_same_outcome(smoke_run, tmp_path):
    out, _ = smoke_run
    done = benchmark(*SMOKE, '--maps', 'back_and_forth', '--wanderers', '5', '--no-detection',
                     '--out', str(tmp_path))
    assert done.returncode == 0, done.stderr
    (plain,) = read_log(tmp_path / 'episodes.csv')
    (measured,) = [row for row in read_log(out / 'episodes.csv')
                   if row['map'] == 'back_and_forth' and row['wanderers'] == 5]
    measures = DETECTION_COLUMNS + ('detection_wall_time',)
    assert all(plain[name] is None for name in measures)
    assert {k: v for k, v in without_wall_time([plain])[0].items() if k not in measures} == \
        {k: v for k, v in without_wall_time([measured])[0].items() if k not in measures}
    assert 'No episode with detection measures.' in (tmp_path / 'summary.md').read_text()
    assert not (tmp_path / 'detection.png').exists()


def test_a_log_is_not_resumed_with_another_navigator(smoke_run):
    out, _ = smoke_run
    done = benchmark(*SMOKE, '--navigator', 'paper', '--out', str(out), timeout=120)
    assert done.returncode == 2
    assert "holds a run with {'navigator': 'dpn'}" in done.stderr
    assert len(read_log(out / 'episodes.csv')) == 6


def test_a_map_server_yaml_runs_with_drawn_tasks(tmp_path):
    # Any map_server pair, under a name the index does not know: a copy of a shipped map.
    from sim_bridge.scenario import INDEX_PATH
    for suffix in ('.yaml', '.pgm'):
        shutil.copy(INDEX_PATH.parent / f'back_and_forth{suffix}', tmp_path)
    own = tmp_path / 'own_lanes.yaml'
    (tmp_path / 'back_and_forth.yaml').rename(own)
    done = benchmark('--maps', str(own), '--tasks', '0', '--wanderers', '0', '--no-progress',
                     '--out', str(tmp_path / 'out'))
    assert done.returncode == 0, done.stderr
    (row,) = read_log(tmp_path / 'out' / 'episodes.csv')
    assert row['map'] == str(own) and row['number'] is None and row['family'] == ''
    assert row['success'] == 1 and row['shortest_path'] >= 5.0     # drawn at least 5 m apart
    assert '| own_lanes |' in (tmp_path / 'out' / 'summary.md').read_text()


@pytest.mark.parametrize(('args', 'message'), [
    (['--maps', 'no_such_map'], "unknown map 'no_such_map'"),
    (['--wanderers', '11'], 'wanderer count must be an integer in'),
    (['--maps', '/nowhere/map.yaml'], 'does not exist'),
    (['--workers', '0'], 'workers must be a positive integer'),
])
def test_bad_selections_are_refused_before_running(tmp_path, args, message):
    done = benchmark(*args, '--out', str(tmp_path / 'out'), timeout=120)
    assert done.returncode == 2
    assert message in done.stderr
    assert not (tmp_path / 'out' / 'episodes.csv').exists() or \
        read_log(tmp_path / 'out' / 'episodes.csv') == []


@pytest.fixture(scope='module', params=['oracle', 'costmap'])
def reference_run(request, tmp_path_factory):
    """Run the smoke profile with a reference navigator; return its name and output folder."""
    out = tmp_path_factory.mktemp(request.param)
    done = benchmark(*SMOKE, '--navigator', request.param, '--workers', '2', '--out', str(out))
    assert done.returncode == 0, done.stderr
    assert 'ran 6 episodes (0 already logged)' in done.stdout
    return request.param, out


@pytest.mark.slow
def test_reference_navigators_run_the_same_episodes_as_dpn(smoke_run, reference_run):
    name, out = reference_run
    rows = read_log(out / 'episodes.csv')
    dpn_rows = read_log(smoke_run[0] / 'episodes.csv')
    # The same episodes: maps, tasks, wanderer counts, seeds (and so the same wanderers).
    assert sorted(row_key(row) for row in rows) == sorted(row_key(row) for row in dpn_rows)
    assert (out / 'run.json').read_text().strip() == '{"navigator": "%s"}' % name
    for row in rows:
        assert row['failure'] in FAILURES and row['success'] == (row['failure'] == '')
        assert 0.0 < row['time'] <= row['time_limit'] + 0.11
        assert row['walls_labelled_mobile'] == 0 or name == 'oracle'
    assert all(row['success'] for row in rows if row['wanderers'] == 0)
    assert f'{name} navigator' in (out / 'summary.md').read_text()
    assert (out / 'success_rate.png').read_bytes()[:4] == b'\x89PNG'
    if name == 'oracle':
        # It builds no map from the laser, so it has no detection measures.
        assert all(row[column] is None for row in rows for column in DETECTION_COLUMNS)
        assert not (out / 'detection.png').exists()
    else:
        # The costmap is measured by its lethal cells; it has no mobile label.
        assert all(row['scans'] >= 10 * row['time'] for row in rows)
        assert all(row['mobile_visible'] == 0 and row['mobile_precision'] is None
                   for row in rows)
        assert '| costmap | 10 | 2 | n/a | n/a | n/a | n/a |' in (out / 'summary.md').read_text()


def test_a_reference_log_is_not_resumed_with_another_navigator(reference_run):
    name, out = reference_run
    other = 'costmap' if name == 'oracle' else 'oracle'
    done = benchmark(*SMOKE, '--navigator', other, '--out', str(out), timeout=120)
    assert done.returncode == 2
    assert "holds a run with {'navigator': '%s'}" % name in done.stderr


@pytest.mark.parametrize('where', ['under_a_file', 'existing_bag'])
def test_a_bad_record_folder_is_refused_before_running(tmp_path, where):
    from dpn_navigator.benchmark.episode_bag import episode_bag_name
    (tmp_path / 'file').write_text('')
    record, message = tmp_path / 'file' / 'bags', 'cannot create the folder'
    if where == 'existing_bag':
        (spec,) = plan_episodes(('back_and_forth',), (0,), (0,), 1, 0)
        record, message = tmp_path / 'bags', 'exists already: a bag is never overwritten'
        (record / episode_bag_name(spec)).mkdir(parents=True)
    done = benchmark('--maps', 'back_and_forth', '--tasks', '0', '--wanderers', '0',
                     '--repeats', '1', '--no-progress', '--record', str(record),
                     '--out', str(tmp_path / 'out'), timeout=120)
    assert done.returncode == 2
    assert message in done.stderr and 'Traceback' not in done.stderr
    assert read_log(tmp_path / 'out' / 'episodes.csv') == []
