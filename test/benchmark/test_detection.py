"""Tests of the detection measures: ground truth, per-scan counts, replan causes, report."""

import math

from dpn_navigator.benchmark.detection import DetectionMeter, ratio
from dpn_navigator.benchmark.detection_report import (detection_markdown, detection_stats,
                                                      save_detection_figure)
from dpn_navigator.benchmark.ground_truth import near_any, wall_belt, wanderer_hit_points
from dpn_navigator.core import CellLabel, GridGeometry, ReplanCause
from dpn_navigator.core.cell_label import ScanInput
from dpn_navigator.core.scan_polygon import ScanPoints
from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
from numpy.testing import assert_array_equal
import pytest
from scan_features import scan_input

N, E, S, M = (CellLabel.NON_EXPLORED, CellLabel.EXPLORED, CellLabel.STEADY_OBSTACLE,
              CellLabel.MOBILE_OBSTACLE)
NONE, INSIDE, HIT = ScanInput.NONE, ScanInput.INSIDE, ScanInput.HIT
#: A 4 x 6 grid of 1 m cells; cell (row, col) has its centre at (col + 0.5, row + 0.5).
GRID = GridGeometry(6.0, 4.0, 1.0)
NO_HITS = (np.zeros(0), np.zeros(0))


def meter(belt=None, wanderer_radius=0.5, safety_radius=0.5):
    """Return a meter on GRID: R + r = 1 m by default; no wall unless ``belt`` is given."""
    if belt is None:
        belt = np.zeros(GRID.shape, dtype=bool)
    return DetectionMeter(GRID, belt, wanderer_radius, safety_radius)


def whole_window(cell_input):
    """Return a `LabelGrid.last_window` covering all of GRID."""
    return (slice(0, 4), slice(0, 6), np.asarray(cell_input, dtype=np.uint8))


# -- ground truth -------------------------------------------------------------------------


def test_wall_belt_is_the_cells_within_r_of_a_wall_pixel():
    truth_geometry = GridGeometry(6.0, 4.0, 0.5)            # 8 x 12 pixels of 0.5 m
    truth = np.zeros(truth_geometry.shape, dtype=bool)
    truth[4, 6] = True                                      # the square [3, 3.5] x [2, 2.5]
    # r = 0.5: centres within 0.5 m of that square: (3.5, 2.5) in it, (2.5, 2.5) exactly
    # 0.5 m left of it and (3.5, 1.5) exactly 0.5 m below; (2.5, 1.5) is 0.71 m from its
    # corner and (4.5, 2.5) 1 m away.
    expected = np.zeros(GRID.shape, dtype=bool)
    expected[2, 3] = True
    assert_array_equal(wall_belt(truth, truth_geometry, GRID, 0.49), expected)
    expected[2, 2] = expected[1, 3] = True
    assert_array_equal(wall_belt(truth, truth_geometry, GRID, 0.5), expected)
    assert_array_equal(wall_belt(np.zeros((8, 12), bool), truth_geometry, GRID, 0.5),
                       np.zeros(GRID.shape, dtype=bool))


@pytest.mark.parametrize(('truth', 'radius', 'message'), [
    (np.zeros((3, 3), bool), 0.5, 'shape'),
    (np.zeros((8, 12), bool), -0.1, 'safety_radius'),
    (np.zeros((8, 12), bool), math.nan, 'safety_radius'),
])
def test_wall_belt_errors(truth, radius, message):
    with pytest.raises(ValueError, match=message):
        wall_belt(truth, GridGeometry(6.0, 4.0, 0.5), GRID, radius)


def test_near_any_counts_the_reach_itself_and_nothing_without_centres():
    x = np.array([0.0, 1.0, 1.5])
    assert_array_equal(near_any(x, np.zeros(3), [[0.0, 0.0]], 1.0), [True, True, False])
    assert_array_equal(near_any(x, np.zeros(3), np.zeros((0, 2)), 1.0), [False] * 3)


