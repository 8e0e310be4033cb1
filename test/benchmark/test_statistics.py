"""Bootstrap intervals stratified by map and the exact sign test for any number of episodes."""

from fractions import Fraction
import math

from dpn_navigator.benchmark.compare_report import sign_test as compare_sign_test
from dpn_navigator.benchmark.statistics import (format_interval, paired_difference, sign_test,
                                                stratified_bootstrap)
import numpy as np
import pytest


def test_sign_test_small_cases_are_exact():
    assert sign_test(0, 0) == 1.0
    assert sign_test(1, 0) == 1.0
    assert sign_test(5, 0) == pytest.approx(2 / 32)
    assert sign_test(170, 30) == pytest.approx(6.2e-25, rel=0.05)   # docs/benchmark.md's value
    assert compare_sign_test is sign_test


def test_sign_test_does_not_overflow_past_1023_episodes():
    # 2.0 ** 1024 overflows a float; the exact test does not.
    assert sign_test(600, 600) == 1.0
    p = sign_test(560, 640)
    expected = Fraction(2 * sum(math.comb(1200, k) for k in range(561)), 2 ** 1200)
    assert p == pytest.approx(float(expected)) and 0.01 < p < 0.05
    assert sign_test(3000, 0) == 0.0            # below the smallest float, not an error
    with pytest.raises(ValueError):
        sign_test(-1, 3)


def test_stratified_bootstrap_covers_the_mean_and_keeps_strata():
    rng = np.random.default_rng(1)
    values = rng.random(200) < 0.8
    maps = np.repeat(np.arange(10), 20)
    estimate, low, high = stratified_bootstrap(values, maps)
    assert estimate == pytest.approx(values.mean()) and low < estimate < high
    assert 0.05 < high - low < 0.2
    # Every map all successes or all failures: resampling within maps cannot move the mean.
    fixed = np.repeat([1.0, 0.0], 20)
    assert stratified_bootstrap(fixed, np.repeat([0, 1], 20)) == (0.5, 0.5, 0.5)
    assert math.isnan(stratified_bootstrap([math.nan], [0])[0])
    with pytest.raises(ValueError):
        stratified_bootstrap([1.0, 2.0], [0])


def test_paired_difference_and_format():
    subject = np.array([1, 1, 1, 0] * 10, dtype=float)
    other = np.array([1, 0, 1, 0] * 10, dtype=float)
    estimate, low, high = paired_difference(subject, other, np.repeat(np.arange(4), 10))
    assert estimate == pytest.approx(0.25) and low <= 0.25 <= high
    assert format_interval(0.5, 0.4, 0.6, scale=100.0) == '50.0 [40.0, 60.0]'
    assert format_interval(math.nan, math.nan, math.nan) == '-'
