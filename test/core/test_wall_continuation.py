"""
Walls that go on where a real laser stops seeing them, and what their cells cost.

``mapping.wall_continuation`` gives the points; ``ExplorationMemory`` and the navigator's
``wall_continuation_*`` settings price their non-explored cells.

The points are checked against a plain-Python twin on random scans, and on a corridor whose
walls the laser sees up to a grazing cut-off: they lie on the walls' lines, past the last hits,
as far as the beams with no return would meet them.
"""

import math

from dpn_navigator.core import CellLabel, Navigator, NavigatorConfig
from dpn_navigator.core.mapping.wall_continuation import continued_walls, POINT_STEP
from dpn_navigator.core.planning.exploration_memory import ExplorationMemory
from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
from numpy.testing import assert_allclose
import pytest
from wall_continuation_reference import reference_continued_walls

CUT_OFF = math.radians(75.0)          # the UTM-30LX profile's grazing cut-off


def corridor_scan(half_width=1.0, beams=1081, fov=math.radians(270.0), range_max=30.0,
                  cut_off=CUT_OFF, wall_end=None):
    """
    Return the scan of a laser at the origin between walls ``y = +-half_width``, along ``x``.

    A beam returns only where it meets a wall within ``cut_off`` of its normal (and before
    ``wall_end`` [m] along ``x``, when given); the rest return nothing (``+inf``).
    """
    angle_min = -fov / 2.0
    increment = fov / (beams - 1)
    angles = angle_min + increment * np.arange(beams)
    sin = np.sin(angles)
    with np.errstate(divide='ignore'):
        ranges = np.where(np.abs(sin) > 1e-12, half_width / np.abs(sin), np.inf)
    incidence = np.abs(np.pi / 2.0 - np.abs(angles))            # from the wall's normal (y)
    x = ranges * np.cos(angles)
    seen = (incidence < cut_off) & (ranges < range_max)
    if wall_end is not None:
        seen &= x < wall_end
    return np.where(seen, ranges, np.inf), angle_min, increment, range_max


def test_a_corridors_walls_go_on_along_their_lines_past_the_last_hits():
    ranges, angle_min, increment, range_max = corridor_scan()
    points = continued_walls(ranges, angle_min, increment, 0.1, range_max, math.radians(60.0),
                             8.0)
    assert_allclose(np.abs(points[:, 1]), 1.0, atol=1e-9)      # on the walls' lines
    # Only ahead: the beams from -15 to 15 deg return nothing (behind, the 270-degree laser
    # sees the walls up to its last beam).
    assert (points[:, 0] > 0.0).all()
    last_hit_x = 1.0 / math.tan(math.pi / 2.0 - CUT_OFF)        # 3.73 m ahead
    for wall in (-1.0, 1.0):
        x = points[np.isclose(points[:, 1], wall)][:, 0]
        assert last_hit_x < x.min() <= last_hit_x + POINT_STEP + 0.01
        # Out to the reach, less the spacing of the beams there (0.25 deg: 0.6 m at 12 m).
        assert last_hit_x + 8.0 - 0.6 <= x.max() <= last_hit_x + 8.0 + 0.01
        assert_allclose(np.diff(np.sort(x)), POINT_STEP)
    short = continued_walls(ranges, angle_min, increment, 0.1, range_max, math.radians(60.0),
                            2.0)
    assert last_hit_x + 2.0 - 0.3 <= short[:, 0].max() <= last_hit_x + 2.0 + 0.01


def test_the_continuation_ends_where_the_last_beam_with_no_return_meets_the_line():
    # One beam a degree: the beam 2 deg off the corridor meets its walls 28.65 m away, within
    # the 30 m range; the one 1 deg off at 57 m, beyond it: the continuation ends at 2 deg.
    ranges, angle_min, increment, range_max = corridor_scan(fov=math.radians(160.0),
                                                            beams=161)
    points = continued_walls(ranges, angle_min, increment, 0.1, range_max, math.radians(60.0),
                             50.0)
    farthest = 1.0 / math.tan(math.radians(2.0))
    assert farthest - POINT_STEP < points[:, 0].max() <= farthest


