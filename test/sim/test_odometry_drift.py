"""The world's drifting odometry and its localiser (sim_bridge.odometry_drift), no ROS."""

import math

from dpn_navigator.core.pose2d import compose
import numpy as np
import pytest
from sim_bridge.odometry_drift import (DriftConfig, DriftingOdometry, inverse_pose, Localiser,
                                       LocaliserConfig, relative_motion)


def straight_line(length, steps=500, start=(1.0, 2.0, 0.5)):
    x, y, yaw = start
    return [(x + k * length / steps * math.cos(yaw), y + k * length / steps * math.sin(yaw),
             yaw) for k in range(steps + 1)]


def drive(odometry, poses):
    for pose in poses[1:]:
        odom = odometry.update(pose)
    return odom


def test_no_drift_is_the_true_pose():
    poses = straight_line(10.0)
    odometry = DriftingOdometry(DriftConfig(), poses[0])
    assert drive(odometry, poses) == poses[-1]


def test_scale_error_lengthens_the_distance():
    poses = straight_line(10.0)
    odometry = DriftingOdometry(DriftConfig(scale=0.02), poses[0])
    odom = drive(odometry, poses)
    driven = math.hypot(odom[0] - poses[0][0], odom[1] - poses[0][1])
    assert driven == pytest.approx(10.2, abs=1e-9)
    assert odom[2] == pytest.approx(0.5)


def test_yaw_per_metre_turns_a_straight_line():
    poses = straight_line(10.0)
    odometry = DriftingOdometry(DriftConfig(yaw_per_metre=0.01), poses[0])
    odom = drive(odometry, poses)
    assert odom[2] - 0.5 == pytest.approx(0.1, abs=1e-9)
    # A curved path of 10 m: it ends off the straight line by about L^2 k / 2 = 0.5 m.
    dx, dy, _ = relative_motion(poses[-1], odom)
    assert dy == pytest.approx(0.5, rel=0.05)


def test_yaw_scale_error_scales_turns():
    poses = [(0.0, 0.0, 0.01 * k) for k in range(101)]     # 1 rad on the spot
    odometry = DriftingOdometry(DriftConfig(yaw_scale=0.05), poses[0])
    assert drive(odometry, poses)[2] == pytest.approx(1.05, abs=1e-9)


def test_noise_is_seeded():
    poses = straight_line(5.0)
    a, b, c = (DriftingOdometry(DriftConfig(noise=0.05), poses[0], seed=s) for s in (1, 1, 2))
    assert drive(a, poses) == drive(b, poses) != drive(c, poses)


def test_exact_localiser_puts_the_odometry_back_on_the_truth():
    poses = straight_line(10.0)
    odometry = DriftingOdometry(DriftConfig(scale=0.03, yaw_per_metre=0.02), poses[0])
    localiser = Localiser(LocaliserConfig())
    for k, pose in enumerate(poses[1:]):
        odom = odometry.update(pose)
        estimate = compose(localiser.update(0.02 * k, pose, odom), odom)
        np.testing.assert_allclose(estimate, pose, atol=1e-9)


def test_localiser_error_and_rate():
    localiser = Localiser(LocaliserConfig(error_xy=0.05, error_yaw=0.02, rate=1.0), seed=3)
    true, odom = (5.0, 5.0, 0.3), (4.0, 5.5, 0.1)
    estimate = compose(localiser.update(0.0, true, odom), odom)
    assert math.hypot(estimate[0] - true[0], estimate[1] - true[1]) == pytest.approx(0.05)
    assert estimate[2] - true[2] == pytest.approx(0.02)
    # Within the period the correction holds, after it, it is refreshed.
    held = compose(localiser.update(0.5, (9.0, 9.0, 0.0), odom), odom)
    np.testing.assert_allclose(held, estimate)
    refreshed = compose(localiser.update(1.0, (9.0, 9.0, 0.0), odom), odom)
    assert refreshed[0] == pytest.approx(9.0, abs=0.06)


def test_inverse_pose_round_trip():
    pose = (1.5, -2.0, 2.5)
    np.testing.assert_allclose(compose(pose, inverse_pose(pose)), (0.0, 0.0, 0.0), atol=1e-12)


@pytest.mark.parametrize('kwargs, match', [
    ({'scale': math.nan}, 'finite'), ({'scale': 0.7}, 'scale'), ({'noise': -1.0}, 'noise')])
def test_bad_drift_config(kwargs, match):
    with pytest.raises(ValueError, match=match):
        DriftConfig(**kwargs)


def test_bad_localiser_config():
    with pytest.raises(ValueError, match='localiser'):
        LocaliserConfig(rate=-1.0)
