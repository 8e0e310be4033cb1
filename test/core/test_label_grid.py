"""Tests of the labelled occupancy grid: f1, f2, the FSM and the replan flag."""

import dataclasses
import math

from dpn_navigator.core.cell_label import CellLabel, OCCUPANCY_VALUE, TRANSITION
from dpn_navigator.core.mapping.label_grid import LabelGrid, LabelRule, PAPER_RULE
from dpn_navigator.core.mapping.label_update import surely_free_update
from hypothesis import given, settings
from hypothesis import strategies as st
from literal_reference import FSM, literal_update, literal_update_with_rule
import numpy as np
from numpy.testing import assert_array_equal
import pytest
from real_sensor_rules import LiteralSurfaceMemory

N, E, S, M = (CellLabel.NON_EXPLORED, CellLabel.EXPLORED,
              CellLabel.STEADY_OBSTACLE, CellLabel.MOBILE_OBSTACLE)

SCAN = {'angle_min': -math.pi / 2, 'angle_increment': math.pi / 639, 'range_min': 0.1,
        'range_max': 30.0}


def test_labels_start_non_explored_with_the_documented_shape():
    grid = LabelGrid(width=40.0, height=30.0, resolution=0.5, origin=(-3.0, 2.0))
    assert grid.labels.shape == (60, 80)
    assert grid.labels.dtype == np.uint8
    assert np.all(grid.labels == N)
    odd = LabelGrid(width=10.2, height=3.1, resolution=0.5)
    assert odd.labels.shape == (7, 21)


def test_label_values_and_occupancy_values_are_fixed():
    assert (N, E, S, M) == (0, 1, 2, 3)
    assert OCCUPANCY_VALUE.tolist() == [-1, 0, 100, 70]
    assert 65 <= OCCUPANCY_VALUE[M] <= 99


@pytest.mark.parametrize('state', list(CellLabel))
@pytest.mark.parametrize('scan_input, f1, f2', [(0, 0, 0), (1, 0, 1), (2, 1, 0)])
def test_transition_table_matches_the_readme_table(state, scan_input, f1, f2):
    assert TRANSITION[state, scan_input] == FSM.get((int(state), f1, f2), int(state))


def wall_scan(distance, beams=181):
    """Ranges of a laser facing +x at a wall ``distance`` m ahead (x = distance)."""
    angles = -math.pi / 2 + np.arange(beams) * (math.pi / (beams - 1))
    with np.errstate(divide='ignore'):
        ranges = distance / np.cos(angles)
    ranges[np.abs(angles) > math.radians(80)] = np.inf
    return ranges, {'angle_min': -math.pi / 2, 'angle_increment': math.pi / (beams - 1),
                    'range_min': 0.1, 'range_max': 30.0}


def test_wall_becomes_steady_and_free_space_explored():
    grid = LabelGrid(width=10.0, height=10.0, resolution=0.5)
    ranges, scan = wall_scan(3.0)
    grid.update((2.0, 5.0, 0.0), ranges, safety_radius=0.3, **scan)
    # The wall at x = 5.0 m lies on the border of columns 9 and 10; centres at 4.75 and 5.25.
    row = grid.geometry.world_to_cell(0.0, 5.0)[0]
    assert grid.labels[row, 9] == S and grid.labels[row, 10] == S
    assert np.all(grid.labels[row, 4:9] == E)
    assert grid.labels[row, 12] == N          # behind the wall: never seen
    assert grid.labels[row, 0] == N           # behind the laser


def test_obstacle_over_explored_space_is_mobile_and_clears_when_gone():
    grid = LabelGrid(width=10.0, height=10.0, resolution=0.5)
    far, scan = wall_scan(4.0)
    laser = (1.0, 5.25, 0.0)                     # on the centre line of row 10
    grid.update(laser, far, safety_radius=0.3, **scan)
    assert grid.labels[10, 6] == E
    near = far.copy()
    near[90] = 2.25                              # something at (3.25, 5.25): centre of (10, 6)
    path = np.array([[10, c] for c in range(2, 9)])
    assert grid.update(laser, near, safety_radius=0.3, path=path, **scan)
    assert grid.labels[10, 6] == M
    assert grid.labels[10, 5] == E and grid.labels[10, 7] == E   # 0.5 m > r: not hit
    # It leaves: the cell is seen free again and goes back to explored.
    assert not grid.update(laser, far, safety_radius=0.3, path=path, **scan)
    assert np.all(grid.labels[10, 3:9] == E)


