"""The label rules for real lasers: no-echo codes and reach, standing, surfaces, edge pixels."""

import dataclasses
import math
from pathlib import Path

from dpn_navigator.core.cell_label import CellLabel
from dpn_navigator.core.grid_geometry import GridGeometry
from dpn_navigator.core.mapping.label_grid import LabelGrid, LabelRule
from dpn_navigator.core.mapping.laser_standing import LaserStanding
from dpn_navigator.core.mapping.scan_reading import (edge_pixels, mixed_pixels, read_no_echo,
                                                     spikes, veiling_points)
from dpn_navigator.core.mapping.surface_memory import SurfaceMemory
from dpn_navigator.core.navigator import NavigatorConfig
from literal_reference import literal_update_with_rule
import numpy as np
from numpy.testing import assert_array_equal
import pytest
from real_sensor_rules import LiteralStanding, LiteralSurfaceMemory

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


def ever_mobile(grid, scans, points):
    """
    Update ``grid`` with ``scans`` from the origin; tell what was ever labelled mobile.

    ``scans`` yields ``(stamp, ranges, legs)``, the legs' positions [m] (the first is the
    walker's); ``points`` [m] are the cells watched. Returns ``(watched cells ever mobile,
    the walker's first leg's cell ever mobile)``.
    """
    watched = np.zeros(grid.labels.shape, dtype=bool)
    for x, y in points:
        watched[grid.geometry.world_to_cell(x, y)] = True
    cells_mobile = walker_mobile = False
    for stamp, ranges, legs in scans:
        grid.update((0.0, 0.0, 0.0), ranges, ANGLE_MIN, INCREMENT, 0.1, 8.0, 0.6, stamp=stamp)
        mobile = grid.labels == CellLabel.MOBILE_OBSTACLE
        cells_mobile |= bool((mobile & watched).any())
        if legs:
            walker_mobile |= bool(mobile[grid.geometry.world_to_cell(*legs[0])])
    return cells_mobile, walker_mobile


@pytest.mark.parametrize('surface_time, wall_ever_mobile', [(0.0, True), (1.0, False)])
def test_a_flickering_wall_is_a_surface_and_a_walker_still_moves(
        surface_time, wall_ever_mobile):
    # A wall 3 m ahead returns in every scan but two, where its middle has no echo (the
    # polygon then shows its place empty); a person walks across 1.5 m ahead afterwards.
    grid = grid_for(dpn_rule(surface_time=surface_time, no_return_reach=1.0))

    def scans():
        for k in range(60):
            legs = []
            if k >= 35:
                x = -1.5 + 0.1 * (k - 35)                   # 1 m/s across the view
                legs = [(1.5, x), (1.5, x + 0.25)]
            ranges = cast(0.0, 3.0, legs)
            if k in (20, 21):
                middle = np.abs(ANGLE_MIN + np.arange(BEAMS) * INCREMENT) < 0.25
                ranges[middle] = np.inf
            yield 0.1 * k, ranges, legs

    wall = [(3.0, y) for y in np.arange(-1.0, 1.01, 0.1)]
    wall_mobile, walker_mobile = ever_mobile(grid, scans(), wall)
    assert wall_mobile == wall_ever_mobile
    assert walker_mobile


def test_the_paper_keeps_every_real_sensor_rule_off():
    from dpn_navigator.benchmark.protocol import NAVIGATORS
    paper = NavigatorConfig(width=10.0, height=10.0, **NAVIGATORS['paper']).label_rule()
    assert paper == LabelRule()
    assert not paper.no_echo_below_range_min and paper.no_return_reach == 1.0
    assert paper.surface_time == 0.0
    assert paper.mixed_pixel_angle == paper.veiling_angle == 0.0
    assert paper.free_burn_in == paper.free_first_sight == paper.object_min_width == 0.0
    assert paper.no_return_standing_distance == 0.0


# --- Mixed pixels and veiling hits (`mixed_pixel_angle`, `veiling_angle`).

