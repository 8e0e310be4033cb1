"""
Tests of the wanderers' mutual yield (``WandererConfig.mutual_yield``).

Off, the option's code is never entered, so a seeded crowd moves exactly as it did before the
option existed (its trajectories equal those of a run whose yield code raises if reached).
On, two wanderers scripted head-on in a corridor with a bay are through within a bound, where
without it they stand face to face until their patience runs out.

"""

import doctest
import hashlib
import math

from dpn_navigator.core import GridGeometry
import numpy as np
import pytest

from sim_bridge import wanderers as wanderers_module
from sim_bridge.free_space import clearance_grid
from sim_bridge.scenario import load_scenario, Scenario
from sim_bridge.tasks import Task
from sim_bridge.wanderers import distance_to_polyline, P3AT_RADIUS, WandererConfig, Wanderers
from sim_bridge.world import wanderer_clearance_grid

DT = 0.02
FAR = (100.0, 100.0)  # the Husky, out of the way [m]


def crowd_digest(wanderers_class, config):
    """
    Hash 120 s of ten seeded wanderers on ``narrow_passages``, the Husky standing at its start.

    Every step's positions and headings (float64 bytes) and the final counters go in. Returns
    the hex digest and the wanderers.
    """
    scenario = load_scenario('narrow_passages')
    start = scenario.tasks[0].start
    grid = wanderer_clearance_grid(scenario, config)
    wanderers = wanderers_class(grid, 10, start[:2], np.random.default_rng(2024), config)
    digest = hashlib.sha256()
    for _ in range(int(120.0 / DT)):
        wanderers.step(DT, start[:2])
        digest.update(wanderers.positions.tobytes())
        digest.update(wanderers.yaws.tobytes())
    digest.update(f'{wanderers.goals_reached} {wanderers.replans}'.encode())
    return digest.hexdigest(), wanderers


class NoYieldWanderers(Wanderers):
    """Wanderers whose yield code fails the test if it is ever reached."""

    def _yield_to(self, i, blocker, husky_xy):
        raise AssertionError('the mutual yield ran with the option off')

    def _give_way(self, i, j, husky_xy):
        raise AssertionError('the mutual yield ran with the option off')


def test_with_the_option_off_a_seeded_crowd_never_enters_the_yield():
    assert not WandererConfig().mutual_yield
    digest, wanderers = crowd_digest(Wanderers, WandererConfig())
    fenced_digest, fenced = crowd_digest(NoYieldWanderers, WandererConfig())
    assert digest == fenced_digest
    assert wanderers.replans > 0 and wanderers.yields == 0 == fenced.yields


def test_the_digest_sees_a_change_of_behaviour():
    # The same crowd with the option on yields and moves otherwise: the test above can fail.
    digest, wanderers = crowd_digest(Wanderers, WandererConfig(mutual_yield=True))
    assert wanderers.yields > 0
    assert digest != crowd_digest(Wanderers, WandererConfig())[0]
    with pytest.raises(AssertionError, match='ran with the option off'):
        crowd_digest(NoYieldWanderers, WandererConfig(mutual_yield=True))


@pytest.mark.parametrize('kwargs, match', [
    ({'mutual_yield': 1}, 'mutual_yield must be True or False'),
    ({'yield_path_margin': -0.1}, 'yield_path_margin must be a finite distance'),
    ({'yield_path_margin': math.nan}, 'yield_path_margin must be a finite distance'),
    ({'yield_path_margin': True}, 'yield_path_margin must be a finite distance'),
])
def test_bad_yield_options_raise(kwargs, match):
    with pytest.raises(ValueError, match=match):
        WandererConfig(**kwargs)


@pytest.mark.parametrize('points, expected', [
    ([[0.0, 0.0], [2.0, 0.0]], [1.0, math.sqrt(2.0), 0.0, math.sqrt(2.0)]),   # a segment
    ([[0.0, 0.0], [2.0, 0.0], [2.0, 3.0]], [1.0, 1.0, 0.0, math.sqrt(2.0)]),  # an L
    ([[2.0, 2.0], [2.0, 2.0]], [math.sqrt(2.0)] * 2 + [math.sqrt(5.0), math.sqrt(10.0)]),
    ([[2.0, 2.0]], [math.sqrt(2.0)] * 2 + [math.sqrt(5.0), math.sqrt(10.0)]),  # one vertex
])
def test_distance_to_polyline(points, expected):
    xs = np.array([1.0, 3.0, 1.0, -1.0])
    ys = np.array([1.0, 1.0, 0.0, 1.0])
    got = distance_to_polyline(xs, ys, np.array(points))
    np.testing.assert_allclose(got, expected, atol=1e-12)


