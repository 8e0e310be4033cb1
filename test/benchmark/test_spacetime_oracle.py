"""
The space-time oracle in a scripted scene: waiting for a crossing agent is the way through.

A straight corridor from west to east, a side passage joining it from the south at x = 8 m and
a niche across from it; a bypass loop north of the corridor. An agent walks slowly out of the
side passage, across the corridor, into the niche: it holds the corridor for about 6 s just
when the robot gets there. Knowing that, the space-time oracle waits at the crossing and goes
on straight; the bare oracle (the agent where it stands, ``OracleGrid``), finding its route
blocked, takes the bypass. Both drive the same kinematic robot (the Husky's limits) with no
physics; a contact is the robot's and the agent's circles overlapping.
"""

import math

from dpn_navigator.benchmark.baselines.oracle_grid import OracleGrid
from dpn_navigator.benchmark.baselines.spacetime_oracle import _box_distance, \
    SpaceTimeConfig, SpaceTimeOracle
from dpn_navigator.benchmark.ground_truth import wall_belt
from dpn_navigator.core import CellLabel, GridGeometry, Navigator, NavigatorConfig
from dpn_navigator.core.cell_label import blocked_mask
from dpn_navigator.core.control.path_follower import STOP, VelocityCommand
from dpn_navigator.core.navigator import NavigatorStatus
import numpy as np
from numpy.testing import assert_allclose, assert_array_equal
import pytest
from sim_bridge.husky import DriveLimits, HUSKY_RADIUS, integrate_pose, ramp

WIDTH, HEIGHT = 16.0, 9.0
START, GOAL = (1.25, 4.0, 0.0), (14.75, 4.0)
AGENT_RADIUS, AGENT_SPEED = 0.4, 0.4
AGENT_FROM, AGENT_TO = (8.0, 0.8), (8.0, 5.6)
SCAN = {'ranges': np.full(19, 30.0), 'angle_min': -math.pi / 2,
        'angle_increment': math.pi / 18, 'range_min': 0.1, 'range_max': 30.0}


def scene_walls():
    """Return the true walls on a 0.1 m grid: free corridors, everything else wall."""
    truth = GridGeometry(WIDTH, HEIGHT, 0.1)
    x, y = truth.cell_to_world(*np.indices(truth.shape))
    free = ((y >= 3.0) & (y <= 5.0))                                     # the corridor
    free |= (x >= 7.0) & (x <= 9.0) & (y <= 3.0) & (y >= 0.2)            # side passage
    free |= (x >= 7.0) & (x <= 9.0) & (y >= 5.0) & (y <= 6.2)            # niche
    free |= (y >= 6.7) & (y <= 8.7) & (x >= 1.0) & (x <= 15.0)           # bypass
    free |= ((x >= 1.0) & (x <= 3.0) | (x >= 13.0) & (x <= 15.0)) & (y >= 3.0) & (y <= 8.7)
    free &= (x >= 0.2) & (x <= WIDTH - 0.2)
    return ~free, truth


def agent_xy(t):
    """Return the agent's position [m] at time ``t`` [s]: up the side passage, then still."""
    travel = min(max(t, 0.0) * AGENT_SPEED, AGENT_TO[1] - AGENT_FROM[1])
    return AGENT_FROM[0], AGENT_FROM[1] + travel


def make_grid(config):
    walls, truth = scene_walls()
    geometry = GridGeometry(WIDTH, HEIGHT, config.resolution)
    belt = wall_belt(walls, truth, geometry, config.safety_radius)
    return OracleGrid(geometry, belt, AGENT_RADIUS + config.safety_radius)


def drive(navigator, time_limit=60.0, bare=False):
    """Run the robot; return (reached, time [s], path length [m], contacts)."""
    limits = DriveLimits()
    pose, velocity = START, (0.0, 0.0)
    navigator.set_goal(*GOAL)
    travelled, contacts, command = 0.0, 0, (0.0, 0.0)
    for tick in range(int(time_limit * 50)):
        t = tick / 50.0
        if tick % 5 == 0:
            if bare:
                navigator.grid.set_wanderers([agent_xy(t)])
            out = navigator.step(t, pose, **SCAN)
            if out.status is NavigatorStatus.GOAL_REACHED:
                return True, t, travelled, contacts
            command = (out.command.linear, out.command.angular)
        velocity = (ramp(velocity[0], command[0], limits.max_linear_accel, 0.02),
                    ramp(velocity[1], command[1], limits.max_angular_accel, 0.02))
        new = integrate_pose(pose, velocity[0], velocity[1], 0.02)
        travelled += math.dist(new[:2], pose[:2])
        pose = new
        if math.dist(pose[:2], agent_xy(t + 0.02)) < HUSKY_RADIUS + AGENT_RADIUS:
            contacts += 1
    return False, time_limit, travelled, contacts


