"""
Tests of the sim_bridge world: walls, Husky drive, laser, contacts and wanderers, without ROS.

Worlds run headless (pybullet DIRECT); most use tiny in-memory scenarios whose geometry makes
the expected ranges, poses and contacts easy to compute by hand.

"""

import dataclasses
import doctest
import math
import subprocess
import sys

from dpn_navigator.core import GridGeometry
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
import numpy as np
from numpy.testing import assert_array_equal
import pytest

from sim_bridge import world as world_module
from sim_bridge.free_space import clearance_grid
from sim_bridge.husky import DriveLimits, HUSKY_RADIUS, LASER_MOUNT
from sim_bridge.laser import LaserConfig
from sim_bridge.scenario import load_scenario, Scenario
from sim_bridge.tasks import Task
from sim_bridge.walls import merge_cells
from sim_bridge.wanderers import P3AT_RADIUS, WandererConfig, Wanderers
from sim_bridge.world import wanderer_clearance_grid, World, WorldConfig

NO_RAMP = DriveLimits(max_linear_accel=None, max_angular_accel=None)
RESOLUTION = 0.1


def room(size=12.0, walls=((0.0, 0.0, 0.1, 12.0), (11.9, 0.0, 12.0, 12.0),
                           (0.0, 0.0, 12.0, 0.1), (0.0, 11.9, 12.0, 12.0))):
    """Return a square scenario with wall rectangles ``(x0, y0, x1, y1)`` [m] and one task."""
    geometry = GridGeometry(size, size, RESOLUTION)
    xs, ys = geometry.cell_to_world(*np.indices(geometry.shape))
    occupied = np.zeros(geometry.shape, dtype=bool)
    for x0, y0, x1, y1 in walls:
        occupied |= (xs > x0) & (xs < x1) & (ys > y0) & (ys < y1)
    task = Task((size / 2, size / 2, 0.0), (size / 2 + 3.0, size / 2))
    return Scenario('room', occupied, ~occupied, RESOLUTION, (0.0, 0.0), (task,))


@pytest.fixture(scope='module')
def back_and_forth():
    return load_scenario('back_and_forth')


# -- configuration ------------------------------------------------------------------------


@pytest.mark.parametrize('physics_rate, scan_rate', [(50.0, 15.0), (100.0, 30.0), (10.0, 20.0),
                                                     (50.0, 0.0), (-50.0, 10.0),
                                                     (math.inf, 10.0), (math.nan, 10.0)])
def test_scan_rate_must_divide_physics_rate(physics_rate, scan_rate):
    with pytest.raises(ValueError, match='scan_rate|physics_rate'):
        WorldConfig(physics_rate=physics_rate, scan_rate=scan_rate)


@pytest.mark.parametrize('physics_rate, scan_rate, ticks', [(50, 10, 5), (100.0, 10.0, 10),
                                                            (40.0, 40.0, 1), (1000, 12.5, 80)])
def test_ticks_per_scan(physics_rate, scan_rate, ticks):
    assert WorldConfig(physics_rate=physics_rate, scan_rate=scan_rate).ticks_per_scan == ticks


@pytest.mark.parametrize('kwargs, match', [
    ({'n_wanderers': -1}, 'n_wanderers'), ({'n_wanderers': 2.0}, 'n_wanderers'),
    ({'wall_height': 0.0}, 'wall_height'),
])
def test_world_config_errors(kwargs, match):
    with pytest.raises(ValueError, match=match):
        WorldConfig(**kwargs)


@pytest.mark.parametrize('kwargs, match', [
    ({'n_beams': 16384}, 'n_beams'), ({'n_beams': 1}, 'n_beams'),
    ({'angle_min': 1.0, 'angle_max': -1.0}, 'angle_min'),
    ({'range_min': 5.0, 'range_max': 2.0}, 'range_min < range_max'),
    ({'noise_std': -0.1}, 'noise_std'), ({'range_max': math.inf}, 'finite'),
])
def test_laser_config_errors(kwargs, match):
    with pytest.raises(ValueError, match=match):
        LaserConfig(**kwargs)


def test_laser_defaults_match_the_paper():
    laser = LaserConfig()
    assert laser.n_beams == 640
    assert (laser.angle_min, laser.angle_max) == (-math.pi / 2, math.pi / 2)
    assert laser.angle_increment == pytest.approx(math.pi / 639)
    assert laser.mount == LASER_MOUNT
    # The scan plane must cut the P3-AT chassis (0.08 to 0.277 m), or wanderers are invisible.
    assert 0.08 < laser.height < 0.277


