"""
Tests of the laser's artefacts and profiles: each artefact's statistics against its parameters.

Worlds run headless (pybullet DIRECT) on tiny scenes whose true ranges are known: the Husky at
(6, 6) facing +x, the laser 0.337 m ahead of it. Rates are checked on thousands of beams with
tolerances of about four standard deviations of the estimate, so a wrong model fails and a right
one passes every seed.

"""

import dataclasses
import math

from dpn_navigator.core import GridGeometry
from dpn_navigator.core.scan_polygon import check_scan
import numpy as np
from numpy.testing import assert_array_equal
import pybullet
import pytest

from sim_bridge.husky import LASER_MOUNT
from sim_bridge.laser import LaserConfig
from sim_bridge.laser_artefacts import (dropped_beams, encode_errors, HOKUYO_ERROR_CODES,
                                        mix_edge_pixels, noise_std_of)
from sim_bridge.laser_profiles import (laser_config, laser_profile, LASER_PROFILE_NAMES,
                                       LASER_PROFILES)
from sim_bridge.scenario import load_scenario, Scenario
from sim_bridge.scene import RAY_MASK
from sim_bridge.tasks import Task
from sim_bridge.world import World, WorldConfig

RESOLUTION = 0.1
LASER_X = 6.0 + LASER_MOUNT[0]


def scene(walls, size=12.0):
    """Return a square scenario with wall rectangles ``(x0, y0, x1, y1)`` [m], start (6, 6, 0)."""
    geometry = GridGeometry(size, size, RESOLUTION)
    xs, ys = geometry.cell_to_world(*np.indices(geometry.shape))
    occupied = np.zeros(geometry.shape, dtype=bool)
    for x0, y0, x1, y1 in walls:
        occupied |= (xs > x0) & (xs < x1) & (ys > y0) & (ys < y1)
    task = Task((size / 2, size / 2, 0.0), (size / 2 + 3.0, size / 2))
    return Scenario('scene', occupied, ~occupied, RESOLUTION, (0.0, 0.0), (task,))


#: One wall across the whole room, its face at x = 9.0 (2.663 m ahead of the laser).
WALL = scene(((9.0, 0.0, 9.2, 12.0),))


def scans(scenario, laser, count, seed=0):
    """Return ``count`` scans of a standing Husky: (count, n) float64 ranges, and hit bodies."""
    ranges, bodies = [], []
    with World(scenario, WorldConfig(laser=laser, seed=seed)) as world:
        for _ in range(count):
            scan = world.advance(0.0, 0.0)
            ranges.append(scan.ranges.astype(np.float64))
            bodies.append(scan.hit_body)
    return np.array(ranges), np.array(bodies)


def exact(scenario, laser):
    """Return the artefact-free ranges of the same layout, (n,) float64."""
    plain = LaserConfig(n_beams=laser.n_beams, angle_min=laser.angle_min,
                        angle_max=laser.angle_max, range_min=laser.range_min,
                        range_max=laser.range_max)
    return scans(scenario, plain, 1)[0][0]


def within(measured, expected, trials):
    """Return True when a rate is within four binomial standard deviations of ``expected``."""
    return abs(measured - expected) <= 4.0 * math.sqrt(expected * (1.0 - expected) / trials)


# -- ideal: today's laser --------------------------------------------------------------------


def today_scan(world):
    """Cast the current scan as the laser did before the artefacts: a literal twin."""
    cfg = world.config.laser
    x, y, yaw = world.laser_pose
    angles = yaw + cfg.angle_min + cfg.angle_increment * np.arange(cfg.n_beams)
    start = np.column_stack([np.full(cfg.n_beams, x), np.full(cfg.n_beams, y),
                             np.full(cfg.n_beams, cfg.height)])
    end = start + cfg.range_max * np.column_stack([np.cos(angles), np.sin(angles),
                                                   np.zeros(cfg.n_beams)])
    results = pybullet.rayTestBatch(start, end, collisionFilterMask=RAY_MASK,
                                    physicsClientId=world.scene.client)
    ranges = np.array([cfg.range_max * r[2] for r in results])
    hit = np.array([r[0] >= 0 for r in results])
    ranges[~hit | (ranges >= cfg.range_max)] = math.inf
    ranges[hit & (ranges < cfg.range_min)] = -math.inf
    return ranges.astype(np.float32)


