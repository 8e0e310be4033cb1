"""A real laser on the move (``core.real_laser``): lost returns, the switch, and its effect."""

import dataclasses
import math

from dpn_navigator.benchmark.protocol import NAVIGATORS
from dpn_navigator.core.mapping.label_grid import LabelGrid, LabelRule, SWITCHABLE_RULE_FIELDS
from dpn_navigator.core.navigator import Navigator, NavigatorConfig
from dpn_navigator.core.real_laser import (lost_returns, real_laser_overrides,
                                           REAL_LASER_SETTINGS, RealLaserSwitch,
                                           STANDING_DISTANCE, SWITCH_MIN_LOST, SWITCH_MIN_SCANS)
import numpy as np
from numpy.testing import assert_array_equal
import pytest

INF = math.inf
NAN = math.nan
BEAMS = 361
ANGLE_MIN = -math.pi / 2
INCREMENT = math.pi / (BEAMS - 1)
ROOM = (-4.0, 12.0, -5.0, 5.0)        # x_min, x_max, y_min, y_max of the walls [m]


def literal_lost_returns(ranges, range_min, range_max):
    """Return the lost returns counted beam by beam, straight from the definition."""
    valid = [range_min <= r < range_max for r in ranges]
    hits = [i for i, ok in enumerate(valid) if ok]
    lost = 0
    for left, right in zip(hits, hits[1:]):
        run = right - left - 1
        if 1 <= run <= 2 and abs(ranges[right] - ranges[left]) <= 0.3:
            lost += run
    return lost


@pytest.mark.parametrize('ranges, expected', [
    ([], 0),
    ([2.0], 0),
    ([2.0, INF, 2.1], 1),                       # one beam lost inside a surface
    ([2.0, INF, NAN, 2.2], 2),                  # two, whatever the code
    ([2.0, INF, INF, INF, 2.1], 0),             # three: a gap, not a lost return
    ([2.0, INF, 2.5], 0),                       # the two sides 0.5 m apart: a depth edge
    ([INF, 2.0, 2.1, INF], 0),                  # open ends
    ([2.0, 0.01, 2.1], 1),                      # a no-echo code below range_min
    ([2.0, 40.0, 2.1], 1),                      # at or beyond range_max
    ([2.0, -INF, 2.1, INF, 2.2, 5.0, INF, 5.05], 3),
])
def test_lost_returns_on_literal_scans(ranges, expected):
    assert lost_returns(ranges, 0.02, 30.0) == expected
    assert literal_lost_returns(ranges, 0.02, 30.0) == expected


def test_lost_returns_agree_with_the_definition_on_random_scans():
    rng = np.random.default_rng(3)
    for _ in range(200):
        ranges = rng.choice([1.0, 1.1, 1.2, 3.0, INF, NAN, 0.0], size=rng.integers(0, 30))
        ranges = ranges + rng.normal(0.0, 0.05, ranges.shape)
        assert lost_returns(ranges, 0.02, 30.0) == literal_lost_returns(list(ranges), 0.02, 30.0)


def test_lost_returns_refuse_a_two_dimensional_scan():
    with pytest.raises(ValueError, match='one-dimensional'):
        lost_returns(np.ones((2, 3)), 0.02, 30.0)


