"""
The benchmark's reference navigators: the oracle's map and both variants in the episode loop.

The oracle plans on the true walls and wanderers; the costmap on Nav2-style layers
(``test_costmap_grid.py`` tests the layers themselves). Both run the same episodes as dpn.

"""

from dpn_navigator.benchmark.baselines.costmap_grid import CostmapGrid
from dpn_navigator.benchmark.baselines.oracle_grid import OracleGrid
from dpn_navigator.benchmark.episode import build_map, run_episode
from dpn_navigator.benchmark.ground_truth import wall_belt
from dpn_navigator.benchmark.protocol import MAP_MODELS, NAVIGATORS, resolve_maps
from dpn_navigator.core import CellLabel, GridGeometry, NavigatorConfig
from dpn_navigator.core.cell_label import blocked_mask
import numpy as np
from numpy.testing import assert_array_equal
import pytest
from sim_bridge.scenario import load_index, load_scenario

E, S, M = CellLabel.EXPLORED, CellLabel.STEADY_OBSTACLE, CellLabel.MOBILE_OBSTACLE
ONE_BEAM = {'angle_min': 0.0, 'angle_increment': 0.01, 'range_min': 0.1, 'range_max': 30.0}


@pytest.fixture(scope='module')
def back_and_forth():
    return load_scenario('back_and_forth')


def oracle_grid():
    """Return a 3 x 2 m oracle (4 rows x 6 columns) with a wall belt along column 0."""
    geometry = GridGeometry(3.0, 2.0, 0.5)
    belt = np.zeros(geometry.shape, dtype=bool)
    belt[:, 0] = True
    return OracleGrid(geometry, belt, wanderer_reach=0.5)


def test_oracle_labels_walls_steady_and_wanderers_mobile():
    grid = oracle_grid()
    assert_array_equal(grid.labels[:, :2], [[S, E]] * 4)
    assert not (grid.labels == CellLabel.NON_EXPLORED).any()
    # A wanderer at the centre of cell (1, 3): the centres within 0.5 m, a plus of 5 cells.
    grid.set_wanderers([(1.75, 0.75)])
    assert (grid.labels != M).all()                        # not before the next update
    assert grid.update((0.0, 0.0, 0.0), [1.0], safety_radius=0.6, **ONE_BEAM) is False
    assert_array_equal(np.argwhere(grid.labels == M), [[0, 3], [1, 2], [1, 3], [1, 4], [2, 3]])
    # It moves on: its old cells are free again at once, walls stay.
    grid.set_wanderers(np.zeros((0, 2)))
    grid.update((0.0, 0.0, 0.0), [1.0], safety_radius=0.6, **ONE_BEAM)
    assert not (grid.labels == M).any() and (grid.labels[:, 0] == S).all()
    assert_array_equal(blocked_mask(grid.labels), grid.labels == S)


def test_oracle_wanderer_on_a_wall_keeps_it_steady():
    grid = oracle_grid()
    grid.set_wanderers([(0.25, 0.25)])
    grid.update((0.0, 0.0, 0.0), [1.0], safety_radius=0.6, **ONE_BEAM)
    assert grid.labels[0, 0] == S and grid.labels[0, 1] == M


def test_oracle_raises_the_replan_flag_when_a_wanderer_steps_on_the_path():
    grid = oracle_grid()
    path = np.array([[3, c] for c in range(1, 6)])
    grid.set_wanderers([(1.75, 0.25)])                     # rows 0-1: off the path
    assert grid.update((0.0, 0.0, 0.0), [1.0], safety_radius=0.6, path=path,
                       **ONE_BEAM) is False
    grid.set_wanderers([(1.75, 1.75)])                     # cell (3, 3)
    assert grid.update((0.0, 0.0, 0.0), [1.0], safety_radius=0.6, path=path,
                       **ONE_BEAM) is True
    assert grid.update((0.0, 0.0, 0.0), [1.0], safety_radius=0.6, path=path,
                       **ONE_BEAM) is False