def random_edge_scan(rng, beams=120):
    """Ranges with depth edges, mixed pixels between them, no returns, invalid readings."""
    ranges = np.repeat(rng.uniform(0.3, 6.0, beams // 10), 10)[:beams]
    ranges = ranges + rng.normal(0.0, 0.01, beams)
    edges = np.flatnonzero(np.abs(np.diff(ranges)) > 0.2)
    for k in edges[rng.random(edges.size) < 0.5]:
        ranges[k] = ranges[k] + rng.uniform(0.1, 0.9) * (ranges[k + 1] - ranges[k])
    ranges[rng.random(beams) < 0.05] = np.inf
    ranges[rng.random(beams) < 0.03] = np.nan
    ranges[rng.random(beams) < 0.03] = 0.05                     # below range_min
    return ranges


@pytest.mark.parametrize('seed', range(8))
def test_mixed_pixels_and_veiling_hits_equal_their_literal_twins(seed):
    from real_sensor_rules import literal_mixed, literal_veiling
    rng = np.random.default_rng(seed)
    ranges = random_edge_scan(rng)
    increment = float(rng.choice([0.0044, 0.0065, 0.0175, 0.1]))
    angle = float(rng.choice([0.1, 0.1745, 0.3]))
    mixed = mixed_pixels(ranges, increment, 0.1, 5.5, angle)
    veiling = veiling_points(ranges, increment, 0.1, 5.5, angle)
    assert_array_equal(mixed, literal_mixed(ranges, increment, 0.1, 5.5, angle))
    assert_array_equal(veiling, literal_veiling(ranges, increment, 0.1, 5.5, angle))
    assert not (mixed & ~veiling).any()                      # a mixed pixel veils
    assert not mixed_pixels(ranges, increment, 0.1, 5.5, 0.0).any()
    assert not veiling_points(ranges, increment, 0.1, 5.5, 0.0).any()


def grazing_wall_scan(beams=1081, field=1.5 * math.pi, distance=1.0, range_max=30.0,
                      noise=0.0, seed=0):
    """Return (ranges, angle_min, increment, incidence [rad]) of a flat wall ``distance`` away."""
    angle_min = -0.5 * field
    increment = field / (beams - 1)
    theta = angle_min + increment * np.arange(beams)
    ranges = np.full(beams, np.inf)
    ahead = np.sin(theta) > 1e-6
    ranges[ahead] = distance / np.sin(theta[ahead])
    ranges += np.random.default_rng(seed).normal(0.0, noise, beams)
    ranges[ranges >= range_max] = np.inf
    return ranges, angle_min, increment, np.abs(0.5 * math.pi - theta)


@pytest.mark.parametrize('noise', [0.0, 0.01])
def test_a_flat_wall_at_grazing_incidence_is_no_mixed_pixel_with_flatness(noise):
    # Past 80 deg from its normal, each hit of a flat wall lies between its neighbours in
    # depth, the segments to both within 10 deg of its beam: the mixed-pixel test alone
    # drops them (and range noise makes spikes); on the line through its neighbours' points
    # it is a surface.
    ranges, _, increment, incidence = grazing_wall_scan(noise=noise)
    alone = mixed_pixels(ranges, increment, 0.1, 30.0, 0.1745)
    assert alone.sum() >= 20 and incidence[alone].min() > math.radians(79.0)
    flat = mixed_pixels(ranges, increment, 0.1, 30.0, 0.1745, flatness=0.03)
    assert not flat.any()
    # Near the laser, beams 0.25 deg apart see centimetres of noise as depth: a spike or two
    # may stay there (off the line by more than the flatness), none where the wall grazes.
    edge = edge_pixels(ranges, increment, 0.1, 30.0, 0.1745, 0.1745, 0.03)
    assert not edge[incidence > math.radians(60.0)].any()


def test_flatness_keeps_few_mixed_pixels_of_depth_edges():
    # A mixed pixel lies where the line of its edge's two surfaces crosses its beam by
    # chance only: 3 cm keeps under 15 % of them (166 in these scans), 0 keeps none.
    found = kept = 0
    for seed in range(20):
        ranges = random_edge_scan(np.random.default_rng(seed))
        for increment in (0.0044, 0.0065, 0.0175):
            alone = mixed_pixels(ranges, increment, 0.1, 5.5, 0.1745)
            flat = mixed_pixels(ranges, increment, 0.1, 5.5, 0.1745, 0.03)
            found += int(alone.sum())
            kept += int((alone & ~flat).sum())
    assert found > 100 and 0 < kept < 0.15 * found


@pytest.mark.parametrize('seed', range(8))
def test_flatness_keeps_the_mixed_pixels_of_depth_edges_and_equals_its_twin(seed):
    from real_sensor_rules import literal_mixed
    rng = np.random.default_rng(seed)
    ranges = random_edge_scan(rng)
    increment = float(rng.choice([0.0044, 0.0065, 0.0175]))
    for flatness in (0.01, 0.03, 0.3):
        flat = mixed_pixels(ranges, increment, 0.1, 5.5, 0.1745, flatness)
        assert_array_equal(flat, literal_mixed(ranges, increment, 0.1, 5.5, 0.1745, flatness))
        alone = mixed_pixels(ranges, increment, 0.1, 5.5, 0.1745)
        assert not (flat & ~alone).any()                     # it only keeps hits
    from real_sensor_rules import literal_spikes
    for flatness in (0.01, 0.3):
        assert_array_equal(spikes(ranges, increment, 0.1, 5.5, 0.1745, flatness),
                           literal_spikes(ranges, increment, 0.1, 5.5, 0.1745, flatness))
    with pytest.raises(ValueError, match='edge_pixel_flatness'):
        LabelRule(edge_pixel_flatness=-0.01)


def test_a_mixed_pixel_veils_towards_both_sides_and_an_object_edge_one():
    increment = math.radians(0.5)
    # A wall 2 m away, a mixed pixel at 3 m, what lies behind the edge 4 m away.
    ranges = np.array([2.0, 2.0, 2.0, 3.0, 4.0, 4.0, 4.0])
    assert_array_equal(mixed_pixels(ranges, increment, 0.1, 10.0, 0.1745),
                       [False, False, False, True, False, False, False])
    # Without it, the edge hits veil towards the other side only, and are kept.
    edge = np.array([2.0, 2.0, 2.0, 4.0, 4.0, 4.0])
    assert_array_equal(veiling_points(edge, increment, 0.1, 10.0, 0.1745),
                       [False, False, True, True, False, False])
    assert not mixed_pixels(edge, increment, 0.1, 10.0, 0.1745).any()
    # A surface facing the laser does not veil.
    assert not veiling_points(np.full(7, 2.0), increment, 0.1, 10.0, 0.1745).any()


@pytest.mark.parametrize('seed', range(40))
def test_spikes_equal_their_literal_twin_and_are_the_rest_of_the_two_sided_veils(seed):
    from real_sensor_rules import literal_spikes, literal_veils
    rng = np.random.default_rng(1000 + seed)
    ranges = random_edge_scan(rng)
    lone = rng.choice(ranges.shape[0], 6, replace=False)      # speckle, nearer or farther
    ranges[lone] = ranges[lone] + rng.choice([-1.0, 1.0], 6) * rng.uniform(0.3, 1.5, 6)
    increment = float(rng.choice([0.0044, 0.0065, 0.0175, 0.1]))
    angle = float(rng.choice([0.1, 0.1745, 0.3]))
    spiked = spikes(ranges, increment, 0.1, 5.5, angle)
    assert_array_equal(spiked, literal_spikes(ranges, increment, 0.1, 5.5, angle))
    # With the mixed pixels: exactly the hits that veil towards both neighbours.
    both = [0 < i < ranges.shape[0] - 1
            and literal_veils(ranges, i, i - 1, increment, 0.1, 5.5, angle)
            and literal_veils(ranges, i, i + 1, increment, 0.1, 5.5, angle)
            for i in range(ranges.shape[0])]
    mixed = mixed_pixels(ranges, increment, 0.1, 5.5, angle)
    assert not (spiked & mixed).any()
    assert_array_equal(spiked | mixed, both)
    assert_array_equal(edge_pixels(ranges, increment, 0.1, 5.5, angle, angle), both)
    other = 0.5 * angle
    assert_array_equal(edge_pixels(ranges, increment, 0.1, 5.5, angle, other),
                       mixed | spikes(ranges, increment, 0.1, 5.5, other))
    assert not spikes(ranges, increment, 0.1, 5.5, 0.0).any()


def test_two_mixed_pixels_side_by_side_are_spikes_and_a_wall_is_not():
    increment = math.radians(0.25)
    # A box 2 m away, its edge beam and the background's edge beam both mixed (3.6 and
    # 2.9 m: each between the surfaces, out of order), the background 5 m away.
    ranges = np.array([2.0, 2.0, 2.0, 3.6, 2.9, 5.0, 5.0, 5.0])
    assert not mixed_pixels(ranges, increment, 0.1, 10.0, 0.1745).any()
    assert_array_equal(spikes(ranges, increment, 0.1, 10.0, 0.1745),
                       [False, False, False, True, True, False, False, False])
    # A wall seen at 70 deg from its normal, and a box's edge, have none.
    angles = np.arange(40) * increment
    wall = 1.0 / np.cos(math.radians(70.0) - angles)
    assert not spikes(wall, increment, 0.1, 10.0, 0.1745).any()
    assert not spikes(np.array([2.0, 2.0, 2.0, 5.0, 5.0]), increment, 0.1, 10.0,
                      0.1745).any()


def test_spikes_read_as_invalid_leave_no_obstacle():
    ranges = np.full(BEAMS, 6.0)
    ranges[90] = 3.0                                          # a lone return off nothing
    kept = grid_for(LabelRule())
    dropped = grid_for(LabelRule(spike_angle=0.1745))
    for grid in (kept, dropped):
        grid.update((0.0, 0.0, 0.0), ranges, ANGLE_MIN, INCREMENT, 0.1, 8.0, 0.6)
    cell = kept.geometry.world_to_cell(3.0, 0.0)
    assert kept.labels[cell] == CellLabel.STEADY_OBSTACLE
    assert dropped.labels[cell] != CellLabel.STEADY_OBSTACLE
    with pytest.raises(ValueError, match='spike_angle'):
        LabelRule(spike_angle=-0.1)
    assert dpn_rule().spike_angle == 0.0


def edge_scan(laser_y, mixed=False):
    """
    From ``(0, laser_y)``: a wall ``x = 2`` for y < 0, a wall ``x = 4`` behind its end.

    With ``mixed`` the first beam past the edge returns 3 m of x instead of 4: a spot that fell
    on both walls, a point floating in the space between them.
    """
    angles = ANGLE_MIN + INCREMENT * np.arange(BEAMS)
    cos = np.cos(angles)
    ahead = cos > 1e-9
    ranges = np.full(BEAMS, np.inf)
    near = ahead & (laser_y + 2.0 * np.tan(np.where(ahead, angles, 0.0)) < 0.0)
    ranges[near] = 2.0 / cos[near]
    far = ahead & ~near
    ranges[far] = 4.0 / cos[far]
    if mixed:
        first = np.flatnonzero(far)[0]
        ranges[first] = 3.0 / cos[first]
    return ranges


@pytest.mark.parametrize('mixed_pixel_angle, ghost', [(0.0, True), (0.1745, False)])
def test_a_mixed_pixel_makes_no_ghost_when_read_as_invalid(mixed_pixel_angle, ghost):
    # The laser drives from y = 1 to y = 0 along x = 0: the space between the two walls
    # behind the near wall's end is seen empty from above, then the mixed pixels float in it.
    grid = grid_for(dpn_rule(mixed_pixel_angle=mixed_pixel_angle))
    ever_mobile = np.zeros(grid.labels.shape, dtype=bool)
    for k in range(41):
        laser_y = 1.0 - 0.025 * k
        grid.update((0.0, laser_y, 0.0), edge_scan(laser_y, mixed=k % 4 == 3), ANGLE_MIN,
                    INCREMENT, 0.1, 8.0, 0.6, stamp=0.1 * k)
        ever_mobile |= grid.labels == CellLabel.MOBILE_OBSTACLE
    assert ever_mobile.any() == ghost
    # The walls are mapped either way.
    assert grid.labels[grid.geometry.world_to_cell(2.0, -1.0)] == CellLabel.STEADY_OBSTACLE
    assert grid.labels[grid.geometry.world_to_cell(4.0, 1.0)] == CellLabel.STEADY_OBSTACLE


def oblique_wall_scan(drop=False):
    """
    Return the scan of a wall ``y = 0.5`` for x in [0.3, 6] from the origin, facing +x.

    Its far part is seen at grazing incidence (beyond about 2.9 m, more than 80 degrees from
    its normal). With ``drop`` it returns nothing (a flicker): its place looks empty.
    """
    angles = ANGLE_MIN + INCREMENT * np.arange(BEAMS)
    ranges = np.full(BEAMS, np.inf)
    up = np.sin(angles) > 1e-9
    ranges[up] = 0.5 / np.sin(angles[up])
    x = ranges * np.cos(angles)
    ranges[~up | (x < 0.3) | (x > 6.0)] = np.inf
    if drop:
        ranges[np.isfinite(ranges)] = np.inf
    return ranges


@pytest.mark.parametrize('veiling_angle, far_wall_ever_mobile', [(0.0, True), (0.1745, False)])
def test_hits_on_a_grazing_wall_show_no_motion_when_veiling(
        veiling_angle, far_wall_ever_mobile):
    # The wall flickers in two scans, so its place was surely seen empty; a long surface
    # memory keeps it from being a known surface within the test, so that only the veiling
    # rule can keep it steady. A person then walks across 1.5 m ahead.
    grid = grid_for(dpn_rule(veiling_angle=veiling_angle, surface_time=100.0,
                             no_return_reach=1.0))

    def scans():
        for k in range(60):
            ranges = oblique_wall_scan(drop=k in (20, 21))
            legs = []
            if k >= 35:
                y = -1.5 + 0.1 * (k - 35)
                legs = [(1.5, y - 0.4), (1.5, y - 0.15)]
                ranges = np.minimum(ranges, cast(0.0, 100.0, legs))
            yield 0.1 * k, ranges, legs

    far = [(x, 0.5) for x in np.arange(3.5, 5.6, 0.1)]
    far_mobile, walker_mobile = ever_mobile(grid, scans(), far)
    assert far_mobile == far_wall_ever_mobile
    assert walker_mobile


def noisy_wall_scans(count, noise, seed=3, walker_x=1.5):
    """
    Yield ``(stamp, ranges, legs)`` of a wall 3 m ahead, read with Gaussian range noise [m].

    From the 8th scan on a person crosses ``walker_x`` ahead.
    """
    rng = np.random.default_rng(seed)
    for k in range(count):
        legs = []
        if k >= 8:
            y = -1.2 + 0.15 * (k - 8)
            legs = [(walker_x, y), (walker_x, y + 0.25)]
        ranges = cast(0.0, 3.0, legs)
        wall = np.isfinite(ranges) & (ranges > 2.5)
        ranges[wall] += rng.normal(0.0, noise, np.count_nonzero(wall))
        yield 0.1 * k, ranges, legs


@pytest.mark.parametrize('margin, fraction, wall_ever_mobile', [
    (0.0, 0.0, True), (0.24, 0.0, False), (0.0, 0.08, False)])
def test_range_noise_is_no_motion_and_a_walker_still_moves(margin, fraction, wall_ever_mobile):
    # A wall 3 m ahead read with 8 cm of range noise: long readings show the wall's place
    # empty, a short one then looks like motion. A long surface memory keeps the wall from
    # being a known surface within the test, so that only the range noise rule keeps it
    # steady: 3 sigma, as a fixed margin or as a share of the range (0.08 * 3 m).
    grid = grid_for(dpn_rule(range_noise_margin=margin, range_noise_fraction=fraction,
                             surface_time=100.0, no_return_reach=1.0))
    wall = [(3.0, y) for y in np.arange(-1.5, 1.51, 0.1)]
    wall_mobile, walker_mobile = ever_mobile(grid, noisy_wall_scans(30, 0.08), wall)
    assert wall_mobile == wall_ever_mobile
    assert walker_mobile


def twin_state(grid, rule, side):
    """
    Return the literal twin's empty state for ``grid`` (centred on the origin, ``side`` m).

    ``(origin, labels, seen_free, last_hit, fine_seen_free, fine_hit_stamp, surfaces)``.
    """
    origin = (-side / 2, -side / 2)
    fine_seen_free = np.zeros(grid.fine_evidence.seen_free.shape, dtype=bool)
    return (origin, np.zeros(grid.labels.shape, dtype=np.uint8),
            np.zeros(grid.labels.shape, dtype=bool), np.full(grid.labels.shape, -math.inf),
            fine_seen_free, np.full(fine_seen_free.shape, -math.inf),
            LiteralSurfaceMemory(origin, rule.noise_margin, rule.surface_time,
                                 rule.surface_memory))


def twin_run(rule, plain_rule, scans, side=8.0):
    """
    Update a grid with ``rule`` and the literal twin from the origin, scan by scan.

    Asserts they agree after every scan (labels, surely-free cells, the fine evidence and its
    two clocks); returns whether a grid with ``plain_rule`` ever differed from them (the
    scene exercises the rule).
    """
    grid = grid_for(rule, side)
    plain = grid_for(plain_rule, side)
    origin, labels, seen_free, last_hit, fine_seen_free, fine_hit_stamp, surfaces = \
        twin_state(grid, rule, side)
    fine_first_free = np.full(fine_seen_free.shape, math.inf)
    first_free = np.full(seen_free.shape, math.inf)
    last_stamp = -math.inf
    differs = False
    for stamp, ranges, _ in scans:
        scan = (ANGLE_MIN, INCREMENT, 0.1, 8.0, 0.6)
        _, last_stamp = literal_update_with_rule(
            labels, seen_free, last_hit, origin, 0.5, (0.0, 0.0, 0.0), ranges, *scan, rule=rule,
            stamp=stamp, last_stamp=last_stamp, fine_seen_free=fine_seen_free,
            surfaces=surfaces, fine_hit_stamp=fine_hit_stamp, fine_first_free=fine_first_free,
            first_free=first_free)
        grid.update((0.0, 0.0, 0.0), ranges, *scan, stamp=stamp)
        plain.update((0.0, 0.0, 0.0), ranges, *scan, stamp=stamp)
        assert_array_equal(grid.labels, labels)
        assert_array_equal(grid.seen_free, seen_free)
        assert_array_equal(grid.fine_evidence.seen_free, fine_seen_free)
        if grid.fine_evidence.hit_stamp is not None:
            assert_array_equal(grid.fine_evidence.hit_stamp, fine_hit_stamp)
        if grid.fine_evidence.first_free is not None:
            assert_array_equal(grid.fine_evidence.first_free, fine_first_free)
            assert_array_equal(grid.first_free, first_free)
        differs |= not (np.array_equal(grid.labels, plain.labels)
                        and np.array_equal(grid.seen_free, plain.seen_free)
                        and np.array_equal(grid.fine_evidence.seen_free,
                                           plain.fine_evidence.seen_free))
    return differs


@pytest.mark.parametrize('margin, fraction, walker_x', [(0.24, 0.0, 2.5), (0.08, 0.05, 2.6)])
def test_range_noise_equals_its_literal_twin(margin, fraction, walker_x):
    # The person crosses 0.4-0.5 m in front of the wall: twice the margin would take its
    # hits' far points onto the wall, so the twin checks the margin itself.
    rule = LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                     object_min_hits=2, fine_evidence_resolution=0.1,
                     fine_evidence_radius=0.2, fine_evidence_range=8.0, surface_time=100.0,
                     surface_memory=200.0, noise_margin=0.1, range_noise_margin=margin,
                     range_noise_fraction=fraction)
    plain = dataclasses.replace(rule, range_noise_margin=0.0, range_noise_fraction=0.0)
    assert twin_run(rule, plain, noisy_wall_scans(16, 0.08, walker_x=walker_x))


def test_bad_edge_pixel_parameters_raise():
    for name in ('mixed_pixel_angle', 'veiling_angle'):
        for value in (-0.1, 2.0, math.nan):
            with pytest.raises(ValueError, match=name):
                LabelRule(**{name: value})
    with pytest.raises(ValueError, match='veiling_angle needs surface_time'):
        LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, veiling_angle=0.1)
    for name in ('range_noise_margin', 'range_noise_fraction'):
        for value in (-0.1, math.inf, math.nan):
            with pytest.raises(ValueError, match=name):
                LabelRule(**{name: value})
        with pytest.raises(ValueError, match='need surface_time'):
            LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, **{name: 0.1})