def lossy_ranges(lost_every=40, beams=BEAMS):
    """Return a wall 3 m away across the scan, every ``lost_every``-th beam returning nothing."""
    angles = ANGLE_MIN + INCREMENT * np.arange(beams)
    ranges = 3.0 / np.maximum(np.cos(angles), 0.2)
    if lost_every:
        ranges[lost_every // 2::lost_every] = INF
    return ranges


def test_the_switch_needs_a_moving_laser_enough_scans_and_lost_returns():
    ranges = lossy_ranges()                   # 9 lost of 361: 2.5 %
    switch = RealLaserSwitch(0.001)
    for k in range(10):                        # standing: never
        assert not switch.watch((0.0, 0.0), ranges, 0.02, 30.0)
    assert switch.switched_at is None and switch.share == pytest.approx(9 / 361)
    assert switch.watch((0.0, STANDING_DISTANCE + 0.01), ranges, 0.02, 30.0, stamp=4.5)
    assert switch.switched_at == 4.5
    assert not switch.watch((0.0, 1.0), ranges, 0.02, 30.0)        # once
    # Too few scans, too few lost returns, or none at all: no switch.
    early = RealLaserSwitch(0.001)
    for k in range(SWITCH_MIN_SCANS - 1):
        assert not early.watch((k * 0.2, 0.0), lossy_ranges(5), 0.02, 30.0)
    assert early.watch((1.0, 0.0), lossy_ranges(5), 0.02, 30.0)
    few = RealLaserSwitch(0.001)
    one_lost = lossy_ranges(0)
    one_lost[100] = INF
    for k in range(SWITCH_MIN_LOST - 1):
        assert not few.watch((k * 0.2, 0.0), one_lost, 0.02, 30.0)
    assert few.watch((2.0, 0.0), one_lost, 0.02, 30.0)
    ideal = RealLaserSwitch(0.001)
    assert not any(ideal.watch((k * 0.2, 0.0), lossy_ranges(0), 0.02, 30.0)
                   for k in range(100))
    # The share: 1 lost of 361 per scan is 0.28 %, below a threshold of 0.5 %.
    high = RealLaserSwitch(0.005)
    assert not any(high.watch((k * 0.2, 0.0), one_lost, 0.02, 30.0) for k in range(50))


@pytest.mark.parametrize('share', [0.0, -0.1, 1.5, NAN])
def test_the_switch_refuses_a_share_out_of_range(share):
    with pytest.raises(ValueError, match='lost_share'):
        RealLaserSwitch(share)


def config(**overrides):
    return NavigatorConfig(width=16.0, height=10.0, origin=(-4.0, -5.0), **overrides)


def test_the_switch_takes_only_the_settings_left_at_their_defaults():
    assert real_laser_overrides(config()) == REAL_LASER_SETTINGS
    mine = real_laser_overrides(config(no_return_reach=0.5, free_burn_in=2.0))
    assert set(mine) == set(REAL_LASER_SETTINGS) - {'no_return_reach', 'free_burn_in'}
    assert real_laser_overrides(config(**REAL_LASER_SETTINGS)) == {}
    assert Navigator(config(**REAL_LASER_SETTINGS)).real_laser is None
    assert REAL_LASER_SETTINGS == NAVIGATORS['dpn_real_laser']


def test_the_paper_has_no_switch_and_takes_only_what_fits_when_asked():
    assert Navigator(config(**NAVIGATORS['paper'])).real_laser is None
    paper_with_switch = config(**{**NAVIGATORS['paper'], 'real_laser_switch': 0.001})
    taken = real_laser_overrides(paper_with_switch)
    # The paper sets its own reach; no burn-in without the free evidence, no range noise,
    # veiling or narrow-things rule without surfaces to take the evidence from.
    assert taken == {'mixed_pixel_angle': 0.1745, 'spike_angle': 0.1745,
                     'wall_continuation_angle': 1.0472}
    navigator = Navigator(paper_with_switch)
    drive(navigator, lost_every=30)
    assert navigator.real_laser_settings == taken
    assert navigator.config.no_return_reach == 1.0 and navigator.config.mixed_pixel_angle > 0.0


def room_scan(x, lost_every):
    """Return the scan of a laser at ``(x, 0)`` facing +x in the room, with lost returns."""
    angles = ANGLE_MIN + INCREMENT * np.arange(BEAMS)
    dx, dy = np.cos(angles), np.sin(angles)
    x_min, x_max, y_min, y_max = ROOM
    with np.errstate(divide='ignore'):
        along_x = np.where(dx > 0, (x_max - x) / dx, INF)
        along_y = np.where(dy > 0, y_max / dy, np.where(dy < 0, y_min / dy, INF))
    ranges = np.minimum(along_x, along_y)
    if lost_every:
        ranges[lost_every // 2::lost_every] = INF
    return ranges


def drive(navigator, lost_every, scans=12, until_switch=False):
    """Drive the laser 0.1 m per scan along the room's middle, 10 scans per second."""
    for k in range(scans):
        navigator.observe((0.1 * k, 0.0, 0.0), room_scan(0.1 * k, lost_every), ANGLE_MIN,
                          INCREMENT, 0.02, 30.0, stamp=0.1 * k)
        navigator.settle()
        if until_switch and navigator.real_laser_settings:
            return


def test_a_navigator_with_a_real_laser_switches_once_and_keeps_what_was_set():
    navigator = Navigator(config(segment_gap=0.4))
    drive(navigator, lost_every=30)
    assert navigator.real_laser.switched_at == pytest.approx(0.2)
    assert navigator.real_laser_settings == REAL_LASER_SETTINGS
    for name, value in REAL_LASER_SETTINGS.items():
        assert getattr(navigator.config, name) == value
    assert navigator.config.segment_gap == 0.4
    assert navigator.grid.rule == navigator.config.label_rule()
    assert navigator.grid.fine_evidence.burn_in == 0.5
    assert navigator._exploration.continued is not None
    # The settings a user gave stay.
    kept = Navigator(config(no_return_reach=0.3))
    drive(kept, lost_every=30)
    assert kept.config.no_return_reach == 0.3 and 'no_return_reach' not in kept.real_laser_settings


def test_a_navigator_with_an_ideal_laser_keeps_its_settings_and_labels():
    switching, off = Navigator(config()), Navigator(config(real_laser_switch=0.0))
    drive(switching, lost_every=0, scans=30)
    drive(off, lost_every=0, scans=30)
    assert switching.real_laser.switched_at is None and switching.real_laser_settings == {}
    assert switching.config == dataclasses.replace(off.config, real_laser_switch=0.001)
    assert_array_equal(switching.grid.labels, off.grid.labels)
    assert_array_equal(switching.grid.seen_free, off.grid.seen_free)


def test_after_the_switch_the_map_is_the_real_laser_settings_map_from_that_scan():
    """The literal twin: a navigator given the real-laser settings from the switch's scan on."""
    navigator = Navigator(config())
    drive(navigator, lost_every=30, until_switch=True)
    # Scan 2 showed the real laser (0.2 m moved, 3 scans); scan 3 is the new map's first.
    assert navigator.real_laser.switched_at == pytest.approx(0.2)
    assert navigator.real_laser_since == pytest.approx(0.3)
    first = 3
    twin = Navigator(config(**REAL_LASER_SETTINGS))
    assert twin.real_laser is None
    for k in range(first, 16):
        pose = (0.1 * k, 0.0, 0.0)
        scan = (room_scan(0.1 * k, 30), ANGLE_MIN, INCREMENT, 0.02, 30.0)
        if k > first:
            navigator.observe(pose, *scan, stamp=0.1 * k)
            navigator.settle()
        twin.observe(pose, *scan, stamp=0.1 * k)
        twin.settle()
        assert_array_equal(navigator.grid.labels, twin.grid.labels)
        assert_array_equal(navigator.grid.seen_free, twin.grid.seen_free)
        assert_array_equal(navigator.grid.fine_evidence.seen_free,
                           twin.grid.fine_evidence.seen_free)
    # A scan whose every beam returns nothing shows nothing empty any more.
    before = navigator.grid.labels.copy()
    navigator.observe((1.6, 0.0, 0.0), np.full(BEAMS, INF), ANGLE_MIN, INCREMENT, 0.02, 30.0,
                      stamp=1.6)
    assert_array_equal(navigator.grid.labels, before)


def grid_of(rule):
    return LabelGrid(16.0, 10.0, 0.5, (-4.0, -5.0), rule)


def dpn_rule(**overrides):
    return config(**overrides).label_rule()


def test_a_grid_switches_only_the_rules_read_scan_by_scan():
    grid = grid_of(dpn_rule())
    grid.update((0.0, 0.0, 0.0), room_scan(0.0, 0), ANGLE_MIN, INCREMENT, 0.02, 30.0, 0.6,
                stamp=0.0)
    labels, seen_free = grid.labels.copy(), grid.seen_free.copy()
    with pytest.raises(ValueError, match='surface_time'):
        grid.switch_rule(dpn_rule(surface_time=1.0))
    assert grid.rule == dpn_rule()
    assert_array_equal(grid.seen_free, seen_free)
    grid.switch_rule(dpn_rule())                        # the same rule: nothing happens
    assert_array_equal(grid.seen_free, seen_free)
    assert grid.fine_evidence.hit_stamp is None
    grid.switch_rule(dpn_rule(**{name: value for name, value in REAL_LASER_SETTINGS.items()
                                 if name in SWITCHABLE_RULE_FIELDS}))
    assert_array_equal(grid.labels, labels)
    assert not grid.seen_free.any() and not grid.fine_evidence.seen_free.any()
    assert grid.fine_evidence.hit_stamp is not None and grid.fine_evidence.burn_in == 0.5
    assert grid.rule.no_return_reach == 0.0
    assert set(REAL_LASER_SETTINGS) - SWITCHABLE_RULE_FIELDS == {'wall_continuation_angle'}
    assert set(SWITCHABLE_RULE_FIELDS) <= set(LabelRule.__dataclass_fields__)


def test_the_watch_waits_for_the_labels_to_be_out():
    """With ``defer_evidence`` the scan is watched in ``settle``, after the map is out."""
    navigator = Navigator(config())
    for k in range(3):
        navigator.observe((0.1 * k, 0.0, 0.0), room_scan(0.1 * k, 30), ANGLE_MIN, INCREMENT,
                          0.02, 30.0, stamp=0.1 * k, defer_evidence=True)
        assert navigator.real_laser.scans == k
        navigator.settle()
        navigator.settle()                                  # a scan is watched once
        assert navigator.real_laser.scans == k + 1
    assert navigator.real_laser.switched_at == pytest.approx(0.2)
    assert navigator.real_laser_settings == {}              # the next observe switches
    navigator.observe((0.3, 0.0, 0.0), room_scan(0.3, 30), ANGLE_MIN, INCREMENT, 0.02, 30.0,
                      stamp=0.3, defer_evidence=True)
    assert navigator.real_laser_settings == REAL_LASER_SETTINGS
