"""Tests of the differential-drive path follower."""

import math

from dpn_navigator.core.control.path_follower import follow_path, FollowerConfig
from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest

CONFIG = FollowerConfig()


def test_inside_goal_tolerance_stops_and_reports_reached():
    command = follow_path((4.9, 0.1, 1.0), np.array([[0.0, 0.0], [5.0, 0.0]]), CONFIG)
    assert command.goal_reached
    assert (command.linear, command.angular) == (0.0, 0.0)


def test_the_goal_approach_margin_drives_on_inside_the_tolerance():
    margin = FollowerConfig(goal_approach_margin=0.1)
    path = np.array([[0.0, 0.0], [5.0, 0.0]])
    # 0.25 m from the goal: reached at the edge (the paper), not yet 0.1 m inside it.
    assert follow_path((4.75, 0.0, 0.0), path, CONFIG).goal_reached
    inside = follow_path((4.75, 0.0, 0.0), path, margin)
    assert not inside.goal_reached and inside.linear > 0.0
    assert follow_path((4.81, 0.0, 0.0), path, margin).goal_reached


def test_with_a_margin_a_localisation_error_still_ends_inside_the_true_tolerance():
    # The robot drives toward the goal on its estimate, which is 5 cm ahead of the true pose
    # (a localiser's error, which the robot cannot see).
    path = np.array([[0.0, 0.0], [5.0, 0.0]])
    for config, inside in ((CONFIG, False), (FollowerConfig(goal_approach_margin=0.1), True)):
        estimate = np.array([0.0, 0.0, 0.0])
        error = np.array([0.05, 0.0])       # true pose = estimate - error
        while True:
            command = follow_path(tuple(estimate), path, config)
            if command.goal_reached:
                break
            estimate[0] += command.linear * 0.05
            estimate[2] += command.angular * 0.05
        true_distance = math.dist(estimate[:2] - error, path[-1])
        assert (true_distance <= config.goal_tolerance) is inside


def test_straight_ahead_drives_at_full_speed():
    path = np.array([[float(x), 0.0] for x in range(11)])
    command = follow_path((0.0, 0.0, 0.0), path, CONFIG)
    assert command.linear == pytest.approx(CONFIG.max_linear_speed)
    assert command.angular == pytest.approx(0.0)
    assert not command.goal_reached


@pytest.mark.parametrize('yaw, turn_sign', [(3 * math.pi / 4, -1.0), (-3 * math.pi / 4, 1.0),
                                            (-math.pi / 2, 1.0),
                                            (math.pi / 2, -1.0)])
def test_large_heading_error_turns_in_place_toward_the_path(yaw, turn_sign):
    path = np.array([[1.0, 0.0], [5.0, 0.0]])
    command = follow_path((0.0, 0.0, yaw), path, CONFIG)
    assert command.linear == 0.0
    assert math.copysign(1.0, command.angular) == turn_sign
    assert abs(command.angular) == pytest.approx(CONFIG.max_angular_speed)


def test_slows_down_near_the_goal():
    path = np.array([[0.0, 0.0], [1.0, 0.0]])
    far = follow_path((-5.0, 0.0, 0.0), np.array([[0.0, 0.0], [5.0, 0.0]]), CONFIG)
    near = follow_path((0.25, 0.0, 0.0), path, CONFIG)
    assert 0.0 < near.linear < far.linear


def test_aims_at_the_lookahead_point_not_the_closest_one():
    path = np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [1.0, 1.0], [1.0, 2.0], [1.0, 3.0]])
    # From (0, 0) facing +x, the first point >= 1 m away is (1.0, 0.0): straight ahead.
    command = follow_path((0.0, 0.0, 0.0), path, CONFIG)
    assert command.angular == pytest.approx(0.0)
    # From (1.0, 0.0) the next point >= 1 m away is (1.0, 1.0): a left turn.
    command = follow_path((1.0, 0.0, 0.0), path, CONFIG)
    assert command.angular > 0.0


@settings(max_examples=200)
@given(pose=st.tuples(st.floats(-10, 10), st.floats(-10, 10), st.floats(-7, 7)),
       points=st.lists(st.tuples(st.floats(-10, 10), st.floats(-10, 10)), min_size=1,
                       max_size=8))
def test_commands_stay_within_limits(pose, points):
    command = follow_path(pose, np.array(points), CONFIG)
    assert 0.0 <= command.linear <= CONFIG.max_linear_speed
    assert abs(command.angular) <= CONFIG.max_angular_speed
    if command.goal_reached:
        assert math.hypot(points[-1][0] - pose[0], points[-1][1] - pose[1]) <= 0.3


@pytest.mark.parametrize('path, pose, message', [
    (np.zeros((0, 2)), (0.0, 0.0, 0.0), 'non-empty'),
    (np.zeros((3,)), (0.0, 0.0, 0.0), r'\(N, 2\)'),
    (np.zeros((2, 2)), (0.0, math.inf, 0.0), 'pose must be finite'),
])
def test_bad_input_raises(path, pose, message):
    with pytest.raises(ValueError, match=message):
        follow_path(pose, path, CONFIG)


@pytest.mark.parametrize('kwargs, message', [
    ({'max_linear_speed': 0.0}, 'max_linear_speed must be positive'),
    ({'max_angular_speed': -1.0}, 'max_angular_speed must be positive'),
    ({'goal_tolerance': math.nan}, 'goal_tolerance must be positive'),
    ({'turn_in_place_angle': 4.0}, 'at most pi'),
    ({'goal_approach_margin': -0.1}, 'goal_approach_margin must be in'),
    ({'goal_approach_margin': 0.3}, 'goal_approach_margin must be in'),
    ({'goal_approach_margin': math.inf}, 'goal_approach_margin must be in'),
])
def test_bad_config_raises(kwargs, message):
    with pytest.raises(ValueError, match=message):
        FollowerConfig(**kwargs)


# A corridor path on 0.5 m cells: east to (2, 0), then north; the robot 0.3 m before the corner.
CORNER_PATH = np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [1.5, 0.0], [2.0, 0.0],
                        [2.0, 0.5], [2.0, 1.0], [2.0, 1.5], [2.0, 2.0]])


def test_the_lookahead_point_stops_at_a_sharp_corner():
    # With a 0.6 m look-ahead the point would be (2.0, 0.5), round the corner: the robot would
    # steer inside it. It aims at the corner instead, straight ahead, at speed.
    command = follow_path((1.7, 0.0, 0.0), CORNER_PATH, CONFIG)
    assert command.angular == pytest.approx(0.0)
    assert command.linear > 0.5
    cutting = follow_path((1.7, 0.0, 0.0), CORNER_PATH, FollowerConfig(corner_angle=math.pi))
    assert cutting.angular > 0.5                     # the old behaviour: turning in early
    # At the corner, the path ahead turns 90 degrees: the robot turns in place.
    at_corner = follow_path((2.0, 0.0, 0.0), CORNER_PATH, CONFIG)
    assert at_corner.linear == 0.0 and at_corner.angular > 0.0


def test_grid_steps_of_45_degrees_are_not_corners():
    staircase = np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 0.5], [1.5, 0.5], [2.0, 1.0],
                          [2.5, 1.0]])
    command = follow_path((0.0, 0.0, 0.0), staircase, CONFIG)
    default_target = follow_path((0.0, 0.0, 0.0), staircase,
                                 FollowerConfig(corner_angle=math.pi))
    assert command == default_target