def test_ideal_is_the_default_laser_and_draws_nothing():
    assert laser_profile('ideal').laser == LaserConfig()
    assert LASER_PROFILE_NAMES[0] == 'ideal'
    with World(load_scenario('back_and_forth'), WorldConfig(n_wanderers=5, seed=3)) as world:
        rng = world._laser.rng
        state = rng.bit_generator.state
        checked = 0
        for step in range(40):
            scan = world.advance(0.6, 0.4 if step < 20 else -0.4)
            if step % 4 == 0:
                # Bit for bit what the laser gave before it had artefacts.
                assert scan.ranges.tobytes() == today_scan(world).tobytes()
                checked += 1
        assert checked == 10 and rng.bit_generator.state == state


# -- range noise -----------------------------------------------------------------------------


def test_noise_std_matches_its_setting():
    laser = LaserConfig(noise_std=0.02)
    truth = exact(WALL, laser)
    ranges, _ = scans(WALL, laser, 20, seed=5)
    seen = np.isfinite(truth)
    error = ranges[:, seen] - truth[seen]
    assert error.size > 5000
    assert np.std(error) == pytest.approx(0.02, rel=0.05)
    assert abs(np.mean(error)) < 0.002


def test_noise_grows_with_range_and_steps_up_beyond_far_range():
    # The wall is 2.66 m ahead; beams to the side meet it up to 6.5 m away.
    laser = LaserConfig(noise_std=0.003, noise_fraction=0.01, noise_std_far=0.08, far_range=5.0)
    truth = exact(WALL, laser)
    ranges, _ = scans(WALL, laser, 30, seed=2)
    seen = np.isfinite(truth)
    expected = noise_std_of(truth[seen], laser)
    assert expected.min() == pytest.approx(0.0266, abs=1e-3) and expected.max() == 0.08
    standardised = (ranges[:, seen] - truth[seen]) / expected
    near, far = truth[seen] <= 5.0, truth[seen] > 5.0
    assert np.std(standardised[:, near]) == pytest.approx(1.0, rel=0.05)
    assert np.std(standardised[:, far]) == pytest.approx(1.0, rel=0.1)


def test_noise_std_of_literal_cases():
    laser = LaserConfig(noise_std=0.01, noise_fraction=0.01, noise_std_far=0.05, far_range=4.0)
    std = noise_std_of(np.array([0.5, 1.0, 2.0, 3.9, 4.1, 6.0]), laser)
    np.testing.assert_allclose(std, [0.01, 0.01, 0.02, 0.039, 0.05, 0.06])


# -- dropout ---------------------------------------------------------------------------------


def test_dropout_fraction_matches_its_setting():
    laser = LaserConfig(dropout=0.2)
    truth = exact(WALL, laser)
    ranges, bodies = scans(WALL, laser, 10, seed=9)
    seen = np.isfinite(truth)
    lost = np.isposinf(ranges[:, seen])
    assert lost.size > 2500 and within(lost.mean(), 0.2, lost.size)
    # A lost return is no hit in the ground truth either; the others are exact.
    assert np.all(bodies[:, seen][lost] == -1) and np.all(bodies[:, seen][~lost] >= 0)
    assert_array_equal(ranges[:, seen][~lost], np.broadcast_to(
        truth[seen].astype(np.float32), lost.shape)[~lost])