def test_wanderer_hit_points_keep_only_valid_returns_on_wanderers():
    ranges = np.array([2.0, 2.0, np.inf, 0.05, 2.0])
    beam_wanderer = np.array([-1, 0, 1, 0, 1])
    hits_x, hits_y = wanderer_hit_points((1.0, 1.0, 0.0), ranges, -math.pi / 2, math.pi / 4,
                                         0.1, 30.0, beam_wanderer)
    # Beams 1 (-45 degrees) and 4 (+90 degrees); beam 2 has no return, beam 3 is too short.
    np.testing.assert_allclose(hits_x, [1.0 + math.sqrt(2.0), 1.0], atol=1e-12)
    np.testing.assert_allclose(hits_y, [1.0 - math.sqrt(2.0), 3.0], atol=1e-12)
    with pytest.raises(ValueError, match='beam_wanderer'):
        wanderer_hit_points((1.0, 1.0, 0.0), ranges, 0.0, 0.1, 0.1, 30.0, beam_wanderer[:2])


# -- per-scan measures --------------------------------------------------------------------


def test_precision_counts_visible_mobile_cells_near_a_wanderer():
    labels = np.array([[M, M, E, E, E, M],
                       [E, E, E, E, E, E],
                       [E, E, E, E, E, E],
                       [M, E, E, E, E, M]], dtype=np.uint8)
    cell_input = np.full(GRID.shape, INSIDE)
    cell_input[labels == M] = HIT
    cell_input[3, 5] = NONE                       # out of view: not counted
    m = meter()
    # A wanderer at (0.5, 0.5): (0, 0) is 0 m away, (0, 1) exactly R + r = 1 m; (0, 5) and
    # (3, 0) are far. Visible mobile cells: (0, 0), (0, 1), (0, 5), (3, 0).
    m.record_scan(labels, whole_window(cell_input), [[0.5, 0.5]], NO_HITS)
    result = m.result()
    assert (result.mobile_visible, result.mobile_visible_true) == (4, 2)
    assert result.mobile_precision == 0.5
    # Over every mobile cell, in view or not: (3, 5) is a ghost out of view and counts.
    assert (result.mobile_all, result.mobile_all_true) == (5, 2)
    assert result.mobile_precision_all == pytest.approx(2 / 5)
    # Pooled over scans: a second scan with no wanderer adds 4 visible, 0 true.
    m.record_scan(labels, whole_window(cell_input), np.zeros((0, 2)), NO_HITS)
    assert m.result().mobile_precision == pytest.approx(2 / 8)


def test_precision_is_undefined_without_visible_mobile_cells():
    m = meter()
    labels = np.full(GRID.shape, M, dtype=np.uint8)
    m.record_scan(labels, whole_window(np.zeros(GRID.shape)), [[0.5, 0.5]], NO_HITS)
    m.record_scan(labels, (slice(0, 0), slice(0, 0), np.zeros((0, 0), np.uint8)), [], NO_HITS)
    result = m.result()
    assert result.scans == 2 and result.mobile_visible == 0
    assert result.mobile_precision is None and result.wanderer_hit_recall is None
    assert result.wall_mobile_share is None
    assert result.as_row()['mobile_precision'] is None


def test_recall_counts_the_wanderers_f1_cells_off_walls_labelled_mobile():
    belt = np.zeros(GRID.shape, dtype=bool)
    belt[2, 2] = True
    m = meter(belt)
    # One hit at (2.0, 2.0), r = 0.5: no centre within 0.5 m (the four around are 0.707 m
    # away). A hit at (2.5, 2.2): cell (2, 2) (0.3 m, but in a wall belt) and (1, 2) (0.7 m:
    # no). A hit at (4.5, 1.5): cell (1, 4), labelled steady.
    labels = np.full(GRID.shape, E, dtype=np.uint8)
    labels[2, 2] = M
    labels[1, 4] = S
    hits = (np.array([2.0, 2.5, 4.5]), np.array([2.0, 2.2, 1.5]))
    m.record_scan(labels, whole_window(np.full(GRID.shape, INSIDE)), [[3.0, 2.0]], hits)
    result = m.result()
    assert (result.wanderer_hit_cells, result.wanderer_hit_cells_mobile) == (1, 0)
    # The cell in the wall belt is reported apart, not dropped: (2, 2), labelled mobile.
    assert (result.wanderer_hit_cells_near_wall,
            result.wanderer_hit_cells_near_wall_mobile) == (1, 1)
    assert result.wanderer_hit_recall_near_wall == 1.0
    labels[1, 4] = M
    m.record_scan(labels, whole_window(np.full(GRID.shape, INSIDE)), [[3.0, 2.0]], hits)
    assert m.result().wanderer_hit_recall == 0.5


@settings(max_examples=60, deadline=None)
@given(hits=st.lists(st.tuples(st.floats(-1.0, 7.0), st.floats(-1.0, 5.0)), max_size=6),
       radius=st.sampled_from([0.0, 0.3, 0.5, 0.6, 1.0, 1.5]))