@pytest.mark.parametrize('belt, reach, error, match', [
    (np.zeros((3, 3), dtype=bool), 0.5, ValueError, 'shape'),
    (np.zeros((4, 6), dtype=bool), -1.0, ValueError, 'wanderer_reach'),
    (np.zeros((4, 6), dtype=bool), np.nan, ValueError, 'wanderer_reach'),
])
def test_oracle_refuses_bad_input(belt, reach, error, match):
    with pytest.raises(error, match=match):
        OracleGrid(GridGeometry(3.0, 2.0, 0.5), belt, reach)
    with pytest.raises(TypeError, match='GridGeometry'):
        OracleGrid((4, 6), np.zeros((4, 6), dtype=bool), 0.5)


def test_build_map_gives_each_variant_its_map(back_and_forth):
    config = NavigatorConfig(width=back_and_forth.width, height=back_and_forth.height,
                             origin=back_and_forth.origin)
    assert build_map('labels', config, back_and_forth, 0.4, 30.0) is None
    costmap = build_map('costmap', config, back_and_forth, 0.4, 30.0)
    assert isinstance(costmap, CostmapGrid)
    assert costmap.config.obstacle_max_range == pytest.approx(30.0 * 2.5 / 3.5)
    oracle = build_map('oracle', config, back_and_forth, 0.4, 30.0)
    belt = wall_belt(back_and_forth.occupied, back_and_forth.geometry, oracle.geometry,
                     config.safety_radius)
    assert_array_equal(oracle.labels == S, belt)
    with pytest.raises(ValueError, match='unknown map model'):
        build_map('voxels', config, back_and_forth, 0.4, 30.0)


def test_every_navigator_has_a_map_model_and_the_references_forget_nothing():
    assert set(MAP_MODELS) == set(NAVIGATORS)
    for name in ('costmap', 'oracle'):
        config = NavigatorConfig(width=10.0, height=10.0, **NAVIGATORS[name])
        assert config.forget_obstacles_after == 0.0
        # The same planner and follower as dpn.
        dpn = NavigatorConfig(width=10.0, height=10.0)
        assert config.obstacle_proximity_cost == dpn.obstacle_proximity_cost
        assert config.follower == dpn.follower


@pytest.mark.parametrize('name', ['oracle', 'oracle-foresight', 'costmap'])
def test_reference_navigators_reach_the_goal_without_wanderers(back_and_forth, name):
    result = run_episode(back_and_forth, 1, wanderers=0, seed=3,
                         navigator_options=NAVIGATORS[name], map_model=MAP_MODELS[name])
    assert result.success and result.wall_contacts == 0
    assert result.path_length >= 0.9 * result.shortest_path
    if name == 'oracle':
        # The space-time oracle plans once a second (SpaceTimeConfig.replan_period).
        assert result.detection is None
        assert abs(result.replans - result.time) <= 1.0
    elif name == 'oracle-foresight':
        assert result.detection is None                     # it builds no map to measure
        assert result.replans == 1                          # the walls are known at once
    else:
        assert result.detection.mobile_visible == 0         # no mobile label
        assert result.detection.steady_ghosts_end == 0      # lethal cells all on walls
        assert result.replans > 1


def test_the_oracle_sees_wanderers_and_repeats_exactly(back_and_forth):
    first = run_episode(back_and_forth, 1, wanderers=3, seed=3,
                        navigator_options=NAVIGATORS['oracle'], map_model='oracle')
    assert first.success and first.wanderer_contacts == 0
    assert first == run_episode(back_and_forth, 1, wanderers=3, seed=3,
                                navigator_options=NAVIGATORS['oracle'], map_model='oracle')


def test_maps_resolve_by_number_range():
    entries = load_index()
    first, last = min(e.number for e in entries), max(e.number for e in entries)
    keys = resolve_maps([f'{first}-{last}'], entries)
    assert len(keys) == len(entries)
    assert resolve_maps(['3-4', '3'], entries) == resolve_maps(['3', '4'], entries)
    with pytest.raises(ValueError, match='holds no map number'):
        resolve_maps([f'{first - 1}-{last}'], entries)
    with pytest.raises(ValueError, match='holds no map number'):
        resolve_maps(['5-3'], entries)