# -- walls --------------------------------------------------------------------------------


@settings(max_examples=80)
@given(hnp.arrays(bool, st.tuples(st.integers(1, 12), st.integers(1, 12))))
def test_merge_cells_covers_each_occupied_cell_once(occupied):
    cover = np.zeros(occupied.shape, dtype=np.int64)
    for r, c, n_rows, n_cols in merge_cells(occupied):
        assert n_rows >= 1 and n_cols >= 1
        cover[r:r + n_rows, c:c + n_cols] += 1
    assert_array_equal(cover, occupied.astype(np.int64))


def test_back_and_forth_has_few_wall_bodies(back_and_forth):
    assert len(merge_cells(back_and_forth.occupied)) <= 12
    with World(back_and_forth) as world:
        assert len(world.scene.wall_bodies) == len(merge_cells(back_and_forth.occupied))


# -- laser --------------------------------------------------------------------------------


def test_scan_of_a_known_wall():
    # The Husky at (6, 6) facing +x; the wall's face is at x = 9.0.
    scenario = room(walls=((9.0, 0.0, 9.2, 12.0),))
    with World(scenario, WorldConfig(laser=LaserConfig(range_max=30.0))) as world:
        scan = world.scan()
        assert scan.pose == pytest.approx((6.0 + LASER_MOUNT[0], 6.0, 0.0))
        angles = scan.angle_min + scan.angle_increment * np.arange(640)
        hits = np.abs(np.tan(angles)) * (9.0 - scan.pose[0]) < 5.9  # beams that meet the wall
        expected = (9.0 - scan.pose[0]) / np.cos(angles[hits])
        np.testing.assert_allclose(scan.ranges[hits], expected, atol=2e-4)
        assert np.all(np.isposinf(scan.ranges[np.abs(angles) > 1.2]))  # REP 117: no return
        assert scan.ranges.dtype == np.float32 and scan.stamp == 0.0


def test_nothing_in_sight_is_all_inf_and_rays_miss_the_husky():
    with World(room(walls=((0.0, 0.0, 0.1, 0.1),))) as world:
        for _ in range(3):
            scan = world.advance(0.0, 1.0)  # turning: beams sweep over the Husky's own body
            assert np.all(np.isposinf(scan.ranges))


def test_too_close_is_minus_inf():
    laser = LaserConfig(range_min=0.5)
    face = 6.0 + LASER_MOUNT[0] + 0.3  # 0.3 m ahead of the laser, 0.14 m ahead of the bumper
    with World(room(walls=((face, 0.0, face + 0.2, 12.0),)), WorldConfig(laser=laser)) as world:
        ranges = world.scan().ranges
        assert np.isneginf(ranges[319]) and np.isneginf(ranges[320])


def test_range_noise_is_seeded():
    scenario = room()
    laser = LaserConfig(noise_std=0.01)
    with World(scenario) as exact, World(scenario, WorldConfig(laser=laser, seed=1)) as noisy, \
            World(scenario, WorldConfig(laser=laser, seed=1)) as again:
        error = noisy.scan().ranges - exact.scan().ranges
        assert 0.005 < np.std(error) < 0.015
        assert_array_equal(noisy.scan().ranges, again.scan().ranges)
        assert_array_equal(noisy.scan().ranges, noisy.scan().ranges)  # once per tick


# -- driving ------------------------------------------------------------------------------


def test_drive_straight_one_second():
    with World(room(), WorldConfig(drive=NO_RAMP)) as world:
        for _ in range(50):
            assert world.step(0.5, 0.0)
        assert world.time == pytest.approx(1.0)
        assert world.husky_pose == pytest.approx((6.5, 6.0, 0.0), abs=1e-9)
        assert world.husky_velocity == (0.5, 0.0)


def test_acceleration_limit_ramps_the_speed():
    with World(room()) as world:  # husky_control's 3 m/s^2
        for _ in range(50):
            world.step(0.5, 0.0)
        assert world.husky_pose[0] - 6.0 == pytest.approx(0.5 - 0.5 ** 2 / (2 * 3.0), abs=0.01)


def test_drive_an_arc():
    with World(room(), WorldConfig(drive=NO_RAMP, physics_rate=100.0)) as world:
        for _ in range(100):
            world.step(0.5, 1.0)
        # A circle of radius 0.5 m about (6, 6.5), 1 rad along it.
        assert world.husky_pose == pytest.approx(
            (6.0 + 0.5 * math.sin(1.0), 6.5 - 0.5 * math.cos(1.0), 1.0), abs=1e-9)