def test_dropout_is_higher_beyond_far_range():
    laser = LaserConfig(dropout=0.05, dropout_far=0.5, far_range=4.0)
    truth = exact(WALL, laser)
    ranges, _ = scans(WALL, laser, 20, seed=4)
    seen = np.isfinite(truth)
    for band, rate in ((seen & (truth <= 4.0), 0.05), (seen & (truth > 4.0), 0.5)):
        lost = np.isposinf(ranges[:, band])
        assert lost.size > 1000 and within(lost.mean(), rate, lost.size)


def test_dropped_beams_only_drops_hits():
    rng = np.random.default_rng(0)
    hit = np.arange(10000) % 2 == 0
    dropped = dropped_beams(np.full(10000, 3.0), hit, LaserConfig(dropout=1.0), rng)
    assert_array_equal(dropped, hit)


# -- grazing incidence -----------------------------------------------------------------------


def test_no_return_beyond_the_grazing_angle():
    cut = math.radians(50.0)
    laser = LaserConfig(max_incidence=cut)
    truth = exact(WALL, laser)
    ranges, bodies = scans(WALL, laser, 1)
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.n_beams)
    # The wall's normal is -x: a beam's incidence angle is its bearing.
    seen = np.isfinite(truth)
    assert np.count_nonzero(seen & (np.abs(angles) > cut + 0.01)) > 40
    steep = seen & (np.abs(angles) < cut - 0.002)
    shallow = seen & (np.abs(angles) > cut + 0.002)
    assert_array_equal(ranges[0, steep], truth[steep].astype(np.float32))
    assert np.all(np.isposinf(ranges[0, shallow])) and np.all(bodies[0, shallow] == -1)


def test_grazing_cut_off_on_a_turned_laser():
    # Turned by 30 degrees, the beams meet the wall at bearing + 30 degrees.
    cut = math.radians(60.0)
    laser = LaserConfig(max_incidence=cut, mount=(LASER_MOUNT[0], 0.0, math.radians(30.0)))
    with World(WALL, WorldConfig(laser=laser)) as world:
        ranges = world.scan().ranges
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.n_beams)
    incidence = np.abs(angles + math.radians(30.0))
    assert np.all(np.isfinite(ranges[incidence < cut - 0.002]))
    assert np.all(np.isposinf(ranges[incidence > cut + 0.002]))


# -- mixed pixels ----------------------------------------------------------------------------


def test_mixed_pixel_rate_and_values_at_an_edge():
    # A near wall fills the left half of the view (from bearing 0), a far wall is behind.
    edge = scene(((8.0, 6.0, 8.2, 12.0), (11.0, 0.0, 11.2, 12.0)))
    laser = LaserConfig(mixed_pixel_probability=0.3, mixed_pixel_jump=0.5)
    truth = exact(edge, laser)
    ranges, _ = scans(edge, laser, 400, seed=1)
    both_seen = np.isfinite(truth[:-1]) & np.isfinite(truth[1:])
    jumps = np.flatnonzero(both_seen & (np.abs(truth[1:] - truth[:-1]) > 0.5))
    assert len(jumps) == 1                                  # one depth edge in view
    edge_beams = [jumps[0], jumps[0] + 1]
    near, far = sorted(truth[edge_beams])
    changed = ranges[:, edge_beams] != truth[edge_beams].astype(np.float32)
    assert within(changed.mean(), 0.3, changed.size)
    mixed = ranges[:, edge_beams][changed]
    assert np.all((mixed >= near - 1e-5) & (mixed <= far + 1e-5))
    others = np.setdiff1d(np.flatnonzero(np.isfinite(truth)), edge_beams)
    assert_array_equal(ranges[:, others], np.broadcast_to(truth[others].astype(np.float32),
                                                          (400, len(others))))


