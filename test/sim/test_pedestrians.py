"""Pedestrians beside the P3-ATs: size, speed, acceleration, (no) politeness and yielding."""

import math

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from sim_bridge.free_space import clearance_grid
from sim_bridge.husky import HUSKY_RADIUS
from sim_bridge.wanderers import _keeps_apart, AGENT_MODELS, P3AT_RADIUS, PEDESTRIANS
from sim_bridge.wanderers import PEDESTRIANS_IGNORING, WandererConfig, Wanderers
from sim_bridge.world import wanderer_clearance_grid, World, WorldConfig
from test_world import room


def walk_until_moving(wanderers, husky, steps=40, dt=0.02):
    for _ in range(steps):
        wanderers.step(dt, husky)


def test_the_presets():
    assert AGENT_MODELS['p3at'] == WandererConfig()
    assert PEDESTRIANS.body_radius == 0.3 and WandererConfig().body_radius == P3AT_RADIUS
    assert PEDESTRIANS.speed_range == (0.8, 1.4) and not PEDESTRIANS.polite
    assert PEDESTRIANS.yield_horizon == 1.0 and PEDESTRIANS_IGNORING.yield_horizon == 0.0
    assert AGENT_MODELS['pedestrians-ignoring'] == PEDESTRIANS_IGNORING
    assert AGENT_MODELS['mixed'].others == PEDESTRIANS
    for bad in ({'body': 'tank'}, {'radius': 0.0}, {'max_accel': -1.0},
                {'speed_range': (1.0, 0.5)}, {'speed_range': (-0.1, 0.5)},
                {'yield_horizon': -1.0}, {'yield_horizon': math.nan},
                {'yield_margin': -0.1}, {'yield_slowest': 0.0}, {'yield_slowest': 1.5}):
        with pytest.raises(ValueError):
            WandererConfig(**bad)


@pytest.mark.parametrize('config, stops', [(WandererConfig(), True),
                                           (PEDESTRIANS_IGNORING, False)])
def test_a_pedestrian_does_not_stop_for_the_husky(config, stops):
    scenario = room()
    grid = clearance_grid(scenario.free, scenario.geometry, config.clearance)
    wanderers = Wanderers(grid, 1, (6.0, 6.0), np.random.default_rng(0), config)
    assert wanderers.radius == config.body_radius
    far = (100.0, 100.0)
    walk_until_moving(wanderers, far, steps=150)
    x, y = wanderers.positions[0]
    yaw = wanderers.yaws[0]
    husky = (x + 1.2 * math.cos(yaw), y + 1.2 * math.sin(yaw))
    for _ in range(30):                              # 0.6 s with the Husky right ahead
        wanderers.step(0.02, husky)
    moved = math.dist(wanderers.positions[0], (x, y))
    assert (moved < 0.2) if stops else (moved > 0.3)


def test_pedestrians_speed_up_at_their_acceleration():
    scenario = room()
    grid = clearance_grid(scenario.free, scenario.geometry, PEDESTRIANS.clearance)
    wanderers = Wanderers(grid, 3, (6.0, 6.0), np.random.default_rng(2), PEDESTRIANS)
    assert np.all((wanderers.speeds >= 0.8) & (wanderers.speeds <= 1.4))
    before = wanderers.positions.copy()
    wanderers.step(0.1, (100.0, 100.0))
    # From standing, at most a * dt^2 = 0.01 m in the first 0.1 s (a P3-AT: up to 0.07 m).
    assert np.all(np.hypot(*(wanderers.positions - before).T) <= 1.0 * 0.1 * 0.1 + 1e-9)


def test_a_world_of_pedestrians_scans_them_as_cylinders(tmp_path):
    scenario = room()
    config = WorldConfig(n_wanderers=2, seed=4, wanderer=PEDESTRIANS)
    with World(scenario, config, start=(2.0, 6.0, 0.0),
               wanderer_grid=wanderer_clearance_grid(scenario, PEDESTRIANS)) as world:
        assert world.wanderer_radius == 0.3
        hit = 0
        for _ in range(50):
            world.advance(0.0, 0.0)
            hit += int((world.scan_wanderer_beams() >= 0).sum())
        assert hit > 0                               # the laser sees them
        assert world.contacts.events == 0


