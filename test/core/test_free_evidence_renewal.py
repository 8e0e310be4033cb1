"""
The free evidence's renewal (``free_evidence_renewal``): a heading error moves no walls.

A pose whose heading is off by a fixed angle places what two poses ``d`` metres apart see that
angle times ``d`` apart. Free evidence kept for good then lies under walls seen again from
farther on, and they turn mobile; renewed evidence was seen from within a few metres.
"""

import math

from dpn_navigator.core.cell_label import CellLabel
from dpn_navigator.core.grid_geometry import GridGeometry
from dpn_navigator.core.mapping.fine_evidence import FineEvidence
from dpn_navigator.core.mapping.label_grid import LabelGrid, LabelRule
from dpn_navigator.core.mapping.map_growth import GridGrowth
from dpn_navigator.core.mapping.travel_generations import TravelGenerations
from dpn_navigator.core.navigator import NavigatorConfig
import numpy as np
import pytest
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, RANGE_MAX, RANGE_MIN, ray_cast

TRUTH_RESOLUTION = 0.05
WIDTH, HEIGHT = 30.0, 8.0


def corridor(box=None):
    """
    Return a 30 m x 8 m corridor with pillars on both walls, and a 0.6 m box at ``box``.

    ``box``: the box's lower-left corner [m], or None. Returns the true occupancy, a
    (rows, cols) bool array of 5 cm pixels with its origin at (0, 0).
    """
    occupied = np.zeros((int(HEIGHT / TRUTH_RESOLUTION), int(WIDTH / TRUTH_RESOLUTION)),
                        dtype=bool)
    occupied[:6, :] = occupied[-6:, :] = True
    occupied[:, :6] = occupied[:, -6:] = True
    for x in np.arange(4.0, 27.0, 4.0):
        col = int(x / TRUTH_RESOLUTION)
        occupied[6:20, col:col + 10] = True
        occupied[-20:-6, col + 20:col + 30] = True
    if box is not None:
        col, row = (int(v / TRUTH_RESOLUTION) for v in box)
        occupied[row:row + 12, col:col + 12] = True
    return occupied


def wall_cells(occupied, geometry, reach=0.6):
    """Label cells whose centre lies within ``reach`` of a true wall pixel."""
    rows, cols = np.indices(geometry.shape)
    x, y = geometry.cell_to_world(rows.ravel(), cols.ravel())
    wall_y, wall_x = (np.argwhere(occupied) + 0.5).T * TRUTH_RESOLUTION
    near = np.zeros(x.shape, dtype=bool)
    for k in range(0, wall_x.shape[0], 4096):
        d = np.hypot(x[:, None] - wall_x[None, k:k + 4096], y[:, None] - wall_y[None, k:k + 4096])
        near |= (d <= reach).any(axis=1)
    return near.reshape(geometry.shape)


def drive_through(renewal, heading_error, box_path=None):
    """
    Drive the corridor east and back along y = 4 m, 0.2 m a scan, with the given errors.

    ``box_path`` maps a scan index to the box's lower-left corner ``(x, y)`` [m] or None (the
    box moves); returns the grid and the label cells ever labelled mobile.
    """
    config = NavigatorConfig(width=WIDTH, height=HEIGHT, free_evidence_renewal=renewal)
    grid = LabelGrid(WIDTH, HEIGHT, 0.5, (0.0, 0.0), config.label_rule())
    ever_mobile = np.zeros(grid.labels.shape, dtype=bool)
    legs = ((np.arange(2.0, 28.0, 0.2), 0.0), (np.arange(28.0, 2.0, -0.2), math.pi))
    index = 0
    for xs, yaw in legs:
        for x in xs:
            occupied = corridor(None if box_path is None else box_path(index))
            ranges = ray_cast(occupied, (x, 4.0, yaw))
            grid.update((x, 4.0, yaw + heading_error), ranges, ANGLE_MIN, ANGLE_INCREMENT,
                        RANGE_MIN, RANGE_MAX, config.safety_radius, stamp=0.2 * index)
            ever_mobile |= grid.labels == CellLabel.MOBILE_OBSTACLE
            index += 1
    return grid, ever_mobile


def test_a_one_degree_heading_error_shows_no_walls_moving_with_renewal():
    walls = wall_cells(corridor(), GridGeometry(WIDTH, HEIGHT, 0.5))
    _, kept_for_good = drive_through(0.0, math.radians(1.0))
    _, renewed = drive_through(6.0, math.radians(1.0))
    assert np.count_nonzero(kept_for_good & walls) >= 20      # 127 when measured
    assert np.count_nonzero(renewed & walls) == 0


def test_renewal_keeps_a_box_moving_in_view_mobile():
    # A 0.6 m box crosses the corridor 8-10 m ahead of the robot on its way east (exact pose):
    # the space it moves into was seen free within the last metres, so it is mobile either way.
    def box_path(index):
        return (16.0, 1.0 + 0.06 * (index - 20)) if 20 <= index < 100 else None

    found = []
    for renewal in (0.0, 6.0):
        _, ever_mobile = drive_through(renewal, 0.0, box_path)
        rows, cols = np.nonzero(ever_mobile)
        x, _ = GridGeometry(WIDTH, HEIGHT, 0.5).cell_to_world(rows, cols)
        found.append(int(np.count_nonzero((x > 13.0) & (x < 19.0))))
    assert found[0] > 0
    assert found[1] >= found[0] - 1