def test_the_real_laser_navigator_is_its_params_file():
    from dpn_navigator.benchmark.protocol import NAVIGATORS, REAL_LASER
    import yaml
    path = Path(__file__).resolve().parents[2] / 'config' / 'dpn_real_laser.yaml'
    overlay = yaml.safe_load(path.read_text())['/**/dpn']['ros__parameters']
    assert overlay == REAL_LASER == NAVIGATORS['dpn_real_laser']
    rule = dpn_rule(**overlay)
    assert rule.no_return_reach == 0.0 and rule.mixed_pixel_angle > 0.0
    assert rule.veiling_angle > 0.0
    assert rule.free_burn_in > 0.0 and rule.object_min_width > 0.0
    # The shipped dpn keeps both off.
    assert dpn_rule().mixed_pixel_angle == dpn_rule().veiling_angle == 0.0


# --- The burn-in of the free evidence (`free_burn_in`) and narrow things (`object_min_width`).

def flickering_scans(count, thing_x=2.5, thing_radius=0.4, walker_from=30, period=2):
    """
    Yield ``(stamp, ranges, legs)`` at 10 Hz: a wall 4 m ahead and a round thing before it.

    The thing (``thing_radius`` [m] at ``thing_x`` ahead) returns an echo in one scan of
    ``period`` and none in the others (``+inf``: the beams then show its place empty out to
    ``range_max``); from ``walker_from`` on a person crosses 1.5 m ahead at 1.5 m/s.
    """
    for k in range(count):
        legs = []
        if k >= walker_from:
            y = -1.5 + 0.15 * (k - walker_from)
            legs = [(1.5, y), (1.5, y + 0.25)]
        ranges = cast(0.0, 4.0, legs)
        thing = cast(0.0, 100.0, [(thing_x, 0.0)], leg_radius=thing_radius)
        behind_thing = np.isfinite(thing) & (thing < ranges)
        if k % period == 0:
            ranges[behind_thing] = thing[behind_thing]
        else:
            ranges[behind_thing & (ranges > thing_x)] = np.inf
        yield 0.1 * k, ranges, legs