def test_replan_only_for_cells_on_the_path():
    grid = LabelGrid(width=10.0, height=10.0, resolution=0.5)
    ranges, scan = wall_scan(3.0)
    row = grid.geometry.world_to_cell(0.0, 5.0)[0]
    off_path = np.array([[0, 0], [1, 1]])
    assert not grid.update((2.0, 5.0, 0.0), ranges, safety_radius=0.3, path=off_path, **scan)
    fresh = LabelGrid(width=10.0, height=10.0, resolution=0.5)
    on_path = np.array([[row, 9]])
    assert fresh.update((2.0, 5.0, 0.0), ranges, safety_radius=0.3, path=on_path, **scan)
    # Seen again: steady stays steady, so no new replan.
    assert not fresh.update((2.0, 5.0, 0.0), ranges, safety_radius=0.3, path=on_path, **scan)


def test_scan_entirely_off_the_map_changes_nothing():
    grid = LabelGrid(width=10.0, height=10.0, resolution=0.5)
    ranges, scan = wall_scan(3.0)
    assert not grid.update((-100.0, -100.0, 0.0), ranges, safety_radius=0.5, **scan)
    assert np.all(grid.labels == N)


def test_empty_scan_changes_nothing():
    grid = LabelGrid(width=10.0, height=10.0, resolution=0.5)
    assert not grid.update((5.0, 5.0, 0.0), np.array([]), safety_radius=0.5, **SCAN)
    assert np.all(grid.labels == N)


@pytest.mark.parametrize('kwargs, message', [
    ({'pose': (1.0, float('nan'), 0.0)}, 'pose must be finite'),
    ({'pose': (1.0, 2.0)}, r'pose must be \(x, y, yaw\)'),
    ({'ranges': np.ones((3, 2))}, 'one-dimensional'),
    ({'angle_increment': 0.0}, 'angle_increment must be positive'),
    ({'angle_increment': -0.01}, 'angle_increment must be positive'),
    ({'angle_increment': float('inf')}, 'angle_increment must be finite'),
    ({'range_max': 0.05}, 'range_min < range_max'),
    ({'range_min': -1.0}, 'range_min < range_max'),
    ({'range_max': float('inf')}, 'range_max must be finite'),
    ({'angle_max': 0.5}, 'ranges has 640 beams'),
    ({'angle_increment': 0.1, 'angle_max': None}, 'more than a full turn'),
    ({'angle_increment': 1e-30, 'angle_max': None}, 'below 1e-06 rad'),
    ({'angle_increment': 5e-7, 'angle_max': None}, 'below 1e-06 rad'),
    ({'angle_min': 20.0, 'angle_max': None}, 'angle_min 20.0 rad is beyond'),
    ({'angle_min': -1e300, 'angle_max': None}, 'angle_min -1e\\+300 rad is beyond'),
    ({'angle_min': -7.0, 'angle_max': 7.0}, 'span more than a full turn'),
    ({'angle_max': 1e9}, 'angle_max 1000000000.0 rad is beyond'),
    ({'angle_max': math.nan}, 'angle_max must be finite'),
    ({'safety_radius': -0.1}, 'safety_radius'),
    ({'safety_radius': float('nan')}, 'safety_radius'),
    ({'path': np.array([1, 2, 3])}, r'\(N, 2\)'),
    ({'path': np.array([[0.5, 1.0]])}, 'integers'),
    ({'path': np.array([[0, 1], [20, 1]])}, 'off the 20x20 grid'),
])
def test_bad_input_raises_and_leaves_labels_unchanged(kwargs, message):
    grid = LabelGrid(width=10.0, height=10.0, resolution=0.5)
    args = {'pose': (5.0, 5.0, 0.0), 'ranges': np.full(640, 2.0), 'safety_radius': 0.5,
            'angle_max': math.pi / 2, **SCAN}
    args.update(kwargs)
    with pytest.raises(ValueError, match=message):
        grid.update(**args)
    assert np.all(grid.labels == N)


@pytest.mark.parametrize('kwargs, message', [
    ({'resolution': 0.0}, 'resolution must be positive'),
    ({'resolution': -0.5}, 'resolution must be positive'),
    ({'width': 0.0}, 'width and height must be positive'),
    ({'height': float('nan')}, 'height must be finite'),
    ({'origin': (0.0,)}, 'origin'),
    ({'origin': (0.0, float('inf'))}, 'origin y must be finite'),
])
def test_bad_grid_raises(kwargs, message):
    args = {'width': 10.0, 'height': 10.0, 'resolution': 0.5, 'origin': (0.0, 0.0)}
    args.update(kwargs)
    with pytest.raises(ValueError, match=message):
        LabelGrid(**args)


def test_angle_max_within_one_beam_is_accepted():
    grid = LabelGrid(width=10.0, height=10.0, resolution=0.5)
    increment = math.pi / 640            # a driver whose angle_max is one increment short
    grid.update((5.0, 5.0, 0.0), np.full(640, 2.0), -math.pi / 2, increment, 0.1, 30.0, 0.5,
                angle_max=math.pi / 2 - increment)
    assert np.any(grid.labels != N)


