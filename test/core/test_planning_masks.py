"""Tests of the compiled refresh of core.planning_masks against the whole-grid numpy masks."""

from dpn_navigator.core.cell_label import blocked_mask, CellLabel
from dpn_navigator.core.planning.planning_masks import (recost_around, refresh_blocked,
                                                        touches_blocked)
from hypothesis import given, strategies as st
import numpy as np
from numpy.testing import assert_array_equal
import pytest


@given(st.data())
def test_refresh_and_recost_equal_the_whole_grid_masks(data):
    shape = data.draw(st.tuples(st.integers(1, 9), st.integers(1, 80)))
    labels = np.zeros(shape, dtype=np.uint8)
    blocked = np.zeros(shape, dtype=bool)
    cost = np.zeros(shape)
    costly = 0
    for _ in range(data.draw(st.integers(1, 5))):
        r0, r1 = sorted(data.draw(st.tuples(st.integers(0, shape[0]),
                                            st.integers(0, shape[0]))))
        c0, c1 = sorted(data.draw(st.tuples(st.integers(0, shape[1]),
                                            st.integers(0, shape[1]))))
        window = labels[r0:r1, c0:c1]
        window[...] = np.reshape(data.draw(st.lists(st.integers(0, 3), min_size=window.size,
                                                    max_size=window.size)), window.shape)
        flipped = refresh_blocked(labels, blocked, slice(r0, r1), slice(c0, c1))
        # Only the window is refreshed, and labels changed only there.
        assert_array_equal(blocked, blocked_mask(labels))
        before = blocked.copy()
        before.ravel()[flipped] = ~before.ravel()[flipped]
        assert np.count_nonzero(before != blocked) == flipped.size
        costly += recost_around(blocked, cost, flipped, 2.5)
        assert_array_equal(cost, 2.5 * touches_blocked(blocked))
        assert costly == np.count_nonzero(cost)


def test_an_unchanged_window_flips_nothing():
    labels = np.full((3, 70), CellLabel.STEADY_OBSTACLE, dtype=np.uint8)
    blocked = np.ones((3, 70), dtype=bool)
    assert refresh_blocked(labels, blocked, slice(0, 3), slice(0, 70)).size == 0
    assert refresh_blocked(labels, blocked, slice(2, 1), slice(0, 70)).size == 0


@pytest.mark.parametrize('labels, blocked, message', [
    (np.zeros((2, 3), dtype=np.uint8), np.zeros((3, 2), dtype=bool), 'for a mask of'),
    (np.zeros((2, 2), dtype=np.uint8), np.zeros((2, 2), dtype=np.uint8), 'ndarray of bool'),
    (np.zeros((4, 2), dtype=np.uint8), np.zeros((2, 4), dtype=bool).T, 'C-contiguous'),
])
def test_refresh_bad_arrays_raise(labels, blocked, message):
    with pytest.raises(ValueError, match=message):
        refresh_blocked(labels, blocked, slice(0, 1), slice(0, 1))


@pytest.mark.parametrize('cost, cells, message', [
    (np.zeros((2, 2), dtype=np.float32), [0], 'must be arrays of one shape'),
    (np.zeros((2, 3)), [0], 'must be arrays of one shape'),
    (np.zeros((2, 2)), [4], 'flat indices into a grid of'),
    (np.zeros((2, 2)), [-1], 'flat indices into a grid of'),
])
def test_recost_bad_arrays_raise(cost, cells, message):
    with pytest.raises(ValueError, match=message):
        recost_around(np.zeros((2, 2), dtype=bool), cost, cells, 1.0)