def real_rule(**changes):
    """Return dpn's rule for these scenes: no-return beams clear to range_max, no known surface."""
    settings = {'surface_time': 100.0, 'surface_memory': 200.0, 'no_return_reach': 1.0}
    settings.update(changes)
    return dpn_rule(**settings)


@pytest.mark.parametrize('burn_in, thing_ever_mobile', [(0.0, True), (0.5, False)])
def test_a_surface_seen_empty_between_its_echoes_shows_no_motion_with_the_burn_in(
        burn_in, thing_ever_mobile):
    # A board 0.8 m wide 2.5 m ahead gives no echo in every other scan: its place is seen
    # empty in between. With the burn-in a place hit 0.1 s before is not surely free, and the
    # board's next echo shows no motion; the person crossing space seen empty for 3 s does.
    grid = grid_for(real_rule(free_burn_in=burn_in))
    board = [(2.5 - 0.4 * math.cos(a), 0.4 * math.sin(a)) for a in np.linspace(-1.2, 1.2, 9)]
    board_mobile, walker_mobile = ever_mobile(grid, flickering_scans(45), board)
    assert board_mobile == thing_ever_mobile
    assert walker_mobile


@pytest.mark.parametrize('min_width, post_ever_mobile', [(0.0, True), (0.05, False)])
def test_a_narrow_flickering_post_shows_no_motion_and_a_walker_still_moves(
        min_width, post_ever_mobile):
    # A post 6 cm thick 1 m ahead, hit by three beams (1 degree apart, 3.5 cm between its
    # end hits), gives no echo in every other scan. Thin things (`object_min_hits`) are off,
    # so that only its width keeps it from showing motion; the legs (16 cm) still show it.
    grid = grid_for(real_rule(object_min_hits=0, object_min_width=min_width))
    scans = list(flickering_scans(45, thing_x=1.0, thing_radius=0.03))
    hits = np.isfinite(scans[0][1]) & (scans[0][1] < 1.5)
    assert hits.sum() == 3
    post = [(0.97, 0.0)]
    post_mobile, walker_mobile = ever_mobile(grid, scans, post)
    assert post_mobile == post_ever_mobile
    assert walker_mobile