def test_f1_cells_are_the_cores_f1_cells(hits, radius):
    # The oracle: the core's own scan_input with these hits and no polygon area.
    hits_x = np.array([h[0] for h in hits], dtype=np.float64)
    hits_y = np.array([h[1] for h in hits], dtype=np.float64)
    geometry = GridGeometry(6.0, 4.0, 0.5)
    m = DetectionMeter(geometry, np.zeros(geometry.shape, bool), 0.5, radius)
    rr, cc = m.f1_cells(hits_x, hits_y)
    mine = np.zeros(geometry.shape, dtype=bool)
    mine[rr, cc] = True
    points = ScanPoints(np.zeros(1), np.zeros(1), hits_x, hits_y, np.arange(len(hits)))
    core = scan_input(geometry, slice(0, geometry.rows), slice(0, geometry.cols), points,
                      radius) == HIT
    assert_array_equal(mine, core)


def test_wall_cells_ever_mobile_need_no_wanderer_near_and_count_once():
    belt = np.zeros(GRID.shape, dtype=bool)
    belt[0, :] = True                             # a wall along the bottom row
    m = meter(belt)
    labels = np.full(GRID.shape, E, dtype=np.uint8)
    labels[0, 0] = labels[0, 4] = labels[0, 5] = M
    cell_input = np.full(GRID.shape, NONE)
    cell_input[0, :4] = HIT                       # sees (0, 0)..(0, 3): (0, 4), (0, 5) unseen
    # A wanderer at (0.5, 1.5) explains (0, 0), 1 m away.
    for _ in range(2):
        m.record_scan(labels, whole_window(cell_input), [[0.5, 1.5]], NO_HITS)
    result = m.result()
    assert (result.wall_cells_seen, result.wall_cells_ever_mobile) == (4, 0)
    # The wanderer leaves: (0, 0) is now a wall cell labelled mobile with no one near.
    m.record_scan(labels, whole_window(cell_input), [[5.5, 3.5]], NO_HITS)
    m.record_scan(labels, whole_window(cell_input), np.zeros((0, 2)), NO_HITS)
    result = m.result()
    assert (result.wall_cells_seen, result.wall_cells_ever_mobile) == (4, 1)
    assert result.wall_mobile_share == 0.25


def test_ghosts_are_obstacles_no_wall_and_no_wanderer_explains():
    belt = np.zeros(GRID.shape, dtype=bool)
    belt[:, 0] = True                             # a wall along the left column
    labels = np.array([[M, E, E, E, E, S],
                       [S, E, E, E, E, E],
                       [E, E, M, E, E, M],
                       [E, E, E, S, E, M]], dtype=np.uint8)
    m = meter(belt)
    # A wanderer at (5.5, 2.5) explains (2, 5) and (3, 5) (1 m away); (0, 0), (1, 0) are wall.
    assert m.ghosts(labels, [[5.5, 2.5]]) == (1, 2)     # mobile (2, 2); steady (0, 5), (3, 3)
    assert m.ghosts(labels, np.zeros((0, 2))) == (3, 2)
    assert m.ghosts(np.full(GRID.shape, E, np.uint8), [[5.5, 2.5]]) == (0, 0)
    # Only out-of-view cells here: ghosts are counted over the whole grid, not the window.
    m.record_scan(labels, whole_window(np.zeros(GRID.shape)), [[5.5, 2.5]], NO_HITS)
    m.record_scan(labels, whole_window(np.zeros(GRID.shape)), np.zeros((0, 2)), NO_HITS)
    labels[2, 2] = E
    m.record_scan(labels, whole_window(np.zeros(GRID.shape)), [[5.5, 2.5]], NO_HITS)
    result = m.result()
    assert result.mobile_ghosts_mean == pytest.approx((1 + 3 + 0) / 3)
    assert result.mobile_ghost_scan_share == pytest.approx(2 / 3)
    assert result.steady_ghosts_mean == 2.0 and result.steady_ghost_scan_share == 1.0
    assert (result.mobile_ghosts_end, result.steady_ghosts_end) == (0, 2)