@pytest.fixture(scope='module')
def config():
    return NavigatorConfig(width=WIDTH, height=HEIGHT, forget_obstacles_after=0.0)


def scripted_forecast(clock):
    """Return the forecast callable: the agent's scripted future from ``clock[0]`` on."""
    def forecast(times, husky_xy_at):
        return np.array([[agent_xy(clock[0] + t)] for t in times])
    return forecast


class ClockedOracle(SpaceTimeOracle):
    """The space-time oracle with its forecast read at the time of each step."""

    def __init__(self, config, grid, clock):
        super().__init__(config, grid, scripted_forecast(clock), AGENT_RADIUS
                         + config.safety_radius, SpaceTimeConfig())
        self._clock = clock

    def step(self, stamp, pose, *args, **kwargs):
        self._clock[0] = stamp
        return super().step(stamp, pose, *args, **kwargs)


def test_the_space_time_oracle_waits_where_the_bare_one_detours(config):
    oracle = ClockedOracle(config, make_grid(config), [0.0])
    reached, arrival, length, contacts = drive(oracle)
    assert reached and contacts == 0
    straight = GOAL[0] - START[0]
    assert length < 1.1 * straight                   # the corridor, no bypass
    assert oracle.waits > 0                          # it held at the crossing
    # Without the agent it arrives sooner: the wait was needed.
    free = SpaceTimeOracle(config, make_grid(config),
                           lambda times, husky: np.zeros((len(times), 0, 2)),
                           AGENT_RADIUS + config.safety_radius)
    free_reached, free_arrival, _, _ = drive(free)
    assert free_reached and free_arrival + 2.0 < arrival
    bare = Navigator(config, make_grid(config))
    bare_reached, bare_arrival, bare_length, bare_contacts = drive(bare, bare=True)
    assert (not bare_reached or bare_contacts or bare_length > 1.5 * length)
    assert not bare_reached or bare_arrival > arrival


def test_blocked_cells_over_time_are_the_oracle_grids(config):
    """Each step's blocked cells: those the bare oracle blocks for the agents then."""
    grid = make_grid(config)
    oracle = SpaceTimeOracle(config, grid, None, AGENT_RADIUS + config.safety_radius)
    rng = np.random.default_rng(4)
    agents = rng.uniform([-1.0, -1.0], [WIDTH + 1.0, HEIGHT + 1.0], size=(5, 3, 2))
    blocked = oracle._blocked_over_time(agents)
    walls, truth = scene_walls()
    belt = wall_belt(walls, truth, grid.geometry, config.safety_radius)
    # R + r and the clearance for the robot's straying from its cells' centres.
    reach = AGENT_RADIUS + config.safety_radius + SpaceTimeConfig().clearance
    for k in range(agents.shape[0]):
        twin = OracleGrid(grid.geometry, belt, reach)
        twin.set_wanderers(agents[k])
        twin.update((0.0, 0.0, 0.0), **SCAN, safety_radius=config.safety_radius)
        assert_array_equal(blocked[k] | oracle._walls, blocked_mask(twin.labels))
        assert (twin.labels == CellLabel.MOBILE_OBSTACLE).any() or not blocked[k].any()