def test_a_mixed_crowd_has_both_kinds():
    from sim_bridge.wanderers import MIXED
    assert [kind.body for kind in MIXED.kinds(5)] == ['p3at'] * 3 + ['cylinder'] * 2
    assert MIXED.largest_radius == P3AT_RADIUS
    with pytest.raises(ValueError):
        WandererConfig(others=WandererConfig(clearance=2.0), others_share=0.5)
    scenario = room()
    config = WorldConfig(n_wanderers=4, seed=1, wanderer=MIXED)
    with World(scenario, config, start=(2.0, 6.0, 0.0),
               wanderer_grid=wanderer_clearance_grid(scenario, MIXED)) as world:
        wanderers = world._wanderers
        assert wanderers.radii == [P3AT_RADIUS, P3AT_RADIUS, 0.3, 0.3]
        assert np.all(wanderers.speeds[:2] <= 0.7) and np.all(wanderers.speeds[2:] >= 0.8)
        for _ in range(30):
            world.advance(0.0, 0.0)
        assert world.contacts.events == 0


def pedestrian_heading_east(config, speed=1.2):
    """Return one pedestrian at (2, 6) walking east at ``speed`` towards (10, 6), in the room."""
    scenario = room()
    grid = clearance_grid(scenario.free, scenario.geometry, config.clearance)
    wanderers = Wanderers(grid, 1, (6.0, 6.0), np.random.default_rng(0), config)
    wanderers.positions[0] = 2.0, 6.0
    wanderers.yaws[0] = 0.0
    wanderers.speeds[0] = wanderers._speeds[0] = wanderers._speed_now[0] = speed
    wanderers._paths[0] = [(10.0, 6.0)]
    wanderers._centring[0] = False
    wanderers._patience[0] = 2.5                     # stopped for 2.5 s, it plans anew
    return wanderers


@pytest.mark.parametrize('config, keeps_clear', [(PEDESTRIANS, True),
                                                 (PEDESTRIANS_IGNORING, False)])
def test_a_yielding_pedestrian_stops_short_of_a_standing_husky_in_its_way(config, keeps_clear):
    wanderers = pedestrian_heading_east(config)
    husky = (5.0, 6.0)                               # standing on its path, 3 m ahead
    reach = 0.3 + HUSKY_RADIUS
    nearest = math.inf
    for _ in range(150):                             # 3 s
        wanderers.step(0.02, husky)
        nearest = min(nearest, math.dist(wanderers.positions[0], husky))
    if keeps_clear:
        # It stopped when even half its speed would close the gap within the 1 s horizon:
        # 0.05 m + 0.6 m from the circles' contact at most.
        assert reach < nearest < reach + 0.05 + 0.6 + 1e-9
        assert wanderers.replans == 0 and wanderers._stopped[0] > 0.0
        for _ in range(400):                         # 8 s: its patience ends, it walks around
            wanderers.step(0.02, husky)
            nearest = min(nearest, math.dist(wanderers.positions[0], husky))
        assert nearest > reach and wanderers.replans >= 1
        assert math.dist(wanderers.positions[0], husky) > reach + 0.3
    else:
        assert nearest < reach                       # it walked into the Husky's circle


def test_a_yielding_pedestrian_walks_on_past_a_husky_out_of_its_way():
    wanderers = pedestrian_heading_east(PEDESTRIANS)
    for _ in range(50):                              # 1 s, the Husky 2 m beside its path
        wanderers.step(0.02, (4.0, 8.0))
    assert wanderers.positions[0][0] == pytest.approx(2.0 + 1.2, abs=1e-6)


def test_a_yielding_pedestrian_slows_for_a_husky_driving_across_its_path():
    nearest = {}
    for config in (PEDESTRIANS, PEDESTRIANS_IGNORING):
        wanderers = pedestrian_heading_east(config)
        nearest[config] = math.inf
        for k in range(200):                         # the Husky crosses at x = 4.5 at 1 m/s
            husky = (4.5, 3.5 + 0.02 * k)
            wanderers.step(0.02, husky)
            nearest[config] = min(nearest[config], math.dist(wanderers.positions[0], husky))
    assert nearest[PEDESTRIANS] > 0.3 + HUSKY_RADIUS
    assert nearest[PEDESTRIANS_IGNORING] < 0.3 + HUSKY_RADIUS


