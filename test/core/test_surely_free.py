"""
The fine free evidence's update (``_kernels.free_space.surely_free_update``) against its twin.

The kernel tests only the f2 cells not yet marked, each against the polygon's vertices and
edges near its bearing; ``surely_free_update_by_marks`` marks every vertex's disc and every
edge band over the window, as the label update does (itself tested against the literal twin
in ``test_label_grid.py``). The two must mark the same cells, scan after scan: on dense,
jagged scans (hits next to no-return and invalid beams, so long edges between neighbours),
over fields of view up to and beyond a full turn, from poses off the grid and far from the
origin, on lattices where centres fall on edges and discs, and on the real recordings.
"""

import math

from dpn_navigator.core._kernels import free_space
from dpn_navigator.core.grid_geometry import squared_bound
from dpn_navigator.core.mapping.scan_reading import no_return_as_reading, read_no_echo
from dpn_navigator.tools import real_data
from hypothesis import given, strategies as st
import numpy as np
from numpy.testing import assert_array_equal
import pytest
from realdata_paths import real_bag, real_bag_ids


def both_updates(seen_free, scans, origin, resolution, radius, hit_stamp=None,
                 fresh_after=0.0):
    """
    Run both kernels over ``scans`` from the same ``seen_free``; return the two results.

    ``scans``: ``(pose, ranges, angle_min, angle_increment, range_min, range_max)`` each.
    The arrays are compared after every scan. With ``hit_stamp`` (the burn-in's clock of each
    cell), cells stamped after ``fresh_after`` must stay as they were.
    """
    fast = seen_free.copy()
    marked = seen_free.copy()
    bound = squared_bound(radius)
    stamps = np.zeros((1, 1)) if hit_stamp is None else hit_stamp
    for pose, ranges, angle_min, increment, range_min, range_max in scans:
        arguments = (np.ascontiguousarray(ranges, dtype=np.float64), *map(float, pose),
                     float(angle_min), float(increment), float(range_min), float(range_max),
                     float(origin[0]), float(origin[1]), float(resolution), float(radius),
                     bound, stamps, float(fresh_after))
        before = fast.copy()
        free_space.surely_free_update(fast, *arguments)
        free_space.surely_free_update_by_marks(marked, *arguments)
        assert_array_equal(fast, marked)
        if hit_stamp is not None:
            held = hit_stamp > fresh_after
            assert_array_equal(fast[held], before[held])
    return fast, marked


@st.composite
def dense_scans(draw):
    """Draw a grid, a radius and a few dense scans with jumps, no-returns and invalid beams."""
    resolution = draw(st.sampled_from([0.05, 0.1, 0.25]))
    radius = resolution * draw(st.sampled_from([0.6, 1.0, 1.49, 1.5, 2.0, 3.5]))
    rows = draw(st.integers(5, 60))
    cols = draw(st.integers(5, 60))
    far = draw(st.booleans())
    shift = 3000.0 if far else 0.0
    origin = (shift + draw(st.floats(-2.0, 2.0)), -shift + draw(st.floats(-2.0, 2.0)))
    rng = np.random.default_rng(draw(st.integers(0, 2 ** 32 - 1)))
    seen_free = rng.random((rows, cols)) < draw(st.sampled_from([0.0, 0.3]))
    range_max = draw(st.sampled_from([3.0, 6.0, 20.0]))
    span = draw(st.sampled_from([0.5, math.pi, 1.5 * math.pi, 2.0 * math.pi, 2.2 * math.pi]))
    beams = draw(st.integers(2, 400))
    scans = []
    for _ in range(draw(st.integers(1, 3))):
        x = origin[0] + draw(st.floats(-1.0, cols * resolution + 1.0))
        y = origin[1] + draw(st.floats(-1.0, rows * resolution + 1.0))
        # A smooth wall with runs of other readings: jumps in and out, no return, invalid.
        ranges = 1.0 + 2.0 * np.abs(np.sin(np.linspace(0.0, 3.0, beams) + rng.random()))
        kinds = rng.integers(0, 6, beams)
        runs = rng.random(beams) < 0.85
        kinds[1:][runs[1:]] = 0
        ranges[kinds == 1] = math.inf
        ranges[kinds == 2] = math.nan
        ranges[kinds == 3] = 0.001
        ranges[kinds == 4] = rng.uniform(0.05, range_max, (kinds == 4).sum())
        scans.append(((x, y, draw(st.floats(-4.0, 4.0))), ranges, draw(st.floats(-3.2, 0.0)),
                      span / (beams - 1), 0.01, range_max))
    return seen_free, scans, origin, resolution, radius


