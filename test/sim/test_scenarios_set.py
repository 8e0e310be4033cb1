"""
Tests of the benchmark set of 34 maps: the index, and every task on its static map.

A task is solvable for the Husky when a disc of its half width plus the navigator's safety
radius can travel from start to goal, and when the navigator's own A*, on its 0.5 m grid with
every cell within the safety radius of a wall blocked (the grid it faces once it has seen every
wall), finds a path. The narrow-route maps must also be really narrow: a slightly wider robot
finds no way through.

The building blocks of the designs (shapes, walls with doors, mazes, scattered posts) are
tested on tiny grids at the end. No ROS and no pybullet: files, numpy and the navigator's A*.

"""

import functools
import itertools
import math

from dpn_navigator.core import astar, GridGeometry, NavigatorConfig
import numpy as np
from numpy.testing import assert_array_equal
import pytest

from sim_bridge.free_space import clearance_grid, label_components, near_cells
from sim_bridge.scenario import load_index, load_scenario
from sim_bridge.scenarios.catalogue import DESIGNS
from sim_bridge.scenarios.design import hwall, MIN_PASSAGE, random_stream, vwall
from sim_bridge.scenarios.families import maze, runs_of, scatter
from sim_bridge.scenarios.shapes import Blocky, Disc, Free, rasterize, Rect, Segment
from sim_bridge.tasks import DEFAULT_TASK_CLEARANCE

#: The paper's named maps, at the paper's numbers.
NAMED_MAPS = {3: 'back_and_forth', 15: 'maze', 23: 'square_spiral', 26: 'tunnel_twisted',
              27: 'tunnel'}
#: The Husky's half width: its 0.67 m, halved and rounded up [m].
HUSKY_HALF_WIDTH = 0.35
#: What the navigator keeps between the Husky's centre and a wall [m].
SAFETY_RADIUS = NavigatorConfig(width=1.0, height=1.0).safety_radius
#: Half a pixel [m]. A pixel of a clearance grid is clear when all of it keeps the clearance,
#: so its centre keeps the clearance plus half a pixel from the walls of a straight corridor.
HALF_PIXEL = 0.05
#: Least width of a passage on the other maps' routes [m].
WIDE_PASSAGE = 2.5

NARROW = sorted(design.name for design in DESIGNS if design.passage == MIN_PASSAGE)
WIDE = sorted(design.name for design in DESIGNS if design.passage > MIN_PASSAGE)


@functools.lru_cache(maxsize=None)
def scenario(name):
    """Return the built-in scenario ``name``, loaded once."""
    return load_scenario(name)


@functools.lru_cache(maxsize=None)
def connections(name, centre_clearance):
    """
    Return, for each task of a map, whether a disc fits at start and goal and between them.

    Parameters
    ----------
    name : str
        The scenario.
    centre_clearance : float
        Least distance from the disc's centre to any wall along a straight corridor [m].

    Returns
    -------
    tuple of (bool, bool, bool)
        Per task: start clear, goal clear, both in one component.

    """
    found = scenario(name)
    grid = clearance_grid(found.free, found.geometry, centre_clearance - HALF_PIXEL,
                          cell_size=found.resolution)
    result = []
    for spec in found.tasks:
        start, goal = grid.cell_of(*spec.start[:2]), grid.cell_of(*spec.goal)
        both = bool(grid.clear[start]) and bool(grid.clear[goal])
        result.append((bool(grid.clear[start]), bool(grid.clear[goal]),
                       both and grid.labels[start] == grid.labels[goal]))
    return tuple(result)


def navigator_blocked(found, config):
    """
    Return the navigator's grid with every cell within the safety radius of a wall blocked.

    Parameters
    ----------
    found : Scenario
        The map; its wall pixels are squares.
    config : NavigatorConfig
        The navigator's grid and safety radius.

    Returns
    -------
    geometry : GridGeometry
        The navigator's grid.
    blocked : (rows, cols) ndarray of bool
        True where some point of a wall pixel lies within ``safety_radius`` of the centre.

    """
    geometry = GridGeometry(config.width, config.height, config.resolution, config.origin)
    xc, yc = geometry.cell_to_world(*np.indices(geometry.shape))
    res = found.resolution
    reach = int(math.ceil(config.safety_radius / res)) + 1
    rr, cc = found.geometry.world_to_cell(xc, yc)
    # The navigator's last row and column may reach past the map; beyond it all is wall.
    pad = reach + int(math.ceil(config.resolution / res))
    walls = np.pad(found.occupied, pad, constant_values=True)
    px, py = found.geometry.cell_to_world(rr, cc)
    blocked = np.zeros(geometry.shape, dtype=bool)
    for dr in range(-reach, reach + 1):
        for dc in range(-reach, reach + 1):
            wall = walls[rr + dr + pad, cc + dc + pad]
            gap_x = np.maximum(np.abs(xc - px - dc * res) - 0.5 * res, 0.0)
            gap_y = np.maximum(np.abs(yc - py - dr * res) - 0.5 * res, 0.0)
            blocked |= wall & (np.hypot(gap_x, gap_y) <= config.safety_radius)
    return geometry, blocked


