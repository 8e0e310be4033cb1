"""``dpn-benchmark --set NAME=VALUE``: a built-in navigator with some settings changed."""

import json

from dpn_navigator.benchmark import cli
from dpn_navigator.benchmark.compare_report import load_runs
from dpn_navigator.benchmark.episode_log import read_log
from dpn_navigator.benchmark.navigator_overrides import parse_overrides, run_label
from dpn_navigator.benchmark.protocol import NAVIGATORS
import pytest

#: One quick episode: tunnel, task 0, no wanderers.
ONE_EPISODE = ['--maps', 'tunnel', '--tasks', '0', '--wanderers', '0', '--repeats', '1',
               '--workers', '1', '--no-progress']


def test_values_take_the_type_of_their_setting():
    overrides = parse_overrides(['give_way_time=15', 'object_min_hits=4',
                                 'track_exclusive=false', 'no_echo_below_range_min=ON',
                                 'map_memory_limit= 64 '])
    assert overrides == {'give_way_time': 15.0, 'object_min_hits': 4,
                         'track_exclusive': False, 'no_echo_below_range_min': True,
                         'map_memory_limit': 64.0}
    assert type(overrides['give_way_time']) is float
    assert type(overrides['object_min_hits']) is int
    assert parse_overrides(['give_way_time=15', 'give_way_time=20']) == {'give_way_time': 20.0}
    assert parse_overrides([]) == {}


@pytest.mark.parametrize('pair, message', [
    ('give_way_time', 'takes NAME=VALUE'),
    ('=3', 'takes NAME=VALUE'),
    ('width=30', 'the scenario sets it'),
    ('height=30', 'the scenario sets it'),
    ('no_such_setting=1', 'no such setting'),
    ('give_way_time=soon', 'expected a number'),
    ('give_way_time=nan', 'expected a finite number'),
    ('give_way_time=-1', 'below its least value'),
    ('resolution=100', 'above its greatest value'),
    ('object_min_hits=2.5', 'expected an integer'),
    ('track_exclusive=maybe', 'expected true or false'),
])
def test_bad_pairs_are_refused_with_the_reason(pair, message):
    with pytest.raises(ValueError, match=message):
        parse_overrides([pair])


def test_the_whole_configuration_is_checked_on_top_of_the_navigators():
    # In range for the setting, refused by the label rule as a whole: dpn leaves trails.
    with pytest.raises(ValueError, match='--set: trail_distance needs track_confirm_time'):
        parse_overrides(['track_confirm_time=0'], NAVIGATORS['dpn'])
    # The paper leaves none: the same override is fine on top of it.
    assert parse_overrides(['track_confirm_time=0'], NAVIGATORS['paper']) == {
        'track_confirm_time': 0.0}


def test_the_label_names_the_overrides_sorted():
    assert run_label({'navigator': 'dpn'}) == 'dpn'
    assert run_label({'navigator': 'paper', 'settings': {'b': 2.0, 'a': True}}) == \
        'paper [a=True, b=2.0]'
    assert run_label({}, 'folder') == 'folder'


def test_run_settings_and_options_carry_the_overrides():
    parse = cli.build_parser().parse_args
    assert cli.run_settings(parse([])) == {'navigator': 'dpn'}
    args = parse(['--navigator', 'paper', '--set', 'give_way_time=15'])
    assert cli.run_settings(args) == {'navigator': 'paper',
                                      'settings': {'give_way_time': 15.0}}
    assert cli.navigator_options(args) == {**NAVIGATORS['paper'], 'give_way_time': 15.0}
    assert cli.navigator_options(parse(['--navigator', 'dpn_real_laser'])) == \
        NAVIGATORS['dpn_real_laser']


def test_a_plug_in_navigator_takes_no_overrides():
    args = cli.build_parser().parse_args(
        ['--navigator', 'tiny_navigator:TinyNavigator', '--set', 'give_way_time=15'])
    with pytest.raises(ValueError, match='built-in navigator'):
        cli.navigator_settings(args)


def test_a_bad_override_ends_the_run_before_the_output_folder(tmp_path, capsys):
    out = tmp_path / 'out'
    with pytest.raises(SystemExit) as stop:
        cli.main(['--set', 'give_way_tme=15', '--out', str(out), *ONE_EPISODE])
    assert stop.value.code == 2
    error = capsys.readouterr().err
    assert 'give_way_tme' in error and 'Traceback' not in error
    assert not out.exists()


@pytest.mark.slow
def test_an_override_reaches_the_navigator_and_labels_the_log(tmp_path, capsys):
    plain, changed = tmp_path / 'plain', tmp_path / 'changed'
    assert cli.main(['--out', str(plain), *ONE_EPISODE]) == 0
    assert cli.main(['--set', 'obstacle_proximity_cost=0', '--out', str(changed),
                     *ONE_EPISODE]) == 0
    assert json.loads((changed / 'run.json').read_text()) == {
        'navigator': 'dpn', 'settings': {'obstacle_proximity_cost': 0.0}}
    assert 'dpn [obstacle_proximity_cost=0.0] navigator' in \
        (changed / 'summary.md').read_text()
    (plain_row,), (changed_row,) = read_log(plain / 'episodes.csv'), read_log(
        changed / 'episodes.csv')
    assert plain_row['seed'] == changed_row['seed']
    # Without the proximity cost A* hugs the tunnel's walls: another path.
    assert plain_row['path_length'] != changed_row['path_length']
    # The reports key the two logs apart.
    assert set(load_runs([plain, changed])) == {'dpn', 'dpn [obstacle_proximity_cost=0.0]'}
    # A log is not resumed with other overrides.
    with pytest.raises(SystemExit) as stop:
        cli.main(['--out', str(changed), *ONE_EPISODE])
    assert stop.value.code == 2
    assert 'obstacle_proximity_cost' in capsys.readouterr().err