# Readings that exercise every REP 117 case: valid, short, NaN, +/-inf, at and past range_max.
reading = st.one_of(
    st.floats(0.0, 9.0), st.sampled_from([math.nan, math.inf, -math.inf, 6.0, 0.2, 7.5]))


def round_poses(case):
    """
    Yield the laser's pose for each of the case's rounds, starting at its pose.

    Later rounds move and turn the laser so that labels go through several transitions.
    """
    x, y, yaw = case['pose']
    for step in range(case['rounds']):
        yield (x + 0.25 * step, y - 0.5 * step, yaw + math.pi / 4 * step)


@st.composite
def scans(draw):
    """Random scans, half of them on a lattice where centres, hits and radii coincide exactly."""
    lattice = draw(st.booleans())
    rows = draw(st.integers(1, 14))
    cols = draw(st.integers(1, 14))
    if lattice:
        # Hits land on cell centres and edges, crossings on centres, distances equal to r.
        quarter = st.integers(-12, 40).map(lambda k: 0.25 * k)
        resolution = 0.5
        origin = (0.0, 0.0)
        x, y = draw(quarter), draw(quarter)
        yaw = draw(st.integers(-4, 4)) * math.pi / 4
        angle_min = draw(st.integers(-4, 0)) * math.pi / 4
        quarter_turns = draw(st.sampled_from([1, 2]))          # increment of 45 or 90 degrees
        increment = quarter_turns * math.pi / 4
        beams = draw(st.integers(0, 8 // quarter_turns + 1))     # at most one full turn
        ranges = draw(st.lists(st.one_of(st.integers(0, 24).map(lambda k: 0.25 * k), reading),
                               min_size=beams, max_size=beams))
        range_max = draw(st.sampled_from([2.0, 4.0, 6.0]))
        safety_radius = draw(st.integers(0, 4).map(lambda k: 0.25 * k))
    else:
        resolution = draw(st.sampled_from([0.25, 0.5, 0.7]))
        origin = (draw(st.floats(-3.0, 3.0)), draw(st.floats(-3.0, 3.0)))
        # Poses inside, near the edge and outside the map.
        x = draw(st.floats(origin[0] - 3.0, origin[0] + cols * resolution + 3.0))
        y = draw(st.floats(origin[1] - 3.0, origin[1] + rows * resolution + 3.0))
        yaw = draw(st.floats(-4.0, 4.0))
        angle_min = draw(st.floats(-3.2, 0.0))
        beams = draw(st.integers(0, 40))
        span = draw(st.sampled_from([math.pi, 1.5 * math.pi, 2.0 * math.pi, 0.5]))
        increment = span / max(beams - 1, 1)
        ranges = draw(st.lists(reading, min_size=beams, max_size=beams))
        range_max = draw(st.floats(1.0, 7.5))
        safety_radius = draw(st.floats(0.0, 1.2))
    return {'rows': rows, 'cols': cols, 'resolution': resolution, 'origin': origin,
            'pose': (x, y, yaw), 'ranges': np.array(ranges, dtype=float),
            'angle_min': angle_min, 'angle_increment': increment, 'range_min': 0.2,
            'range_max': range_max, 'safety_radius': safety_radius,
            'path_seed': draw(st.integers(0, 2**31 - 1)), 'rounds': draw(st.integers(1, 3))}


@settings(max_examples=400)
@given(scans())
def test_update_equals_the_literal_reference(case):
    grid = LabelGrid(case['cols'] * case['resolution'], case['rows'] * case['resolution'],
                     case['resolution'], case['origin'])
    assert grid.labels.shape == (case['rows'], case['cols'])
    rng = np.random.default_rng(case['path_seed'])
    expected = rng.integers(0, 4, grid.labels.shape).astype(np.uint8)
    grid.labels[...] = expected
    path = np.argwhere(rng.random(grid.labels.shape) < 0.3)
    scan = {k: case[k] for k in ('angle_min', 'angle_increment', 'range_min', 'range_max',
                                 'safety_radius')}
    for pose in round_poses(case):
        want = literal_update(expected, case['origin'], case['resolution'], pose,
                              case['ranges'], path=path, **scan)
        got = grid.update(pose, case['ranges'], path=path, **scan)
        assert_array_equal(grid.labels, expected)
        assert got == want


def test_dense_640_beam_scan_equals_the_literal_reference():
    rng = np.random.default_rng(7)
    grid = LabelGrid(width=12.0, height=9.0, resolution=0.5, origin=(-1.0, -1.0))
    expected = grid.labels.copy()
    for _ in range(3):
        ranges = rng.uniform(0.05, 8.0, 640)
        ranges[rng.random(640) < 0.05] = np.nan
        ranges[rng.random(640) < 0.05] = np.inf
        pose = (rng.uniform(0.0, 10.0), rng.uniform(0.0, 7.0), rng.uniform(-math.pi, math.pi))
        path = np.argwhere(rng.random(grid.labels.shape) < 0.2)
        want = literal_update(expected, (-1.0, -1.0), 0.5, pose, ranges, safety_radius=0.6,
                              path=path, **SCAN)
        got = grid.update(pose, ranges, safety_radius=0.6, path=path, **SCAN)
        assert_array_equal(grid.labels, expected)
        assert got == want


def test_last_window_holds_the_updates_window_and_fsm_input():
    grid = LabelGrid(width=10.0, height=10.0, resolution=0.5)
    rows, cols, cell_input = grid.last_window
    assert cell_input.shape == (0, 0) and rows.start == rows.stop
    ranges, scan = wall_scan(3.0)
    grid.update((2.0, 5.0, 0.0), ranges, safety_radius=0.3, **scan)
    rows, cols, cell_input = grid.last_window
    assert cell_input.shape == (rows.stop - rows.start, cols.stop - cols.start)
    assert cell_input.dtype == np.uint8
    row = grid.geometry.world_to_cell(0.0, 5.0)[0] - rows.start
    assert cell_input[row, 9 - cols.start] == 2 and cell_input[row, 5 - cols.start] == 1
    # Every label that changed lies in the window, where the input was not (0, 0).
    changed = np.argwhere(grid.labels != N)
    assert np.all((changed[:, 0] >= rows.start) & (changed[:, 0] < rows.stop))
    assert np.all(cell_input[changed[:, 0] - rows.start, changed[:, 1] - cols.start] != 0)
    grid.update((-50.0, -50.0, 0.0), ranges, safety_radius=0.3, **scan)   # misses the grid
    assert grid.last_window[2].shape == (0, 0)


# The dpn rule against its literal twin: each addition alone and all together.
RULES = {
    'free_evidence': LabelRule(free_evidence_radius=0.5),
    'objects': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6),
    'thin': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                      object_min_hits=3),
    'fine': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                      object_min_hits=2, fine_evidence_resolution=0.25,
                      fine_evidence_radius=0.3, fine_evidence_range=2.5),
    'expiry': LabelRule(mobile_expiry=1.0),
    'all': LabelRule(free_evidence_radius=0.75, moving_object_size=1.0, segment_gap=1.1,
                     object_min_hits=2, mobile_expiry=0.5),
    # The rules for real lasers: no-echo codes, no-return reach, intermittent surfaces.
    'real': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                      object_min_hits=2, fine_evidence_resolution=0.25,
                      fine_evidence_radius=0.3, fine_evidence_range=2.5,
                      no_echo_below_range_min=True, no_return_reach=0.6, surface_time=0.3,
                      surface_memory=2.0, noise_margin=0.25),
    'no_return_clears_nothing': LabelRule(free_evidence_radius=0.5, no_return_reach=0.0,
                                          no_echo_below_range_min=True),
    'no_return_short': LabelRule(no_return_reach=0.3),
    # Mixed pixels read as invalid, veiling hits without evidence of their own.
    'edge_pixels': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                             object_min_hits=2, no_return_reach=0.0, surface_time=0.3,
                             surface_memory=2.0, noise_margin=0.25, mixed_pixel_angle=0.5,
                             veiling_angle=0.4),
    'mixed_pixels_alone': LabelRule(mixed_pixel_angle=0.6),
    'spikes': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                        surface_time=0.3, surface_memory=2.0, noise_margin=0.25,
                        mixed_pixel_angle=0.5, spike_angle=0.5, veiling_angle=0.4),
    'spikes_alone': LabelRule(spike_angle=0.6),
    'flat_walls': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                            surface_time=0.3, surface_memory=2.0, noise_margin=0.25,
                            mixed_pixel_angle=0.5, spike_angle=0.5, edge_pixel_flatness=0.3,
                            veiling_angle=0.4),
    # A hit's motion evidence checked the range noise margin beyond it, coarse and fine.
    'range_noise': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                             object_min_hits=2, fine_evidence_resolution=0.25,
                             fine_evidence_radius=0.3, fine_evidence_range=2.5,
                             surface_time=0.3, surface_memory=2.0, noise_margin=0.25,
                             range_noise_margin=0.3, range_noise_fraction=0.1),
    # The fine free evidence's burn-in, and narrow free-standing segments without evidence.
    'burn_in': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                         object_min_hits=2, fine_evidence_resolution=0.25,
                         fine_evidence_radius=0.3, fine_evidence_range=2.5,
                         no_echo_below_range_min=True, no_return_reach=0.6,
                         mobile_expiry=0.5, free_burn_in=0.3),
    'narrow': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                        fine_evidence_resolution=0.25, fine_evidence_radius=0.3,
                        fine_evidence_range=2.5, surface_time=0.3, surface_memory=2.0,
                        noise_margin=0.25, object_min_width=0.6, mobile_expiry=1.0,
                        free_burn_in=0.2),
    # Segments across beams without a hit (lost returns), in the kernel's own object rule
    # and in the intermittent surfaces' (with fine evidence and narrow things).
    'bridged_thin': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7,
                              segment_gap=0.6, object_min_hits=3, segment_bridge_beams=2),
    'bridged_real': LabelRule(free_evidence_radius=0.5, moving_object_size=0.7,
                              segment_gap=0.6, object_min_hits=2,
                              fine_evidence_resolution=0.25, fine_evidence_radius=0.3,
                              fine_evidence_range=2.5, no_echo_below_range_min=True,
                              no_return_reach=0.0, surface_time=0.3, surface_memory=2.0,
                              noise_margin=0.25, mixed_pixel_angle=0.5,
                              object_min_width=0.6, segment_bridge_beams=3),
}
REAL_SENSOR_RULES = ('real', 'no_return_clears_nothing', 'no_return_short', 'edge_pixels',
                     'mixed_pixels_alone', 'spikes', 'spikes_alone', 'flat_walls', 'range_noise',
                     'burn_in', 'narrow', 'bridged_real')


