"""Tests of the needless-standstill measure (issue 31): still spells, open routes, reruns."""

import json

from dpn_navigator.benchmark import standstill
from dpn_navigator.benchmark.episode_log import EpisodeLog
from dpn_navigator.benchmark.protocol import episode_seed, EpisodeSpec
from dpn_navigator.benchmark.runner import run_spec
from dpn_navigator.benchmark.standstill import (longest_needless_standstill, RouteCheck,
                                                still_spells)
from dpn_navigator.core.grid_geometry import GridGeometry
import numpy as np
import pytest

DT = 0.1


def test_still_spells_are_the_runs_of_still_scans():
    velocities = np.array([[0.5, 0.0], [0.0, 0.0], [0.01, 0.02], [0.0, 0.3], [0.0, 0.0],
                           [0.0, 0.0]])
    assert still_spells(np.arange(6) * DT, velocities) == [(1, 3), (4, 6)]
    assert still_spells(np.arange(2) * DT, [[1.0, 0.0], [0.0, 1.0]]) == []


class FixedRoute:
    """A route check whose route is one fixed line, open or closed by a schedule of times."""

    def __init__(self, closed_at=()):
        self.closed_at = set(closed_at)
        self.calls = []

    def route(self, xy):
        self.calls.append(tuple(xy))
        if round(xy[0], 6) in self.closed_at:      # the test encodes time in x
            return None
        return np.column_stack((np.linspace(10.0, 20.0, 41), np.zeros(41)))


def trajectory(still_from, still_to, end, agents=None):
    """Return scans every 0.1 s, still between two times; the x is the time (`FixedRoute`)."""
    times = np.round(np.arange(0.0, end + 1e-9, DT), 6)
    moving = (times < still_from) | (times >= still_to)
    velocities = np.column_stack((np.where(moving, 0.5, 0.0), np.zeros_like(times)))
    poses = np.column_stack((times, np.zeros_like(times), np.zeros_like(times)))
    if agents is None:
        agents = [np.empty((0, 2))] * times.shape[0]
    return times, poses, velocities, agents


def test_an_open_route_makes_the_whole_spell_needless():
    times, poses, velocities, agents = trajectory(2.0, 7.0, 10.0)
    still, needless = longest_needless_standstill(times, poses, velocities, agents,
                                                  FixedRoute())
    assert still == pytest.approx(5.0) and needless == pytest.approx(5.0)


def test_a_closed_route_or_an_agent_near_it_is_not_needless():
    times, poses, velocities, _ = trajectory(2.0, 7.0, 10.0)
    closed = FixedRoute(closed_at=np.round(np.arange(2.0, 7.0, 0.5), 6).tolist())
    assert longest_needless_standstill(times, poses, velocities,
                                       [np.empty((0, 2))] * len(times), closed)[1] == 0.0
    # An agent 1.5 m from the route until 4 s, then 2.5 m away: needless from 4 s to 7 s.
    agents = [np.array([[15.0, 1.5 if t < 4.0 else 2.5]]) for t in times]
    still, needless = longest_needless_standstill(times, poses, velocities, agents,
                                                  FixedRoute())
    assert still == pytest.approx(5.0) and needless == pytest.approx(3.0)


def test_routes_are_checked_every_period_not_every_scan():
    times, poses, velocities, agents = trajectory(2.0, 7.0, 10.0)
    route = FixedRoute()
    longest_needless_standstill(times, poses, velocities, agents, route, period=0.5)
    assert len(route.calls) == 10
    with pytest.raises(ValueError, match='period'):
        longest_needless_standstill(times, poses, velocities, agents, route, period=0.0)


def test_the_route_check_finds_a_gap_and_snaps_a_robot_beside_a_wall():
    geometry = GridGeometry(4.0, 4.0, 0.25)          # 16 x 16 cells
    clear = np.ones(geometry.shape, dtype=bool)
    clear[:, 8] = False                                # a wall across x = 2.0-2.25 m
    check = RouteCheck(clear, geometry, goal=(3.5, 0.5))
    assert check.route((0.5, 0.5)) is None             # closed
    clear[14, 8] = True                                # a gap at y = 3.5-3.75 m
    route = check.route((0.5, 0.5))
    assert route is not None and route[:, 1].max() > 3.4
    assert np.allclose(route[-1], (3.625, 0.625))
    # A robot in the wall's cell starts from the nearest clear one; far out of the map, none.
    assert check.route((2.1, 0.5)) is not None
    assert check.route((40.0, 40.0)) is None


@pytest.mark.slow
def test_the_tool_reruns_a_logged_episode_and_reproduces_it(tmp_path, capsys):
    spec = EpisodeSpec('back_and_forth', 0, 1, 0, episode_seed(0, 'back_and_forth', 0, 1, 0))
    row = run_spec(spec, navigator_options={}, detection=False)
    with EpisodeLog(tmp_path / 'episodes.csv') as log:
        log.append(row)
    (tmp_path / 'run.json').write_text(json.dumps({'navigator': 'dpn'}))
    assert standstill.main([str(tmp_path), '--min-still', '0']) == 0
    out = capsys.readouterr().out
    assert '1 of 1 episodes stood still' in out
    line = next(text for text in out.splitlines() if text.startswith('back_and_forth'))
    assert line.endswith('| yes')
    longest_still, longest_needless = (float(v) for v in line.split('|')[2].split())
    assert 0.0 <= longest_needless <= longest_still <= row['still_time'] + 1e-9