def test_commands_are_clamped():
    with World(room(), WorldConfig(drive=NO_RAMP)) as world:
        assert world.step(5.0, -9.0)
        assert world.command == (1.0, -1.5)
        assert world.husky_velocity == (1.0, -1.5)
        world.set_command(-3.0, 2.0)
        assert world.command == (-1.0, 1.5)


@pytest.mark.parametrize('v, omega', [(math.nan, 0.0), (0.2, math.inf), (-math.inf, 0.1),
                                      (None, 0.0), ('fast', 0.0)])
def test_non_finite_commands_are_rejected_and_counted(v, omega):
    with World(room(), WorldConfig(drive=NO_RAMP)) as world:
        world.step(0.4, 0.0)
        assert not world.step(v, omega)
        assert (world.rejected_commands, world.last_command_accepted) == (1, False)
        assert world.command == (0.4, 0.0)  # the previous command stays
        assert world.husky_pose[0] == pytest.approx(6.0 + 2 * 0.4 / 50)
        world.advance(v, omega)  # ticks 3, 4 and 5, each rejected
        assert world.rejected_commands == 4 and world.tick == 5
        assert world.step(0.0, 0.0) and world.last_command_accepted


def test_advance_runs_to_the_next_scan():
    with World(room(), WorldConfig(physics_rate=100.0, scan_rate=20.0)) as world:
        assert world.scan_due and world.tick == 0
        stamps = [world.advance(0.2, 0.0).stamp for _ in range(3)]
        assert stamps == pytest.approx([0.05, 0.1, 0.15])
        assert world.tick == 15 and world.scan_due
        world.step(0.2, 0.0)
        assert not world.scan_due


def test_start_in_a_wall_is_refused():
    with pytest.raises(ValueError, match='collides with a wall'):
        World(room(), start=(0.3, 6.0, 0.0))
    with pytest.raises(ValueError, match='no task'):
        World(dataclasses.replace(room(), tasks=()))
    with pytest.raises(ValueError, match='start pose must be finite'):
        World(room(), start=(6.0, math.nan, 0.0))


# -- contacts -----------------------------------------------------------------------------


def test_driving_into_a_wall_is_one_contact_event():
    scenario = room(walls=((8.0, 0.0, 8.2, 12.0),))
    with World(scenario, WorldConfig(drive=NO_RAMP)) as world:
        for _ in range(150):  # 3 s at 1 m/s: the bumper reaches the wall after about 1.5 s
            world.step(1.0, 0.0)
        contacts = world.contacts
        assert (contacts.wall_events, contacts.wanderer_events) == (1, 0)
        # The front of the collision box (0.504 m ahead of the base) meets x = 8.0 at 1.496 s.
        assert contacts.first_wall_time == pytest.approx(1.5, abs=0.021)
        assert contacts.first_contact_time == contacts.first_wall_time
        assert 7.47 < world.husky_pose[0] < 7.5  # held at the wall, not through it
        assert world.blocked_ticks > 60 and world.husky_velocity == (0.0, 0.0)
        assert contacts.touching_wall
        for _ in range(25):
            world.step(-1.0, 0.0)
        assert not world.contacts.touching_wall
        for _ in range(50):
            world.step(1.0, 0.0)
        assert world.contacts.wall_events == 2


def test_driving_into_a_wanderer_is_counted():
    scenario = room()
    config = WorldConfig(drive=NO_RAMP, n_wanderers=1, seed=2,
                         wanderer=WandererConfig(speed_range=(0.0, 0.0)))  # it stays put
    with World(scenario, config) as probe:
        target = probe.wanderer_positions[0]
    heading = math.atan2(target[1] - 6.0, target[0] - 6.0)
    with World(scenario, config, start=(6.0, 6.0, heading)) as world:
        assert_array_equal(world.wanderer_positions[0], target)
        for _ in range(int(50 * math.dist(target, (6.0, 6.0)))):
            world.step(1.0, 0.0)
        assert (world.contacts.wanderer_events, world.contacts.wall_events) == (1, 0)
        assert world.contacts.touching_wanderers == {0}
        assert math.dist(world.husky_pose[:2], target) > HUSKY_RADIUS * 0.5
        # The Husky drove into a standing wanderer: its own doing.
        assert (world.contacts.robot_caused_events, world.contacts.agent_caused_events) == (1, 0)


@pytest.mark.parametrize('command, robot_caused', [((0.0, 0.0), False), ((-0.3, 0.0), False),
                                                   ((0.3, 0.0), True)])