@settings(max_examples=120)
@given(case=scans(), rule_name=st.sampled_from(sorted(RULES)),
       stamps=st.lists(st.sampled_from([0.0, 0.25, 0.5, 1.0, 2.0, 3.5]), min_size=3,
                       max_size=3))
def test_rule_update_equals_the_literal_twin(case, rule_name, stamps):
    check_rule_against_the_literal_twin(case, RULES[rule_name], stamps)


@settings(max_examples=150)
@given(case=scans(), rule_name=st.sampled_from(sorted(REAL_SENSOR_RULES)),
       stamps=st.lists(st.sampled_from([0.0, 0.1, 0.25, 0.5, 1.0, 0.9]), min_size=3,
                       max_size=3))
def test_real_sensor_rules_equal_the_literal_twin(case, rule_name, stamps):
    check_rule_against_the_literal_twin(case, RULES[rule_name], stamps)


def check_rule_against_the_literal_twin(case, rule, stamps):
    """Update a grid and the literal twin with ``rule`` from the same random state."""
    grid = LabelGrid(case['cols'] * case['resolution'], case['rows'] * case['resolution'],
                     case['resolution'], case['origin'], rule)
    rng = np.random.default_rng(case['path_seed'])
    labels = rng.integers(0, 4, grid.labels.shape).astype(np.uint8)
    seen_free = rng.random(grid.labels.shape) < 0.4
    last_hit = np.where(rng.random(grid.labels.shape) < 0.5, -math.inf,
                        rng.choice([0.0, 0.5, 1.0], grid.labels.shape))
    grid.labels[...] = labels
    if grid.seen_free is not None:
        grid.seen_free[...] = seen_free
    if grid.last_hit is not None:
        grid.last_hit[...] = last_hit
    fine_seen_free = fine_hit_stamp = None
    if grid.fine_evidence is not None:
        fine_seen_free = rng.random(grid.fine_evidence.seen_free.shape) < 0.3
        grid.fine_evidence.seen_free[...] = fine_seen_free
        if grid.fine_evidence.hit_stamp is not None:
            fine_hit_stamp = rng.choice([-math.inf, 0.0, 0.25, 0.5],
                                        grid.fine_evidence.hit_stamp.shape)
            grid.fine_evidence.hit_stamp[...] = fine_hit_stamp
    surfaces = None
    if grid.surface_memory is not None:
        memory = grid.surface_memory
        surfaces = LiteralSurfaceMemory(case['origin'], rule.noise_margin, rule.surface_time,
                                        rule.surface_memory)
        levels = np.where(rng.random(memory.hit_time.shape) < 0.3,
                          rng.choice([0.1, 0.3, 0.6], memory.hit_time.shape), 0.0)
        for row, col in np.argwhere(levels > 0.0):
            memory.hit_time[row, col] = levels[row, col]
            memory.filled[row, col] = 0.0
            surfaces.buckets[(int(row), int(col))] = (float(levels[row, col]), 0.0)
    grid.labels_changed()
    path = np.argwhere(rng.random(grid.labels.shape) < 0.3)
    scan = {k: case[k] for k in ('angle_min', 'angle_increment', 'range_min', 'range_max',
                                 'safety_radius')}
    last_stamp = -math.inf
    for pose, stamp in zip(round_poses(case), stamps):
        want, last_stamp = literal_update_with_rule(
            labels, seen_free, last_hit, case['origin'], case['resolution'], pose,
            case['ranges'], rule=rule, stamp=stamp, last_stamp=last_stamp, path=path,
            fine_seen_free=fine_seen_free, surfaces=surfaces, fine_hit_stamp=fine_hit_stamp,
            **scan)
        got = grid.update(pose, case['ranges'], path=path, stamp=stamp, **scan)
        assert_array_equal(grid.labels, labels)
        if grid.seen_free is not None:
            assert_array_equal(grid.seen_free, seen_free)
        if grid.last_hit is not None:
            assert_array_equal(grid.last_hit, last_hit)
        if fine_seen_free is not None:
            assert_array_equal(grid.fine_evidence.seen_free, fine_seen_free)
        if fine_hit_stamp is not None:
            assert_array_equal(grid.fine_evidence.hit_stamp, fine_hit_stamp)
        assert got == want


