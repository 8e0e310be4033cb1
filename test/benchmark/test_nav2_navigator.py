"""
The Nav2-faithful costmap: NavFn's cost of unknown space, 1 Hz replanning and the recoveries.

The tree's order is driven with a planner that always fails (every recovery in turn, then the
abort after six); the unknown cost and the replanning rate on a small open costmap.

"""

import math

from dpn_navigator.benchmark.baselines import nav2_navigator as nav2
from dpn_navigator.benchmark.baselines.costmap_grid import CostmapConfig, CostmapGrid
from dpn_navigator.benchmark.protocol import NAVIGATORS
from dpn_navigator.core import CellLabel, NavigatorConfig, NavigatorStatus
import numpy as np
import pytest

SCAN = {'angle_min': -math.pi / 2, 'angle_increment': math.pi / 180, 'range_min': 0.1,
        'range_max': 30.0}


def navigator(size=20.0):
    # As the benchmark runs it: dpn's own additions (issue 31's costs among them) off.
    config = NavigatorConfig(width=size, height=size, **NAVIGATORS['costmap'])
    grid = CostmapGrid(size, size, 0.5, (0.0, 0.0), CostmapConfig.scaled_to_laser(30.0),
                       layer_resolution=0.1)
    return nav2.Nav2Navigator(config, grid)


def drive(nav, pose, seconds, dt=0.1, ranges=None):
    """Step the navigator with empty scans, moving the pose by its commands; yield outputs."""
    ranges = np.full(181, np.inf) if ranges is None else ranges
    t = getattr(nav, '_test_clock', 0.0)
    pose = list(pose)
    for _ in range(int(round(seconds / dt))):
        out = nav.step(t, tuple(pose), ranges, **SCAN)
        yield t, tuple(pose), out
        pose[0] += out.command.linear * math.cos(pose[2]) * dt
        pose[1] += out.command.linear * math.sin(pose[2]) * dt
        pose[2] += out.command.angular * dt
        t += dt
    nav._test_clock = t


def test_navfn_costs_unknown_cells_253_against_50():
    assert nav2.UNKNOWN_EXTRA_COST == pytest.approx(253 / 50 - 1)
    nav = navigator()
    # Row 10 (y = 5.25 m) known free from x = 2 to 18 m; the rest unknown. A straight line
    # from (2, 8) to (18, 8) through unknown costs 16 m * 5.06; the detour down to row 10,
    # along it and back up (3 + 16 + 3 m, mostly free) is cheaper.
    grid = nav.grid
    grid.labels[10, 4:37] = CellLabel.EXPLORED
    grid.labels_changed()
    nav.set_goal(18.25, 8.25)
    nav._plan((2.25, 8.25, 0.0))
    rows = nav.path[:, 0]
    assert rows.min() <= 10 and (rows == 10).sum() >= 20
    # With unknown as free (the bare costmap's rule) the straight line wins.
    nav._masks.unknown_cost = 0.0
    nav._plan((2.25, 8.25, 0.0))
    assert (nav.path[:, 0] == 16).all()


def test_replans_once_a_second():
    nav = navigator()
    nav.set_goal(18.0, 10.0)
    outputs = list(drive(nav, (2.0, 10.0, 0.0), 5.0))
    planned = [t for t, _, out in outputs if out.replanned]
    assert planned == pytest.approx([0.0, 1.0, 2.0, 3.0, 4.0], abs=1e-6)
    assert outputs[-1][2].command.linear > 0.5           # and drives in between