def test_mix_edge_pixels_literal_cases():
    rng = np.random.default_rng(3)
    ranges = np.array([1.0, 1.0, 5.0, 5.0, 5.1, np.inf])
    hit = np.array([True, True, True, True, True, False])
    out, mixed = mix_edge_pixels(ranges, hit, 1.0, 0.5, rng)
    assert_array_equal(mixed, [False, True, True, False, False, False])
    assert 1.0 <= out[1] <= 5.0 and 1.0 <= out[2] <= 5.0
    assert_array_equal(out[[0, 3, 4, 5]], ranges[[0, 3, 4, 5]])
    # The first and last beams are neighbours only on a full-turn scan.
    ring = np.array([1.0, 1.0, 1.0, 4.0])
    hits = np.ones(4, dtype=bool)
    assert_array_equal(mix_edge_pixels(ring, hits, 1.0, 0.5, rng)[1], [False, False, True, True])
    assert_array_equal(mix_edge_pixels(ring, hits, 1.0, 0.5, rng, wraps=True)[1],
                       [True, False, True, True])


# -- the driver's encoding of errors ---------------------------------------------------------


@pytest.mark.parametrize('encoding', ['rep117', 'nan', 'tiny_codes'])
def test_error_encodings(encoding):
    # Range limits 0.5-3.0 m: beams ahead hit the wall at 2.66 m, those beside it beyond 3 m
    # (no return), and a post 0.26-0.4 m away at bearings -0.85 to -0.36 rad is too close.
    room = scene(((9.0, 0.0, 9.2, 12.0), (6.6, 5.7, 6.8, 5.9)))
    laser = LaserConfig(range_min=0.5, range_max=3.0, error_encoding=encoding)
    ranges, _ = scans(room, laser, 5)
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.n_beams)
    ahead = np.abs(angles) < 0.2
    beside = np.abs(angles) > 1.0
    close = (angles > -0.8) & (angles < -0.42)              # the post
    assert np.all((ranges[:, ahead] > 2.6) & (ranges[:, ahead] < 3.0))
    assert np.count_nonzero(close) >= 10
    if encoding == 'rep117':
        assert np.all(np.isposinf(ranges[:, beside])) and np.all(np.isneginf(ranges[:, close]))
    elif encoding == 'nan':
        assert np.all(np.isnan(ranges[:, beside])) and np.all(np.isnan(ranges[:, close]))
    else:
        codes = ranges[:, beside | close]
        assert np.all((codes >= 0.0) & (codes <= 0.019) & (codes < laser.range_min))
        assert set(np.round(codes.ravel() * 1000).astype(int)) <= {0, 6, 7, 8, 9, 15}
    assert not np.any(np.isnan(ranges[:, ahead]))


def test_tiny_codes_follow_their_weights():
    rng = np.random.default_rng(8)
    laser = LaserConfig(range_min=0.02, error_encoding='tiny_codes')
    ranges = np.full(50000, 1.0)
    invalid = np.ones(50000, dtype=bool)
    encode_errors(ranges, invalid, np.zeros(50000, dtype=bool), laser, rng)
    weights = np.array([w for _, w in HOKUYO_ERROR_CODES])
    for (code, _), share in zip(HOKUYO_ERROR_CODES, weights / weights.sum()):
        assert within(np.mean(ranges == code), share, ranges.size), code


# -- profiles --------------------------------------------------------------------------------


#: Each profile's data-sheet layout: beams, first and last angle [deg], step [deg], range [m].
DATA_SHEET_LAYOUTS = {
    'ideal': (640, -90.0, 90.0, 180.0 / 639, 0.1, 30.0),
    'sick_lms1xx': (541, -135.0, 135.0, 0.5, 0.5, 20.0),
    'hokuyo_utm30lx': (1081, -135.0, 135.0, 0.25, 0.1, 30.0),
    'hokuyo_urg04lx': (682, -340 * 360 / 1024, 341 * 360 / 1024, 360 / 1024, 0.02, 5.6),
    'rplidar_a2': (800, -180.0, 179.55, 0.45, 0.15, 12.0),
    'lds_01': (360, 0.0, 359.0, 1.0, 0.12, 3.5),
}