def test_paper_rule_is_the_default_and_keeps_no_evidence():
    grid = LabelGrid(width=10.0, height=10.0)
    assert grid.rule == PAPER_RULE == LabelRule()
    assert grid.seen_free is None and grid.last_hit is None


def test_grazing_wall_is_steady_under_conservative_free_space():
    # A wall along y = 0.5 seen first from far at a grazing angle (hits about 2 m apart):
    # the chords between hits run along the wall, so the cells next to it are explored.
    # Seen again from close by, the paper calls them mobile; the dpn rule keeps them steady.
    results = {}
    for name, rule in (('paper', PAPER_RULE), ('dpn', LabelRule(free_evidence_radius=0.6))):
        grid = LabelGrid(width=30.0, height=10.0, rule=rule)
        far, far_scan = grazing_wall_scan((1.0, 4.0), 0.5)
        grid.update((1.0, 4.0, 0.0), far, safety_radius=0.6, **far_scan)
        near, near_scan = grazing_wall_scan((15.0, 1.3), 0.5)
        grid.update((15.0, 1.3, 0.0), near, safety_radius=0.6, **near_scan)
        results[name] = grid.labels.copy()
    wall_row = 1                                 # centres at y = 0.75, 0.25 m from the wall
    assert np.count_nonzero(results['paper'][wall_row] == M) >= 3
    assert not np.any(results['dpn'] == M)
    assert np.count_nonzero(results['dpn'] == S) >= np.count_nonzero(results['paper'] == S)


