"""
Robot profiles (issue 29): the TurtleBot3 Burger beside the Husky, body, limits and laser.

Data-sheet values are checked against their sources' numbers; the world runs the Burger's box
body (contacts where its front meets a wall), its limits (commands clamped to 0.22 m/s and
2.84 rad/s) and its LDS-01 (360 beams of 1 degree, 0.12-3.5 m).
"""

import math

from dpn_navigator.core.grid_geometry import GridGeometry
import numpy as np
import pytest

from sim_bridge.husky import DriveLimits, HUSKY_LENGTH, HUSKY_WIDTH, LASER_MOUNT
from sim_bridge.laser_profiles import laser_config
from sim_bridge.robot_profiles import robot_profile, ROBOT_PROFILES
from sim_bridge.scenario import Scenario
from sim_bridge.tasks import Task
from sim_bridge.world import World, WorldConfig
from sim_bridge.world_parameters import robot_settings, WorldNodeParameters

BURGER = robot_profile('turtlebot3_burger')


def room(walls):
    """Return a 12 m square scenario at 0.1 m with wall rectangles ``(x0, y0, x1, y1)``."""
    geometry = GridGeometry(12.0, 12.0, 0.1)
    xs, ys = geometry.cell_to_world(*np.indices(geometry.shape))
    occupied = np.zeros(geometry.shape, dtype=bool)
    for x0, y0, x1, y1 in walls:
        occupied |= (xs > x0) & (xs < x1) & (ys > y0) & (ys < y1)
    return Scenario('room', occupied, ~occupied, 0.1, (0.0, 0.0),
                    (Task((6.0, 6.0, 0.0), (9.0, 6.0)),))


def burger_world(walls, drive=BURGER.drive):
    laser = laser_config('lds_01', noise_std=0.0, noise_fraction=0.0, dropout=0.0,
                         max_incidence=0.5 * math.pi,
                         mixed_pixel_probability=0.0, mount=BURGER.laser_mount,
                         height=BURGER.laser_height)
    return World(room(walls), WorldConfig(scan_rate=BURGER.scan_rate, drive=drive,
                                          body=BURGER.body, laser=laser))


def test_the_profiles_hold_their_data_sheet_values():
    assert set(ROBOT_PROFILES) == {'husky', 'turtlebot3_burger'}
    husky = robot_profile('husky')
    assert (husky.body.length, husky.body.width) == (HUSKY_LENGTH, HUSKY_WIDTH)
    assert husky.drive == DriveLimits() and husky.laser_mount == LASER_MOUNT
    assert (husky.laser_profile, husky.scan_rate) == ('ideal', 10.0)
    assert (BURGER.body.length, BURGER.body.width, BURGER.body.height) == (0.138, 0.178, 0.192)
    assert BURGER.body.radius == pytest.approx(0.1126, abs=1e-4)
    assert (BURGER.drive.max_linear, BURGER.drive.max_angular) == (0.22, 2.84)
    assert BURGER.laser_mount == (-0.032, 0.0, 0.0) and BURGER.laser_height == 0.182
    assert (BURGER.laser_profile, BURGER.scan_rate) == ('lds_01', 5.0)
    with pytest.raises(ValueError, match="unknown robot profile 'kobuki'.*husky"):
        robot_profile('kobuki')


def test_the_node_parameters_override_parts_of_a_profile():
    default = robot_settings(WorldNodeParameters())
    assert default.body == robot_profile('husky').body
    assert (default.laser_mount, default.laser_profile, default.scan_rate) == (
        LASER_MOUNT, 'ideal', 10.0)
    burger = robot_settings(WorldNodeParameters(robot_profile='turtlebot3_burger',
                                                max_vel_x=0.1, laser_yaw=0.5, robot_width=0.2))
    assert burger.drive.max_linear == 0.1 and burger.drive.max_angular == 2.84
    assert burger.laser_mount == (-0.032, 0.0, 0.5)
    assert (burger.body.length, burger.body.width) == (0.138, 0.2)
    assert (burger.laser_profile, burger.scan_rate) == ('lds_01', 5.0)
    with pytest.raises(ValueError, match=r'laser_x = 11.0 is outside \[-10.0, 10.0\]'):
        robot_settings(WorldNodeParameters(laser_x=11.0))
    with pytest.raises(ValueError, match='robot width must be a positive'):
        robot_settings(WorldNodeParameters(robot_width=-1.0))


def test_the_burger_is_clamped_to_its_limits_and_scans_360_degrees():
    with burger_world(()) as world:
        assert world.husky_footprint == (0.138, 0.178)
        world.set_command(1.0, 5.0)
        assert world.command == (0.22, 2.84)
        scan = world.scan()
        assert scan.ranges.shape == (360,)
        assert (scan.angle_min, math.degrees(scan.angle_increment)) == (0.0, pytest.approx(1.0))
        assert (scan.range_min, scan.range_max) == (0.12, 3.5)
        # Nothing within 3.5 m of the room's centre: no return on any beam (it misses itself).
        assert np.all(np.isposinf(scan.ranges))


def test_the_burger_body_meets_a_wall_with_its_front():
    # A wall 1 m ahead of the base: the box's front (0.069 m ahead) touches it after
    # (1 - 0.069) / 0.22 = 4.23 s at full speed.
    with burger_world(((7.0, 0.0, 7.2, 12.0),), drive=DriveLimits(
            max_linear=0.22, max_angular=2.84, max_linear_accel=None,
            max_angular_accel=None)) as world:
        scan = world.scan()
        assert scan.ranges[0] == pytest.approx(1.0 + 0.032, abs=1e-3)     # beam 0 ahead
        for _ in range(300):
            world.step(0.22, 0.0)
        assert world.contacts.wall_events == 1
        assert world.contacts.first_wall_time == pytest.approx(4.23, abs=0.05)
        assert 6.92 < world.husky_pose[0] < 6.94


def test_an_unhashable_profile_name_is_a_clear_error_too():
    # A parameter file may hand a list where a name belongs: the same error, not a TypeError.
    with pytest.raises(ValueError, match=r"unknown robot profile \['husky'\]: choose one of"):
        robot_profile(['husky'])
