"""
The compiled label update against the numpy update it replaced, on long realistic sequences.

The hypothesis tests of ``test_label_grid.py`` hold the kernel to the literal twin on small
grids; these run many 640-beam scans of a hall with boxes that move (wanderers), under the
paper's rule and the navigator's default rule, and compare every array after every scan with
``NumpyLabelGrid`` (the numpy update and whole-grid ghost expiry of commit 83e3dc1).

"""

import math

from dpn_navigator.core.cell_label import CellLabel
from dpn_navigator.core.mapping.label_grid import LabelGrid, LabelRule, PAPER_RULE
from dpn_navigator.core.navigator import NavigatorConfig
import numpy as np
from numpy.testing import assert_array_equal
from numpy_label_grid import NumpyLabelGrid
import pytest
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, free_pose, hall, RANGE_MAX, RANGE_MIN
from scan_scenes import moving_box_world, ray_cast

TRUTH_RESOLUTION = 0.05
# dpn's rule but the rules for real lasers, which the numpy update predates (their twin is
# the literal one, test_label_grid.py).
DPN_RULE = NavigatorConfig(width=1.0, height=1.0, no_return_reach=1.0,
                           surface_time=0.0).label_rule()


def assert_same_state(fast, reference):
    assert_array_equal(fast.labels, reference.labels)
    for name in ('seen_free', 'last_hit'):
        if getattr(reference, name) is not None:
            assert_array_equal(getattr(fast, name), getattr(reference, name))
    rows, cols, cell_input = fast.last_window
    ref_rows, ref_cols, ref_input = reference.last_window
    assert (rows, cols) == (ref_rows, ref_cols)
    assert_array_equal(cell_input, ref_input)


@pytest.mark.parametrize('rule, resolution', [
    (PAPER_RULE, 0.5), (DPN_RULE, 0.5), (PAPER_RULE, 0.1), (DPN_RULE, 0.1),
    (LabelRule(free_evidence_radius=0.9, moving_object_size=1.2, mobile_expiry=0.6), 0.5)],
    ids=['paper', 'dpn', 'paper-fine', 'dpn-fine', 'wide'])
def test_kernel_equals_the_numpy_update_on_hall_sequences(rule, resolution):
    # Fine cells put many rows in each disc and band, and polygon edges shorter than a cell.
    rng = np.random.default_rng(3)
    size = 30.0 if resolution == 0.5 else 12.0
    static = hall(size, 12 if resolution == 0.5 else 3, rng, TRUTH_RESOLUTION)
    fast = LabelGrid(size, size, resolution, rule=rule)
    reference = NumpyLabelGrid(size, size, resolution, rule=rule)
    replans = 0
    stamp = 0.0
    for step in range(70):
        world = moving_box_world(static, step, 11)
        pose = free_pose(world, rng, TRUTH_RESOLUTION)
        ranges = ray_cast(world, pose, TRUTH_RESOLUTION)
        ranges[rng.random(ranges.shape[0]) < 0.02] = np.nan
        # A cross through the middle of the hall, so that the flag fires.
        middle = fast.labels.shape[0] // 2
        path = np.array([[middle, c] for c in range(2 * middle)]
                        + [[r, middle] for r in range(2 * middle)])
        # Time mostly goes forward, by up to 0.4 s; once it jumps back (a restart).
        stamp = 1.0 if step == 50 else stamp + rng.choice([0.1, 0.2, 0.4])
        args = (pose, ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, 0.6)
        want = reference.update(*args, path=path, stamp=stamp)
        got = fast.update(*args, path=path, stamp=stamp)
        assert got == want
        replans += got
        assert_same_state(fast, reference)
    assert replans > 0
    assert np.count_nonzero(fast.labels == CellLabel.STEADY_OBSTACLE) > 100
    assert np.count_nonzero(fast.seen_free if fast.seen_free is not None else 1) > 0
    if rule.moving_object_size > 0.0:
        assert np.count_nonzero(fast.labels == CellLabel.MOBILE_OBSTACLE) > 0


