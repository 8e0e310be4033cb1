"""Tests of the lockstep benchmark episode: rules, determinism and the map-quality counts."""

import math

from dpn_navigator.benchmark.detection import DETECTION_FIELDS
from dpn_navigator.benchmark.episode import (
    map_quality, run_episode, shortest_path_length, task_setup)
from dpn_navigator.core import CellLabel, GridGeometry
import numpy as np
import pytest
from sim_bridge.scenario import load_scenario
from sim_bridge.tasks import Task
from sim_bridge.wanderers import WandererConfig

N, E, S, M = (CellLabel.NON_EXPLORED, CellLabel.EXPLORED, CellLabel.STEADY_OBSTACLE,
              CellLabel.MOBILE_OBSTACLE)


@pytest.fixture(scope='module')
def back_and_forth():
    return load_scenario('back_and_forth')


def test_map_quality_counts_walls_labelled_mobile_and_ghosts():
    geometry = GridGeometry(3.0, 1.0, 0.5)                 # 2 rows x 6 columns
    truth_geometry = GridGeometry(3.0, 1.0, 0.25)          # 4 rows x 12 columns
    truth = np.zeros((4, 12), dtype=bool)
    truth[0, 0] = True                                     # a wall pixel in cell (0, 0)
    labels = np.array([[M, M, S, M, E, M],
                       [N, E, E, M, M, M]], dtype=np.uint8)
    # r = 0.4 m: the wall's belt is 1 cell, so (0, 0) and (0, 1) are wall errors. A wanderer
    # at the centre of cell (1, 5) explains centres within 0.1 + 0.4 m of it: (0, 5), (1, 4)
    # and (1, 5), the first two exactly 0.5 m away.
    walls, ghosts = map_quality(labels, geometry, truth, truth_geometry,
                                np.array([[2.75, 0.75]]), 0.1, 0.4)
    assert (walls, ghosts) == (2, 2)                       # ghosts (0, 3) and (1, 3)
    walls, ghosts = map_quality(labels, geometry, truth, truth_geometry, np.zeros((0, 2)),
                                0.1, 0.4)
    assert (walls, ghosts) == (2, 5)


def test_shortest_path_of_the_tasks(back_and_forth):
    lengths = [shortest_path_length(back_and_forth, task) for task in back_and_forth.tasks]
    assert 65.0 < lengths[0] < 80.0 and 25.0 < lengths[1] < 35.0 and 50.0 < lengths[2] < 65.0
    walled_in = Task(start=back_and_forth.tasks[0].start, goal=(12.5, 3.95))   # in a wall
    assert shortest_path_length(back_and_forth, walled_in) == math.inf


def test_an_episode_succeeds_and_repeats_exactly(back_and_forth):
    first = run_episode(back_and_forth, 1, wanderers=2, seed=3)
    assert first.success and first.failure == ''
    assert first.time < first.time_limit
    assert first.wall_contacts == first.wanderer_contacts == 0
    assert first.replans >= 2
    assert first.path_length >= 0.9 * first.shortest_path
    # The benchmark's own view: the true pose within 0.3 m, SPL and BARN from L and the time.
    metrics = first.metrics
    assert metrics.judged_success and metrics.end_reason == '' and metrics.goal_distance <= 0.3
    assert first.time_limit == pytest.approx(30.0 + 3.0 * first.shortest_path, abs=2e-3)
    expected_spl = first.shortest_path / max(first.path_length, first.shortest_path)
    assert metrics.spl == pytest.approx(expected_spl, rel=1e-4)   # the result's rounding
    assert 0.0 < metrics.barn_score <= 0.5 and metrics.path_ratio >= 0.9
    assert metrics.min_agent_distance is not None and metrics.min_agent_distance > 0.0
    # Again with the setup a benchmark worker keeps between episodes: the very same episode.
    setup = task_setup(back_and_forth, 1)
    assert setup.shortest_path == shortest_path_length(back_and_forth, back_and_forth.tasks[1])
    assert first == run_episode(back_and_forth, 1, wanderers=2, seed=3, setup=setup)
    assert not setup.wanderer_grid.clear.flags.writeable


def test_the_wanderer_config_reaches_the_world(back_and_forth):
    # The setup's grid is for the default clearance: the world refuses it for another one.
    setup = task_setup(back_and_forth, 0)
    with pytest.raises(ValueError, match='clearance of .* the wanderers keep 1.0 m'):
        run_episode(back_and_forth, 0, wanderers=1, seed=0, time_limit=1.0, setup=setup,
                    wanderer_config=WandererConfig(clearance=1.0))


def test_running_out_of_time_is_a_timeout(back_and_forth):
    result = run_episode(back_and_forth, 0, wanderers=0, seed=0, time_limit=5.0)
    assert not result.success and result.failure == 'timeout'
    assert result.time == pytest.approx(5.0, abs=0.11)
    # Driving when time ran out: the benchmark says so.
    assert result.metrics.end_reason == 'timeout_moving' and result.metrics.spl == 0.0
    assert result.metrics.min_agent_distance is None and result.metrics.goal_distance > 0.3
    assert {'end_reason', 'spl', 'barn_score', 'jerk_rms'} <= set(result.as_row())
    assert set(result.as_row()) >= {'scenario', 'success', 'failure', 'ghost_obstacles'}


def test_detection_measures_do_not_change_the_episode(back_and_forth):
    measured = run_episode(back_and_forth, 1, wanderers=3, seed=1, time_limit=25.0)
    plain = run_episode(back_and_forth, 1, wanderers=3, seed=1, time_limit=25.0,
                        detection=False)
    assert plain.detection is None and plain.detection_wall_time is None
    outcome = {name: value for name, value in plain.as_row().items()
               if name not in DETECTION_FIELDS + ('detection_wall_time',)}
    assert {name: measured.as_row()[name] for name in outcome} == outcome
    assert all(plain.as_row()[name] is None for name in DETECTION_FIELDS)
    detection = measured.detection
    assert detection.scans == round(measured.time * 10)     # 10 Hz, up to the time limit
    assert 0 < measured.detection_wall_time < 25.0
    assert (detection.replans_wall + detection.replans_wanderer
            + detection.replans_no_path_retry + detection.replans_other) == measured.replans
    assert 0.0 <= detection.mobile_precision <= 1.0
    assert 0.0 <= detection.wanderer_hit_recall <= 1.0
    assert 0 <= detection.wall_cells_ever_mobile <= detection.wall_cells_seen
    assert detection.wall_cells_seen > 0