@pytest.mark.parametrize('scene', ['board', 'post', 'wide'])
def test_the_burn_in_and_narrow_things_equal_their_literal_twin(scene):
    # 'post' and 'wide': echoes 0.8 s apart, longer than the burn-in, of a thing 6 cm across
    # (the narrow things keep it) and one 2 m across (seen empty long enough for the label
    # cells' discs too).
    rule = LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                     fine_evidence_resolution=0.1, fine_evidence_radius=0.2,
                     fine_evidence_range=8.0, mobile_expiry=3.0, surface_time=100.0,
                     surface_memory=200.0, noise_margin=0.1, free_burn_in=0.5,
                     object_min_width=0.05)
    scans = {'board': flickering_scans(12, walker_from=6),
             'post': flickering_scans(20, thing_x=1.0, thing_radius=0.03, period=8),
             'wide': flickering_scans(20, thing_radius=1.0, period=8)}[scene]
    plain = dataclasses.replace(rule, free_burn_in=0.0, object_min_width=0.0)
    assert twin_run(rule, plain, scans)


def test_the_burn_in_holds_through_deferred_evidence_and_time_going_back():
    # Deferring the evidence to `settle` marks the same cells; a bag played again from its
    # start (time goes back) leaves no hit in the future holding cells back for good.
    settings = {'surface_time': 100.0, 'surface_memory': 200.0, 'no_return_reach': 1.0,
                'free_burn_in': 0.5, 'free_first_sight': 0.15}
    eager, deferred = grid_for(dpn_rule(**settings)), grid_for(dpn_rule(**settings))
    scans = list(flickering_scans(20))
    for stamp, ranges, _ in scans + scans:
        for grid, defer in ((eager, False), (deferred, True)):
            grid.update((0.0, 0.0, 0.0), ranges, ANGLE_MIN, INCREMENT, 0.1, 8.0, 0.6,
                        stamp=stamp, defer_evidence=defer)
        deferred.settle()
        assert_array_equal(eager.labels, deferred.labels)
        assert_array_equal(eager.seen_free, deferred.seen_free)
        assert_array_equal(eager.fine_evidence.seen_free, deferred.fine_evidence.seen_free)
        assert eager.fine_evidence.hit_stamp.max() <= stamp
        assert_array_equal(eager.fine_evidence.first_free, deferred.fine_evidence.first_free)
        assert_array_equal(eager.first_free, deferred.first_free)
        assert eager.fine_evidence.first_free.min() <= stamp
        assert eager.first_free.min() <= stamp


