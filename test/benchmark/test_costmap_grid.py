"""
The Nav2-style costmap: Bresenham clearing, marking ranges, +inf, inflation and the ghost.

Grids are 0.5 m cells with the origin at (0, 0), so cell ``(row, col)`` holds ``x`` in
``[0.5 col, 0.5 col + 0.5)`` and ``y`` in ``[0.5 row, 0.5 row + 0.5)``. The Bresenham lines
are checked against a literal transcription of Nav2 Jazzy's ``Costmap2D::raytraceLine`` and
``bresenham2D`` (``nav2_costmap_2d/include/nav2_costmap_2d/costmap_2d.hpp``).

"""

import math
import subprocess
import sys

from dpn_navigator.benchmark.baselines.costmap_grid import (any_in_blocks, bresenham_cells,
                                                            CostmapConfig, CostmapGrid, inflate,
                                                            layer_geometry_for)
from dpn_navigator.core._kernels.costmap import clear_rays
from dpn_navigator.core.cell_label import blocked_mask, CellLabel, ScanInput
from dpn_navigator.core.grid_geometry import GridGeometry
from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
from numpy.testing import assert_array_equal
import pytest

#: A wide beam layout: one beam, straight along the laser's x axis.
ONE_BEAM = {'angle_min': 0.0, 'angle_increment': 0.01, 'range_min': 0.1, 'range_max': 30.0}
#: Ranges that make the walls of these tests ghosts or not: 20 m marking, 25 m clearing.
CONFIG = CostmapConfig(obstacle_max_range=20.0, raytrace_max_range=25.0)


def nav2_raytrace_line(x0, y0, x1, y1, max_length):
    """Nav2's ``raytraceLine`` + ``bresenham2D`` for ``min_length = 0``, literally (x: col)."""
    cells = []
    dx, dy = x1 - x0, y1 - y0
    abs_dx, abs_dy = abs(dx), abs(dy)
    offset_dx = 1 if dx > 0 else -1
    offset_dy = 1 if dy > 0 else -1
    dist = math.hypot(dx, dy)
    scale = 1.0 if dist == 0.0 else min(1.0, max_length / dist)
    x, y = x0, y0
    if abs_dx >= abs_dy:
        abs_da, abs_db, error_b = abs_dx, abs_dy, abs_dx // 2
        end = min(int(scale * abs_dx), abs_da)
        for _ in range(end):
            cells.append((y, x))
            x += offset_dx
            error_b += abs_db
            if error_b >= abs_da:
                y += offset_dy
                error_b -= abs_da
    else:
        abs_da, abs_db, error_b = abs_dy, abs_dx, abs_dy // 2
        end = min(int(scale * abs_dy), abs_da)
        for _ in range(end):
            cells.append((y, x))
            y += offset_dy
            error_b += abs_db
            if error_b >= abs_da:
                x += offset_dx
                error_b -= abs_da
    cells.append((y, x))
    return cells


@settings(max_examples=300, deadline=None)
@given(start=st.tuples(st.integers(0, 60), st.integers(0, 60)),
       ends=st.lists(st.tuples(st.integers(0, 60), st.integers(0, 60)), min_size=1,
                     max_size=6),
       max_cells=st.integers(0, 90))
def test_bresenham_cells_are_nav2s_raytrace_line(start, ends, max_cells):
    ends = np.array(ends, dtype=np.int64)
    rr, cc = bresenham_cells(start[0], start[1], ends[:, 0], ends[:, 1], max_cells)
    expected = [cell for end_rr, end_cc in ends
                for cell in nav2_raytrace_line(start[1], start[0], int(end_cc), int(end_rr),
                                               max_cells)]
    assert list(zip(rr.tolist(), cc.tolist())) == expected


def test_bresenham_cells_of_no_line_is_empty():
    rr, cc = bresenham_cells(3, 4, np.zeros(0, np.int64), np.zeros(0, np.int64), 10)
    assert rr.shape == (0,) and cc.shape == (0,)


def grid(config=CONFIG, size=30.0):
    """Return a ``size`` x ``size`` m costmap of 0.5 m cells."""
    return CostmapGrid(size, size, 0.5, (0.0, 0.0), config)


def beam(costmap, x, y, yaw, distance, **scan):
    """Fold a one-beam scan from ``(x, y, yaw)`` in; return the replan flag."""
    return costmap.update((x, y, yaw), [distance], safety_radius=0.6, **(ONE_BEAM | scan))