def test_a_wall_seen_squarely_or_one_hit_short_does_not_go_on():
    # Incidence below the angle: a 75-degree cut-off seen with an angle of 80 degrees.
    ranges, angle_min, increment, range_max = corridor_scan()
    assert continued_walls(ranges, angle_min, increment, 0.1, range_max, math.radians(80.0),
                           8.0).shape == (0, 2)
    # A wall that ends where the laser sees it squarely: its last hits face the laser.
    ranges, angle_min, increment, range_max = corridor_scan(wall_end=0.5)
    points = continued_walls(ranges, angle_min, increment, 0.1, range_max, math.radians(60.0),
                             8.0)
    assert not (points[:, 0] > 0.0).any()
    # A depth gap among the hits that give the left wall's line, or an invalid one: that wall
    # does not go on; the right one does.
    ranges, angle_min, increment, range_max = corridor_scan()
    angles = angle_min + increment * np.arange(ranges.size)
    left = int(np.flatnonzero(np.isfinite(ranges) & (angles > 0.0))[0])     # its last hit
    gapped = ranges.copy()
    gapped[left + 1] += 0.5
    invalid = ranges.copy()
    invalid[left + 2] = np.nan
    for broken in (gapped, invalid):
        points = continued_walls(broken, angle_min, increment, 0.1, range_max,
                                 math.radians(60.0), 8.0)
        assert not (points[:, 1] > 0.0).any()
        assert (points[:, 1] < 0.0).any()


@st.composite
def scans(draw):
    """Random scans made of wall pieces, gaps with no return and bad readings."""
    beams = draw(st.integers(2, 120))
    angle_min = draw(st.floats(-math.pi, 0.0))
    increment = draw(st.floats(0.002, 0.06))
    angles = angle_min + increment * np.arange(beams)
    ranges = np.full(beams, np.inf)
    start = 0
    while start < beams:
        length = draw(st.integers(1, 40))
        kind = draw(st.sampled_from(['wall', 'none', 'bad']))
        part = slice(start, start + length)
        if kind == 'wall':
            distance = draw(st.floats(0.3, 12.0))
            normal = draw(st.floats(-math.pi, math.pi))
            facing = np.cos(angles[part] - normal)
            with np.errstate(divide='ignore'):
                ranges[part] = np.where(facing > 1e-3, distance / facing, np.inf)
        elif kind == 'bad':
            ranges[part] = draw(st.sampled_from([np.nan, -np.inf, 0.01]))
        start += length
    range_max = draw(st.floats(2.0, 30.0))
    ranges[np.isfinite(ranges) & (ranges > range_max)] = np.inf
    return ranges, angle_min, increment, range_max


@settings(max_examples=300, deadline=None)
@given(scans(), st.floats(0.2, 1.4), st.floats(0.5, 20.0))
def test_the_points_are_the_plain_twins(scan, min_incidence, reach):
    ranges, angle_min, increment, range_max = scan
    points = continued_walls(ranges, angle_min, increment, 0.1, range_max, min_incidence,
                             reach)
    expected = reference_continued_walls(ranges.tolist(), angle_min, increment, 0.1,
                                         range_max, min_incidence, reach)
    assert points.shape == (len(expected), 2)
    if expected:
        assert_allclose(points, np.array(expected), atol=1e-9)


def test_only_non_explored_cells_are_marked_and_they_cost_the_most():
    memory = ExplorationMemory((3, 4), unknown_cost=1.0, forgotten_cost=20.0,
                               continued_cost=100.0)
    labels = np.full((3, 4), CellLabel.NON_EXPLORED, dtype=np.uint8)
    labels[0, 1] = CellLabel.EXPLORED
    memory.once_blocked[2, 2] = True
    memory.continue_walls(labels, np.array([0, 0, 1, 2]), np.array([0, 1, 1, 2]))
    assert memory.continued.sum() == 3 and not memory.continued[0, 1]
    cost = memory.cost(labels)
    assert cost[0, 0] == cost[1, 1] == cost[2, 2] == 100.0
    assert cost[0, 1] == 0.0 and cost[2, 0] == 1.0
    # Seen and explored later, a marked cell costs nothing more.
    labels[1, 1] = CellLabel.EXPLORED
    assert memory.cost(labels)[1, 1] == 0.0
    assert memory.max_cost == 100.0
    # Off: no cells kept.
    assert ExplorationMemory((3, 4), 1.0, 20.0).continued is None
    with pytest.raises(ValueError, match='continued_cost'):
        ExplorationMemory((3, 4), 1.0, 20.0, continued_cost=-1.0)


