"""ObstacleConfirmations: when hits last confirmed each cell, stale cells, dropping them."""

import math

from dpn_navigator.core import CellLabel, LabelGrid
from dpn_navigator.core.cell_label import ScanInput
from dpn_navigator.core.mapping.stale_obstacles import ObstacleConfirmations
import numpy as np


def window(inputs, row=0, col=0):
    inputs = np.asarray(inputs, dtype=np.uint8)
    return (slice(row, row + inputs.shape[0]), slice(col, col + inputs.shape[1]), inputs)


def test_hits_confirm_cells_and_count():
    confirmations = ObstacleConfirmations((3, 4))
    confirmations.observe(window([[ScanInput.HIT, ScanInput.INSIDE]], 1, 1), 2.0)
    confirmations.observe(window([[ScanInput.HIT, ScanInput.NONE]], 1, 1), 5.0)
    assert confirmations.confirmed[1, 1] == 5.0
    assert confirmations.hits[1, 1] == 2
    assert confirmations.confirmed[1, 2] == -math.inf and confirmations.hits[1, 2] == 0


def test_stale_cells_are_obstacles_unconfirmed_for_the_age():
    confirmations = ObstacleConfirmations((1, 4))
    labels = np.array([[CellLabel.STEADY_OBSTACLE, CellLabel.MOBILE_OBSTACLE,
                        CellLabel.STEADY_OBSTACLE, CellLabel.EXPLORED]], dtype=np.uint8)
    confirmations.observe(window([[ScanInput.HIT] * 4]), 0.0)
    confirmations.observe(window([[ScanInput.NONE, ScanInput.NONE, ScanInput.HIT,
                                   ScanInput.NONE]]), 4.0)
    assert confirmations.stale(labels, 6.0, 6.0).tolist() == [[True, True, False, False]]
    assert not confirmations.stale(labels, 5.9, 6.0).any()


def test_time_going_back_makes_nothing_stale():
    confirmations = ObstacleConfirmations((1, 2))
    confirmations.observe(window([[ScanInput.HIT, ScanInput.NONE]]), 100.0)
    confirmations.observe(window([[ScanInput.NONE, ScanInput.NONE]]), 1.0)
    labels = np.full((1, 2), CellLabel.STEADY_OBSTACLE, dtype=np.uint8)
    assert confirmations.stale(labels, 1.0, 0.5).tolist() == [[False, True]]


def test_drop_sends_cells_back_to_what_the_evidence_says():
    grid = LabelGrid(2.0, 1.0, 0.5)
    grid.seen_free = np.zeros(grid.geometry.shape, dtype=bool)
    grid.seen_free[0, 1] = True
    grid.labels[0, :3] = [CellLabel.STEADY_OBSTACLE, CellLabel.MOBILE_OBSTACLE,
                          CellLabel.EXPLORED]
    confirmations = ObstacleConfirmations(grid.geometry.shape)
    assert confirmations.drop(grid, [(0, 0), (0, 1), (0, 2)]) == 2
    assert grid.labels[0, :3].tolist() == [CellLabel.NON_EXPLORED, CellLabel.EXPLORED,
                                           CellLabel.EXPLORED]
    assert confirmations.dropped == 2
    assert confirmations.drop(grid, np.zeros((0, 2), dtype=int)) == 0