def test_a_pedestrian_walking_into_the_husky_is_its_own_contact(command, robot_caused):
    from sim_bridge.wanderers import PEDESTRIANS_IGNORING
    scenario = room()
    config = WorldConfig(drive=NO_RAMP, n_wanderers=1, seed=2, wanderer=PEDESTRIANS_IGNORING)
    with World(scenario, config, start=(6.0, 6.0, math.pi)) as world:
        walker = world._wanderers               # one pedestrian at (2, 6) walking east at 1 m/s
        walker.positions[0] = 2.0, 6.0
        walker.yaws[0] = 0.0
        walker.speeds[0] = walker._speeds[0] = walker._speed_now[0] = 1.0
        walker._paths[0] = [(10.0, 6.0)]
        walker._centring[0] = False
        world._place_wanderer(0)
        for _ in range(300):                    # the Husky faces it: stands, backs off, meets it
            world.step(*command)
        contacts = world.contacts
        assert contacts.wanderer_events >= 1
        assert contacts.robot_caused_events + contacts.agent_caused_events == \
            contacts.wanderer_events
        assert (contacts.robot_caused_events >= 1) == robot_caused
        assert (contacts.agent_caused_events >= 1) == (not robot_caused)


@pytest.mark.parametrize('velocity, point, expected', [
    ((1.0, 0.0), (3.0, 0.0), 1.0),             # driving straight at it
    ((1.0, 0.0), (-3.0, 0.0), -1.0),           # driving away
    ((0.0, 0.0), (0.6, 0.2), 0.0),             # standing
    ((1.0, 0.0), (0.0, 2.0), 0.0),             # passing beside it
    ((0.0, 1.0), (0.495, 1.0), 0.495),         # turning: the front corner sweeps towards it
    ((0.0, 1.0), (0.0, 0.0), 0.0),             # a point at the centre
])
def test_approach_speed_of_the_nearest_footprint_point(velocity, point, expected):
    from sim_bridge.contacts import approach_speed
    assert approach_speed((0.0, 0.0, 0.0), velocity, 0.99, 0.67, point) == \
        pytest.approx(expected, abs=1e-9)
    # The same in a moved and turned frame.
    yaw = 0.7
    c, s = math.cos(yaw), math.sin(yaw)
    moved = (1.0 + c * point[0] - s * point[1], -2.0 + s * point[0] + c * point[1])
    assert approach_speed((1.0, -2.0, yaw), velocity, 0.99, 0.67, moved) == \
        pytest.approx(expected, abs=1e-9)


@pytest.mark.parametrize('velocity, agent_velocity, expected', [
    ((0.0, 0.0), (-1.0, 0.0), False),          # standing, the agent walks into it
    ((-0.3, 0.0), (-1.0, 0.0), False),         # backing off, the agent faster
    ((0.0, 0.0), (0.0, 0.0), True),            # both still: the Husky's own small motion
    ((0.0, -0.04), (0.0, 0.0), True),          # a slow turn into a standing agent
    ((0.04, 0.0), (-0.02, 0.0), True),         # creeping in faster than the agent comes
    ((0.3, 0.0), (-1.0, 0.0), True),           # driving at it
])
def test_robot_caused_unless_the_agent_closed_the_gap(velocity, agent_velocity, expected):
    from sim_bridge.contacts import robot_caused
    # The agent's centre 0.8 m ahead of the Husky's centre, slightly to the left.
    assert robot_caused((0.0, 0.0, 0.0), velocity, 0.99, 0.67, (0.8, 0.1),
                        agent_velocity) == expected