def wall_distance(found, x, y):
    """Return the distance from map-frame ``(x, y)`` to the nearest wall pixel [m]."""
    res = found.resolution
    rr, cc = np.nonzero(found.occupied)
    px, py = found.geometry.cell_to_world(rr, cc)
    gap = np.hypot(np.maximum(np.abs(px - x) - 0.5 * res, 0.0),
                   np.maximum(np.abs(py - y) - 0.5 * res, 0.0))
    return float(gap.min())


# -- the index ----------------------------------------------------------------------------


def test_the_index_lists_34_maps_with_the_named_ones_in_place():
    entries = load_index()
    assert [entry.number for entry in entries] == list(range(1, 35))
    assert len({entry.name for entry in entries}) == 34
    assert {entry.number: entry.name for entry in entries if entry.number in NAMED_MAPS} == \
        NAMED_MAPS
    assert [(entry.number, entry.name) for entry in entries] == \
        [(design.number, design.name) for design in DESIGNS]
    for entry in entries:
        assert entry.map_yaml.name == f'{entry.name}.yaml' and len(entry.tasks) == 3
        assert entry.family and entry.name.isidentifier() and entry.name.islower()


@pytest.mark.parametrize('name', sorted(design.name for design in DESIGNS))
def test_map_size_resolution_and_closure(name):
    found = scenario(name)
    assert found.resolution == 0.1 and found.origin == (0.0, 0.0)
    assert 20.0 <= max(found.width, found.height) <= 80.0
    assert min(found.width, found.height) >= 12.0
    # Closed all round: the border pixels are walls, and nothing is unknown.
    assert found.occupied[[0, -1], :].all() and found.occupied[:, [0, -1]].all()
    assert not (found.free == found.occupied).any()


# -- the tasks ----------------------------------------------------------------------------


@pytest.mark.parametrize('name', sorted(design.name for design in DESIGNS))
def test_tasks_keep_their_clearance_and_are_apart(name):
    found = scenario(name)
    for spec in found.tasks:
        for x, y in (spec.start[:2], spec.goal):
            assert wall_distance(found, x, y) >= DEFAULT_TASK_CLEARANCE, (x, y)
        assert math.dist(spec.start[:2], spec.goal) >= 5.0
        assert abs(spec.start[2]) <= round(math.pi, 4)   # as the index rounds it


@pytest.mark.parametrize('name', sorted(design.name for design in DESIGNS))
def test_tasks_are_solvable_for_the_husky(name):
    assert all(ok for _, _, ok in connections(name, HUSKY_HALF_WIDTH + SAFETY_RADIUS))


@pytest.mark.parametrize('name', sorted(design.name for design in DESIGNS))
def test_the_navigator_plans_each_task_once_it_knows_every_wall(name):
    found = scenario(name)
    config = NavigatorConfig(width=found.width, height=found.height, origin=found.origin)
    geometry, blocked = navigator_blocked(found, config)
    for spec in found.tasks:
        start = tuple(int(v) for v in geometry.world_to_cell(*spec.start[:2]))
        goal = tuple(int(v) for v in geometry.world_to_cell(*spec.goal))
        assert not blocked[goal], spec.goal
        assert astar(blocked, start, goal) is not None, spec


@pytest.mark.parametrize('name', NARROW)
def test_narrow_maps_are_no_wider_than_needed(name):
    # 0.15 m wider than the Husky plus its safety radius: no task can be done, and for one at
    # least that is not for want of room at its ends but on the way.
    wider = connections(name, HUSKY_HALF_WIDTH + SAFETY_RADIUS + 0.15)
    assert not any(ok for _, _, ok in wider)
    assert any(start and goal and not ok for start, goal, ok in wider)


@pytest.mark.parametrize('name', WIDE)
def test_other_maps_leave_wider_passages(name):
    assert all(ok for _, _, ok in connections(name, 0.5 * WIDE_PASSAGE))


def test_the_narrow_route_maps():
    assert {'maze', 'square_spiral', 'tunnel_twisted', 'tunnel'} <= set(NARROW)
    assert len(NARROW) + len(WIDE) == 34
    assert all(design.passage >= WIDE_PASSAGE for design in DESIGNS if design.name in WIDE)


# -- building blocks ----------------------------------------------------------------------


def paint(*shapes, size=(0.5, 0.4)):
    """Rasterize shapes on a tiny 0.1 m grid; return the walls with row 0 at the bottom."""
    return rasterize(shapes, size, 0.1)[::-1] == 0


def test_shapes_take_the_pixels_whose_centre_lies_inside():
    # Pixel centres are at 0.05, 0.15, ...: the rectangle's edges on pixel edges are exact.
    assert_array_equal(paint(Rect(0.1, 0.0, 0.3, 0.2)), [[0, 1, 1, 0, 0], [0, 1, 1, 0, 0],
                                                         [0, 0, 0, 0, 0], [0, 0, 0, 0, 0]])
    # A ring keeps its hole: (0.15, 0.05) is 0.18 m from the centre, (0.05, 0.05) 0.25 m.
    assert_array_equal(paint(Disc(0.25, 0.2, 0.2, inner=0.1)),
                       [[0, 1, 1, 1, 0], [0, 1, 0, 1, 0], [0, 1, 0, 1, 0], [0, 1, 1, 1, 0]])
    # A slanted segment covers a diagonal.
    assert_array_equal(paint(Segment(0.05, 0.05, 0.35, 0.35, 0.1)),
                       [[1, 0, 0, 0, 0], [0, 1, 0, 0, 0], [0, 0, 1, 0, 0], [0, 0, 0, 1, 0]])