def test_mobile_list_follows_forgetting_and_reset():
    rule = LabelRule(mobile_expiry=1.0)
    fast = LabelGrid(10.0, 10.0, rule=rule)
    reference = NumpyLabelGrid(10.0, 10.0, rule=rule)
    ranges = np.full(640, 3.0)
    for grid in (fast, reference):
        grid.labels[2:5, 2:5] = CellLabel.EXPLORED
        grid.labels_changed()
        # Something stands in explored space: those cells become mobile.
        grid.update((3.0, 1.0, math.pi / 2), ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN,
                    RANGE_MAX, 0.6, stamp=0.0)
        grid.labels[grid.labels == CellLabel.MOBILE_OBSTACLE] = CellLabel.STEADY_OBSTACLE
        grid.labels[0, 0] = CellLabel.MOBILE_OBSTACLE          # set by hand, never hit
        grid.labels_changed()
    assert_same_state(fast, reference)
    for stamp in (0.5, 1.5, 2.5):
        for grid in (fast, reference):
            grid.update((8.0, 8.0, 0.0), ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN,
                        RANGE_MAX, 0.6, stamp=stamp)
        assert_same_state(fast, reference)
    assert fast.labels[0, 0] == CellLabel.EXPLORED
    fast.reset()
    assert not fast.labels.any() and fast._mobile_count == 0


def test_planning_masks_equal_the_full_recompute_at_every_plan(monkeypatch):
    from dpn_navigator.core.planning import planning_masks
    from dpn_navigator.core.cell_label import blocked_mask
    from dpn_navigator.core.navigator import Navigator
    from dpn_navigator.core.planning.planning_masks import touches_blocked
    from dpn_navigator.benchmark.protocol import NOT_GETTING_STUCK_OFF
    # The masks alone: without issue 31's opened stale cells and extra costs.
    config = NavigatorConfig(width=30.0, height=30.0, mobile_expiry=0.5,
                             forget_obstacles_after=1.0, **NOT_GETTING_STUCK_OFF)
    navigator = Navigator(config)
    searched = []
    real_search = planning_masks.astar_checked

    def checked_search(blocked, start, goal, cost, max_cost, cut_corners):
        # The old navigator: masks from the whole label grid, footprint cleared, then cost.
        full = blocked_mask(navigator.grid.labels)
        rows, cols, near = navigator._footprint(pose)
        full[rows, cols] &= ~near
        full[start] = False
        assert_array_equal(blocked, full)
        full_cost = config.obstacle_proximity_cost * touches_blocked(full)
        assert_array_equal(cost, full_cost)
        assert max_cost == full_cost.max()
        searched.append(start)
        return real_search(blocked, start, goal, cost, max_cost, cut_corners)

    monkeypatch.setattr(planning_masks, 'astar_checked', checked_search)
    rng = np.random.default_rng(5)
    static = hall(30.0, 12, rng, TRUTH_RESOLUTION)
    navigator.set_goal(25.0, 25.0)
    for step in range(60):
        world = moving_box_world(static, step, 2)
        pose = free_pose(world, rng, TRUTH_RESOLUTION)
        ranges = ray_cast(world, pose, TRUTH_RESOLUTION)
        navigator.step(0.3 * step, pose, ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN,
                       RANGE_MAX)
        if step % 7 == 0:
            navigator._plan(pose)                  # also right after scans, not only on flags
        if step == 30:
            navigator._spell_forgets = step % 2
            navigator._forget_unseen_obstacles(pose)
    assert len(searched) > 20