def test_the_default_tree_recovers_in_order_then_aborts(monkeypatch):
    nav = navigator()
    nav.set_goal(18.0, 10.0)

    def no_path(pose, count=True):
        return nav._no_path('no path to the goal on the current map')
    monkeypatch.setattr(nav, '_plan', no_path)
    outputs = list(drive(nav, (10.0, 10.0, 0.0), 60.0))
    reasons = [out.reason for _, _, out in outputs]
    # Each planner failure clears the costmap once before the recovery (the context clear).
    order = [reason for k, reason in enumerate(reasons)
             if reason.startswith('recovery:') and (k == 0 or reasons[k - 1] != reason)]
    assert order == ['recovery: spin', 'recovery: wait', 'recovery: back up',
                     'recovery: spin', 'recovery: wait'][:len(order)] and len(order) == 4
    spin = [(t, pose, out) for t, pose, out in outputs if out.reason == 'recovery: spin']
    first_spin = [pose[2] for t, pose, out in spin if t < spin[0][0] + 5.0]
    assert first_spin[-1] - first_spin[0] == pytest.approx(1.57, abs=0.15)
    assert all(0.4 - 1e-9 <= out.command.angular <= 1.0 for _, _, out in spin)
    waits = [t for t, _, out in outputs if out.reason == 'recovery: wait']
    first_wait = [t for t in waits if t < waits[0] + 6.0]
    assert first_wait[-1] - first_wait[0] == pytest.approx(5.0, abs=0.15)
    assert all(out.command.linear == out.command.angular == 0.0 for _, _, out in outputs
               if out.reason == 'recovery: wait')
    backup = [(pose, out) for _, pose, out in outputs if out.reason == 'recovery: back up']
    assert all(out.command.linear == -0.15 for _, out in backup)
    assert math.dist(backup[0][0][:2], backup[-1][0][:2]) == pytest.approx(0.3, abs=0.03)
    # Six recoveries (clear, spin, wait, back up, clear, spin), then the goal is aborted.
    assert nav.recoveries == 6 and nav.aborted
    assert nav.status is NavigatorStatus.NO_PATH and 'aborted' in nav.reason
    assert nav.clears == 7 + 2                          # 7 context clears, 2 recovery clears


def test_a_spin_next_to_a_wall_fails_and_the_round_robin_moves_on():
    nav = navigator()
    nav.set_goal(18.0, 10.0)
    # A lethal layer cell 0.45 m to the left of the robot's centre: the Husky (0.99 x 0.67 m)
    # standing along x does not touch it, but turning it would.
    layer = nav.grid.layer_geometry
    rr, cc = layer.world_to_cell(10.0, 10.45)
    nav.grid.lethal[rr, cc] = True
    assert not nav._footprint_hits((10.0, 10.0, 0.0), spin=False)
    assert nav._footprint_hits((10.0, 10.0, 0.0), spin=True)
    nav._round_robin = 1                                 # next: spin
    nav._start_next_behaviour(0.0, (10.0, 10.0, 0.0))
    assert nav._behaviour[0] is nav2.Recovery.WAIT


def test_the_controller_stops_for_a_lethal_cell_ahead_and_fails_without_progress():
    nav = navigator()
    nav.set_goal(18.0, 10.0)
    outputs = list(drive(nav, (2.0, 10.0, 0.0), 0.5))
    assert outputs[-1][2].command.linear > 0.0
    pose = outputs[-1][1]
    # A wall right ahead on the path (cells 0.5 to 0.9 m ahead), seen after the last plan.
    grid = nav.grid
    rows, cols = grid.geometry.world_to_cell(np.array([pose[0] + 0.7]), np.array([pose[1]]))
    grid.labels[rows[0], cols[0]] = CellLabel.STEADY_OBSTACLE
    out = nav.decide(0.55, pose)
    assert out.command.linear == 0.0 and 'lethal cell on the path ahead' in out.reason
    # Held without progress: after 10 s the first failure clears the costmap (the context
    # clear), the second one starts the recovery round robin.
    nav._next_plan = math.inf                          # no replanning in this test
    clears = nav.clears
    t = 0.6
    while t < 11.0:
        nav.decide(t, pose)
        t += 0.1
    assert nav.clears == clears + 1 and nav.recoveries == 0
    grid.labels[rows[0], cols[0]] = CellLabel.STEADY_OBSTACLE
    while t < 22.0 and nav.recoveries == 0:
        nav.decide(t, pose)
        t += 0.1
    assert nav.recoveries == 1 and nav.clears == clears + 2   # the round robin's first: clear
