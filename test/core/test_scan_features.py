"""Tests of f1's runs and f2's crossings against the literal equations, on boundary cases."""

import math

from dpn_navigator.core.grid_geometry import GridGeometry
from dpn_navigator.core.grid_geometry import squared_radius_bound
from hypothesis import given, settings
from hypothesis import strategies as st
from literal_reference import literal_f1
import numpy as np
from numpy.testing import assert_array_equal
import pytest
from scan_features import hit_runs


def runs_to_mask(starts, ends, shape):
    mask = np.zeros(shape[0] * shape[1], dtype=bool)
    for start, end in zip(starts.tolist(), ends.tolist()):
        mask[start:end] = True
    return mask.reshape(shape)


def literal_mask(geometry, rows, cols, hits, radius):
    mask = np.zeros((rows.stop - rows.start, cols.stop - cols.start), dtype=bool)
    x0, y0 = geometry.origin
    for i in range(rows.start, rows.stop):
        for j in range(cols.start, cols.stop):
            cx = x0 + (j + 0.5) * geometry.resolution
            cy = y0 + (i + 0.5) * geometry.resolution
            mask[i - rows.start, j - cols.start] = literal_f1(cx, cy, hits, radius)
    return mask


def check_against_literal(geometry, rows, cols, hits, radius):
    hits_x = np.array([h[0] for h in hits], dtype=float)
    hits_y = np.array([h[1] for h in hits], dtype=float)
    centres = geometry.window_centres(rows, cols)
    starts, ends = hit_runs(geometry, rows, cols, centres, hits_x, hits_y, radius)
    shape = (rows.stop - rows.start, cols.stop - cols.start)
    assert np.all(ends > starts)
    assert_array_equal(runs_to_mask(starts, ends, shape),
                       literal_mask(geometry, rows, cols, hits, radius))


@pytest.mark.parametrize('radius', [0.0, 0.25, 0.3, 0.5, 0.6, 1.0, 1e-300, 7.3])
def test_squared_radius_bound_is_the_largest_passing_square(radius):
    bound = squared_radius_bound(radius)
    assert math.sqrt(bound) <= radius
    assert math.sqrt(math.nextafter(bound, math.inf)) > radius


@pytest.mark.parametrize('hit, radius, resolution', [
    ((0.75, 0.25), 0.5, 0.5),            # centres exactly r away along a row and a column
    ((0.5, 0.5), 0.5 * math.sqrt(2.0), 0.5),
    ((1.0, 1.0), 0.25, 0.5),             # hit on a cell corner, r shorter than the corner gap
    ((1.25, 1.25), 0.0, 0.5),            # r = 0 marks only the cell whose centre is the hit
    ((1.3, 1.3), 0.0, 0.5),
    ((7.0, 26.449999990972657), 0.25, 0.1),   # the circle's estimate of the run is one cell off
])
def test_hit_runs_on_exact_boundaries(hit, radius, resolution):
    geometry = GridGeometry(40.0, 40.0, resolution)
    rows, cols = geometry.cell_window(hit[0] - 2.0, hit[0] + 2.0, hit[1] - 2.0, hit[1] + 2.0)
    check_against_literal(geometry, rows, cols, [hit], radius)


@settings(max_examples=150)
@given(hits=st.lists(st.tuples(st.floats(-1.0, 6.0), st.floats(-1.0, 6.0)), max_size=6),
       radius=st.floats(0.0, 1.5), resolution=st.sampled_from([0.1, 0.25, 0.5, 0.3]),
       lattice=st.booleans())
def test_hit_runs_equal_literal_f1(hits, radius, resolution, lattice):
    if lattice:
        # Snap to quarter cells so that distances equal r exactly.
        hits = [(round(x * 4 / resolution) * resolution / 4,
                 round(y * 4 / resolution) * resolution / 4) for x, y in hits]
        radius = round(radius * 4 / resolution) * resolution / 4
    geometry = GridGeometry(5.0, 5.0, resolution)
    rows, cols = geometry.cell_window(0.0, 5.0, 0.0, 5.0)
    check_against_literal(geometry, rows, cols, hits, radius)