@pytest.mark.parametrize('agents', ['p3at', 'mixed'])
def test_the_worlds_forecast_is_its_future_and_changes_nothing(agents):
    """Stepping a copy of the agents gives their very positions later; the world goes on."""
    from sim_bridge.scenario import load_scenario
    from sim_bridge.wanderers import AGENT_MODELS
    from sim_bridge.world import World, WorldConfig
    scenario = load_scenario('maze')
    config = WorldConfig(n_wanderers=10, seed=7, wanderer=AGENT_MODELS[agents])
    times = np.arange(0.0, 6.01, 0.25)
    with World(scenario, config) as world, World(scenario, config) as twin:
        for _ in range(10):                        # 1 s, the Husky still
            world.advance(0.0, 0.0)
            twin.advance(0.0, 0.0)
        husky = world.husky_pose[:2]
        forecast = world.forecast_wanderers(times, lambda t: husky)
        start = world.tick
        seen = []
        for t in times:
            while world.tick - start < math.floor(t * 50 + 1e-9):   # rounded down
                world.step(0.0, 0.0)
                twin.step(0.0, 0.0)
            seen.append(world.wanderer_positions)
        assert_array_equal(forecast, np.array(seen))
        assert np.abs(np.diff(forecast, axis=0)).max() > 0.0         # they do move
        # The world that forecast is where the twin that did not is.
        assert_array_equal(world.wanderer_positions, twin.wanderer_positions)
    with pytest.raises(ValueError, match='non-decreasing'):
        World(scenario, config).forecast_wanderers([1.0, 0.5], lambda t: (0.0, 0.0))


@pytest.mark.parametrize('agents', ['pedestrians', 'mixed'])
def test_the_forecast_of_yielding_agents_around_a_moving_husky_is_their_future(agents):
    """Yielding pedestrians answer the Husky's motion: given its path, the forecast is exact."""
    from sim_bridge.scenario import load_scenario
    from sim_bridge.wanderers import AGENT_MODELS
    from sim_bridge.world import World, WorldConfig
    scenario = load_scenario('maze')
    config = WorldConfig(n_wanderers=10, seed=7, wanderer=AGENT_MODELS[agents])
    command = (0.6, 0.3)
    ticks = 6 * 50
    with World(scenario, config) as world, World(scenario, config) as scout:
        for _ in range(10):
            world.advance(*command)
            scout.advance(*command)
        husky_at = []                               # the Husky's path ahead, driven by a scout
        for _ in range(ticks + 1):
            husky_at.append(scout.husky_pose[:2])
            scout.step(*command)
        forecast = world.forecast_wanderers(np.arange(ticks + 1) / 50.0,
                                            lambda t: husky_at[round(t * 50)])
        seen = [world.wanderer_positions]
        for _ in range(ticks):
            world.step(*command)
            seen.append(world.wanderer_positions)
        assert_array_equal(forecast, np.array(seen))


def still_agent_oracle(config, agent, **planning):
    """Return an oracle whose one agent stands at ``agent`` [m] for good."""
    return SpaceTimeOracle(config, make_grid(config),
                           lambda times, husky: np.array([[agent]] * len(times), dtype=float),
                           AGENT_RADIUS + config.safety_radius, SpaceTimeConfig(**planning))


def test_the_body_guard_holds_a_turn_that_would_sweep_a_corner_into_an_agent(config):
    # The Husky's corners sweep a 0.6 m disc as it turns; an agent of radius 0.4 whose centre
    # is 0.84 m away is within it (the turn that hit a stopped P3-AT on crossroads, task 0,
    # 5 wanderers, held-out seed 1).
    turn = VelocityCommand(0.0, 1.0, turn=1.0)
    pose = (5.0, 4.0, 0.0)
    assert still_agent_oracle(config, (5.0, 4.84))._held(pose, turn)
    assert not still_agent_oracle(config, (5.0, 6.0))._held(pose, turn)


def test_the_body_guard_lets_a_turn_pass_an_agent_its_corners_do_not_reach(config):
    # Held-out seed 1, back_and_forth 0/3/1: a P3-AT stopped 0.98 m beside the Husky, which
    # had to turn left by 0.6 rad, away from it. The circle of the box's corners plus the
    # margin reached the agent, so the old guard held every turn, and both stood for 183 s.
    pose = (5.0, 4.0, -0.15)
    agent = (4.86, 4.98)
    turn = VelocityCommand(0.0, 1.2, turn=0.62)
    assert not still_agent_oracle(config, agent)._held(pose, turn)
    assert still_agent_oracle(config, agent, exact_turns=False)._held(pose, turn)
    # Turning the other way round by half a turn brings a corner onto it: held.
    back = VelocityCommand(0.0, -1.2, turn=-math.pi)
    assert still_agent_oracle(config, agent)._held(pose, back)
    with pytest.raises(ValueError, match='turn_margin'):
        SpaceTimeConfig(turn_margin=-0.1)