def test_the_standing_laser_file_is_the_real_data_row():
    # config/dpn_standing_laser.yaml holds the rules docs/real_data.md measures as `dpn with
    # range noise, burn-in 5 s, a second look, narrow things`, and they make a valid rule.
    import yaml
    from dpn_navigator.tools.real_data import STANDING_LASER, TABLE_RULES
    path = Path(__file__).resolve().parents[2] / 'config' / 'dpn_standing_laser.yaml'
    overlay = yaml.safe_load(path.read_text())['/**/dpn']['ros__parameters']
    assert overlay == STANDING_LASER
    assert any(settings is STANDING_LASER for _, _, settings in TABLE_RULES)
    rule = dpn_rule(**overlay)
    assert rule.free_first_sight > 0.0 and rule.free_burn_in > rule.free_first_sight
    assert rule.no_return_reach == dpn_rule().no_return_reach


# --- Free evidence needs a second look (`free_first_sight`).

BOARD_X = 3.5


def first_silent_scans(count, walker_from=20):
    """
    Yield ``(stamp, ranges, legs)`` at 10 Hz: a post silent in the first scan only.

    A wall 4 m ahead and a post 0.4 m wide 0.3 m before it that gives no echo in the first
    scan (its beams then read ``+inf``, and the polygon takes its place for empty), then one
    in every scan; from ``walker_from`` on a person crosses 1.5 m ahead at 1.5 m/s.
    """
    for stamp, ranges, legs in flickering_scans(count, thing_x=BOARD_X, thing_radius=0.2,
                                                walker_from=walker_from, period=1):
        if stamp == 0.0:
            board = cast(0.0, 100.0, [(BOARD_X, 0.0)], leg_radius=0.2)
            ranges[np.isfinite(board) & (board <= ranges)] = np.inf
        yield stamp, ranges, legs


BOARD = [(BOARD_X - 0.2 * math.cos(a), 0.2 * math.sin(a)) for a in np.linspace(-1.2, 1.2, 9)]


@pytest.mark.parametrize('first_sight, board_ever_mobile', [(0.0, True), (0.15, False)])
def test_a_surface_silent_in_the_first_scan_shows_no_motion_with_a_second_look(
        first_sight, board_ever_mobile):
    # The first scan sees through the board to the wall, the next ones hit the board: without
    # a second look its place was surely free and the board seems to have moved in. The
    # person crosses space seen empty for 2 s and moves either way.
    grid = grid_for(real_rule(free_first_sight=first_sight))
    board_mobile, walker_mobile = ever_mobile(grid, first_silent_scans(35), BOARD)
    assert board_mobile == board_ever_mobile
    assert walker_mobile


@pytest.mark.parametrize('scene, burn_in', [('first silent', 0.0), ('first silent', 0.5),
                                            ('board', 0.5)])
def test_the_second_look_equals_its_literal_twin(scene, burn_in):
    rule = LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, segment_gap=0.6,
                     fine_evidence_resolution=0.1, fine_evidence_radius=0.2,
                     fine_evidence_range=8.0, mobile_expiry=3.0, surface_time=100.0,
                     surface_memory=200.0, noise_margin=0.1, free_burn_in=burn_in,
                     free_first_sight=0.15)
    scans = {'first silent': first_silent_scans(12, walker_from=6),
             'board': flickering_scans(12, walker_from=6)}[scene]
    assert twin_run(rule, dataclasses.replace(rule, free_first_sight=0.0), scans)


def test_the_second_look_waits_from_the_first_scan_that_showed_a_cell_empty():
    # Scans 0.1 s apart: with 0.25 s the cells first seen empty at 0 count from the scan at
    # 0.3 s on, and a bag played again from its start takes no first time in the future.
    from dpn_navigator.core.mapping.fine_evidence import FineEvidence
    evidence = FineEvidence(GridGeometry(8.0, 8.0, 0.5, origin=(-4.0, -4.0)), 0.1, 0.2, 8.0,
                            first_sight=0.25)
    ranges = cast(0.0, 4.0, [])
    marked = []
    for stamp in (0.0, 0.1, 0.2, 0.3, 0.4):
        evidence.update((0.0, 0.0, 0.0), ranges, ANGLE_MIN, INCREMENT, 0.1, 8.0, stamp=stamp)
        marked.append(int(evidence.seen_free.sum()))
    assert marked[:3] == [0, 0, 0] and marked[3] > 0 and marked[4] == marked[3]
    assert evidence.first_free[evidence.seen_free].max() == 0.0
    evidence.update((0.0, 0.0, 0.0), ranges, ANGLE_MIN, INCREMENT, 0.1, 8.0, stamp=0.05)
    assert evidence.first_free[np.isfinite(evidence.first_free)].max() <= 0.05
    evidence.reset()
    assert np.isinf(evidence.first_free).all() and not evidence.seen_free.any()


@pytest.mark.parametrize('seed', range(8))
def test_narrow_segments_equal_their_literal_twin(seed):
    from dpn_navigator.core._kernels.motion_evidence import narrow_segments
    from dpn_navigator.core._kernels.scan_window import scan_points
    from real_sensor_rules import literal_narrow
    rng = np.random.default_rng(seed)
    ranges = random_edge_scan(rng)
    # Short runs of two to four beams in front of or behind their neighbours.
    for start in rng.choice(ranges.size - 4, 12, replace=False):
        ranges[start:start + rng.integers(2, 5)] = rng.uniform(0.3, 6.0)
    increment = float(rng.choice([0.0044, 0.0065, 0.0175]))
    _, _, hits_x, hits_y, beams = scan_points(ranges, 0.0, 0.0, 0.0, -0.3, increment, 0.1, 5.5)
    bridge = seed % 3                       # 0: every beam without a hit ends a segment
    narrow = narrow_segments(hits_x, hits_y, beams, 0.3, 0.05, bridge)
    assert_array_equal(narrow, literal_narrow(list(zip(hits_x, hits_y)), list(beams), 0.3,
                                              0.05, bridge))
    assert narrow.any() and not narrow.all()
    assert not narrow_segments(hits_x, hits_y, beams, 0.3, 0.0, bridge).any()


