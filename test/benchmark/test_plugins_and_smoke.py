"""
Your own navigator through the plug-in API, and every navigator and agent model on a short run.

The short runs are the smoke check that ``colcon test`` makes of each built-in navigator and
each agent model: one episode each on one map, a few seconds apiece.

"""

from dpn_navigator.benchmark import cli
from dpn_navigator.benchmark.episode import run_episode, task_setup
from dpn_navigator.benchmark.episode_log import read_log
from dpn_navigator.benchmark.navigator_plugin import (BenchmarkNavigator, load_navigator_class,
                                                      PluginNavigator)
from dpn_navigator.benchmark.protocol import MAP_MODELS, NAVIGATORS
from dpn_navigator.benchmark.runner import episode_keywords
from dpn_navigator.core import Navigator, NavigatorConfig, NavigatorStatus
import numpy as np
import pytest
from sim_bridge.scenario import load_scenario
from sim_bridge.wanderers import AGENT_MODELS
from sim_bridge.world import wanderer_clearance_grid
import tiny_navigator


@pytest.fixture(scope='module')
def back_and_forth():
    return load_scenario('back_and_forth')


def test_built_in_navigators_implement_the_protocol():
    assert isinstance(Navigator(NavigatorConfig(width=5.0, height=5.0)), BenchmarkNavigator)
    assert isinstance(tiny_navigator.StraightToGoal(NavigatorConfig(width=5.0, height=5.0)),
                      BenchmarkNavigator)


@pytest.mark.parametrize('spec, message', [
    ('tiny_navigator', 'package.module:Class'), ('no_such_module_x:Nav', 'cannot import'),
    ('tiny_navigator:Missing', 'has no class'), ('tiny_navigator:NoStep', 'no step')])
def test_bad_plug_ins_are_refused(spec, message):
    with pytest.raises(ValueError, match=message):
        load_navigator_class(spec)


def test_a_plug_in_returns_a_command():
    adapter = PluginNavigator(tiny_navigator.StraightToGoal(NavigatorConfig(width=5.0,
                                                                            height=5.0)))
    adapter.set_goal(4.0, 1.0)
    out = adapter.step(0.0, (1.0, 1.0, 0.0), np.full(10, np.inf), 0.0, 0.1, 0.1, 30.0)
    assert out.command.linear == pytest.approx(1.0) and out.status is NavigatorStatus.ACTIVE
    assert adapter.replans == 0 and adapter.grid is None

    class Broken(tiny_navigator.StraightToGoal):

        def step(self, *args):
            return 'fast'
    broken = PluginNavigator(Broken(NavigatorConfig(width=5.0, height=5.0)))
    broken.set_goal(4.0, 1.0)
    with pytest.raises(ValueError, match='NavigatorOutput or'):
        broken.step(0.0, (1.0, 1.0, 0.0), np.full(10, np.inf), 0.0, 0.1, 0.1, 30.0)


def test_an_external_navigator_runs_through_the_cli(tmp_path):
    out = tmp_path / 'mine'
    assert cli.main(['--maps', 'back_and_forth', '--tasks', '0', '--wanderers', '0',
                     '--navigator', 'tiny_navigator:StraightToGoal', '--workers', '1',
                     '--no-progress', '--out', str(out)]) == 0
    (row,) = read_log(out / 'episodes.csv')
    # Driving straight at the goal on back_and_forth meets a wall: the benchmark says how.
    assert row['end_reason'] in ('', 'collision', 'stuck', 'timeout_moving', 'oscillating')
    assert row['success'] == (row['end_reason'] == '')
    assert row['scans'] is None and row['replans'] == 0
    assert 'tiny_navigator:StraightToGoal' in (out / 'run.json').read_text()


@pytest.mark.parametrize('navigator', sorted(NAVIGATORS))
def test_every_navigator_on_a_short_episode(back_and_forth, navigator):
    result = run_episode(back_and_forth, 1, 2, seed=3, time_limit=20.0,
                         navigator_options=NAVIGATORS[navigator],
                         map_model=MAP_MODELS[navigator])
    assert result.wall_contacts == result.wanderer_contacts == 0
    assert result.path_length > 5.0                              # it drives
    assert result.metrics.end_reason in ('', 'timeout_moving')


@pytest.mark.parametrize('agents', sorted(AGENT_MODELS))
def test_every_agent_model_on_a_short_episode(back_and_forth, agents):
    config = AGENT_MODELS[agents]
    setup = task_setup(back_and_forth, 1, wanderer_clearance_grid(back_and_forth, config))
    keywords = episode_keywords({'agents': agents, 'pose_noise': (0.05, 0.01)})
    result = run_episode(back_and_forth, 1, 3, seed=3, time_limit=20.0, setup=setup,
                         **keywords)
    assert result.path_length > 5.0
    assert result.metrics.min_agent_distance is not None
    assert result.detection.scans > 100


def test_cli_refuses_bad_plug_ins_and_options_before_running(tmp_path, capsys):
    for args, message in ((['--navigator', 'tiny_navigator:NoStep'], 'no step'),
                          (['--navigator', 'nomodule'], 'invalid choice'),
                          (['--navigator', 'tiny_navigator:StraightToGoal', '--record',
                            str(tmp_path / 'bags')], '--record needs a built-in'),
                          (['--pose-noise', '-0.1', '0.0'], 'finite and >= 0')):
        with pytest.raises(SystemExit) as exited:
            cli.main(['--maps', 'back_and_forth', '--out', str(tmp_path / 'out')] + args)
        assert exited.value.code == 2 and message in capsys.readouterr().err
    assert not (tmp_path / 'out' / 'episodes.csv').exists()


def test_unknown_episode_options_are_refused():
    with pytest.raises(ValueError, match='unknown agent model'):
        episode_keywords({'agents': 'robots'})
    with pytest.raises(ValueError, match='unknown episode options'):
        episode_keywords({'speed': 2})


@pytest.mark.parametrize('agents', ['pedestrians-ignoring', 'pedestrians'])
def test_pedestrians_walk_into_a_standing_robot_only_when_blind(agents):
    """A robot that never moves: each contact is the agent's; yielding people make none."""
    tunnel = load_scenario('tunnel')
    config = AGENT_MODELS[agents]
    setup = task_setup(tunnel, 0, wanderer_clearance_grid(tunnel, config))
    result = run_episode(tunnel, 0, 10, seed=1, time_limit=60.0, setup=setup,
                         navigator_class=tiny_navigator.StandStill,
                         **episode_keywords({'agents': agents}))
    row = result.as_row()
    assert row['robot_caused_contacts'] == 0
    assert row['agent_caused_contacts'] == row['wanderer_contacts']
    if agents == 'pedestrians':
        assert row['wanderer_contacts'] == 0 and result.success is False
    else:
        assert row['wanderer_contacts'] >= 1        # blind people walk into it (6 here)