def test_a_hit_marks_its_cell_lethal_and_clears_the_cells_before_it():
    costmap = grid()
    beam(costmap, 1.25, 5.25, 0.0, 4.0)                  # hit at (5.25, 5.25): cell (10, 10)
    assert costmap.lethal[10, 10] and np.count_nonzero(costmap.lethal) == 1
    assert costmap.known_free[10, 2:10].all() and not costmap.known_free[10, 10]
    assert not costmap.known_free[10, 11:].any() and not costmap.known_free[9].any()
    # Inflated to 0.6 m between cell centres: the cell and its four neighbours.
    blocked = blocked_mask(costmap.labels)
    assert_array_equal(np.argwhere(blocked), [[9, 10], [10, 9], [10, 10], [10, 11], [11, 10]])
    assert costmap.labels[10, 5] == CellLabel.EXPLORED
    assert costmap.labels[20, 20] == CellLabel.NON_EXPLORED
    assert not (costmap.labels == CellLabel.MOBILE_OBSTACLE).any()


def test_a_cell_is_cleared_only_by_a_ray_through_it():
    costmap = grid()
    beam(costmap, 1.25, 5.25, 0.0, 4.0)                  # lethal (10, 10)
    # Rays that pass beside the cell (one row up, and ending one cell short) leave it lethal.
    beam(costmap, 1.25, 5.75, 0.0, 8.0)
    beam(costmap, 1.25, 5.25, 0.0, 3.5)
    assert costmap.lethal[10, 10]
    # A ray through it, ending beyond, clears it.
    beam(costmap, 1.25, 5.25, 0.0, 8.0)
    assert not costmap.lethal[10, 10] and costmap.known_free[10, 10]
    assert costmap.lethal[10, 18]


def test_a_ray_ending_in_a_cell_clears_then_marks_it_again():
    costmap = grid()
    beam(costmap, 1.25, 5.25, 0.0, 4.0)
    beam(costmap, 1.25, 5.25, 0.0, 4.2)                  # same cell, hit again
    assert costmap.lethal[10, 10] and np.count_nonzero(costmap.lethal) == 1


def test_the_ghost_behind_a_nearer_obstacle_stays():
    """An obstacle that left where no ray passes stays lethal: the Nav2 ghost."""
    costmap = grid()
    beam(costmap, 1.25, 5.25, 0.0, 6.0)                  # a wanderer at x = 7.25: (10, 14)
    # It leaves; another stands nearer on the same line, so no ray reaches the first's cell.
    beam(costmap, 1.25, 5.25, 0.0, 3.0)                  # (10, 8)
    assert costmap.lethal[10, 14] and costmap.lethal[10, 8]
    assert costmap.labels[10, 14] == CellLabel.STEADY_OBSTACLE
    # The second leaves too: the laser now reaches a wall behind both, and clears both.
    beam(costmap, 1.25, 5.25, 0.0, 12.0)
    assert not costmap.lethal[10, 14] and not costmap.lethal[10, 8]


def test_the_ghost_beyond_raytrace_range_stays():
    config = CostmapConfig(obstacle_max_range=5.0, raytrace_max_range=6.0)
    costmap = grid(config)
    beam(costmap, 2.25, 5.25, 0.0, 4.9)                  # marked at 4.9 m: (10, 14)
    assert costmap.lethal[10, 14]
    # The robot backs off to x = 0.25: a ray through the cell to a wall 15 m off clears only
    # 6 m (12 cells past the laser's), so the obstacle's cell, 14 cells off, stays lethal.
    beam(costmap, 0.25, 5.25, 0.0, 15.0)
    assert costmap.lethal[10, 14] and np.count_nonzero(costmap.lethal) == 1
    assert costmap.known_free[10, :14].all() and not costmap.known_free[10, 14:].any()


def test_marking_stops_at_obstacle_max_range_but_clearing_does_not():
    config = CostmapConfig(obstacle_max_range=5.0, raytrace_max_range=10.0)
    costmap = grid(config)
    beam(costmap, 0.25, 5.25, 0.0, 6.0)                  # beyond 5 m: clears, marks nothing
    assert not costmap.lethal.any() and costmap.known_free[10, :13].all()
    beam(costmap, 0.25, 5.25, 0.0, 4.99)
    assert costmap.lethal[10, 10]
    config = CostmapConfig(obstacle_max_range=5.0, obstacle_min_range=2.0,
                           raytrace_max_range=10.0)
    costmap = grid(config)
    beam(costmap, 0.25, 5.25, 0.0, 1.5)                  # closer than obstacle_min_range
    assert not costmap.lethal.any() and costmap.known_free[10, :4].all()