@pytest.mark.parametrize('velocity, contact, normal, agent, agent_velocity, yaw_rate, expected', [
    # Held-out narrow_passages 1/2/0: the Husky curving left, its front-right corner into a
    # P3-AT standing ahead-right.
    ((0.5, 0.7), (0.495, -0.335), (-1.0, 0.0), (0.86, -0.41), (0.0, 0.0), 0.0, True),
    # Held-out maze 2/9/1: a P3-AT turning in place sweeps its corner into a standing Husky;
    # its centre does not move.
    ((0.0, 0.0), (0.5, 0.2), (-1.0, 0.0), (0.9, 0.0), (0.0, 0.0), 1.0, False),
    # The same turn the other way sweeps the corner away: the Husky's own small motion.
    ((0.0, 0.0), (0.5, 0.2), (-1.0, 0.0), (0.9, 0.0), (0.0, 0.0), -1.0, True),
    # Both still: the Husky's.
    ((0.0, 0.0), (0.5, 0.0), (-1.0, 0.0), (0.8, 0.0), (0.0, 0.0), 0.0, True),
    # A walker into a Husky backing off.
    ((-0.3, 0.0), (0.5, 0.0), (-1.0, 0.0), (0.8, 0.0), (-1.0, 0.0), 0.0, False),
    # The Husky turning in place, its corner into a standing agent beside it.
    ((0.0, 1.0), (0.495, 0.335), (0.0, -1.0), (0.5, 0.7), (0.0, 0.0), 0.0, True),
])
def test_robot_caused_at_the_contact_point(velocity, contact, normal, agent, agent_velocity,
                                           yaw_rate, expected):
    from sim_bridge.contacts import robot_caused, robot_caused_at_contact
    assert robot_caused_at_contact((0.0, 0.0, 0.0), velocity, contact, normal, agent,
                                   agent_velocity, yaw_rate) is expected
    # Moved and turned, the same.
    yaw = -1.1
    c, s = math.cos(yaw), math.sin(yaw)

    def moved(p):
        return (2.0 + c * p[0] - s * p[1], 3.0 + s * p[0] + c * p[1])

    def turned(v):
        return (c * v[0] - s * v[1], s * v[0] + c * v[1])
    assert robot_caused_at_contact((2.0, 3.0, yaw), velocity, moved(contact), turned(normal),
                                   moved(agent), turned(agent_velocity), yaw_rate) is expected
    if yaw_rate > 0.0:
        # The centre rule blamed the standing Husky for the turning P3-AT's corner.
        assert robot_caused((0.0, 0.0, 0.0), velocity, 0.99, 0.67, agent, agent_velocity)
    with pytest.raises(ValueError, match='normal'):
        robot_caused_at_contact((0.0, 0.0, 0.0), velocity, contact, (0.0, 0.0), agent,
                                agent_velocity, yaw_rate)


def test_a_p3at_turning_its_corner_into_a_standing_husky_is_its_own_contact(monkeypatch):
    scenario = room()
    config = WorldConfig(drive=NO_RAMP, n_wanderers=1, seed=2,
                         wanderer=WandererConfig(speed_range=(0.0, 0.0)))
    with World(scenario, config, start=(6.0, 6.0, 0.0)) as world:
        wanderers = world._wanderers
        # A P3-AT just ahead of the Husky, facing along it, 5 cm clear of its front.
        wanderers.positions[0] = 6.0 + 0.504 + 0.254 + 0.05, 6.0
        wanderers.yaws[0] = 0.0
        world._place_wanderer(0)
        world.step(0.0, 0.0)
        assert world.contacts.wanderer_events == 0

        def turn_in_place(dt, husky_xy):
            wanderers.yaws[0] += 1.0 * dt                     # 1 rad/s, centre fixed
            return [0]
        monkeypatch.setattr(wanderers, 'step', turn_in_place)
        for _ in range(60):                                   # up to 1.2 rad
            world.step(0.0, 0.0)
            if world.contacts.wanderer_events:
                break
        contacts = world.contacts
        assert contacts.wanderer_events == 1
        assert (contacts.robot_caused_events, contacts.agent_caused_events) == (0, 1)


def test_the_contact_log_splits_wanderer_events_by_who_closed_the_gap():
    from sim_bridge.contacts import ContactLog
    log = ContactLog()
    log.update(0.0, False, {0, 1}, approached={1})
    log.update(0.1, False, {0, 1})               # still touching: no new event
    log.update(0.2, False, {2})                  # default: the Husky's doing
    assert (log.wanderer_events, log.robot_caused_events, log.agent_caused_events) == (3, 2, 1)


# -- wanderers ----------------------------------------------------------------------------


def wall_distance(scenario, points):
    """Least distance from each point to the area of any wall cell [m]."""
    geometry = scenario.geometry
    xs, ys = geometry.cell_to_world(*np.nonzero(scenario.occupied))
    half = 0.5 * geometry.resolution
    dx = np.maximum(np.abs(points[:, 0, np.newaxis] - xs) - half, 0.0)
    dy = np.maximum(np.abs(points[:, 1, np.newaxis] - ys) - half, 0.0)
    return np.hypot(dx, dy).min(axis=1)


