"""Pedestrians beside the P3-ATs: size, speed, acceleration and (no) politeness."""

import math

import numpy as np
import pytest
from sim_bridge.free_space import clearance_grid
from sim_bridge.wanderers import AGENT_MODELS, P3AT_RADIUS, PEDESTRIANS, WandererConfig
from sim_bridge.wanderers import Wanderers
from sim_bridge.world import wanderer_clearance_grid, World, WorldConfig
from test_world import room


def walk_until_moving(wanderers, husky, steps=40, dt=0.02):
    for _ in range(steps):
        wanderers.step(dt, husky)


def test_the_presets():
    assert AGENT_MODELS['p3at'] == WandererConfig()
    assert PEDESTRIANS.body_radius == 0.3 and WandererConfig().body_radius == P3AT_RADIUS
    assert PEDESTRIANS.speed_range == (0.8, 1.4) and not PEDESTRIANS.polite
    for bad in ({'body': 'tank'}, {'radius': 0.0}, {'max_accel': -1.0},
                {'speed_range': (1.0, 0.5)}, {'speed_range': (-0.1, 0.5)}):
        with pytest.raises(ValueError):
            WandererConfig(**bad)


@pytest.mark.parametrize('config, stops', [(WandererConfig(), True), (PEDESTRIANS, False)])
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