@given(case=dense_scans())
def test_dense_scans_mark_the_cells_of_the_marks(case):
    seen_free, scans, origin, resolution, radius = case
    both_updates(seen_free, scans, origin, resolution, radius)


@given(case=dense_scans(), seed=st.integers(0, 2 ** 32 - 1))
def test_the_burn_in_holds_back_the_same_cells_in_both(case, seed):
    # Cells a hit came near after `fresh_after` are not marked, by either kernel; the others
    # are marked as without the burn-in.
    seen_free, scans, origin, resolution, radius = case
    rng = np.random.default_rng(seed)
    hit_stamp = np.where(rng.random(seen_free.shape) < 0.3, 1.0, -math.inf)
    held, _ = both_updates(seen_free, scans, origin, resolution, radius, hit_stamp, 0.5)
    plain, _ = both_updates(seen_free, scans, origin, resolution, radius)
    free = hit_stamp < 0.5
    assert_array_equal(held[free], plain[free])
    assert_array_equal(held[~free], seen_free[~free])


@st.composite
def lattice_scans(draw):
    """Draw scans whose vertices lie on centres and cell sides, radii equal to their spacing."""
    resolution = 0.25
    radius = resolution * draw(st.sampled_from([1.0, 1.5, 2.0]))
    rows = draw(st.integers(4, 30))
    cols = draw(st.integers(4, 30))
    eighth = st.integers(0, 4 * cols).map(lambda k: 0.125 * k)
    scans = []
    for _ in range(draw(st.integers(1, 3))):
        x, y = draw(eighth), draw(st.integers(0, 4 * rows).map(lambda k: 0.125 * k))
        step = draw(st.sampled_from([math.pi / 4, math.pi / 8, math.pi / 180]))
        beams = draw(st.integers(2, min(int(round(2.0 * math.pi / step)), 120)))
        ranges = draw(st.lists(st.integers(0, 40).map(lambda k: 0.125 * k),
                               min_size=beams, max_size=beams))
        scans.append(((x, y, draw(st.integers(-4, 4)) * math.pi / 4), np.array(ranges),
                      draw(st.integers(-4, 0)) * math.pi / 4, step, 0.0, 4.0))
    seen_free = np.zeros((rows, cols), dtype=bool)
    return seen_free, scans, (0.0, 0.0), resolution, radius


@given(case=lattice_scans())
def test_lattice_scans_mark_the_cells_of_the_marks(case):
    seen_free, scans, origin, resolution, radius = case
    both_updates(seen_free, scans, origin, resolution, radius)


def segment_distance(px, py, bx, by):
    """Distance of points ``(px, py)`` from the segment from the origin to ``(bx, by)``."""
    t = np.clip((px * bx + py * by) / (bx * bx + by * by), 0.0, 1.0)
    return np.hypot(px - t * bx, py - t * by)