def test_wanderers_roam_without_touching_walls_or_the_husky(back_and_forth):
    config = WorldConfig(n_wanderers=10, seed=7)
    with World(back_and_forth, config) as world:
        start = world.husky_pose
        positions = world.wanderer_positions
        assert np.all(np.hypot(*(positions - start[:2]).T) >= 3.0)
        gaps = np.hypot(*(positions[:, np.newaxis] - positions[np.newaxis]).transpose(2, 0, 1))
        assert np.all(gaps[~np.eye(10, dtype=bool)] >= 2 * P3AT_RADIUS + 0.5)
        travelled = np.zeros(10)
        still = np.zeros(10)
        longest_still = np.zeros(10)
        nearest_husky = math.inf
        for _ in range(1200):  # 120 s; the Husky stands still
            world.advance(0.0, 0.0)
            now = world.wanderer_positions
            assert wall_distance(back_and_forth, now).min() > P3AT_RADIUS
            step = np.hypot(*(now - positions).T)
            travelled += step
            still = np.where(step > 0.0, 0.0, still + 0.1)
            longest_still = np.maximum(longest_still, still)
            nearest_husky = min(nearest_husky, np.hypot(*(now - start[:2]).T).min())
            positions = now
        assert world.contacts.events == 0
        assert nearest_husky > HUSKY_RADIUS + P3AT_RADIUS
        assert np.all(travelled > 10.0)
        assert np.all(longest_still < 15.0)  # blocked wanderers pick new goals
        speeds = world._wanderers.speeds
        assert np.all((speeds >= 0.3) & (speeds <= 0.7))


def test_wanderer_stops_for_the_husky_then_picks_another_goal():
    scenario = room()
    grid = clearance_grid(scenario.free, scenario.geometry, WandererConfig().clearance)
    husky = (100.0, 100.0)  # far away at first
    wanderers = Wanderers(grid, 1, (6.0, 6.0), np.random.default_rng(0))
    for _ in range(40):
        wanderers.step(0.02, husky)
    x, y = wanderers.positions[0]
    yaw = wanderers.yaws[0]
    husky = (x + 1.2 * math.cos(yaw), y + 1.2 * math.sin(yaw))  # right ahead of it
    for _ in range(60):  # 1.2 s, less than the least patience
        wanderers.step(0.02, husky)
    assert math.dist(wanderers.positions[0], (x, y)) < 0.2  # at most centred in its cell
    replans = wanderers.replans
    for _ in range(400):  # 8 s: patience runs out, it turns away and walks on
        wanderers.step(0.02, husky)
    assert wanderers.replans > replans
    assert math.dist(wanderers.positions[0], (x, y)) > 1.0
    assert math.dist(wanderers.positions[0], husky) > HUSKY_RADIUS + P3AT_RADIUS


def whole_grid_goal(grid, anchor, blocked, goal_distance_range, rng):
    """Draw a goal as the wanderers did, over the whole grid: the twin of `_pick_goal`."""
    rr, cc = np.nonzero((grid.labels == grid.labels[anchor]) & ~blocked)
    if len(rr) == 0:
        return None
    xs, ys = grid.geometry.cell_to_world(rr, cc)
    ax, ay = grid.centre(*anchor)
    dist = np.hypot(xs - ax, ys - ay)
    lo, hi = goal_distance_range
    pool = np.flatnonzero((dist >= lo) & (dist <= hi))
    if len(pool) == 0:
        pool = np.flatnonzero(dist > 0.0)
    if len(pool) == 0:
        return None
    k = int(pool[rng.integers(len(pool))])
    return int(rr[k]), int(cc[k])


@pytest.mark.parametrize('goal_distance_range', [(3.0, 15.0), (0.0, 1.0), (40.0, 50.0)])
def test_goals_drawn_in_the_window_are_the_whole_grid_draws(back_and_forth,
                                                            goal_distance_range):
    # (40, 50) m is beyond the map: every draw takes the fallback over the whole grid.
    grid = wanderer_clearance_grid(back_and_forth, WandererConfig())
    config = WandererConfig(goal_distance_range=goal_distance_range)
    wanderers = Wanderers(grid, 0, (2.0, 2.0), np.random.default_rng(0), config)
    twin_rng = np.random.default_rng(5)
    wanderers.rng = np.random.default_rng(5)
    blocked = ~grid.clear
    rr, cc = np.nonzero(grid.clear)
    draws = 0
    for k in np.random.default_rng(1).choice(len(rr), size=40, replace=False):
        anchor = (int(rr[k]), int(cc[k]))
        expected = whole_grid_goal(grid, anchor, blocked, goal_distance_range, twin_rng)
        assert wanderers._pick_goal(anchor, blocked) == expected
        draws += expected is not None
    assert draws == 40
    assert wanderers.rng.integers(1 << 30) == twin_rng.integers(1 << 30)