def grazing_wall_scan(position, wall_y, beams=91):
    """Return ranges of a laser at ``position`` facing +x, a wall along ``y = wall_y`` below."""
    angles = -math.pi / 2 + np.arange(beams) * (math.pi / (beams - 1))
    height = position[1] - wall_y
    with np.errstate(divide='ignore'):
        ranges = np.where(np.sin(angles) < 0.0, height / -np.sin(angles), np.inf)
    ranges[ranges >= 29.0] = np.inf
    return ranges, {'angle_min': -math.pi / 2, 'angle_increment': math.pi / (beams - 1),
                    'range_min': 0.1, 'range_max': 29.0}


def test_object_moving_into_surely_free_space_is_mobile_all_over():
    rule = LabelRule(free_evidence_radius=0.6, moving_object_size=0.7)
    grid = LabelGrid(width=12.0, height=12.0, rule=rule)
    laser = (1.0, 6.0, 0.0)
    empty = np.full(181, np.inf)
    scan = {'angle_min': -math.pi / 2, 'angle_increment': math.pi / 180, 'range_min': 0.1,
            'range_max': 8.0}
    grid.update(laser, empty, safety_radius=0.6, **scan)          # open space, seen free
    assert grid.seen_free[grid.geometry.world_to_cell(5.0, 6.0)]
    # A 0.5 m box now stands at x = 5 m, half in space seen free, half beyond the range.
    ranges = empty.copy()
    ranges[85:96] = 4.0
    grid.update(laser, ranges, safety_radius=0.6, **scan)
    hit_cells = grid.labels[grid.geometry.world_to_cell(4.75, 6.0)]
    assert hit_cells == M
    rows, cols, cell_input = grid.last_window
    window = grid.labels[rows, cols]
    assert np.all(window[cell_input == 2] == M)                   # every hit cell of it
    # Without object-level relabelling the cells not surely seen free would be steady.


def test_wall_hits_never_turn_mobile_without_evidence():
    rule = LabelRule(free_evidence_radius=0.6, moving_object_size=0.7)
    grid = LabelGrid(width=10.0, height=10.0, rule=rule)
    ranges, scan = wall_scan(3.0)
    for step in range(3):
        grid.update((2.0 + 0.3 * step, 5.0, 0.0), ranges - 0.3 * step, safety_radius=0.6,
                    **scan)
    assert np.count_nonzero(grid.labels == S) > 10
    assert not np.any(grid.labels == M)


def test_unconfirmed_mobile_cells_out_of_view_expire():
    rule = LabelRule(mobile_expiry=2.0)
    grid = LabelGrid(width=10.0, height=10.0, rule=rule)
    ranges, scan = wall_scan(3.0)
    grid.labels[1, 1] = M                                 # behind the laser: never seen
    grid.last_hit[1, 1] = 0.0
    grid.labels_changed()
    grid.update((5.0, 5.0, 0.0), ranges, safety_radius=0.3, stamp=1.9, **scan)
    assert grid.labels[1, 1] == M
    grid.update((5.0, 5.0, 0.0), ranges, safety_radius=0.3, stamp=2.0, **scan)
    assert grid.labels[1, 1] == E
    with pytest.raises(ValueError, match='needs a finite scan stamp'):
        grid.update((5.0, 5.0, 0.0), ranges, safety_radius=0.3, **scan)