def test_the_body_guard_stops_a_drive_onto_an_agent_but_not_away_from_it(config):
    oracle = still_agent_oracle(config, (6.0, 4.0))          # 1.0 m ahead of the centre
    toward, away = VelocityCommand(0.8, 0.0), VelocityCommand(0.8, 0.0)
    assert oracle._held((5.0, 4.0, 0.0), toward)
    assert not oracle._held((5.0, 4.0, math.pi), away)
    # Passing beside it with room to spare is no contact.
    assert not oracle._held((5.0, 2.7, 0.0), toward)


def test_the_body_guard_lets_a_drive_swing_a_corner_nearer_by_less_than_a_turns_margin(config):
    # Held-out seed 1, crossroads 0/2/0: 0.58 m from its goal, the Husky had to drive on
    # turning right; its rear corner would swing 4 cm nearer a P3-AT behind it on the left,
    # 0.49 m from the box, which could not turn away from the Husky either (its turn guard).
    pose = (34.42, 34.98, 0.23)
    agent = (33.88, 35.7)
    drive = VelocityCommand(0.338, -0.39)
    assert not still_agent_oracle(config, agent)._held(pose, drive)
    assert still_agent_oracle(config, agent, exact_swings=False)._held(pose, drive)
    # Driving towards an agent is still held: the same drive with the agent ahead of the box.
    ahead = (34.42 + 0.95 * math.cos(0.23), 34.98 + 0.95 * math.sin(0.23))
    assert still_agent_oracle(config, ahead)._held(pose, drive)


def test_a_drive_inside_the_margin_is_held_only_by_the_margin_of_a_turn(config):
    # Held-out seed 1, l_corridor 1/4/1: the Husky's box 0.099 m from a P3-AT that had stopped
    # for it, its plan passing the P3-AT a millimetre nearer.
    pose = (5.0, 4.0, 0.0)
    agent = (5.0, 4.0 + 0.335 + 0.099 + AGENT_RADIUS)     # beside the box, 0.099 m from it
    past = VelocityCommand(0.8, 0.01)                      # along it, a hair to the left
    gap = _box_distance(pose, (0.495, 0.335), np.array([agent]))[0] - AGENT_RADIUS
    assert gap == pytest.approx(0.099)
    assert not still_agent_oracle(config, agent)._held(pose, past)
    assert still_agent_oracle(config, agent, close_drives=False)._held(pose, past)
    # Still held when the drive would take the box within turn_margin of the body: the
    # same drive with the agent 0.099 m ahead of the box.
    ahead = (5.0 + 0.495 + 0.099 + AGENT_RADIUS, 4.0)
    assert still_agent_oracle(config, ahead)._held(pose, past)


def scheduled_oracle(config, agent, xy, when, **planning):
    """Return an oracle (one agent standing at ``agent``) that follows the schedule given."""
    oracle = still_agent_oracle(config, agent, **planning)
    oracle.set_goal(*GOAL)
    oracle._schedule = (np.asarray(when, dtype=float), np.asarray(xy, dtype=float))
    oracle._next_plan = math.inf                           # no plan of its own
    return oracle


def test_a_held_turn_toward_a_plan_behind_the_robot_backs_along_it(config):
    # Held-out seed 1, l_corridor 0/8/0: the plan leads back past a P3-AT standing beside
    # the Husky; a half turn would swing the box's corners into it, and the P3-AT waits for
    # the Husky. Backing along the plan passes it.
    pose = (5.0, 4.0, 0.0)
    agent = (5.1, 4.88)
    plan = [(5.0, 4.0), (4.5, 4.0), (4.0, 4.0), (3.5, 4.0)]
    for reverse in (True, False):
        oracle = scheduled_oracle(config, agent, plan, [0.0, 0.5, 1.0, 1.5],
                                  reverse_when_held=reverse)
        turn = oracle._command(0.0, pose)
        assert turn.linear == 0.0 and abs(turn.turn) > 0.5 * math.pi
        assert oracle._held(pose, turn)
        command = oracle.step(0.0, pose, **SCAN).command
        if reverse:
            assert command.linear < 0.0 and abs(command.angular) < 0.1
            assert not oracle._held(pose, command)
        else:
            assert command is STOP
    # With the agent gone, the robot turns round as before.
    oracle = scheduled_oracle(config, (14.0, 8.0), plan, [0.0, 0.5, 1.0, 1.5])
    assert oracle.step(0.0, pose, **SCAN).command.linear == 0.0
    # No reverse when the held command is not a turn of more than a quarter turn.
    # (a 60-degree turn left; the front-left corner would swing into the agent's body)
    oracle = scheduled_oracle(config, (5.462, 4.894), [(5.0, 4.0), (5.3, 4.52), (5.6, 5.04)],
                              [0.0, 0.6, 1.2])
    held = oracle._command(0.0, pose)
    assert oracle._held(pose, held) and abs(held.turn) < 0.5 * math.pi
    assert oracle.step(0.0, pose, **SCAN).command is STOP