def test_a_prebuilt_wanderer_grid_must_fit(back_and_forth):
    with pytest.raises(ValueError, match='clearance of 0.3 m'):
        World(back_and_forth, wanderer_grid=wanderer_clearance_grid(
            back_and_forth, WandererConfig(clearance=0.3)))
    with pytest.raises(ValueError, match="not a grid of this scenario's map"):
        World(back_and_forth, wanderer_grid=wanderer_clearance_grid(room(), WandererConfig()))


def test_ray_twins_are_in_place_at_every_scan(back_and_forth):
    # The wanderers' ray twins move only when a scan is due; then they must stand exactly
    # where their bodies do.
    import pybullet
    with World(back_and_forth, WorldConfig(n_wanderers=4, seed=2)) as world:
        scene = world.scene
        start = world.wanderer_positions
        for _ in range(30):
            world.advance(0.0, 0.0)
            twins = [pybullet.getBasePositionAndOrientation(body, physicsClientId=scene.client)
                     for body in scene.wanderer_ray_bodies]
            for i in range(4):
                world._place_wanderer(i)       # both the body and the twin, afresh
            assert twins == [
                pybullet.getBasePositionAndOrientation(body, physicsClientId=scene.client)
                for body in scene.wanderer_ray_bodies]
        assert np.all(np.hypot(*(world.wanderer_positions - start).T) > 0.5)


def test_no_room_to_spawn():
    with pytest.raises(ValueError, match='no room to spawn wanderer'):
        World(room(size=5.0), WorldConfig(n_wanderers=3))


def test_same_seed_same_episode(back_and_forth):
    config = WorldConfig(n_wanderers=5, seed=11, laser=LaserConfig(noise_std=0.005))

    def run(config):
        with World(back_and_forth, config) as world:
            scans = [world.scan().ranges]
            for k in range(60):
                scans.append(world.advance(0.6, 0.4 * math.sin(0.1 * k)).ranges)
            return np.array(scans), world.wanderer_positions, world.husky_pose

    first, second = run(config), run(config)
    assert_array_equal(first[0], second[0])
    assert_array_equal(first[1], second[1])
    assert first[2] == second[2]
    other = run(dataclasses.replace(config, seed=12))
    assert not np.array_equal(first[1], other[1])


# -- the package ----------------------------------------------------------------------------