def test_bad_burn_in_and_width_parameters_raise():
    for name in ('free_burn_in', 'free_first_sight', 'object_min_width'):
        for value in (-0.1, math.inf, math.nan):
            with pytest.raises(ValueError, match=name):
                LabelRule(**{name: value})
    with pytest.raises(ValueError, match='free_burn_in needs'):
        LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, free_burn_in=0.5)
    with pytest.raises(ValueError, match='free_first_sight needs'):
        LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, free_first_sight=0.15)
    with pytest.raises(ValueError, match='object_min_width needs surface_time'):
        LabelRule(free_evidence_radius=0.5, moving_object_size=0.7, object_min_width=0.05)
    grid = grid_for(real_rule(free_burn_in=0.5))
    with pytest.raises(ValueError, match='no_return_standing_distance. needs a finite scan stamp'):
        grid.update((0.0, 0.0, 0.0), np.full(BEAMS, 3.0), ANGLE_MIN, INCREMENT, 0.1, 8.0, 0.6)


# --- Beams with no return clear only while the laser stands (`no_return_standing_distance`).

WALL_Y = 1.25


def grazing_wall_scans(start_x=-3.0, stand=12, moves=16, step=0.25, cutoff=math.radians(75)):
    """
    Yield ``(stamp, pose, ranges)`` of a laser beside a wall it drives along.

    The laser faces +x at y = 0; the wall runs along y = ``WALL_Y`` and returns nothing where
    a beam meets it more than ``cutoff`` from its normal (a real laser at grazing incidence).
    The laser stands at ``start_x`` for ``stand`` scans, then drives ``step`` per scan; 10 Hz.
    """
    x = start_x
    for k in range(stand + moves):
        if k >= stand:
            x += step
        yield 0.1 * k, (x, 0.0, 0.0), grazing_wall_ranges(0.0, cutoff)


def grazing_wall_ranges(yaw, cutoff=math.radians(75)):
    """Ranges to the wall of `grazing_wall_scans` from a laser at y = 0 heading ``yaw``."""
    ranges = np.full(BEAMS, np.inf)
    for i in range(BEAMS):
        theta = yaw + ANGLE_MIN + i * INCREMENT
        if math.sin(theta) > 1e-9 and abs(math.pi / 2 - theta) <= cutoff:
            ranges[i] = WALL_Y / math.sin(theta)
    ranges[ranges >= 8.0] = np.inf
    return ranges


def wall_cells_ever_mobile(grid, scans):
    """Return how many cells of the wall's row were ever labelled mobile."""
    row, _ = grid.geometry.world_to_cell(0.0, WALL_Y)
    ever = np.zeros(grid.labels.shape[1], dtype=bool)
    for stamp, pose, ranges in scans:
        grid.update(pose, ranges, ANGLE_MIN, INCREMENT, 0.1, 8.0, 0.6, stamp=stamp)
        ever |= grid.labels[row] == CellLabel.MOBILE_OBSTACLE
    return int(np.count_nonzero(ever))


@pytest.mark.parametrize('standing_distance, wall_ever_mobile', [(0.0, True), (0.1, False)])
def test_a_wall_at_grazing_incidence_stays_steady_when_no_return_beams_clear_only_standing(
        standing_distance, wall_ever_mobile):
    # Standing, the beams past the wall's grazing cut-off return nothing and show its far
    # part empty; driving along it, the wall turns towards the laser and its echoes land there.
    grid = grid_for(real_rule(no_return_reach=0.8, no_return_standing_distance=standing_distance,
                              no_return_standing_time=0.5))
    assert (wall_cells_ever_mobile(grid, grazing_wall_scans()) > 0) == wall_ever_mobile


def test_a_standing_laser_still_sees_a_walker_in_open_space_move():
    # Nothing behind the walker returns an echo: only beams with no return show its path
    # empty. Standing, they do (after the standing time); from a moving laser they do not.
    rule = real_rule(no_return_reach=0.8, no_return_standing_distance=0.1,
                     no_return_standing_time=0.5)
    walker = [(0.1 * k, cast(0.0, 100.0, [(2.5, -1.5 + 0.15 * k)]),
               [(2.5, -1.5 + 0.15 * k)]) for k in range(25)]
    assert ever_mobile(grid_for(rule), walker, [])[1]
    grid = grid_for(rule)
    for k, (stamp, ranges, _) in enumerate(walker):
        grid.update((-0.2 * k, 0.0, 0.0), cast(-0.2 * k, 100.0, [(2.5, -1.5 + 0.15 * k)]),
                    ANGLE_MIN, INCREMENT, 0.1, 8.0, 0.6, stamp=stamp)
        assert not grid.laser_standing.standing
        assert not (grid.labels == CellLabel.MOBILE_OBSTACLE).any()


def test_no_return_beams_clear_standing_equals_its_literal_twin():
    # The laser's standing, from the definition (`LiteralStanding`), composed with the literal
    # rule: no_return_reach while it stands, 0 while it moves, evidence dropped as it starts.
    rule = real_rule(no_return_reach=0.8, no_return_standing_distance=0.1,
                     no_return_standing_time=0.5)
    literal_rule = dataclasses.replace(rule, no_return_standing_distance=0.0)
    side = 8.0
    grid = grid_for(rule, side)
    state = twin_state(grid, rule, side)
    origin, labels, seen_free, last_hit, fine_seen_free, _, surfaces = state
    standing = LiteralStanding(0.1, 0.5)
    last_stamp = -math.inf
    states = []
    # Stands, drives along the wall, stands again (jittering 5 cm, turning), drives on.
    scans = list(grazing_wall_scans(stand=8, moves=6)) + [
        (3.0 + 0.1 * k, (-1.5 + 0.05 * (k % 2), 0.0, 0.1 * k), grazing_wall_ranges(0.1 * k))
        for k in range(9)]
    scans += [(4.0 + 0.1 * k, (-1.5 + 0.3 * k, 0.0, 0.0), ranges)
              for k, (_, _, ranges) in enumerate(grazing_wall_scans(start_x=-1.5, stand=0,
                                                                    moves=5, step=0.3))]
    dropped = 0
    for stamp, pose, ranges in scans:
        if standing.step(pose[0], pose[1], stamp):
            # Started to move: the free evidence goes (coarse and fine).
            dropped += int(np.count_nonzero(seen_free) + np.count_nonzero(fine_seen_free))
            seen_free[...] = False
            fine_seen_free[...] = False
        states.append(standing.standing)
        reach = rule.no_return_reach if standing.standing else 0.0
        _, last_stamp = literal_update_with_rule(
            labels, seen_free, last_hit, origin, 0.5, pose, ranges, ANGLE_MIN, INCREMENT, 0.1,
            8.0, 0.6, rule=dataclasses.replace(literal_rule, no_return_reach=reach),
            stamp=stamp, last_stamp=last_stamp, fine_seen_free=fine_seen_free,
            surfaces=surfaces)
        grid.update(pose, ranges, ANGLE_MIN, INCREMENT, 0.1, 8.0, 0.6, stamp=stamp)
        assert grid.laser_standing.standing == standing.standing
        assert_array_equal(grid.labels, labels)
        assert_array_equal(grid.seen_free, seen_free)
        assert_array_equal(grid.fine_evidence.seen_free, fine_seen_free)
    # The scene stands, moves and stands again (twice a start), and drops evidence.
    assert dropped > 0
    assert states[:4] == [False] * 4 and states[6] and not states[9]
    assert sum(1 for a, b in zip(states, states[1:]) if a and not b) == 2


