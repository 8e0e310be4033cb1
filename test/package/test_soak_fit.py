"""The soak tool's fitted RSS growth: a least-squares slope and its Student-t interval."""

import math
from pathlib import Path
import sys

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / 'tools'))
from soak_ros import fitted_growth, student_t_quantile  # noqa: E402, I100


@pytest.mark.parametrize('dof, expected', [(1, 12.7062047), (3, 3.1824463), (10, 2.2281389),
                                           (52, 2.0066468), (1000, 1.9623391)])
def test_the_t_quantile_is_the_tabled_one(dof, expected):
    assert student_t_quantile(0.975, dof) == pytest.approx(expected, abs=1e-5)


def test_the_slope_and_its_interval_come_from_the_samples():
    rng = np.random.default_rng(3)
    times = np.arange(60) * 10.0                                 # [s]
    covered = 0
    for _ in range(200):
        rss = 200.0 + 2.0 / 3600.0 * times + rng.normal(0.0, 0.2, times.shape)
        slope, half_width = fitted_growth(times, rss)
        covered += abs(slope - 2.0) <= half_width
    assert 0.9 <= covered / 200 <= 0.99                          # a 95 % interval
    exact = fitted_growth(times, 5.0 + 1.0 / 3600.0 * times)
    assert exact[0] == pytest.approx(1.0) and exact[1] == pytest.approx(0.0, abs=1e-9)
    assert all(math.isnan(v) for v in fitted_growth([0.0, 10.0], [1.0, 2.0]))
