"""Tests of the pose history: the robot's pose at a scan's stamp."""

import math

from dpn_navigator.core.pose_history import PoseHistory
import pytest


def test_pose_at_a_kept_stamp_is_that_pose():
    history = PoseHistory()
    for k in range(5):
        history.add(0.01 * k, (float(k), 0.0, 0.1 * k))
    assert history.pose_at(0.02) == (2.0, 0.0, 0.2)
    assert history.pose_at(0.04) == (4.0, 0.0, 0.4)
    assert history.pose_at(0.0) == (0.0, 0.0, 0.0)


def test_pose_between_stamps_is_interpolated_on_the_short_arc():
    history = PoseHistory()
    history.add(1.0, (0.0, 0.0, math.pi - 0.1))
    history.add(2.0, (2.0, 4.0, -math.pi + 0.1))       # turned 0.2 rad through +pi
    x, y, yaw = history.pose_at(1.25)
    assert (x, y) == pytest.approx((0.5, 1.0))
    assert yaw == pytest.approx(math.pi - 0.05)


@pytest.mark.parametrize(('stamp', 'expected'), [
    (0.97, (0.0, 0.0, 0.0)),            # within the tolerance before the oldest
    (3.0, (3.0, 0.0, 0.0)),             # the newest
    (0.9, None),
    (3.2, None),                        # more than the extrapolation after the newest
])
def test_stamps_outside_the_history(stamp, expected):
    history = PoseHistory(span=5.0, tolerance=0.05, extrapolation=0.1)
    for k in range(4):
        history.add(1.0 + k * (2.0 / 3.0), (float(k), 0.0, 0.0))
    assert history.pose_at(stamp) == expected


def test_a_stamp_after_the_newest_pose_moves_it_on_with_its_velocity():
    history = PoseHistory(extrapolation=0.2)
    history.add(1.0, (0.0, 0.0, 0.0), (1.0, 0.0))
    assert history.pose_at(1.1) == pytest.approx((0.1, 0.0, 0.0))
    history.add(2.0, (0.0, 0.0, 0.0), (1.0, 1.0))     # on an arc of radius 1 m
    x, y, yaw = history.pose_at(2.15)
    assert yaw == pytest.approx(0.15)
    assert math.hypot(x - math.sin(0.15), y - (1.0 - math.cos(0.15))) < 1e-3


def test_old_poses_are_dropped_and_time_going_back_starts_anew():
    history = PoseHistory(span=1.0)
    for k in range(30):
        history.add(k / 10, (float(k), 0.0, 0.0))
    assert len(history) == 11                      # 1.9 .. 2.9 s
    assert history.pose_at(1.0) is None
    history.add(0.5, (7.0, 7.0, 0.0))              # a restarted simulation
    assert len(history) == 1
    assert history.pose_at(0.5) == (7.0, 7.0, 0.0)
    assert PoseHistory().pose_at(0.0) is None


@pytest.mark.parametrize(('kwargs', 'message'), [
    ({'span': 0.0}, 'span must be positive'),
    ({'tolerance': -1.0}, 'tolerance must be finite'),
    ({'extrapolation': math.inf}, 'extrapolation must be finite'),
])
def test_bad_arguments_raise(kwargs, message):
    with pytest.raises(ValueError, match=message):
        PoseHistory(**kwargs)


def test_sample_step_is_the_step_a_pose_is_interpolated_across():
    history = PoseHistory(span=5.0)
    history.add(1.0, (0.0, 0.0, 3.0))
    history.add(1.5, (0.3, 0.4, -3.0))
    duration, distance, turn = history.sample_step(1.2)
    assert duration == pytest.approx(0.5) and distance == pytest.approx(0.5)
    assert turn == pytest.approx(2 * math.pi - 6.0)                  # the short arc
    assert history.sample_step(1.5) == (0.0, 0.0, 0.0)
    assert history.sample_step(0.9) is None and history.sample_step(1.6) is None
    assert PoseHistory().sample_step(1.0) is None


def test_odometry_whose_stamps_do_not_advance_keeps_memory_bounded():
    # A stuck clock: every pose at one stamp replaces the last; stamps 1 us apart fill the
    # 1 s span with a million poses unless the count is bounded too.
    from dpn_navigator.core.pose_history import MAX_KEPT_POSES
    history = PoseHistory()
    for k in range(5000):
        history.add(7.0, (float(k), 0.0, 0.0))
    assert len(history) == 1
    assert history.pose_at(7.0) == (4999.0, 0.0, 0.0)
    for k in range(3 * MAX_KEPT_POSES):
        history.add(8.0 + 1e-6 * k, (float(k), 0.0, 0.0))
    assert len(history) == MAX_KEPT_POSES
    newest = 8.0 + 1e-6 * (3 * MAX_KEPT_POSES - 1)
    assert history.newest_stamp == newest
    assert history.pose_at(newest) == (3.0 * MAX_KEPT_POSES - 1.0, 0.0, 0.0)