def test_laser_standing_follows_the_place_and_the_clock():
    standing = LaserStanding(0.1, 0.5)
    assert not standing.step((0.0, 0.0), 0.0)
    assert not standing.standing
    standing.step((0.05, 0.0), 0.4)
    assert not standing.standing
    standing.step((0.0, 0.08), 0.5)
    assert standing.standing                      # 0.5 s within 0.1 m of the place
    assert standing.step((0.2, 0.0), 0.6)         # it started to move
    assert not standing.standing
    assert not standing.step((0.4, 0.0), 0.7)     # moving on is no new start
    standing.step((0.4, 0.0), 0.2)                # time went back: it arrived then
    standing.step((0.4, 0.0), 0.69)
    assert not standing.standing
    standing.step((0.4, 0.0), 0.75)
    assert standing.standing
    standing.reset()
    assert not standing.step((0.4, 0.0), 5.0) and not standing.standing
    for distance, time in ((0.0, 1.0), (-0.1, 1.0), (math.inf, 1.0), (0.1, -1.0),
                           (0.1, math.nan)):
        with pytest.raises(ValueError):
            LaserStanding(distance, time)


def test_bad_standing_parameters_raise():
    for name in ('no_return_standing_distance', 'no_return_standing_time'):
        for value in (-0.1, math.inf, math.nan):
            with pytest.raises(ValueError, match=name):
                LabelRule(**{name: value})
    assert LabelRule().no_return_standing_distance == 0.0      # off in the paper


def walker_along_a_wall(bridge_beams, lost_share, seed, beams=721, scans=80):
    """
    Run a walker along a wall past a laser that loses ``lost_share`` of its returns.

    The laser stands 5 m from the wall; a disc (r 0.25 m) walks along it, 0.6 m from it, at
    0.8 m/s. Returns (mobile cells farther than 0.95 m from the walker, summed over the
    scans; scans with the walker's near rim mobile).
    """
    rule = NavigatorConfig(width=1.0, height=1.0, segment_bridge_beams=bridge_beams)
    grid = LabelGrid(width=12.0, height=12.0, rule=rule.label_rule())
    scan = {'angle_min': -math.pi / 2, 'angle_increment': math.pi / (beams - 1),
            'range_min': 0.1, 'range_max': 20.0}
    angles = scan['angle_min'] + np.arange(beams) * scan['angle_increment']
    ux, uy = np.cos(angles), np.sin(angles)
    laser, wall_x = (1.0, 6.0, 0.0), 6.0
    rng = np.random.default_rng(seed)
    far = found = 0
    for step in range(scans):
        centre = (5.4, 3.0 + 0.08 * step)
        ranges = np.full(beams, np.inf)
        ahead = ux > 1e-9
        ranges[ahead] = (wall_x - laser[0]) / ux[ahead]
        ox, oy = centre[0] - laser[0], centre[1] - laser[1]
        along = ox * ux + oy * uy
        inside = 0.25 ** 2 - (ox * ox + oy * oy - along * along)
        hit = (inside >= 0.0) & (along > 0.0)
        ranges[hit] = np.minimum(ranges[hit], along[hit] - np.sqrt(inside[hit]))
        ranges[rng.random(beams) < lost_share] = np.inf
        grid.update(laser, ranges, safety_radius=0.6, stamp=step / 10, **scan)
        rows, cols = np.nonzero(grid.labels == CellLabel.MOBILE_OBSTACLE)
        x, y = grid.geometry.cell_to_world(rows, cols)
        far += int(np.count_nonzero(np.hypot(x - centre[0], y - centre[1]) > 0.95))
        rr, cc = grid.geometry.world_to_cell(np.array([centre[0] - 0.25]), np.array([centre[1]]))
        found += grid.labels[rr[0], cc[0]] == CellLabel.MOBILE_OBSTACLE
    return far, found


@pytest.mark.parametrize('seed', range(2))
def test_lost_returns_in_a_wall_do_not_let_it_follow_a_walker(seed):
    # Every beam without a hit ends a segment (0, the paper): lost returns cut the wall into
    # short pieces that stand free, and those next to the walker continue its track. dpn
    # bridges 2 beams.
    assert NavigatorConfig(width=1.0, height=1.0).segment_bridge_beams == 2
    assert NavigatorConfig(width=1.0, height=1.0).label_rule().segment_bridge_beams == 2
    assert NavigatorConfig(width=1.0, height=1.0,
                           segment_bridge_beams=0).label_rule().segment_bridge_beams == 0
    cut_far, cut_found = walker_along_a_wall(0, 0.03, seed)
    bridged_far, bridged_found = walker_along_a_wall(2, 0.03, seed)
    assert cut_far > 50 and bridged_far == 0
    assert bridged_found >= cut_found - 2 and bridged_found > 60       # the walker: mobile
    # With every return, the rule changes nothing.
    assert walker_along_a_wall(0, 0.0, seed) == walker_along_a_wall(2, 0.0, seed)


def test_bad_segment_bridge_beams_raise():
    for value in (-1, 1.5, True):
        with pytest.raises(ValueError, match='segment_bridge_beams'):
            LabelRule(segment_bridge_beams=value)
    with pytest.raises(ValueError, match='bridge_beams'):
        from dpn_navigator.core.mapping.motion_tracks import TrackConfig
        TrackConfig(bridge_beams=-1)
