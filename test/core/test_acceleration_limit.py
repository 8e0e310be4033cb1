"""Acceleration limits on the commands (core.control.acceleration_limit)."""

import math

from dpn_navigator.core.control.acceleration_limit import AccelerationLimiter
import pytest


def test_speed_grows_at_most_by_the_limit():
    limiter = AccelerationLimiter(2.5, 3.2)
    assert limiter.limit(1.0, 1.5, 0.0) == pytest.approx((0.25, 0.32))    # first period 0.1 s
    assert limiter.limit(1.0, 1.5, 0.1) == pytest.approx((0.5, 0.64))
    assert limiter.limit(1.0, -1.5, 0.2) == pytest.approx((0.75, -0.32))  # reversal via zero
    assert limiter.limit(1.0, -1.5, 0.4) == pytest.approx((1.0, -0.96))


def test_slowing_down_and_stopping_pass_at_once():
    limiter = AccelerationLimiter(2.5, 3.2)
    for k in range(10):
        limiter.limit(1.0, 0.0, 0.1 * k)
    assert limiter.limit(0.2, 0.0, 1.0) == (0.2, 0.0)
    assert limiter.limit(0.0, 0.0, 1.1) == (0.0, 0.0)


def test_zero_limit_is_off_and_reset_starts_from_standing():
    limiter = AccelerationLimiter(0.0, 0.0)
    assert limiter.limit(1.0, 1.5, 0.0) == (1.0, 1.5)
    limiter = AccelerationLimiter(1.0, 1.0)
    for k in range(20):
        limiter.limit(1.0, 0.0, 0.1 * k)
    limiter.reset(2.0)
    assert limiter.limit(1.0, 0.0, 2.1) == pytest.approx((0.1, 0.0))


def test_time_going_back_counts_as_one_period():
    limiter = AccelerationLimiter(1.0, 1.0)
    limiter.limit(0.5, 0.0, 10.0)
    assert limiter.limit(1.0, 0.0, 5.0)[0] == pytest.approx(0.2)


@pytest.mark.parametrize('values', [(-1.0, 1.0), (math.nan, 1.0), (1.0, math.inf)])
def test_bad_limits_are_refused(values):
    with pytest.raises(ValueError, match='finite and >= 0'):
        AccelerationLimiter(*values)
