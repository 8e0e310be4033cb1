"""
Maps that grow (issue 29): the grid grows by whole blocks, every cell keeps its place.

A navigator whose map grows as the robot and its scans near the edges labels every cell as a
navigator given a map large enough from the start does; a growth beyond the memory limit is
refused and counted; a goal behind a robot that starts at the corner of its map is reached.
"""

import math

from dpn_navigator.core import Navigator, NavigatorConfig, NavigatorStatus
from dpn_navigator.core.grid_geometry import GridGeometry
from dpn_navigator.core.mapping.map_growth import (embed_at, GridGrowth, growth_to_cover,
                                                   subgrid_offset)
import numpy as np
from numpy.testing import assert_array_equal
import pytest

BEAMS = 360
ANGLE_MIN = -math.pi
ANGLE_INCREMENT = 2.0 * math.pi / BEAMS
RANGE_MIN, RANGE_MAX = 0.1, 30.0
#: A 180-degree laser's: it sees one side of the room at a time.
HALF = (181, -0.5 * math.pi, math.pi / 180.0)


def room_scan(pose, room, layout=(BEAMS, ANGLE_MIN, ANGLE_INCREMENT)):
    """
    Return the ranges [m] a laser at ``pose`` measures inside a rectangle room.

    ``room`` is ``(x_min, x_max, y_min, y_max)`` [m]; ``layout`` is ``(beams, angle_min,
    angle_increment)``, 360 degrees by default; exact ray casting, every beam returns.
    """
    x, y, yaw = pose
    beams, angle_min, angle_increment = layout
    theta = yaw + angle_min + np.arange(beams) * angle_increment
    dx, dy = np.cos(theta), np.sin(theta)
    with np.errstate(divide='ignore'):
        tx = np.where(dx > 0, (room[1] - x) / dx, np.where(dx < 0, (room[0] - x) / dx, np.inf))
        ty = np.where(dy > 0, (room[3] - y) / dy, np.where(dy < 0, (room[2] - y) / dy, np.inf))
    return np.minimum(tx, ty)


def observe(navigator, pose, room, stamp, layout=(BEAMS, ANGLE_MIN, ANGLE_INCREMENT)):
    navigator.observe(pose, room_scan(pose, room, layout), layout[1], layout[2], RANGE_MIN,
                      RANGE_MAX, stamp=stamp)
    navigator.settle()


def test_growth_covers_a_box_in_whole_blocks():
    geometry = GridGeometry(10.0, 8.0, 0.5, (0.0, 0.0))
    assert not growth_to_cover(geometry, 1.0, 9.0, 1.0, 7.0, 10)
    growth = growth_to_cover(geometry, -0.1, 9.0, 1.0, 13.5, 10)
    assert growth == GridGrowth(below=0, above=20, left=10, right=0)
    grown = growth.geometry(geometry)
    assert grown.shape == (16 + 20, 20 + 10)
    assert grown.origin == pytest.approx((-5.0, 0.0))
    # The old cell (i, j) is the new (i + below, j + left), at the same centre.
    assert np.allclose(geometry.cell_to_world(3, 4), grown.cell_to_world(3, 4 + 10))
    flat = np.array([3 * 20 + 4, 15 * 20 + 19])
    assert_array_equal(growth.remap(flat, 20, 30), [3 * 30 + 14, 15 * 30 + 29])
    with pytest.raises(ValueError, match='whole number'):
        GridGrowth(below=-1)
    with pytest.raises(ValueError, match='step'):
        growth_to_cover(geometry, 0.0, 1.0, 0.0, 1.0, 0)
    with pytest.raises(ValueError, match='does not fit'):
        embed_at(np.zeros((3, 3)), (3, 3), 1, 0, 0.0)
    # A finer grid whose origin moved by a fraction of its cell cannot keep its cells.
    fine = GridGeometry(10.0, 8.0, 0.2, (0.0, 0.0))
    assert subgrid_offset(fine, GridGeometry(10.5, 8.0, 0.2, (-0.5, 0.0))) is None
    assert subgrid_offset(fine, GridGeometry(11.0, 8.0, 0.2, (-1.0, 0.0))) == (0, 5)