@pytest.mark.parametrize(('kwargs', 'message'), [
    ({'free_evidence_radius': -0.1}, 'free_evidence_radius must be finite'),
    ({'mobile_expiry': math.nan}, 'mobile_expiry must be finite'),
    ({'segment_gap': 0.0}, 'segment_gap must be positive'),
    ({'moving_object_size': 1.0}, 'moving_object_size needs free_evidence_radius'),
    ({'fine_evidence_resolution': 0.1}, 'both 0'),
    ({'free_evidence_radius': 0.6, 'moving_object_size': 0.7, 'fine_evidence_resolution': 0.1,
      'fine_evidence_radius': 0.2, 'fine_evidence_range': 0.0}, 'fine_evidence_range must'),
    ({'fine_evidence_resolution': 0.1, 'fine_evidence_radius': 0.2},
     'fine_evidence_radius needs moving_object_size'),
    ({'fine_evidence_range': -1.0}, 'fine_evidence_range must be finite'),
])
def test_bad_rule_raises(kwargs, message):
    with pytest.raises(ValueError, match=message):
        LabelRule(**kwargs)


@settings(max_examples=80)
@given(case=scans(), share=st.sampled_from([0.3, 0.7, 1.0]))
def test_fine_evidence_equals_the_literal_twin(case, share):
    # No label cell surely free to start with: whatever shows motion in the first scan, the
    # fine evidence showed.
    rule = RULES['fine']
    grid = LabelGrid(case['cols'] * case['resolution'], case['rows'] * case['resolution'],
                     case['resolution'], case['origin'], rule)
    rng = np.random.default_rng(case['path_seed'])
    labels = rng.integers(0, 4, grid.labels.shape).astype(np.uint8)
    seen_free = np.zeros(grid.labels.shape, dtype=bool)
    fine_seen_free = rng.random(grid.fine_evidence.seen_free.shape) < share
    grid.labels[...] = labels
    grid.fine_evidence.seen_free[...] = fine_seen_free
    grid.labels_changed()
    scan = {k: case[k] for k in ('angle_min', 'angle_increment', 'range_min', 'range_max',
                                 'safety_radius')}
    for pose in round_poses(case):
        literal_update_with_rule(labels, seen_free, None, case['origin'], case['resolution'],
                                 pose, case['ranges'], rule=rule, stamp=0.0,
                                 last_stamp=-math.inf, fine_seen_free=fine_seen_free, **scan)
        grid.update(pose, case['ranges'], **scan)
        assert_array_equal(grid.labels, labels)
        assert_array_equal(grid.seen_free, seen_free)
        assert_array_equal(grid.fine_evidence.seen_free, fine_seen_free)


@given(case=scans())
def test_surely_free_update_equals_the_literal_twin_of_a_free_only_grid(case):
    # The fine evidence's own update: seen_free alone, as a grid with only the conservative
    # free space on and the safety radius equal to its radius marks it.
    radius = max(case['safety_radius'], 0.25)
    rule = LabelRule(free_evidence_radius=radius)
    grid = LabelGrid(case['cols'] * case['resolution'], case['rows'] * case['resolution'],
                     case['resolution'], case['origin'], rule)
    rng = np.random.default_rng(case['path_seed'])
    labels = rng.integers(0, 4, grid.labels.shape).astype(np.uint8)
    seen_free = rng.random(grid.labels.shape) < 0.2
    kernel_seen_free = seen_free.copy()
    scan = {k: case[k] for k in ('angle_min', 'angle_increment', 'range_min', 'range_max')}
    for pose in round_poses(case):
        literal_update_with_rule(labels, seen_free, None, case['origin'], case['resolution'],
                                 pose, case['ranges'], rule=rule, stamp=0.0,
                                 last_stamp=-math.inf, safety_radius=radius, **scan)
        surely_free_update(kernel_seen_free, grid.geometry, pose, case['ranges'], **scan,
                           radius=radius)
        assert_array_equal(kernel_seen_free, seen_free)


def corridor_ranges(angles, board):
    """Ranges from (1, 4) down a corridor 1.2 m wide ending at x = 2.4, with a board or not."""
    cos, sin = np.cos(angles), np.abs(np.sin(angles))
    with np.errstate(divide='ignore'):
        ranges = np.minimum(np.where(cos > 1e-9, 1.4 / cos, np.inf),
                            np.where(sin > 1e-9, 0.6 / sin, np.inf))
    if board:
        # A board 0.3 m wide across the corridor, 1.0 m ahead.
        on_board = np.abs(np.tan(angles)) <= 0.15
        ranges[on_board] = 1.0 / cos[on_board]
    return ranges


