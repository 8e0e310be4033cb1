"""The label rules for real lasers: no-echo codes, no-return reach, intermittent surfaces."""

import math

from dpn_navigator.core.cell_label import CellLabel
from dpn_navigator.core.grid_geometry import GridGeometry
from dpn_navigator.core.mapping.label_grid import LabelGrid, LabelRule
from dpn_navigator.core.mapping.scan_reading import read_no_echo
from dpn_navigator.core.mapping.surface_memory import SurfaceMemory
from dpn_navigator.core.navigator import NavigatorConfig
import numpy as np
from numpy.testing import assert_array_equal
import pytest
from real_sensor_rules import LiteralSurfaceMemory

BEAMS = 181
ANGLE_MIN = -math.pi / 2
INCREMENT = math.pi / (BEAMS - 1)


def grid_for(rule, side=16.0):
    """Return a grid of ``side`` metres centred on the laser at the origin."""
    return LabelGrid(side, side, 0.5, (-side / 2, -side / 2), rule)


def explored_reach(grid):
    """Largest distance from the origin of an explored cell's centre [m] (0 when none)."""
    rr, cc = np.nonzero(grid.labels == CellLabel.EXPLORED)
    if not rr.size:
        return 0.0
    x, y = grid.geometry.cell_to_world(rr, cc)
    return float(np.hypot(x, y).max())


def test_no_echo_codes_are_invalid_unless_read_as_no_return():
    ranges = np.full(BEAMS, 0.005)                # the old Hokuyo driver's "no echo"
    scan = (ANGLE_MIN, INCREMENT, 0.02, 5.0, 0.6)
    plain = grid_for(LabelRule())
    plain.update((0.0, 0.0, 0.0), ranges, *scan)
    assert explored_reach(plain) == 0.0           # REP 117: invalid, nothing seen
    decoded = grid_for(LabelRule(no_echo_below_range_min=True))
    decoded.update((0.0, 0.0, 0.0), ranges, *scan)
    no_return = grid_for(LabelRule())
    no_return.update((0.0, 0.0, 0.0), np.full(BEAMS, np.inf), *scan)
    assert explored_reach(decoded) > 4.0
    assert_array_equal(decoded.labels, no_return.labels)
    # -inf (too close, REP 117) and NaN stay invalid; the caller's array is not changed.
    odd = np.array([-np.inf, np.nan, 0.01, 3.0, -0.5])
    read = read_no_echo(odd, 0.02, True)
    assert_array_equal(read, [-np.inf, np.nan, np.inf, 3.0, -0.5])
    assert odd[2] == 0.01