def test_a_room_marks_its_inside_and_only_once():
    # A square room seen from its middle over a full turn: marked are the centres more than
    # 0.2 m from the walls, the laser and the polygon's two closing edges (laser to the first
    # and the last beam's hit; much new space: the kernel marks the window). A second scan
    # finds them all marked and marks nothing more.
    beams = 720
    angles = np.arange(beams) * (2.0 * math.pi / beams)
    ranges = 2.0 / np.maximum(np.abs(np.cos(angles)), np.abs(np.sin(angles)))
    scan = ((0.0, 0.0, 0.0), ranges, 0.0, 2.0 * math.pi / beams, 0.05, 10.0)
    seen_free = np.zeros((50, 50), dtype=bool)
    first, _ = both_updates(seen_free, [scan], (-2.5, -2.5), 0.1, 0.2)
    cy, cx = np.meshgrid(-2.5 + (np.arange(50) + 0.5) * 0.1, -2.5 + (np.arange(50) + 0.5) * 0.1,
                         indexing='ij')
    last = (ranges[-1] * math.cos(angles[-1]), ranges[-1] * math.sin(angles[-1]))
    clearance = np.minimum.reduce([2.0 - np.maximum(np.abs(cx), np.abs(cy)), np.hypot(cx, cy),
                                   segment_distance(cx, cy, 2.0, 0.0),
                                   segment_distance(cx, cy, *last)])
    assert not (np.abs(clearance - 0.2) < 1e-6).any()       # no centre on a disc's rim
    assert_array_equal(first, clearance > 0.2)
    assert first.sum() > 800
    again, _ = both_updates(first, [scan], (-2.5, -2.5), 0.1, 0.2)
    assert_array_equal(again, first)
    # A few rows not yet marked (few cells to test, each tested against the edges near it,
    # rather than the whole window marked): they are marked as the first scan marked them.
    partly = first.copy()
    partly[[5, 24, 25, 40], :] = False
    partly[:, 30] = False
    rest, _ = both_updates(partly, [scan], (-2.5, -2.5), 0.1, 0.2)
    assert_array_equal(rest, first)


@pytest.mark.parametrize('name', [name for name in real_bag_ids()
                                  if not name.endswith('_extracted.bag')])
def test_real_recordings_mark_the_cells_of_the_marks(name):
    # As the default rule's fine evidence takes them (0.1 m, 0.2 m, no echo as no return,
    # no-return beams out to 0.8 of range_max), as recorded and resampled to 1081 beams. The
    # `_extracted` bags hold the annotations of the others' scans: not taken.
    path = real_bag(name)
    recording = real_data.read_recording(path)
    config = real_data.grid_config(recording, 'dpn')
    rule = config.label_rule()
    shape = (int(round(config.height / rule.fine_evidence_resolution)),
             int(round(config.width / rule.fine_evidence_resolution)))
    for beams in (None, 1081):
        scans = []
        for scan in recording.scans[::4]:
            stamp, ranges, angle_min, increment, range_min, range_max = (
                scan if beams is None else real_data.resample(scan, beams))
            ranges = read_no_echo(np.asarray(ranges, dtype=float), range_min, True)
            ranges = no_return_as_reading(ranges, range_min, range_max, rule.no_return_reach)
            scans.append(((0.0, 0.0, 0.0), ranges, angle_min, increment, range_min,
                          min(range_max, max(rule.fine_evidence_range, range_min))))
        fast, _ = both_updates(np.zeros(shape, dtype=bool), scans, config.origin,
                               rule.fine_evidence_resolution, rule.fine_evidence_radius)
        assert fast.sum() > 1000                  # the recordings show much free space


@pytest.mark.parametrize('resolution, radius', [(0.1, 0.2), (0.25, 0.3), (0.1, 0.25),
                                                (0.05, 0.2), (0.5, 0.6), (0.1, 0.05)])
def test_stamp_hits_stamps_every_centre_within_the_radius(resolution, radius):
    # The burn-in's clock: every cell whose centre passes a hit's disc test, and no other,
    # hits on cell sides included (the box searched around each hit must reach them all).
    rng = np.random.default_rng(int(radius * 1000 + resolution * 100))
    cells = 40
    hits = rng.uniform(-0.5, cells * resolution + 0.5, (200, 2))
    hits[:40] = np.round(hits[:40] / resolution) * resolution
    stamps = np.full((cells, cells), -math.inf)
    bound = squared_bound(radius)
    free_space.stamp_hits(stamps, hits[:, 0].copy(), hits[:, 1].copy(), 0.0, 0.0, resolution,
                          bound, 2.5)
    centre = (np.arange(cells) + 0.5) * resolution
    cy, cx = np.meshgrid(centre, centre, indexing='ij')
    near = np.zeros((cells, cells), dtype=bool)
    for x, y in hits:
        near |= (cx - x) ** 2 + (cy - y) ** 2 <= bound
    assert near.any() and not near.all()
    assert_array_equal(stamps == 2.5, near)
    assert_array_equal(stamps[~near], -math.inf)