def test_a_leg_that_ends_in_a_wait_is_driven_to_the_waits_cell(config):
    # Held-out seed 1, l_corridor 0/8/1: the robot stopped 0.29 m short of the cell its plan
    # waited in, inside the follower's goal tolerance; the forecast, with the robot there,
    # had a P3-AT pass that did not pass the robot where it stood.
    pose = (5.0, 4.29, -math.pi / 2)
    plan = [(5.0, 4.29), (5.0, 4.0), (5.0, 4.0), (5.0, 4.5)]
    when = [0.0, 0.5, 2.5, 3.0]
    drive = scheduled_oracle(config, (14.0, 8.0), plan, when)._command(0.1, pose)
    assert drive.linear > 0.0
    assert scheduled_oracle(config, (14.0, 8.0), plan, when, exact_waits=False)._command(
        0.1, pose) is STOP
    # Within wait_tolerance of the cell the leg is done.
    assert scheduled_oracle(config, (14.0, 8.0), plan, when)._command(
        0.1, (5.0, 4.09, -math.pi / 2)) is STOP
    with pytest.raises(ValueError, match='wait_tolerance'):
        SpaceTimeConfig(wait_tolerance=0.0)


@pytest.mark.parametrize('still_start', [True, False])
def test_a_wait_where_the_robot_stands_keeps_its_pose(config, monkeypatch, still_start):
    # Held-out seed 1, maze 0/2/0: the plan waited in the robot's own cell, 0.1 m from its
    # centre; the next forecast put the robot at the centre, where a P3-AT would pass, while
    # at the robot's true place the P3-AT stopped for it.
    from dpn_navigator.benchmark.baselines import spacetime_oracle
    oracle = still_agent_oracle(config, (14.0, 8.0), still_start=still_start)
    oracle.set_goal(*GOAL)
    pose = (5.1, 4.1, 0.0)
    row, col = (int(v) for v in oracle.grid.geometry.world_to_cell(pose[0], pose[1]))
    plan = [(row, col, 0), (row, col, 2), (row, col, 4), (row, col + 1, 6)]
    monkeypatch.setattr(spacetime_oracle, 'spacetime_plan', lambda *args: (plan, None))
    oracle._plan_in_time(0.0, pose)
    _, xy = oracle._schedule
    centre = oracle.grid.geometry.cell_to_world(row, col)
    assert_allclose(xy[0], pose[:2])
    assert_allclose(xy[1:3], [pose[:2]] * 2 if still_start else [centre] * 2)
    assert_allclose(xy[3], oracle.grid.geometry.cell_to_world(row, col + 1))


def test_the_box_distance_is_zero_inside_and_the_gap_outside():
    half = (0.495, 0.335)
    points = np.array([[0.2, 0.1], [1.0, 0.0], [0.0, -1.0], [1.495, 1.335]])
    assert_allclose(_box_distance((0.0, 0.0, 0.0), half, points),
                    [0.0, 0.505, 0.665, math.sqrt(2.0)])
    # Turned by a quarter turn, length and width swap.
    assert_allclose(_box_distance((0.0, 0.0, math.pi / 2), half, points[1:2]), [0.665])


def test_without_the_body_guard_the_plan_is_followed_as_it_is(config):
    with pytest.raises(ValueError, match='body_margin must be finite'):
        SpaceTimeConfig(body_margin=-0.1)
    drive_on = VelocityCommand(0.8, 0.0)
    commands = {}
    for guard in (True, False):
        oracle = still_agent_oracle(config, (2.4, 4.0), body_guard=guard)   # 1.15 m ahead
        oracle.set_goal(*GOAL)
        oracle.step(0.0, START, **SCAN)                 # plans once
        oracle._command = lambda stamp, pose: drive_on  # the plan says: drive on
        commands[guard] = oracle.step(0.1, START, **SCAN).command
    assert commands[True] is STOP and commands[False] is drive_on
