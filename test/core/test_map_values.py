"""Tests of core.map_values: the compiled box refresh against the numpy conversion."""

from dpn_navigator.core.cell_label import CellLabel, OCCUPANCY_VALUE
from dpn_navigator.core.mapping.map_values import MapValues
from hypothesis import given, strategies as st
import numpy as np
from numpy.testing import assert_array_equal
import pytest

MOBILE_100 = np.array([-1, 0, 100, 100], dtype=np.int8)     # mobile and steady alike


def numpy_refresh(values, labels, rows, cols, table):
    """Convert, compare and write the box with numpy; return the changed box (or None)."""
    fresh = np.take(table, labels[rows, cols])
    changed = fresh != values[rows, cols]
    values[rows, cols] = fresh
    if not changed.any():
        return None
    changed_rows = np.flatnonzero(changed.any(axis=1))
    changed_cols = np.flatnonzero(changed.any(axis=0))
    return (slice(rows.start + changed_rows[0], rows.start + changed_rows[-1] + 1),
            slice(cols.start + changed_cols[0], cols.start + changed_cols[-1] + 1))


@given(st.data(), st.sampled_from([OCCUPANCY_VALUE, MOBILE_100]))
def test_refresh_equals_the_numpy_conversion(data, table):
    shape = data.draw(st.tuples(st.integers(1, 9), st.integers(1, 9)))
    labels = np.full(shape, CellLabel.NON_EXPLORED, dtype=np.uint8)
    values = np.zeros(shape, dtype=np.int8)
    twin = np.full(shape, table[CellLabel.NON_EXPLORED], dtype=np.int8)
    map_values = MapValues(values, table)
    assert_array_equal(values, twin)
    for _ in range(data.draw(st.integers(1, 6))):
        r0, r1 = sorted(data.draw(st.tuples(st.integers(0, shape[0]),
                                            st.integers(0, shape[0]))))
        c0, c1 = sorted(data.draw(st.tuples(st.integers(0, shape[1]),
                                            st.integers(0, shape[1]))))
        # Labels change anywhere; only the box given is refreshed.
        flat = data.draw(st.lists(st.integers(0, 3), min_size=labels.size,
                                  max_size=labels.size))
        keep = data.draw(st.lists(st.booleans(), min_size=labels.size, max_size=labels.size))
        labels[...] = np.where(np.reshape(keep, shape), labels,
                               np.reshape(flat, shape).astype(np.uint8))
        rows, cols = slice(r0, r1), slice(c0, c1)
        box = map_values.refresh(labels, rows, cols)
        want = numpy_refresh(twin, labels, rows, cols, table)
        if want is None:
            assert box == (slice(0, 0), slice(0, 0))
        else:
            assert box == want
        assert_array_equal(values, twin)


def test_same_value_labels_change_no_value():
    values = np.zeros((2, 3), dtype=np.int8)
    map_values = MapValues(values, MOBILE_100)
    labels = np.full((2, 3), CellLabel.STEADY_OBSTACLE, dtype=np.uint8)
    assert map_values.refresh(labels, slice(0, 2), slice(0, 3)) == (slice(0, 2), slice(0, 3))
    labels[1, 1] = CellLabel.MOBILE_OBSTACLE
    assert map_values.refresh(labels, slice(0, 2), slice(0, 3)) == (slice(0, 0), slice(0, 0))
    labels[1, 1] = CellLabel.EXPLORED
    assert map_values.refresh(labels, slice(0, 2), slice(0, 3)) == (slice(1, 2), slice(1, 2))
    assert_array_equal(values, [[100, 100, 100], [100, 0, 100]])


@pytest.mark.parametrize('values, table, message', [
    (np.zeros((2, 2), dtype=np.int16), OCCUPANCY_VALUE, '2-D ndarray of int8'),
    (np.zeros(4, dtype=np.int8), OCCUPANCY_VALUE, '2-D ndarray of int8'),
    (np.zeros((2, 2), dtype=np.int8), OCCUPANCY_VALUE.astype(np.int16), 'a value per label'),
    (np.zeros((2, 2), dtype=np.int8), np.zeros(0, dtype=np.int8), 'a value per label'),
])
def test_bad_values_or_table_raise(values, table, message):
    with pytest.raises(ValueError, match=message):
        MapValues(values, table)


def test_bad_labels_raise():
    map_values = MapValues(np.zeros((2, 2), dtype=np.int8), OCCUPANCY_VALUE)
    with pytest.raises(ValueError, match='for a buffer of'):
        map_values.refresh(np.zeros((2, 3), dtype=np.uint8), slice(0, 1), slice(0, 1))
    with pytest.raises(ValueError, match='label 7 has no map value'):
        map_values.refresh(np.full((2, 2), 7, dtype=np.uint8), slice(0, 2), slice(0, 2))


def test_a_read_only_table_needs_no_kernel_beyond_the_warm_up():
    # The node's table is read-only (OCCUPANCY_VALUE and copies of it may be): after
    # warm_up_map_values its first map must load no second specialisation of the kernel
    # (each one loaded after start is native memory the node's RSS shows growing).
    from dpn_navigator.core._kernels import map_values as kernels
    from dpn_navigator.core.mapping.map_values import warm_up_map_values
    warm_up_map_values()
    signatures = list(kernels.refresh_values.signatures)
    table = MOBILE_100.copy()
    table.setflags(write=False)
    values = np.zeros((3, 4), dtype=np.int8)
    map_values = MapValues(values, table)
    labels = np.full((3, 4), CellLabel.EXPLORED, dtype=np.uint8)
    assert map_values.refresh(labels, slice(0, 3), slice(0, 4)) == (slice(0, 3), slice(0, 4))
    assert_array_equal(values, np.zeros((3, 4), dtype=np.int8))
    assert list(kernels.refresh_values.signatures) == signatures