def test_a_navigator_plans_round_a_wall_that_goes_on_not_through_it():
    """
    Plan round a wall that goes on: a robot in a corridor, its goal beyond the north wall.

    The robot is in a 2 m corridor (y 4-6 m) and sees its walls up to the grazing cut-off; the
    goal lies beyond the north wall, 6 m ahead. Beams with no return clear nothing (a real laser's
    file). A* goes through the unseen wall; with the wall going on, round it.
    """
    half = 1.0
    ranges, angle_min, increment, range_max = corridor_scan(half_width=half)
    paths = {}
    for angle in (0.0, math.radians(60.0)):
        config = NavigatorConfig(width=30.0, height=10.0, forget_obstacles_after=0.0,
                                 no_return_reach=0.0, wall_continuation_angle=angle)
        navigator = Navigator(config)
        navigator.set_goal(8.0, 8.5)
        navigator.step(0.0, (2.0, 5.0, 0.0), ranges, angle_min, increment, 0.1, range_max)
        paths[angle] = navigator.grid.geometry.cell_to_world(*navigator.path.T)
        path = navigator.path
        memory = navigator._exploration
        if angle == 0.0:
            assert memory is None or memory.continued is None
        else:
            continued = memory.continued
            x, y = navigator.grid.geometry.cell_to_world(*np.nonzero(continued))
            assert len(x) > 0 and np.all(np.abs(np.abs(y - 5.0) - half) <= 0.25 + 1e-9)
    # Where the path leaves the corridor northwards (y above 6 m).
    leave = {angle: xy[0][np.argmax(xy[1] > 6.0)] for angle, xy in paths.items()}
    seen_end = 2.0 + 1.0 / math.tan(math.pi / 2.0 - CUT_OFF)   # the last hit, x 5.73 m
    assert seen_end < leave[0.0] < seen_end + 4.0          # through the unseen wall
    # Round it: back west past the wall's end the laser saw (x 1 m, its field of view's
    # edge), or east past the continuation's end; never across it.
    with_it = leave[math.radians(60.0)]
    assert with_it < 2.0 or with_it > seen_end + 8.0 - 0.6
    assert not continued[tuple(path.T)].any()


def test_bad_settings_are_refused():
    size = {'width': 10.0, 'height': 10.0}
    with pytest.raises(ValueError, match='wall_continuation_angle'):
        NavigatorConfig(**size, wall_continuation_angle=math.pi / 2)
    with pytest.raises(ValueError, match='wall_continuation_reach'):
        NavigatorConfig(**size, wall_continuation_reach=0.0)
    with pytest.raises(ValueError, match='wall_continuation_cost'):
        NavigatorConfig(**size, wall_continuation_cost=-1.0)


@pytest.mark.parametrize('min_incidence, reach, match', [
    (0.0, 8.0, 'min_incidence'), (math.pi / 2, 8.0, 'min_incidence'),
    (1.0, 0.0, 'reach'), (1.0, math.inf, 'reach'), (math.nan, 8.0, 'min_incidence')])
def test_bad_arguments_are_refused(min_incidence, reach, match):
    ranges, angle_min, increment, range_max = corridor_scan()
    with pytest.raises(ValueError, match=match):
        continued_walls(ranges, angle_min, increment, 0.1, range_max, min_incidence, reach)


def test_a_driver_s_no_echo_codes_count_as_no_return_when_read_so():
    """With ``no_echo_below_range_min`` the tiny no-echo codes are beams with no return."""
    ranges, angle_min, increment, range_max = corridor_scan()
    coded = np.where(np.isfinite(ranges), ranges, 0.005)            # the old Hokuyo driver
    marked = {}
    for no_echo in (False, True):
        config = NavigatorConfig(width=30.0, height=10.0, forget_obstacles_after=0.0,
                                 no_return_reach=0.0, no_echo_below_range_min=no_echo,
                                 wall_continuation_angle=math.radians(60.0))
        navigator = Navigator(config)
        navigator.set_goal(8.0, 8.5)
        navigator.step(0.0, (2.0, 5.0, 0.0), coded, angle_min, increment, 0.1, range_max)
        marked[no_echo] = int(navigator._exploration.continued.sum())
    assert marked[False] == 0 and marked[True] > 0