def test_world_docstring_example_runs():
    result = doctest.testmod(world_module, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 1 and result.failed == 0


def test_no_ros_in_the_simulator_core():
    code = ('import sys\n'
            'import sim_bridge.world, sim_bridge.scenario, sim_bridge.scenarios.generate\n'
            "assert 'rclpy' not in sys.modules, 'rclpy was imported'\n")
    subprocess.run([sys.executable, '-c', code], check=True)


def test_the_laser_sees_the_wanderers(back_and_forth):
    # The navigator can only label mobile obstacles it sees: some scans must hit wanderers.
    hits_on_wanderers = 0
    with World(back_and_forth, WorldConfig(n_wanderers=10, seed=3)) as world:
        while world.time < 20.0:
            scan = world.advance(0.0, 0.6)                # turn on the spot, look around
            x, y, yaw = scan.pose
            angles = yaw + scan.angle_min + np.arange(len(scan.ranges)) * scan.angle_increment
            finite = np.isfinite(scan.ranges)
            hit_x = x + scan.ranges[finite] * np.cos(angles[finite])
            hit_y = y + scan.ranges[finite] * np.sin(angles[finite])
            for wx, wy in world.wanderer_positions:
                near = np.hypot(hit_x - wx, hit_y - wy) <= P3AT_RADIUS + 0.05
                hits_on_wanderers += int(np.count_nonzero(near))
    assert hits_on_wanderers > 20


def test_scans_on_the_ray_meshes_match_the_collision_bodies(back_and_forth):
    # The laser casts against triangle-mesh copies of the walls and wanderers (cheaper in
    # Bullet); they must stand exactly where the collision bodies are, moving wanderers too.
    import pybullet
    from sim_bridge.scene import HUSKY_GROUP, RAY_GROUP, WALL_GROUP, WANDERER_GROUP
    with World(back_and_forth, WorldConfig(n_wanderers=10, seed=5)) as world:
        scene = world.scene
        # Let rays see the collision bodies too (they pair with nothing else by this bit).
        for bodies, group in ((scene.wall_bodies, WALL_GROUP),
                              (scene.wanderer_bodies, WANDERER_GROUP)):
            for body in bodies:
                pybullet.setCollisionFilterGroupMask(body, -1, group, HUSKY_GROUP | RAY_GROUP,
                                                     physicsClientId=scene.client)
        compared = near_wanderers = 0
        while world.time < 15.0:
            scan = world.advance(0.0, 0.8)
            x, y, yaw = scan.pose
            angles = yaw + scan.angle_min + np.arange(len(scan.ranges)) * scan.angle_increment
            height = world.config.laser.height
            start = np.column_stack((np.full(len(angles), x), np.full(len(angles), y),
                                     np.full(len(angles), height)))
            end = start + np.column_stack((scan.range_max * np.cos(angles),
                                           scan.range_max * np.sin(angles),
                                           np.zeros(len(angles))))
            results = pybullet.rayTestBatch(start, end,
                                            collisionFilterMask=WALL_GROUP | WANDERER_GROUP,
                                            physicsClientId=world.scene.client)
            assert len(results) == len(angles)
            on_bodies = np.array([r[2] * scan.range_max if r[0] >= 0 else np.inf
                                  for r in results])
            on_meshes = scan.ranges.astype(np.float64)
            both = np.isfinite(on_bodies) & np.isfinite(on_meshes)
            # Bullet stops up to ~1 mm short of curved shapes; grazing wheel edges may differ.
            close = np.abs(on_bodies[both] - on_meshes[both]) <= 0.01
            assert np.mean(close) >= 0.99
            assert np.mean(np.isfinite(on_bodies) == np.isfinite(on_meshes)) >= 0.99
            compared += int(np.count_nonzero(both))
            for wx, wy in world.wanderer_positions:
                hx = x + on_meshes[both] * np.cos(angles[both])
                hy = y + on_meshes[both] * np.sin(angles[both])
                near_wanderers += int(np.count_nonzero(np.hypot(hx - wx, hy - wy) < 0.5))
        assert compared > 10000 and near_wanderers > 20


def test_husky_can_back_away_from_a_wanderer_that_moved_into_it(back_and_forth):
    # A wanderer turning in place can sweep into the Husky; the Husky must still be free to
    # move away (only moves deeper into an obstacle are held).
    with World(back_and_forth, WorldConfig(n_wanderers=1, seed=0)) as world:
        x, y, yaw = world.husky_pose
        # Husky collision box half-length 0.504 m, P3-AT half-length 0.254 m: 5 cm overlap,
        # the wanderer facing the Husky (so it waits instead of walking off).
        front = 0.504 + 0.254 - 0.05
        world._wanderers.positions[0] = (x + front * math.cos(yaw), y + front * math.sin(yaw))
        world._wanderers.yaws[0] = yaw + math.pi
        world._place_wanderer(0)
        assert world.scene.husky_contacts()[1] == {0}
        for _ in range(50):                              # 1 s backwards at 0.5 m/s
            world.step(-0.5, 0.0)
        assert math.dist(world.husky_pose[:2], (x, y)) > 0.2


def test_scan_wanderer_beams_name_the_wanderer_each_beam_hit():
    scenario = room()
    config = WorldConfig(n_wanderers=2, seed=2, wanderer=WandererConfig(speed_range=(0.0, 0.0)))
    with World(scenario, config) as probe:
        targets = probe.wanderer_positions
    heading = math.atan2(targets[0, 1] - 6.0, targets[0, 0] - 6.0)   # face wanderer 0
    with World(scenario, config, start=(6.0, 6.0, heading)) as world:
        scan = world.scan()
        beam_wanderer = world.scan_wanderer_beams()
        assert beam_wanderer.shape == (640,) and np.any(beam_wanderer == 0)
        angles = scan.pose[2] + scan.angle_min + scan.angle_increment * np.arange(640)
        hit_x = scan.pose[0] + scan.ranges * np.cos(angles)
        hit_y = scan.pose[1] + scan.ranges * np.sin(angles)
        for i in (0, 1):
            on = beam_wanderer == i
            distance = np.hypot(hit_x[on] - targets[i, 0], hit_y[on] - targets[i, 1])
            assert np.all(distance <= world.wanderer_radius + 1e-6)
        # The other beams end on a wall (or nowhere), far from both wanderers.
        off = (beam_wanderer < 0) & np.isfinite(scan.ranges)
        assert np.all(wall_distance(scenario, np.column_stack((hit_x[off], hit_y[off])))
                      < 0.2)
        assert np.all(scan.hit_body[~np.isfinite(scan.ranges)] == -1)
