"""
``dpn-benchmark --laser``: the option, its wiring into the episodes, and its record in the run.

In-process runs of one short episode on one worker; the installed-executable runs of the
benchmark are in ``test_benchmark_cli.py``.

"""

import json

from dpn_navigator.benchmark import cli
from dpn_navigator.benchmark.episode import run_episode
from dpn_navigator.benchmark.episode_log import read_log
from dpn_navigator.benchmark.protocol import plan_episodes
from dpn_navigator.benchmark.runner import episode_keywords, run_protocol
import numpy as np
import pytest
from sim_bridge.laser_profiles import laser_profile, LASER_PROFILE_NAMES
from sim_bridge.scenario import load_scenario

#: One quick episode: tunnel, task 0, no wanderers.
ONE_EPISODE = ['--maps', 'tunnel', '--tasks', '0', '--wanderers', '0', '--repeats', '1',
               '--workers', '1', '--no-progress']


def test_the_cli_lists_every_profile():
    assert cli.LASER_PROFILE_NAMES == LASER_PROFILE_NAMES
    args = cli.build_parser().parse_args(['--laser', 'hokuyo_urg04lx'])
    assert args.laser == 'hokuyo_urg04lx'
    assert cli.build_parser().parse_args([]).laser == 'ideal'


def test_an_unknown_laser_is_refused_with_the_choices(tmp_path, capsys):
    with pytest.raises(SystemExit) as stop:
        cli.main(['--laser', 'lms200', '--out', str(tmp_path / 'out'), *ONE_EPISODE])
    assert stop.value.code == 2
    error = capsys.readouterr().err
    assert "unknown --laser 'lms200'" in error and 'hokuyo_utm30lx' in error
    assert 'Traceback' not in error and not (tmp_path / 'out').exists()


def test_run_protocol_refuses_an_unknown_laser(tmp_path):
    specs = plan_episodes(('tunnel',), (0,), (0,), 1, 0)
    with pytest.raises(ValueError, match='unknown laser profile'):
        run_protocol(specs, tmp_path / 'episodes.csv', workers=1, progress=False,
                     episode_options={'laser': 'lms200'})


def test_run_settings_and_episode_options_name_the_laser_unless_ideal():
    parse = cli.build_parser().parse_args
    assert cli.run_settings(parse([])) == {'navigator': 'dpn'}
    assert cli.episode_options(parse([])) is None
    args = parse(['--navigator', 'paper', '--laser', 'rplidar_a2'])
    assert cli.run_settings(args) == {'navigator': 'paper', 'laser': 'rplidar_a2'}
    assert cli.episode_options(args) == {'laser': 'rplidar_a2'}
    assert episode_keywords({'laser': 'rplidar_a2'}) == {
        'laser': laser_profile('rplidar_a2').laser}
    assert episode_keywords({'laser': 'ideal'}) == {}


@pytest.mark.slow
def test_a_laser_run_is_recorded_and_not_resumed_with_another(tmp_path, capsys):
    out = tmp_path / 'out'
    assert cli.main(['--laser', 'sick_lms1xx', '--out', str(out), *ONE_EPISODE]) == 0
    assert json.loads((out / 'run.json').read_text()) == {'navigator': 'dpn',
                                                          'laser': 'sick_lms1xx'}
    assert 'dpn navigator, sick_lms1xx laser' in (out / 'summary.md').read_text()
    (row,) = read_log(out / 'episodes.csv')
    assert row['scans'] > 0
    with pytest.raises(SystemExit) as stop:
        cli.main(['--out', str(out), *ONE_EPISODE])
    assert stop.value.code == 2
    assert "holds a run with {'laser': 'sick_lms1xx', 'navigator': 'dpn'}" in \
        capsys.readouterr().err


@pytest.mark.parametrize('name', ['hokuyo_utm30lx', 'rplidar_a2'])
def test_the_navigator_gets_the_profiles_scans_and_mount(name):
    laser = laser_profile(name).laser
    seen = []

    def recorder(world, navigator):
        scan = world.scan()
        seen.append((scan.ranges.shape[0], scan.angle_min, scan.angle_increment,
                     scan.range_min, scan.range_max, navigator.config.laser_offset))
    result = run_episode(load_scenario('tunnel'), 0, 2, 7, time_limit=2.0, recorder=recorder,
                         laser=laser)
    assert result.time == pytest.approx(2.0, abs=0.11) and len(seen) >= 19
    expected = (laser.n_beams, laser.angle_min, laser.angle_increment, laser.range_min,
                laser.range_max, laser.mount)
    assert all(entry[:5] == expected[:5] for entry in seen)
    assert all(np.allclose(entry[5], laser.mount) for entry in seen)