def test_replans_by_cause():
    m = meter()
    path = np.array([[1, 1], [1, 2], [1, 3], [1, 4]])
    before = np.array([E, E, N, E], dtype=np.uint8)
    labels = np.full(GRID.shape, E, dtype=np.uint8)
    labels[1, 3] = S                              # (1, 3) turned obstacle, centre (3.5, 1.5)
    m.record_replan(ReplanCause.FLAG, path, before, labels, [[3.5, 2.5]])      # 1 m: wanderer
    m.record_replan(ReplanCause.FLAG, path, before, labels, [[0.5, 3.5]])      # far: wall
    m.record_replan(ReplanCause.FLAG, path, before, labels, np.zeros((0, 2)))  # none: wall
    # (1, 1) was blocked already and stays so: it did not turn, so it explains nothing.
    labels[1, 1] = M
    m.record_replan(ReplanCause.FLAG, path, np.array([M, E, N, E], np.uint8), labels,
                    [[1.5, 1.5]])
    m.record_replan(ReplanCause.NO_PATH_RETRY, None, None, labels, [])
    m.record_replan(ReplanCause.OTHER, path, before, labels, [])
    m.record_replan(ReplanCause.NONE, path, before, labels, [])
    result = m.result()
    assert (result.replans_wall, result.replans_wanderer, result.replans_no_path_retry,
            result.replans_other) == (3, 1, 1, 1)


def test_meter_refuses_a_belt_of_another_shape():
    with pytest.raises(ValueError, match='wall_belt has shape'):
        DetectionMeter(GRID, np.zeros((2, 2), bool), 0.5, 0.5)


def test_ratio_is_none_when_undefined():
    assert ratio(1, 4) == 0.25 and ratio(0, 0) is None


# -- report -------------------------------------------------------------------------------


def detection_row(wanderers, scans, visible, true, **extra):
    """Return a log row with detection columns (other measures zero)."""
    row = {'wanderers': wanderers, 'scans': scans, 'mobile_visible': visible,
           'mobile_visible_true': true, 'wanderer_hit_cells': 0, 'wanderer_hit_cells_mobile': 0,
           'wall_cells_seen': 10, 'wall_cells_ever_mobile': 1, 'mobile_ghosts_mean': 0.0,
           'steady_ghosts_mean': 0.0, 'mobile_ghost_scan_share': 0.0,
           'steady_ghost_scan_share': 0.0, 'mobile_ghosts_end': 0, 'steady_ghosts_end': 0,
           'replans_wall': 1, 'replans_wanderer': 2, 'replans_no_path_retry': 0,
           'replans_other': 1, 'wall_time': 10.0, 'detection_wall_time': 0.5}
    row.update(extra)
    return row


def test_detection_stats_pool_counts_and_weigh_ghosts_by_scans():
    rows = [detection_row(5, 100, 10, 9, mobile_ghosts_mean=1.0, wanderer_hit_cells=4,
                          wanderer_hit_cells_mobile=1),
            detection_row(5, 300, 90, 0, mobile_ghosts_mean=3.0),
            detection_row(5, None, None, None)]   # an episode without the measures
    stats = detection_stats(rows)
    assert stats.episodes == 2 and stats.scans == 400
    assert stats.precision == pytest.approx(9 / 100)   # pooled, not (0.9 + 0.0) / 2
    assert stats.recall == 0.25 and stats.wall_mobile_share == pytest.approx(2 / 20)
    assert stats.mobile_ghosts == pytest.approx((100 * 1.0 + 300 * 3.0) / 400)
    assert stats.replans == {'wall': 1.0, 'wanderer': 2.0, 'no_path_retry': 0.0, 'other': 1.0}
    assert stats.cost_share == pytest.approx(0.05)
    assert detection_stats(rows[2:]) is None


def test_detection_table_and_figure(tmp_path):
    rows = [detection_row(0, 100, 0, 0), detection_row(5, 100, 10, 5)]
    text = detection_markdown({'paper': rows})
    assert '| paper | 0 | 1 | - | - | 10.0 |' in text        # undefined ratios: '-'
    assert '| paper | 5 | 1 | 0.50 | - | 10.0 | 0.0 (0) |' in text
    assert '1.0 / 2.0 / 0.0 / 1.0 | 5.0 |' in text
    assert 'No episode with detection measures.' in detection_markdown(
        {'dpn': [detection_row(0, None, None, None)]})
    save_detection_figure(tmp_path / 'detection.png', {'paper': rows, 'dpn': rows})
    assert (tmp_path / 'detection.png').read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    with pytest.raises(ValueError, match='no episodes'):
        save_detection_figure(tmp_path / 'none.png', {'dpn': []})