@pytest.mark.parametrize('resolution', [0.05, 0.5])
def test_edge_bands_and_discs_equal_a_test_of_every_cell(resolution):
    from dpn_navigator.core._kernels import raster
    from dpn_navigator.core.grid_geometry import squared_bound
    rng = np.random.default_rng(8)
    n_rows, n_cols, row0, col0 = 40, 50, 7, 3
    x0, y0 = -1.3, 0.4
    cx = x0 + (np.arange(col0, col0 + n_cols) + 0.5) * resolution
    cy = y0 + (np.arange(row0, row0 + n_rows) + 0.5) * resolution
    cx, cy = np.meshgrid(cx, cy)
    low = np.array([x0 + col0 * resolution, y0 + row0 * resolution])
    span = np.array([n_cols, n_rows]) * resolution
    radius = 0.6
    bound = squared_bound(radius)
    for case in range(300):
        # Edges of every length, from a tenth of a cell to across the window; every third
        # along an axis, every third with both ends on a quarter-cell lattice (so that cell
        # centres fall exactly on a band's sides and ends).
        a = low + rng.uniform(-0.2, 1.2, 2) * span
        b = a + rng.normal(0.0, 1.0, 2) * resolution * rng.choice([0.1, 1.0, 10.0])
        if case % 3 == 1:
            axis = (case // 3) % 2
            b[axis] = a[axis]
        elif case % 3 == 2:
            origin = np.array([x0, y0])
            quarter = resolution / 4
            a = origin + np.round((a - origin) / quarter) * quarter
            b = origin + np.round((b - origin) / quarter) * quarter
            if case % 2:
                b[case % 4 // 2] = a[case % 4 // 2]
            if np.array_equal(a, b):
                continue
        xs, ys = np.array([a[0], b[0]]), np.array([a[1], b[1]])
        band = np.zeros((n_rows, n_cols), dtype=bool)
        raster.mark_edge_bands(band, row0, col0, x0, y0, resolution, xs, ys, radius)
        ex, ey = b[0] - a[0], b[1] - a[1]
        length2 = ex * ex + ey * ey
        dot = (cx - a[0]) * ex + (cy - a[1]) * ey
        cross = (cx - a[0]) * ey - (cy - a[1]) * ex
        want = (dot >= 0.0) & (dot <= length2) & (np.abs(cross) / np.sqrt(length2) <= radius)
        assert_array_equal(band, want)
        # What the update marks for its free evidence: the band less some cells within the
        # radius of the ends (their discs are marked besides), never any other cell.
        uncovered = np.zeros((n_rows, n_cols), dtype=bool)
        raster.mark_uncovered_edge_bands(uncovered, row0, col0, x0, y0, resolution, xs,
                                         ys, radius)
        near_ends = np.zeros((n_rows, n_cols), dtype=bool)
        for end_x, end_y in ((a[0], a[1]), (b[0], b[1])):
            dx, dy = cx - end_x, cy - end_y
            near_ends |= dx * dx + dy * dy <= bound
        assert not (uncovered & ~want).any()
        assert not (want & ~near_ends & ~uncovered).any()
        disc = np.zeros((n_rows, n_cols), dtype=bool)
        raster.mark_discs(disc, True, xs, ys, 1, np.zeros(0, dtype=bool), row0, col0,
                          x0, y0, resolution, radius, bound, np.zeros((0, 2), np.int64))
        dx, dy = a[0] - cx, a[1] - cy
        assert_array_equal(disc, np.sqrt(dx * dx + dy * dy) <= radius)


@pytest.mark.parametrize('resolution, x0, y0', [(0.1, -2.15, 0.7), (0.125, -2.25, 0.75),
                                                (0.5, -2.25, 0.75)])
def test_small_discs_and_their_evidence_equal_a_test_of_every_cell(resolution, x0, y0):
    # Discs of up to three cells are marked from a box around their point's cell: radii from
    # a fifth of a cell to three, points on and off the window and on lattices of half and
    # eighth cells (with dyadic cells, centres then lie exactly on a disc's edge), some values
    # and extents.
    from dpn_navigator.core._kernels import motion_evidence, raster
    from dpn_navigator.core.grid_geometry import squared_bound
    rng = np.random.default_rng(5)
    n_rows, n_cols, row0, col0 = 24, 31, 4, 9
    cx = x0 + (np.arange(col0, col0 + n_cols) + 0.5) * resolution
    cy = y0 + (np.arange(row0, row0 + n_rows) + 0.5) * resolution
    cx, cy = np.meshgrid(cx, cy)
    low = np.array([x0 + col0 * resolution, y0 + row0 * resolution])
    span = np.array([n_cols, n_rows]) * resolution
    marked_cells = cells_on_edges = found = 0
    for case in range(600):
        radius = float(rng.choice([0.2, 0.5, 1.0, 1.3, 2.0, 2.5, 3.0])) * resolution
        bound = squared_bound(radius)
        count = int(rng.integers(1, 6))
        points = low + rng.uniform(-0.15, 1.15, (count, 2)) * span
        if case % 2:
            origin = np.array([x0, y0])
            step = resolution / (2 if case % 4 == 1 else 8)
            points = origin + np.round((points - origin) / step) * step
        selected = rng.random(count) < 0.7 if case % 3 == 0 else np.zeros(0, dtype=bool)
        xs, ys = points[:, 0].copy(), points[:, 1].copy()
        want = np.zeros((n_rows, n_cols), dtype=bool)
        for k in range(count):
            if selected.size and not selected[k]:
                continue
            dx, dy = cx - xs[k], cy - ys[k]
            want |= dx * dx + dy * dy <= bound
        mark = np.zeros((n_rows, n_cols), dtype=np.uint8)
        extent = np.empty((n_rows, 2), dtype=np.int64)
        extent[:, 0], extent[:, 1] = n_cols, 0
        raster.mark_discs(mark, 3, xs, ys, count, selected, row0, col0, x0, y0,
                          resolution, radius, bound, extent)
        assert_array_equal(mark, np.where(want, 3, 0))
        rows_marked = want.any(axis=1)
        columns = np.arange(n_cols)
        assert_array_equal(extent[rows_marked, 0],
                           [columns[row].min() for row in want[rows_marked]])
        assert_array_equal(extent[rows_marked, 1],
                           [columns[row].max() + 1 for row in want[rows_marked]])
        assert (extent[~rows_marked, 0] == n_cols).all()
        marked_cells += int(want.sum())
        # The evidence of hits: a True cell of the whole grid within the radius.
        grid_free = rng.random((row0 + n_rows + 3, col0 + n_cols + 2)) < 0.1
        gx = x0 + (np.arange(grid_free.shape[1]) + 0.5) * resolution
        gy = y0 + (np.arange(grid_free.shape[0]) + 0.5) * resolution
        gx, gy = np.meshgrid(gx, gy)
        # Discs of any size are searched in their box: the radius and 3.7 times it.
        for evidence_radius in (radius, 3.7 * radius):
            evidence_bound = squared_bound(evidence_radius)
            evidence = motion_evidence.hit_evidence(grid_free, xs, ys, x0, y0, resolution,
                                                    evidence_radius, evidence_bound)
            expected = [bool((grid_free
                              & ((gx - x) ** 2 + (gy - y) ** 2 <= evidence_bound)).any())
                        for x, y in zip(xs, ys)]
            assert evidence.tolist() == expected
            found += sum(expected)
        on_edge = [(cx - x) ** 2 + (cy - y) ** 2 == bound for x, y in zip(xs, ys)]
        cells_on_edges += int(np.logical_or.reduce(on_edge).sum())
    assert marked_cells > 1000 and 300 < found < 2 * 600 * 5 - 300
    if resolution != 0.1:
        assert cells_on_edges > 20, cells_on_edges


@pytest.mark.parametrize('resolution', [0.05, 0.5])
def test_uncovered_bands_of_short_edges_hold_every_band_cell_beyond_the_ends(resolution):
    # Edges no longer than the radius are searched only along two thin strips beside them:
    # many such edges, so that cell centres fall in those strips, some exactly on a band side.
    from dpn_navigator.core._kernels import raster
    from dpn_navigator.core.grid_geometry import squared_bound
    rng = np.random.default_rng(11)
    n_rows, n_cols, row0, col0 = 30, 30, 2, 5
    x0, y0 = 0.35, -0.8
    cx = x0 + (np.arange(col0, col0 + n_cols) + 0.5) * resolution
    cy = y0 + (np.arange(row0, row0 + n_rows) + 0.5) * resolution
    cx, cy = np.meshgrid(cx, cy)
    centre = np.array([x0 + (col0 + n_cols / 2) * resolution,
                       y0 + (row0 + n_rows / 2) * resolution])
    strips = 0
    for case in range(4000):
        radius = float(rng.choice([0.6, 0.45, 1.1]))
        bound = squared_bound(radius)
        a = centre + rng.uniform(-0.6, 0.6, 2) * n_rows * resolution
        angle = rng.uniform(0.0, 2.0 * np.pi) if case % 4 else rng.integers(8) * np.pi / 4
        length = radius * rng.uniform(0.01, 1.0)
        b = a + length * np.array([np.cos(angle), np.sin(angle)])
        if case % 2:
            a = np.round(a / resolution * 8) * resolution / 8
            b = np.round(b / resolution * 8) * resolution / 8
        if np.array_equal(a, b):
            continue
        ex, ey = b[0] - a[0], b[1] - a[1]
        length2 = ex * ex + ey * ey
        dot = (cx - a[0]) * ex + (cy - a[1]) * ey
        cross = (cx - a[0]) * ey - (cy - a[1]) * ex
        band = (dot >= 0.0) & (dot <= length2) & (np.abs(cross) / np.sqrt(length2) <= radius)
        near_ends = np.zeros_like(band)
        for end_x, end_y in (a, b):
            dx, dy = cx - end_x, cy - end_y
            near_ends |= dx * dx + dy * dy <= bound
        marked = np.zeros((n_rows, n_cols), dtype=bool)
        raster.mark_uncovered_edge_bands(marked, row0, col0, x0, y0, resolution,
                                         np.array([a[0], b[0]]), np.array([a[1], b[1]]),
                                         radius)
        assert not (marked & ~band).any()
        assert not (band & ~near_ends & ~marked).any()
        strips += int((band & ~near_ends).any())
    assert strips > 100                 # the strips held cells often enough to be tested