def evidence_scan(fine, x):
    """Fold one scan of an empty 8 m x 8 m room, laser at ``(x, 4)``, into ``fine``."""
    room = np.zeros((160, 400), dtype=bool)
    room[:2, :] = room[-2:, :] = room[:, :2] = room[:, -2:] = True
    fine.update((x, 4.0, 0.0), ray_cast(room, (x, 4.0, 0.0)), ANGLE_MIN, ANGLE_INCREMENT,
                RANGE_MIN, RANGE_MAX)


def blind_update(fine, x):
    """Move the laser to ``(x, 4)`` with a scan that marks nothing (every beam invalid)."""
    fine.update((x, 4.0, 0.0), np.full(640, np.nan), ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN,
                RANGE_MAX)


def test_fine_evidence_is_dropped_after_the_renewal_travel_and_kept_before():
    geometry = GridGeometry(20.0, 8.0, 0.5)
    point = (np.array([3.0]), np.array([4.0]))
    fine = FineEvidence(geometry, 0.1, 0.2, 20.0, renewal=4.0)
    forever = FineEvidence(geometry, 0.1, 0.2, 20.0)
    for evidence in (fine, forever):
        evidence_scan(evidence, 1.0)
    assert fine.evidence(*point)[0] and forever.evidence(*point)[0]
    for x in (2.5, 3.5, 5.5):      # 1.5 m, then 2.5 m (a new generation), then 4.5 m
        blind_update(fine, x)
        blind_update(forever, x)
        assert fine.evidence(*point)[0] == (x < 5.0)
        assert forever.evidence(*point)[0]
    assert not fine.seen_free.any() and forever.seen_free.any()
    assert fine.nbytes == 2 * forever.nbytes


def test_fine_evidence_of_both_generations_keeps_its_place_when_the_map_grows():
    geometry = GridGeometry(20.0, 8.0, 0.5)
    fine = FineEvidence(geometry, 0.1, 0.2, 20.0, renewal=4.0)
    evidence_scan(fine, 1.0)
    blind_update(fine, 3.5)                      # the first marks are now the older ones
    evidence_scan(fine, 3.5)
    before = fine.seen_free.copy()
    # 1 m below and 2 m left: 10 fine rows and 20 fine columns before the old ones.
    fine.grow(GridGrowth(below=2, left=4).geometry(geometry))
    assert np.array_equal(fine.seen_free[10:, 20:], before)
    assert not fine.seen_free[:10].any() and not fine.seen_free[:, :20].any()


def test_label_grid_evidence_is_renewed_and_reset():
    rule = LabelRule(free_evidence_radius=0.6, free_evidence_renewal=4.0)
    grid = LabelGrid(20.0, 8.0, 0.5, (0.0, 0.0), rule)
    room = np.zeros((160, 400), dtype=bool)
    room[:2, :] = room[-2:, :] = room[:, :2] = room[:, -2:] = True
    grid.update((1.0, 4.0, 0.0), ray_cast(room, (1.0, 4.0, 0.0)), ANGLE_MIN, ANGLE_INCREMENT,
                RANGE_MIN, RANGE_MAX, 0.5)
    first = grid.seen_free.copy()
    assert first.any()
    blank = np.full(640, np.nan)
    grid.update((3.5, 4.0, 0.0), blank, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, 0.5)
    # A new generation: the first scan's marks are the older ones, still there (the kernel's
    # marks and the generation's own agree).
    assert np.array_equal(grid.seen_free, first)
    grid.update((5.5, 4.0, 0.0), blank, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, 0.5)
    assert not grid.seen_free.any()
    grid.update((1.0, 4.0, 0.0), ray_cast(room, (1.0, 4.0, 0.0)), ANGLE_MIN, ANGLE_INCREMENT,
                RANGE_MIN, RANGE_MAX, 0.5)
    grid.reset()
    assert not grid.seen_free.any() and grid.nbytes == LabelGrid(
        20.0, 8.0, 0.5, (0.0, 0.0), rule).nbytes


@pytest.mark.parametrize('renewal', [-1.0, math.nan, math.inf])
def test_a_bad_renewal_is_refused(renewal):
    with pytest.raises(ValueError, match='free_evidence_renewal must be finite'):
        LabelRule(free_evidence_renewal=renewal)
    with pytest.raises(ValueError, match='renewal must be finite'):
        FineEvidence(GridGeometry(4.0, 4.0, 0.5), 0.1, 0.2, 20.0, renewal=renewal)


def test_a_generation_ends_after_its_travel_and_the_count_starts_again():
    generations = TravelGenerations(3.0)
    ends = [generations.step((x, 0.0, 0.0)) for x in (0.0, 1.0, 2.9, 3.1, 5.0, 6.2)]
    assert ends == [False, False, False, True, False, True]
    assert generations.step((6.2, 0.0)) is False        # standing still: no travel
    generations.reset()
    assert generations.step((100.0, 0.0)) is False       # no travel counted across a reset
    with pytest.raises(ValueError, match='period must be finite and > 0'):
        TravelGenerations(0.0)