def test_free_carves_and_blocky_fills_whole_blocks():
    solid = Rect(0.0, 0.0, 0.5, 0.4)
    assert_array_equal(paint(solid, Free(Rect(0.1, 0.1, 0.4, 0.2))),
                       [[1, 1, 1, 1, 1], [1, 0, 0, 0, 1], [1, 1, 1, 1, 1], [1, 1, 1, 1, 1]])
    # One pixel of the segment in a 0.2 m block makes the whole block wall.
    assert_array_equal(paint(Blocky(Segment(0.05, 0.05, 0.25, 0.05, 0.05), 0.2, 0.1)),
                       [[1, 1, 1, 1, 0], [1, 1, 1, 1, 0], [0, 0, 0, 0, 0], [0, 0, 0, 0, 0]])


def test_shapes_must_have_a_finite_extent():
    with pytest.raises(ValueError, match='no finite extent'):
        paint(Rect(0.0, 0.0, math.inf, 0.2))
    with pytest.raises(ValueError, match='no finite extent'):
        paint(Rect(0.3, 0.0, 0.1, 0.2))


def test_walls_with_doors_and_runs():
    assert hwall(0.0, 10.0, 2.0, [(3.0, 5.0), (8.0, 10.0)]) == \
        [Rect(0.0, 2.0, 3.0, 2.2), Rect(5.0, 2.0, 8.0, 2.2)]
    assert vwall(1.0, 0.0, 4.0) == [Rect(1.0, 0.0, 1.2, 4.0)]
    assert runs_of([0, 1, 1, 0, 1]) == [(1, 3), (4, 5)]
    assert runs_of([]) == []


def test_random_stream_is_reproducible_and_in_range():
    first = list(itertools.islice(random_stream(7), 1000))
    assert first == list(itertools.islice(random_stream(7), 1000))
    assert first != list(itertools.islice(random_stream(8), 1000))
    assert 0.0 <= min(first) and max(first) < 1.0 and 0.4 < np.mean(first) < 0.6


def test_a_perfect_maze_joins_every_cell_once():
    # 4 x 3 cells of 2 m corridors and 0.2 m walls, closed all round.
    geometry = GridGeometry(9.0, 6.8, 0.1)

    def open_walls(walls):
        image = paint(*walls, size=(9.0, 6.8))
        assert image[[0, -1], :].all() and image[:, [0, -1]].all()
        middles = [((c + 1) * 2.2 + 0.1, 1.2 + 2.2 * r) for c in range(3) for r in range(3)] + \
            [(1.2 + 2.2 * c, (r + 1) * 2.2 + 0.1) for c in range(4) for r in range(2)]
        _, count = label_components(~image)
        return count, sum(not image[geometry.world_to_cell(x, y)] for x, y in middles)

    # A tree: one component, 12 cells joined by 11 of the 17 inner walls opened.
    assert open_walls(maze((0.0, 0.0), (4, 3), 2.0, seed=1)) == (1, 11)
    assert open_walls(maze((0.0, 0.0), (4, 3), 2.0, seed=1, loops=6)) == (1, 17)
    assert open_walls(maze((0.0, 0.0), (4, 3), 2.0, seed=1, rooms=((0, 0, 2, 2),)))[1] >= 11
    assert maze((0.0, 0.0), (4, 3), 2.0, seed=1) != maze((0.0, 0.0), (4, 3), 2.0, seed=2)


def test_scattered_posts_keep_their_gap():
    args = ((0.0, 0.0, 30.0, 30.0), 40, (0.5, 2.0))
    kwargs = {'seed': 3, 'gap': 2.5, 'round_share': 0.5, 'keep_out': [(15.0, 15.0, 4.0)]}
    posts = scatter(*args, **kwargs)
    assert 10 <= len(posts) <= 40 and posts == scatter(*args, **kwargs)
    assert any(isinstance(post, Disc) for post in posts)
    assert any(isinstance(post, Blocky) for post in scatter(*args, round_step=0.5, **kwargs))
    image = paint(*posts, size=(30.0, 30.0))
    x, y = GridGeometry(30.0, 30.0, 0.1).cell_to_world(*np.nonzero(image))
    assert np.hypot(x - 15.0, y - 15.0).min() >= 4.0
    labels, count = label_components(image)
    assert count == len(posts)
    # Two posts are 2.5 m apart, less the rounding to pixels; 2.5 m from the edges as well.
    for k in range(1, count + 1):
        assert not (near_cells(labels == k, 23.0) & (labels > 0) & (labels != k)).any()
    assert not near_cells(image, 23.0)[[0, -1], :].any()
    assert not near_cells(image, 23.0)[:, [0, -1]].any()