@pytest.mark.parametrize('reach', [0.0, 0.25, 0.5, 1.0])
def test_no_return_beams_clear_up_to_their_reach(reach):
    grid = grid_for(LabelRule(no_return_reach=reach))
    grid.update((0.0, 0.0, 0.0), np.full(BEAMS, np.inf), ANGLE_MIN, INCREMENT, 0.1, 6.0, 0.6)
    furthest = explored_reach(grid)
    assert furthest <= reach * 6.0 + 1e-9
    assert furthest >= reach * 6.0 - 0.5 * math.sqrt(2.0)
    # A valid return beyond the reach still clears out to it and marks its hit.
    grid = grid_for(LabelRule(no_return_reach=reach))
    ranges = np.full(BEAMS, np.inf)
    ranges[BEAMS // 2] = 5.0
    grid.update((0.0, 0.0, 0.0), ranges, ANGLE_MIN, INCREMENT, 0.1, 6.0, 0.6)
    row, col = grid.geometry.world_to_cell(5.0, 0.0)
    assert grid.labels[row, col] == CellLabel.STEADY_OBSTACLE


def test_surface_memory_equals_its_literal_twin():
    rng = np.random.default_rng(7)
    geometry = GridGeometry(4.0, 3.0, 0.5, (-1.0, -0.5))
    memory = SurfaceMemory(geometry, 0.1, 0.4, 2.0)
    twin = LiteralSurfaceMemory((-1.0, -0.5), 0.1, 0.4, 2.0)
    stamp = 0.0
    for scan in range(120):
        stamp += rng.choice([0.0, 0.05, 0.1, 0.7, -0.3])      # repeats, gaps, jumps back
        # A few places hit again and again, others at random, some off the grid.
        hits = np.concatenate([rng.normal([0.52, 0.43], 0.04, (3, 2)),
                               rng.uniform([-1.5, -1.0], [3.5, 3.0], (rng.integers(0, 6), 2))])
        if rng.random() < 0.3:
            hits = hits[3:]                                     # the surface has no echo
        fill = rng.random(hits.shape[0]) < 0.8 if scan % 2 else None
        got = memory.on_surface(hits[:, 0], hits[:, 1], stamp)
        memory.fill(hits[:, 0], hits[:, 1], stamp, fill)
        want = twin.surface_hits([tuple(h) for h in hits], stamp, geometry_shape(memory), fill)
        assert got.tolist() == want
        for (row, col), (hit_time, filled) in twin.buckets.items():
            assert memory.hit_time[row, col] == hit_time and memory.filled[row, col] == filled
    assert np.count_nonzero(memory.hit_time) == len(
        [1 for hit_time, _ in twin.buckets.values() if hit_time > 0.0])


def geometry_shape(memory):
    return memory.geometry.shape


def test_surface_memory_checks_its_arguments():
    geometry = GridGeometry(4.0, 3.0, 0.5)
    for margin, surface_time, memory in ((0.0, 1.0, 1.0), (0.1, 0.0, 1.0), (0.1, 1.0, 0.0)):
        with pytest.raises(ValueError, match='must be > 0'):
            SurfaceMemory(geometry, margin, surface_time, memory)
    with pytest.raises(ValueError, match='surface_time needs moving_object_size'):
        LabelRule(surface_time=1.0)
    with pytest.raises(ValueError, match='no_return_reach'):
        LabelRule(no_return_reach=1.5)


def cast(pose_x, walls_x, legs, leg_radius=0.08, range_max=8.0):
    """
    Ranges from the origin to a wall piece ``x = walls_x`` (|y| <= 1.5) and round legs.

    Beams that hit nothing read ``+inf``.
    """
    ranges = np.full(BEAMS, np.inf)
    for i in range(BEAMS):
        theta = ANGLE_MIN + i * INCREMENT
        c, s = math.cos(theta), math.sin(theta)
        best = math.inf
        if c > 1e-9:
            t = (walls_x - pose_x) / c
            if abs(t * s) <= 1.5:
                best = t
        for lx, ly in legs:
            b = (lx - pose_x) * c + ly * s
            d2 = (lx - pose_x) ** 2 + ly ** 2 - b * b
            if b > 0.0 and d2 <= leg_radius ** 2:
                best = min(best, b - math.sqrt(leg_radius ** 2 - d2))
        if best < range_max:
            ranges[i] = best
    return ranges


def dpn_rule(**changes):
    return NavigatorConfig(width=16.0, height=16.0, **changes).label_rule()


@pytest.mark.parametrize('surface_time, wall_ever_mobile', [(0.0, True), (1.0, False)])
def test_a_flickering_wall_is_a_surface_and_a_walker_still_moves(
        surface_time, wall_ever_mobile):
    # A wall 3 m ahead returns in every scan but two, where its middle has no echo (the
    # polygon then shows its place empty); a person walks across 1.5 m ahead afterwards.
    grid = grid_for(dpn_rule(surface_time=surface_time, no_return_reach=1.0))
    wall_cells = np.zeros(grid.labels.shape, dtype=bool)
    for y in np.arange(-1.0, 1.01, 0.1):
        wall_cells[grid.geometry.world_to_cell(3.0, y)] = True
    wall_mobile = walker_mobile = False
    for k in range(60):
        stamp = 0.1 * k
        legs = []
        if k >= 35:
            x = -1.5 + 0.1 * (k - 35)                   # 1 m/s across the view
            legs = [(1.5, x), (1.5, x + 0.25)]
        ranges = cast(0.0, 3.0, legs)
        if k in (20, 21):
            middle = np.abs(ANGLE_MIN + np.arange(BEAMS) * INCREMENT) < 0.25
            ranges[middle] = np.inf
        grid.update((0.0, 0.0, 0.0), ranges, ANGLE_MIN, INCREMENT, 0.1, 8.0, 0.6, stamp=stamp)
        mobile = grid.labels == CellLabel.MOBILE_OBSTACLE
        wall_mobile |= bool((mobile & wall_cells).any())
        if legs:
            row, col = grid.geometry.world_to_cell(1.5, legs[0][1])
            walker_mobile |= bool(mobile[row, col])
    assert wall_mobile == wall_ever_mobile
    assert walker_mobile


def test_the_paper_keeps_every_real_sensor_rule_off():
    from dpn_navigator.benchmark.protocol import NAVIGATORS
    paper = NavigatorConfig(width=10.0, height=10.0, **NAVIGATORS['paper']).label_rule()
    assert paper == LabelRule()
    assert not paper.no_echo_below_range_min and paper.no_return_reach == 1.0
    assert paper.surface_time == 0.0