def test_a_grown_map_labels_every_cell_where_a_large_map_does():
    room = (-8.0, 12.0, -6.0, 10.0)
    poses = [(5.0, 4.0, 0.0), (2.0, 1.0, 2.5), (-2.0, -1.0, 3.0), (-5.0, -3.0, -2.0),
             (0.0, 6.0, 1.0), (9.0, 7.0, 0.5), (9.5, -3.0, -1.0), (3.0, 2.0, 0.2)]
    growing = Navigator(NavigatorConfig(width=10.0, height=8.0, origin=(0.0, 0.0),
                                        map_growth_step=5.0, map_growth_margin=2.0))
    large = Navigator(NavigatorConfig(width=30.0, height=30.0, origin=(-10.0, -10.0)))
    shapes = {growing.grid.geometry.shape}
    for k, pose in enumerate(poses):
        observe(growing, pose, room, 0.1 * k, HALF)
        observe(large, pose, room, 0.1 * k, HALF)
        shapes.add(growing.grid.geometry.shape)
    assert growing.map_growths >= 2 and len(shapes) >= 3
    geometry = growing.grid.geometry
    # The room and the margin beyond its walls are covered, and no more than a block beyond.
    x0, y0 = geometry.origin
    assert x0 <= room[0] - 2.0 and y0 <= room[2] - 2.0
    assert x0 + geometry.width >= room[1] + 2.0 and y0 + geometry.height >= room[3] + 2.0
    assert growing.config.origin == geometry.origin
    assert growing.config.width == geometry.width
    rr, cc = np.indices(geometry.shape)
    x, y = geometry.cell_to_world(rr, cc)
    r_large, c_large = large.grid.geometry.world_to_cell(x, y)
    assert_array_equal(growing.grid.labels, large.grid.labels[r_large, c_large])
    assert np.count_nonzero(growing.grid.labels) > 500
    # The memories moved with their cells too.
    assert_array_equal(growing.grid.seen_free, large.grid.seen_free[r_large, c_large])
    assert_array_equal(growing.grid.last_hit, large.grid.last_hit[r_large, c_large])
    # Outside the grown map the large one saw nothing.
    outside = np.ones(large.grid.geometry.shape, dtype=bool)
    outside[r_large, c_large] = False
    assert not large.grid.labels[outside].any()


def test_the_memory_limit_refuses_growth_with_a_reason():
    config = NavigatorConfig(width=10.0, height=8.0, origin=(0.0, 0.0), map_growth_step=50.0,
                             map_memory_limit=1.0)
    navigator = Navigator(config)
    shape = navigator.grid.geometry.shape
    observe(navigator, (0.5, 0.5, 0.0), (-8.0, 12.0, -6.0, 10.0), 0.0)
    assert navigator.grid.geometry.shape == shape
    assert navigator.map_growths == 0
    assert navigator.map_growth_refusals == 1
    assert 'map_memory_limit 1 MB' in navigator.map_growth_refusal
    # The next scans ask for the same growth: refused, counted once.
    observe(navigator, (0.5, 0.5, 0.0), (-8.0, 12.0, -6.0, 10.0), 0.1)
    assert navigator.map_growth_refusals == 1
    with pytest.raises(ValueError, match='may not grow.*map_memory_limit'):
        navigator.set_goal(-3.0, 0.5)                   # another growth, refused too
    assert navigator.map_growth_refusals == 2
    with pytest.raises(ValueError, match='may not grow'):
        navigator.set_goal(-3.0, 0.5)
    assert navigator.map_growth_refusals == 2
    assert navigator.goal is None


def test_the_paper_map_stays_fixed():
    navigator = Navigator(NavigatorConfig(width=10.0, height=8.0, origin=(0.0, 0.0)))
    observe(navigator, (0.5, 0.5, 0.0), (-8.0, 12.0, -6.0, 10.0), 0.0)
    assert navigator.grid.geometry.shape == (16, 20)
    assert navigator.map_growths == navigator.map_growth_refusals == 0
    with pytest.raises(ValueError, match='outside the map$'):
        navigator.set_goal(-3.0, 0.0)


def test_a_goal_3_m_behind_a_robot_at_the_corner_of_its_map_is_reached():
    # The dpn node's defaults: a 25 m x 20 m map at origin (0, 0), the robot's odometry
    # starting at (0, 0): it stands on the map's corner.
    navigator = Navigator(NavigatorConfig(width=25.0, height=20.0, origin=(0.0, 0.0),
                                          map_growth_step=5.0))
    room = (-6.0, 6.0, -4.0, 4.0)
    pose = np.array([0.0, 0.0, 0.0])
    observe(navigator, tuple(pose), room, 0.0)
    assert navigator.grid.geometry.origin[0] <= -5.0
    navigator.set_goal(-3.0, 0.0)
    dt = 0.1
    for k in range(1, 400):
        stamp = k * dt
        observe(navigator, tuple(pose), room, stamp)
        out = navigator.decide(stamp, tuple(pose))
        if out.status is NavigatorStatus.GOAL_REACHED:
            break
        pose[2] += out.command.angular * dt
        pose[0] += out.command.linear * math.cos(pose[2]) * dt
        pose[1] += out.command.linear * math.sin(pose[2]) * dt
    assert out.status is NavigatorStatus.GOAL_REACHED, (navigator.status, navigator.reason, pose)
    assert math.hypot(pose[0] + 3.0, pose[1]) <= navigator.config.follower.goal_tolerance


def test_a_map_grows_no_further_than_its_cell_limit():
    # Without the memories (the paper's rule) the arrays are small; the cell limit still holds.
    navigator = Navigator(NavigatorConfig(
        width=10.0, height=8.0, resolution=0.05, map_growth_step=200.0, map_memory_limit=1e6,
        free_evidence_radius=0.0, moving_object_size=0.0, fine_evidence_resolution=0.0,
        fine_evidence_radius=0.0, surface_time=0.0, object_memory=0.0, track_confirm_time=0.0,
        track_still_distance=0.0, trail_distance=0.0))
    with pytest.raises(ValueError, match='would pass 4,194,304 cells'):
        navigator.set_goal(-3.0, 1.0)
    assert navigator.map_growth_refusals == 1 and navigator.map_growths == 0