def test_the_docstring_examples_run():
    result = doctest.testmod(wanderers_module)
    assert result.attempted > 0 and result.failed == 0


def test_distance_to_an_empty_polyline_raises():
    with pytest.raises(ValueError, match='one vertex or more'):
        distance_to_polyline(np.zeros(1), np.zeros(1), np.zeros((0, 2)))


# -- a head-on pair in a corridor ------------------------------------------------------------


def corridor_with_bay(bay=True):
    """Make a 24 m corridor 1.8 m wide along y = 1.9 m, with a 2.5 m x 2.2 m bay at x = 10-12.5."""
    resolution = 0.1
    geometry = GridGeometry(24.0, 6.0, resolution)
    x, y = geometry.cell_to_world(*np.indices(geometry.shape))
    free = (x > 0.1) & (x < 23.9) & (y > 1.0) & (y < 2.8)
    if bay:
        free |= (x > 10.0) & (x < 12.5) & (y >= 2.75) & (y < 5.0)
    task = Task((1.5, 1.9, 0.0), (22.5, 1.9))
    return Scenario('corridor_with_bay', ~free, free, resolution, (0.0, 0.0), (task,))


def head_on(config, seconds, bay=True):
    """
    Script wanderer 0 from x = 2 m to 23.3 m (the end), wanderer 1 from 14 m to 1 m; run them.

    Returns the wanderers and their positions at every step, (steps, 2, 2) [m].
    """
    scenario = corridor_with_bay(bay)
    grid = clearance_grid(scenario.free, scenario.geometry, config.clearance)
    wanderers = Wanderers(grid, 2, FAR, np.random.default_rng(0), config)
    wanderers.script(0, [(2.0, 1.9), (23.3, 1.9)])
    wanderers.script(1, [(14.0, 1.9), (1.0, 1.9)])
    track = []
    for _ in range(int(seconds / DT)):
        wanderers.step(DT, FAR)
        assert all(grid.is_clear(x, y) for x, y in wanderers.positions)
        track.append(wanderers.positions.copy())
    return wanderers, np.array(track)


def longest_standstill(track):
    """Return the longest time in which no wanderer of ``track`` (steps, n, 2) moved [s]."""
    still = np.all(track[1:] == track[:-1], axis=(1, 2))
    longest = run = 0
    for flag in still.tolist():
        run = run + 1 if flag else 0
        longest = max(longest, run)
    return longest * DT


# Patience far longer than the scene, so that only the yield can part them.
PATIENT = WandererConfig(speed_range=(0.5, 0.5), patience_range=(60.0, 60.0))


def test_head_on_without_the_option_both_wait():
    wanderers, track = head_on(PATIENT, 20.0)
    gap = np.hypot(*(track[:, 0] - track[:, 1]).T)
    assert gap.min() > 2 * P3AT_RADIUS
    # Face to face from about 11 s on: neither moves any more.
    assert np.ptp(track[-400:], axis=0).max() < 0.2
    assert track[-1, 0, 0] < 9.0 and track[-1, 1, 0] > 7.0
    assert longest_standstill(track) > 8.0
    assert wanderers.yields == 0 and wanderers.replans == 0


def test_head_on_with_the_option_the_higher_index_backs_into_the_bay_and_both_go_on():
    config = WandererConfig(speed_range=(0.5, 0.5), patience_range=(60.0, 60.0),
                            mutual_yield=True)
    wanderers, track = head_on(config, 40.0)
    gap = np.hypot(*(track[:, 0] - track[:, 1]).T)
    assert gap.min() > 2 * P3AT_RADIUS
    assert wanderers.yields == 1
    # Wanderer 1 went into the bay, off wanderer 0's line by more than the margin...
    assert track[:, 1, 1].max() > 1.9 + config.yield_path_margin
    # ...and wanderer 0 got past it within 30 s, on its scripted route (no replan).
    passed = np.flatnonzero(track[:, 0, 0] > 13.0)
    assert len(passed) and passed[0] * DT < 30.0
    assert wanderers.replans == 1
    # Both stood still (wanderer 1 turning round) for less than 3 s; without the option they
    # stand face to face until the end.
    assert longest_standstill(track) < 3.0


def test_head_on_with_the_option_but_no_room_off_the_way_nothing_changes():
    # Without the bay every cell wanderer 1 can reach is on wanderer 0's way: both wait.
    config = WandererConfig(speed_range=(0.5, 0.5), patience_range=(60.0, 60.0),
                            mutual_yield=True)
    wanderers, track = head_on(config, 20.0, bay=False)
    _, track_off = head_on(PATIENT, 20.0, bay=False)
    np.testing.assert_array_equal(track, track_off)
    assert wanderers.yields == 0