@pytest.mark.parametrize('inf_is_valid, cleared, lethal', [(True, 31, 0), (False, 16, 1)])
def test_inf_returns_clear_to_range_max_only_when_valid(inf_is_valid, cleared, lethal):
    config = CostmapConfig(obstacle_max_range=10.0, raytrace_max_range=15.0,
                           inf_is_valid=inf_is_valid)
    costmap = grid(config, size=40.0)
    beam(costmap, 0.25, 30.25, 0.0, 8.0)                 # an obstacle 8 m ahead: (60, 16)
    assert costmap.lethal[60, 16] and costmap.known_free[60, :16].all()
    beam(costmap, 0.25, 30.25, 0.0, math.inf)
    # +inf becomes a point at range_max (30 m, cell 60), beyond obstacle_max_range: it marks
    # nothing; its ray clears 15 m, 30 cells past the laser's (31 with it), the obstacle's
    # cell included. Without inf_is_valid the beam does nothing.
    assert np.count_nonzero(costmap.known_free[60]) == cleared
    assert costmap.known_free[60, :cleared].all()
    assert np.count_nonzero(costmap.lethal) == lethal


@pytest.mark.parametrize('bad', [math.nan, -math.inf, 0.05, 30.0, 31.0])
def test_invalid_returns_neither_mark_nor_clear(bad):
    costmap = grid()
    beam(costmap, 1.25, 5.25, 0.0, bad)
    assert not costmap.lethal.any() and not costmap.known_free.any()


def test_rays_leaving_the_map_are_clipped_to_its_edge():
    costmap = grid(CostmapConfig(obstacle_max_range=20.0, raytrace_max_range=25.0), size=10.0)
    beam(costmap, 1.25, 5.25, 0.0, 15.0)                 # wall 15 m away, off the 10 m map
    assert costmap.known_free[10, 2:].all() and not costmap.lethal.any()
    beam(costmap, 1.25, 5.25, math.pi, 20.0)             # off the left edge
    assert costmap.known_free[10, :2].all()


def test_a_laser_off_the_map_clears_nothing_but_still_marks():
    costmap = grid(size=10.0)
    beam(costmap, -1.0, 5.25, 0.0, 3.0)
    assert costmap.lethal[10, 4] and not costmap.known_free.any()


def test_replan_flag_when_a_path_cell_becomes_blocked():
    costmap = grid()
    path = np.array([[10, c] for c in range(2, 20)])
    assert beam(costmap, 1.25, 5.25, 0.0, 4.0, path=None) is False
    costmap = grid()
    assert beam(costmap, 1.25, 5.25, 0.0, 4.0, path=path) is True
    assert beam(costmap, 1.25, 5.25, 0.0, 4.0, path=path) is False    # already blocked
    assert beam(costmap, 1.25, 8.25, 0.0, 4.0, path=path) is False    # away from the path


def test_window_reports_marked_and_cleared_cells():
    costmap = grid()
    beam(costmap, 1.25, 5.25, 0.0, 4.0)
    rows, cols, cell_input = costmap.last_window
    window = np.full(costmap.geometry.shape, ScanInput.NONE)
    window[rows, cols] = cell_input
    assert window[10, 10] == ScanInput.HIT
    assert (window[10, 2:10] == ScanInput.INSIDE).all()
    assert np.count_nonzero(window) == 9
    assert_array_equal(costmap.lethal_labels()[10, 9:11],
                       [CellLabel.EXPLORED, CellLabel.STEADY_OBSTACLE])


def test_reset_forgets_everything():
    costmap = grid()
    beam(costmap, 1.25, 5.25, 0.0, 4.0)
    costmap.reset()
    assert not costmap.lethal.any() and not costmap.known_free.any()
    assert (costmap.labels == CellLabel.NON_EXPLORED).all()


def inflate_twin(lethal, layer_geometry, geometry, radius):
    """Mark planning cells within ``radius`` of a lethal layer cell, centre to centre, plainly."""
    inflated = np.zeros(geometry.shape, dtype=bool)
    centre_x, centre_y = geometry.cell_to_world(*np.indices(geometry.shape))
    for rr, cc in zip(*np.nonzero(lethal)):
        x, y = layer_geometry.cell_to_world(rr, cc)
        inflated |= (centre_x - x) ** 2 + (centre_y - y) ** 2 <= radius * radius + 1e-9
    return inflated