def test_fine_evidence_shows_a_hit_moving_where_no_label_cell_was_surely_free():
    # The corridor is too narrow for a label cell's 0.6 m disc, not for a fine cell's 0.2 m.
    rule = LabelRule(free_evidence_radius=0.6, moving_object_size=0.7,
                     fine_evidence_resolution=0.1, fine_evidence_radius=0.2)
    without_rule = dataclasses.replace(rule, fine_evidence_resolution=0.0,
                                       fine_evidence_radius=0.0)
    beams = 181
    scan = {'angle_min': -math.pi / 2, 'angle_increment': math.pi / (beams - 1),
            'range_min': 0.1, 'range_max': 8.0, 'safety_radius': 0.6}
    angles = scan['angle_min'] + np.arange(beams) * scan['angle_increment']
    laser = (1.0, 4.0, 0.0)
    grids = {}
    for name, grid_rule in (('with', rule), ('without', without_rule)):
        grid = LabelGrid(8.0, 8.0, 0.5, rule=grid_rule)
        grid.update(laser, corridor_ranges(angles, board=False), **scan)
        grid.update(laser, corridor_ranges(angles, board=True), **scan)
        grids[name] = grid
    rr, cc = grids['with'].geometry.world_to_cell(np.array([2.0]), np.array([4.0]))
    assert not grids['without'].seen_free.any()
    assert grids['with'].fine_evidence.seen_free.any()
    assert grids['without'].labels[rr[0], cc[0]] == CellLabel.STEADY_OBSTACLE
    assert grids['with'].labels[rr[0], cc[0]] == CellLabel.MOBILE_OBSTACLE


def grid_state(grid):
    """Every array of a grid's state that an update writes, by name."""
    state = {'labels': grid.labels, 'window': grid.last_window[2]}
    for name in ('seen_free', 'last_hit', 'cell_track'):
        if getattr(grid, name) is not None:
            state[name] = getattr(grid, name)
    if grid.fine_evidence is not None:
        state['fine'] = grid.fine_evidence.seen_free
    if grid.object_memory is not None:
        state['anchored'] = grid.object_memory.anchored
        state['provisional'] = grid.object_memory.provisional
    return {name: np.array(value) for name, value in state.items()}


def assert_same_state(got, want, skip=()):
    assert got.keys() == want.keys()
    for name in got:
        if name not in skip:
            assert_array_equal(got[name], want[name], err_msg=name)


@settings(max_examples=120)
@given(case=scans(), rule_name=st.sampled_from(sorted(RULES)),
       stamps=st.lists(st.sampled_from([0.0, 0.25, 0.5, 1.0, 2.0]), min_size=3, max_size=3),
       settle=st.lists(st.booleans(), min_size=3, max_size=3))
def test_deferred_evidence_leaves_the_labels_and_is_marked_when_settled(
        case, rule_name, stamps, settle):
    # One grid marks the free evidence in the update, the other later: in `settle`, or in
    # the next update when settle is not called. Right after each update everything but the
    # evidence is the same and the evidence is that of before the scan; once settled, all.
    rule = RULES[rule_name]
    grids = [LabelGrid(case['cols'] * case['resolution'], case['rows'] * case['resolution'],
                       case['resolution'], case['origin'], rule) for _ in range(2)]
    rng = np.random.default_rng(case['path_seed'])
    labels = rng.integers(0, 4, grids[0].labels.shape).astype(np.uint8)
    seen_free = rng.random(labels.shape) < 0.4
    for grid in grids:
        grid.labels[...] = labels
        if grid.seen_free is not None:
            grid.seen_free[...] = seen_free
        grid.labels_changed()
    now, deferred = grids
    path = np.argwhere(rng.random(labels.shape) < 0.3)
    scan = {k: case[k] for k in ('angle_min', 'angle_increment', 'range_min', 'range_max',
                                 'safety_radius')}
    evidence = ('seen_free', 'fine')
    for pose, stamp, settle_now in zip(round_poses(case), stamps, settle):
        before = grid_state(now)            # the deferred grid's once settled
        want = now.update(pose, case['ranges'], path=path, stamp=stamp, **scan)
        got = deferred.update(pose, case['ranges'], path=path, stamp=stamp, **scan,
                              defer_evidence=True)
        assert got == want
        after = grid_state(deferred)
        assert_same_state(after, grid_state(now), skip=evidence)
        for name in evidence:
            if name in after:
                assert_array_equal(after[name], before[name], err_msg=name)
        if settle_now:
            deferred.settle()
            assert_same_state(grid_state(deferred), grid_state(now))
    deferred.settle()
    assert_same_state(grid_state(deferred), grid_state(now))
