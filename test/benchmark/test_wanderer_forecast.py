"""The foresight oracle's forecast: constant velocity over 2 s, for the agents near the robot."""

from dpn_navigator.benchmark.baselines import wanderer_forecast as wf
import numpy as np
from numpy.testing import assert_allclose


def test_agents_near_the_robot_are_forecast_at_constant_velocity():
    now = np.array([[2.0, 0.0], [50.0, 0.0]])
    before = np.array([[2.1, 0.0], [50.0, 0.0]])          # the first walks -x at 1 m/s
    points = wf.forecast_positions(now, before, 0.1, (0.0, 0.0), reach=1.0)
    # The far one (50 m > 1 + 2.4 * 2 m) is left out; the near one at 0, 0.25, ..., 2 s.
    assert points.shape == (9, 2)
    assert_allclose(points[:, 0], 2.0 - np.arange(0.0, 2.01, 0.25), atol=1e-12)
    assert_allclose(points[:, 1], 0.0, atol=1e-12)
    assert wf.interest_radius(1.0) == 1.0 + 2.4 * 2.0


def test_without_a_previous_position_agents_stand():
    points = wf.forecast_positions([[1.0, 1.0]], None, 0.1, (0.0, 0.0), reach=1.0)
    assert_allclose(points, np.tile([1.0, 1.0], (9, 1)))
    assert wf.forecast_positions(np.zeros((0, 2)), None, 0.1, (0.0, 0.0), 1.0).shape == (0, 2)
    # Another number of agents than before (cannot happen in an episode): standing.
    assert_allclose(wf.forecast_positions([[1.0, 1.0]], [[0.0, 0.0], [2.0, 2.0]], 0.1,
                                          (0.0, 0.0), 1.0), np.tile([1.0, 1.0], (9, 1)))