def test_inflate_uses_distance_between_cell_centres():
    geometry = GridGeometry(3.5, 3.5, 0.5)
    lethal = np.zeros((7, 7), dtype=bool)
    lethal[3, 3] = True
    assert np.count_nonzero(inflate(lethal, geometry, geometry, 0.0)) == 1
    assert np.count_nonzero(inflate(lethal, geometry, geometry, 0.6)) == 5
    assert np.count_nonzero(inflate(lethal, geometry, geometry, 0.71)) == 9
    assert np.count_nonzero(inflate(lethal, geometry, geometry, 1.0)) == 13
    with pytest.raises(ValueError, match='shape'):
        inflate(lethal[:3], geometry, geometry, 0.6)
    with pytest.raises(ValueError, match='radius'):
        inflate(lethal, geometry, geometry, -0.1)


@settings(max_examples=100, deadline=None)
@given(cells=st.lists(st.tuples(st.integers(0, 49), st.integers(0, 39)), max_size=12),
       radius=st.sampled_from([0.0, 0.25, 0.5, 0.6, 0.75, 1.3]))
def test_inflate_onto_the_planning_grid_matches_its_twin(cells, radius):
    geometry = GridGeometry(4.0, 5.0, 0.5, (-1.0, 2.0))
    layer, _ = layer_geometry_for(geometry, 0.1)
    lethal = np.zeros(layer.shape, dtype=bool)
    for rr, cc in cells:
        lethal[rr, cc] = True
    assert_array_equal(inflate(lethal, layer, geometry, radius),
                       inflate_twin(lethal, layer, geometry, radius))


@settings(max_examples=100, deadline=None)
@given(start=st.tuples(st.integers(0, 59), st.integers(0, 59)),
       ends=st.lists(st.tuples(st.integers(0, 59), st.integers(0, 59)), max_size=6),
       max_cells=st.integers(0, 90))
def test_the_clearing_kernel_clears_exactly_the_bresenham_cells(start, ends, max_cells):
    ends = np.array(ends, dtype=np.int64).reshape(-1, 2)
    lethal = np.ones((60, 60), dtype=bool)
    known_free = np.zeros((60, 60), dtype=bool)
    cleared = np.zeros((12, 12), dtype=bool)
    clear_rays(start[0], start[1], ends[:, 0].copy(), ends[:, 1].copy(), max_cells, 5, lethal,
               known_free, cleared)
    rr, cc = bresenham_cells(start[0], start[1], ends[:, 0], ends[:, 1], max_cells)
    expected = np.zeros((60, 60), dtype=bool)
    expected[rr, cc] = True
    assert_array_equal(known_free, expected)
    assert_array_equal(lethal, ~expected)
    assert_array_equal(cleared, expected.reshape(12, 5, 12, 5).any(axis=(1, 3)))


def test_a_finer_layer_keeps_a_corridor_open_that_half_metre_cells_close():
    """A 1.4 m corridor: 0.5 m lethal cells inflate across it, 0.1 m cells leave it open."""
    closed = CostmapGrid(10.0, 10.0, 0.5, (0.0, 0.0), CONFIG)
    open_ = CostmapGrid(10.0, 10.0, 0.5, (0.0, 0.0), CONFIG, layer_resolution=0.1)
    assert open_.layer_geometry.shape == (100, 100)
    # Walls at y = 4.55 and y = 5.95 seen in one scan from (1.0, 5.25), looking along +x.
    angles = np.linspace(-1.5, 1.5, 301)
    with np.errstate(divide='ignore'):
        ranges = np.where(np.sin(angles) < 0.0, (4.55 - 5.25) / np.sin(angles),
                          (5.95 - 5.25) / np.sin(angles))
    ranges = np.where(ranges < 30.0, ranges, np.inf)
    for costmap in (closed, open_):
        costmap.update((1.0, 5.25, 0.0), ranges, -1.5, 0.01, 0.1, 30.0, safety_radius=0.6)
    # The hit cells' centres: y = 4.75 and 5.75 at 0.5 m, both 0.5 m from row 10's centre
    # (y = 5.25); y = 4.55 and 5.95 at 0.1 m, 0.7 m from it.
    assert blocked_mask(closed.labels)[10, 4:16].all()
    open_blocked = blocked_mask(open_.labels)
    assert not open_blocked[10, 4:16].any()
    assert (open_.labels[10, 4:16] == CellLabel.EXPLORED).all()
    assert open_blocked[9, 4:16].all() and open_blocked[11, 4:16].all()


@pytest.mark.parametrize('layer_resolution', [0.3, 0.0, -0.1, 1.0, math.nan])
def test_layer_resolution_must_divide_the_grid(layer_resolution):
    with pytest.raises(ValueError, match='layer_resolution'):
        CostmapGrid(10.0, 10.0, 0.5, (0.0, 0.0), CONFIG, layer_resolution=layer_resolution)