@settings(max_examples=300, deadline=None)
@given(st.tuples(*[st.floats(-5.0, 5.0)] * 4), st.floats(0.1, 2.0), st.floats(0.0, 3.0))
def test_keeps_apart_matches_sampling_the_horizon(pw, reach, horizon):
    px, py, wx, wy = pw
    times = np.linspace(0.0, horizon, 4001)
    distance = np.hypot(px + wx * times, py + wy * times)
    if math.hypot(px, py) < reach:
        expected = px * wx + py * wy >= 0.0
    else:
        expected = bool(distance.min() >= reach)
        # Sampling can miss the true minimum by a hair: skip the knife-edge cases.
        if abs(distance.min() - reach) < 1e-3:
            return
    assert _keeps_apart(px, py, wx, wy, reach, horizon) == expected


@pytest.mark.parametrize('seed', range(4))
def test_a_yielding_pedestrian_turns_back_from_a_husky_blocking_its_corridor(seed):
    """In a corridor the Husky closes, a stopped pedestrian takes a goal behind it."""
    outer = ((0.0, 0.0, 0.1, 12.0), (11.9, 0.0, 12.0, 12.0), (0.0, 0.0, 12.0, 0.1),
             (0.0, 11.9, 12.0, 12.0))
    scenario = room(walls=outer + ((0.0, 0.0, 12.0, 4.9), (0.0, 7.1, 12.0, 12.0)))
    grid = clearance_grid(scenario.free, scenario.geometry, PEDESTRIANS.clearance)
    wanderers = Wanderers(grid, 1, (6.0, 6.0), np.random.default_rng(seed), PEDESTRIANS)
    wanderers.positions[0] = 2.5, 6.0
    wanderers.yaws[0] = 0.0
    wanderers._paths[0] = [(10.0, 6.0)]
    wanderers._centring[0] = False
    wanderers._patience[0] = 2.0
    husky = (6.0, 6.0)                               # standing across the corridor
    nearest = math.inf
    for _ in range(500):                             # 10 s
        wanderers.step(0.02, husky)
        nearest = min(nearest, math.dist(wanderers.positions[0], husky))
    assert nearest > 0.3 + HUSKY_RADIUS
    assert wanderers.positions[0][0] < 4.0           # it walked back west, away from the Husky


def p3at_facing_north(config, husky):
    """Return one P3-AT at (6, 6) facing north whose next waypoint lies west, in the room."""
    scenario = room()
    grid = clearance_grid(scenario.free, scenario.geometry, config.clearance)
    wanderers = Wanderers(grid, 1, husky, np.random.default_rng(0), config)
    wanderers.positions[0] = 6.0, 6.0
    wanderers.yaws[0] = math.pi / 2
    wanderers._paths[0] = [(3.0, 6.0)]
    wanderers._centring[0] = False
    wanderers._patience[0] = 100.0                   # no new goal within the test
    return wanderers


@pytest.mark.parametrize('guard', [True, False])
def test_a_polite_p3at_does_not_turn_its_corners_into_a_standing_husky(guard):
    # The Husky stands 0.89 m from the P3-AT's centre, within the two circles (0.36 + 0.60 m):
    # a turn in place would sweep the P3-AT's corner into it (maze, task 2, 9 wanderers,
    # held-out seed 1).
    config = WandererConfig(turn_guard=guard)
    husky = (6.0 + 0.89 * math.cos(-0.4), 6.0 + 0.89 * math.sin(-0.4))
    wanderers = p3at_facing_north(config, husky)
    for _ in range(25):                              # 0.5 s
        wanderers.step(0.02, husky)
    turned = abs(wanderers.yaws[0] - math.pi / 2)
    if guard:
        assert turned == 0.0 and wanderers._stopped[0] > 0.0
    else:
        assert turned > 0.5
    # With the Husky out of reach, it turns.
    far = p3at_facing_north(config, (6.0 + 1.2 * math.cos(-0.4), 6.0 + 1.2 * math.sin(-0.4)))
    for _ in range(25):
        far.step(0.02, (6.0 + 1.2 * math.cos(-0.4), 6.0 + 1.2 * math.sin(-0.4)))
    assert abs(far.yaws[0] - math.pi / 2) > 0.5
    assert 0.89 < HUSKY_RADIUS + P3AT_RADIUS + 0.05 < 1.2