@pytest.mark.parametrize('name', sorted(DATA_SHEET_LAYOUTS))
def test_profiles_have_their_data_sheet_layout(name):
    beams, first, last, step, near, far = DATA_SHEET_LAYOUTS[name]
    laser = laser_profile(name).laser
    assert laser.n_beams == beams
    assert math.degrees(laser.angle_min) == pytest.approx(first)
    assert math.degrees(laser.angle_max) == pytest.approx(last)
    assert math.degrees(laser.angle_increment) == pytest.approx(step)
    assert (laser.range_min, laser.range_max) == (near, far)
    assert laser.mount == LASER_MOUNT
    assert laser.full_turn == (name in ('rplidar_a2', 'lds_01'))


def test_every_profile_is_tested():
    assert set(LASER_PROFILES) == set(DATA_SHEET_LAYOUTS)


@pytest.mark.parametrize('name', [n for n in LASER_PROFILE_NAMES if n != 'ideal'])
def test_realistic_profiles_scan_a_world_the_navigator_accepts(name):
    laser = laser_profile(name).laser
    with World(load_scenario('back_and_forth'), WorldConfig(n_wanderers=3, seed=1,
                                                            laser=laser)) as world:
        first = world.scan()
        check_scan(first.ranges, first.angle_min, first.angle_increment, first.range_min,
                   first.range_max, angle_max=first.angle_max)
        again = World(load_scenario('back_and_forth'), WorldConfig(n_wanderers=3, seed=1,
                                                                   laser=laser))
        with again:
            assert again.scan().ranges.tobytes() == first.ranges.tobytes()   # seeded
        other = World(load_scenario('back_and_forth'), WorldConfig(n_wanderers=3, seed=2,
                                                                   laser=laser))
        with other:
            assert other.scan().ranges.tobytes() != first.ranges.tobytes()


def test_unknown_profile_is_a_clear_error():
    with pytest.raises(ValueError, match="unknown laser profile 'lms200'.*ideal, sick_lms1xx"):
        laser_profile('lms200')


def test_overrides_keep_unset_values():
    base = laser_profile('hokuyo_utm30lx').laser
    assert laser_config('hokuyo_utm30lx', noise_std=math.nan, dropout=None,
                        error_encoding='') is base
    changed = laser_config('hokuyo_utm30lx', dropout=0.0, error_encoding='nan')
    assert changed == dataclasses.replace(base, dropout=0.0, error_encoding='nan')
    with pytest.raises(ValueError, match='cannot override error_codes'):
        laser_config('ideal', error_codes=((0.0, 1.0),))
    mounted = laser_config('ideal', mount=(0.1, 0.0, 3.0), height=0.5, upside_down=True)
    assert (mounted.mount, mounted.height, mounted.upside_down) == ((0.1, 0.0, 3.0), 0.5, True)
    with pytest.raises(ValueError, match='dropout must be a probability'):
        laser_config('ideal', dropout=1.5)


@pytest.mark.parametrize('kwargs, match', [
    ({'noise_fraction': -0.1}, 'noise_fraction'), ({'noise_std_far': math.nan}, 'noise_std_far'),
    ({'far_range': 0.0}, 'far_range'), ({'dropout': -0.01}, 'dropout'),
    ({'dropout_far': math.nan}, 'dropout_far'), ({'mixed_pixel_probability': 2.0}, 'mixed'),
    ({'max_incidence': 0.0}, 'max_incidence'), ({'max_incidence': 2.0}, 'max_incidence'),
    ({'mixed_pixel_jump': 0.0}, 'mixed_pixel_jump'), ({'error_encoding': 'zero'}, 'rep117'),
    ({'error_codes': ()}, 'error_codes'), ({'error_codes': ((0.0, -1.0),)}, 'error_codes'),
    ({'error_encoding': 'tiny_codes', 'range_min': 0.005}, 'below|range_min'),
    ({'angle_min': -4.0, 'angle_max': 4.0}, 'full turn'),
])
def test_laser_artefact_errors(kwargs, match):
    with pytest.raises(ValueError, match=match):
        LaserConfig(**kwargs)