def test_nav2_defaults_scaled_to_the_laser():
    config = CostmapConfig.scaled_to_laser(30.0)
    assert config.obstacle_max_range == pytest.approx(2.5 / 3.5 * 30.0)
    assert config.raytrace_max_range == pytest.approx(3.0 / 3.5 * 30.0)
    assert config.inf_is_valid
    assert CostmapConfig.scaled_to_laser(3.5).obstacle_max_range == pytest.approx(2.5)


@pytest.mark.parametrize('fields, message', [
    ({'obstacle_max_range': -1.0}, 'obstacle_max_range'),
    ({'raytrace_max_range': math.inf}, 'raytrace_max_range'),
    ({'obstacle_min_range': 3.0, 'obstacle_max_range': 2.0}, 'above obstacle_max_range'),
])
def test_bad_config_is_refused(fields, message):
    with pytest.raises(ValueError, match=message):
        CostmapConfig(**fields)


@pytest.mark.parametrize('range_max', [0.0, -3.0, math.inf, math.nan])
def test_bad_laser_range_is_refused(range_max):
    with pytest.raises(ValueError, match='range_max'):
        CostmapConfig.scaled_to_laser(range_max)


def test_bad_scan_leaves_the_costmap_unchanged():
    costmap = grid()
    beam(costmap, 1.25, 5.25, 0.0, 4.0)
    lethal = costmap.lethal.copy()
    with pytest.raises(ValueError, match='safety_radius'):
        costmap.update((1.25, 5.25, 0.0), [2.0], safety_radius=-1.0, **ONE_BEAM)
    with pytest.raises(ValueError, match='range_min'):
        costmap.update((1.25, 5.25, 0.0), [2.0], safety_radius=0.6,
                       **(ONE_BEAM | {'range_min': 5.0, 'range_max': 1.0}))
    assert_array_equal(costmap.lethal, lethal)


def test_core_module_needs_no_ros():
    code = ('import sys; import dpn_navigator.benchmark.baselines.costmap_grid; '
            "assert 'rclpy' not in sys.modules")
    subprocess.run([sys.executable, '-c', code], check=True)


@settings(max_examples=200, deadline=None)
@given(factor=st.integers(1, 6), rows=st.integers(1, 7), cols=st.integers(1, 7),
       density=st.floats(0.0, 1.0), seed=st.integers(0, 2**32 - 1))
def test_any_in_blocks_is_numpys_block_reduction(factor, rows, cols, density, seed):
    mask = np.random.default_rng(seed).random((rows * factor, cols * factor)) < density
    expected = mask.reshape(rows, factor, cols, factor).any(axis=(1, 3))
    np.testing.assert_array_equal(any_in_blocks(mask, factor), expected)


def test_any_in_blocks_refuses_a_mask_that_does_not_split():
    with pytest.raises(ValueError, match='does not split'):
        any_in_blocks(np.zeros((10, 9), dtype=bool), 2)
    with pytest.raises(ValueError, match='does not split'):
        any_in_blocks(np.zeros((10, 10), dtype=bool), 0)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), scans=st.integers(1, 8), factor=st.sampled_from([1, 5]))
def test_labels_reduce_the_whole_layer_after_windowed_updates(seed, scans, factor):
    """Labels and ``lethal_labels`` equal a whole-layer reduction after every update."""
    rng = np.random.default_rng(seed)
    costmap = CostmapGrid(20.0, 15.0, 0.5, (-2.0, 1.0), CONFIG, layer_resolution=0.5 / factor)
    rows, cols = costmap.geometry.shape
    for _ in range(scans):
        pose = (rng.uniform(-4.0, 20.0), rng.uniform(-1.0, 18.0), rng.uniform(-math.pi, math.pi))
        ranges = rng.uniform(0.2, 30.0, 64)
        ranges[rng.random(64) < 0.1] = np.inf
        costmap.update(pose, ranges, -1.5, 0.05, 0.1, 30.0, 0.6)
        lethal = costmap.lethal.reshape(rows, factor, cols, factor).any(axis=(1, 3))
        free = costmap.known_free.reshape(rows, factor, cols, factor).any(axis=(1, 3))
        blocked = inflate(costmap.lethal, costmap.layer_geometry, costmap.geometry, 0.6)
        assert_array_equal(costmap.labels, np.where(blocked, CellLabel.STEADY_OBSTACLE, np.where(
            free, CellLabel.EXPLORED, CellLabel.NON_EXPLORED)))
        assert_array_equal(costmap.lethal_labels(), np.where(
            lethal, CellLabel.STEADY_OBSTACLE, np.where(free, CellLabel.EXPLORED,
                                                        CellLabel.NON_EXPLORED)))
