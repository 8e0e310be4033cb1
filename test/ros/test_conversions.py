"""Tests of the message <-> array conversions, in memory."""

from array import array
import math

from builtin_interfaces.msg import Time
from dpn_navigator.core import CellLabel
from dpn_navigator.ros.conversions import (apply_occupancy_grid_update, labels_to_occupancy_grid,
                                           laser_scan_fields,
                                           line_strip_marker, make_laser_scan, marker_points,
                                           occupancy_grid_values, OccupancyGridBuffer,
                                           odometry_to_pose,
                                           pose_to_odometry, quaternion_to_yaw, sphere_marker,
                                           twist_to_velocity, velocity_to_twist, yaw_to_quaternion)
from geometry_msgs.msg import Quaternion
from map_msgs.msg import OccupancyGridUpdate
import numpy as np
from numpy.testing import assert_array_equal
import pytest
from visualization_msgs.msg import Marker

STAMP = Time(sec=12, nanosec=500)


@pytest.mark.parametrize('yaw', [0.0, 0.3, -2.0, math.pi / 2, 3.1])
def test_yaw_round_trips_through_a_quaternion(yaw):
    assert quaternion_to_yaw(yaw_to_quaternion(yaw)) == pytest.approx(yaw)


@pytest.mark.parametrize('quaternion, message', [
    (Quaternion(x=0.0, y=0.0, z=0.0, w=0.0), 'zero quaternion'),
    (Quaternion(x=0.0, y=0.0, z=math.nan, w=1.0), 'non-finite'),
])
def test_bad_quaternion_raises(quaternion, message):
    with pytest.raises(ValueError, match=message):
        quaternion_to_yaw(quaternion)


def test_odometry_round_trip_and_rejection():
    msg = pose_to_odometry((1.5, -2.0, 0.7), (0.4, -0.2), STAMP)
    assert msg.header.frame_id == 'map' and msg.child_frame_id == 'base_link'
    assert odometry_to_pose(msg) == pytest.approx((1.5, -2.0, 0.7))
    assert (msg.twist.twist.linear.x, msg.twist.twist.angular.z) == (0.4, -0.2)
    msg.pose.pose.position.x = math.inf
    with pytest.raises(ValueError, match='position is not finite'):
        odometry_to_pose(msg)


def test_laser_scan_round_trip_keeps_rep117_values():
    ranges = np.array([1.0, math.inf, math.nan, 0.05, 29.0], dtype=np.float32)
    msg = make_laser_scan(ranges, -1.0, 0.5, 0.1, 30.0, STAMP, scan_time=0.1)
    assert msg.header.frame_id == 'laser'
    assert msg.angle_max == pytest.approx(1.0)
    fields = laser_scan_fields(msg)
    assert_array_equal(fields['ranges'], ranges)
    assert fields['ranges'].dtype == np.float32
    assert (fields['angle_min'], fields['angle_increment'], fields['range_min'],
            fields['range_max']) == pytest.approx((-1.0, 0.5, 0.1, 30.0))


def test_occupancy_grid_carries_the_four_values_row_major():
    labels = np.array([[0, 1, 2], [3, 1, 0]], dtype=np.uint8)
    msg = labels_to_occupancy_grid(labels, 0.5, (-1.0, 2.0), STAMP)
    assert (msg.info.width, msg.info.height) == (3, 2)
    assert msg.info.resolution == pytest.approx(0.5)
    assert (msg.info.origin.position.x, msg.info.origin.position.y) == (-1.0, 2.0)
    assert isinstance(msg.data, array)
    assert_array_equal(occupancy_grid_values(msg), [[-1, 0, 100], [70, 0, -1]])
    assert labels[1, 0] == CellLabel.MOBILE_OBSTACLE


@pytest.mark.parametrize('mobile_value', [70, 99])
def test_buffer_refreshed_in_windows_equals_the_full_conversion(mobile_value):
    rng = np.random.default_rng(4)
    labels = np.zeros((37, 53), dtype=np.uint8)
    buffer = OccupancyGridBuffer(labels.shape, mobile_value)
    full = (slice(0, 37), slice(0, 53))
    for step in range(40):
        r0, c0 = rng.integers(0, 37), rng.integers(0, 53)
        rows = slice(r0, min(37, r0 + rng.integers(0, 12)))
        cols = slice(c0, min(53, c0 + rng.integers(0, 12)))
        labels[rows, cols] = rng.integers(0, 4, labels[rows, cols].shape)
        buffer.refresh(labels, *(full if step == 0 else (rows, cols)))
        msg = buffer.message(0.5, (-1.0, 2.0), STAMP, frame_id='odom')
        want = labels_to_occupancy_grid(labels, 0.5, (-1.0, 2.0), STAMP, frame_id='odom',
                                        mobile_value=mobile_value)
        assert msg.data == want.data and isinstance(msg.data, array)
        assert msg.info == want.info and msg.header == want.header
    # Cells changed outside the box given are not refreshed: the box is the contract.
    labels[0, 0] = CellLabel.STEADY_OBSTACLE
    buffer.refresh(labels, slice(5, 6), slice(5, 6))
    assert occupancy_grid_values(buffer.message(0.5, (0.0, 0.0), STAMP))[0, 0] != 100


def test_updates_applied_to_the_first_map_give_every_later_map():
    rng = np.random.default_rng(11)
    labels = np.zeros((41, 29), dtype=np.uint8)
    buffer = OccupancyGridBuffer(labels.shape)
    buffer.refresh(labels, slice(0, 41), slice(0, 29))
    subscriber = occupancy_grid_values(buffer.message(0.5, (0.0, 0.0), STAMP)).copy()
    sizes = []
    for _ in range(60):
        r0, c0 = rng.integers(0, 41), rng.integers(0, 29)
        rows = slice(r0, min(41, r0 + rng.integers(1, 15)))
        cols = slice(c0, min(29, c0 + rng.integers(1, 15)))
        # A few cells of the window change; the update covers them, not the whole window.
        changed = rng.random(labels[rows, cols].shape) < 0.05
        labels[rows, cols] = np.where(changed, rng.integers(0, 4, changed.shape),
                                      labels[rows, cols])
        update = buffer.update_message(labels, rows, cols, STAMP, frame_id='odom')
        want = occupancy_grid_values(labels_to_occupancy_grid(labels, 0.5, (0.0, 0.0), STAMP))
        if update is None:
            assert_array_equal(subscriber, want)
            continue
        assert update.header.frame_id == 'odom' and update.header.stamp == STAMP
        assert isinstance(update.data, array)
        # The smallest box: its first and last rows and columns each hold a changed cell.
        box = (subscriber != want)[update.y:update.y + update.height,
                                   update.x:update.x + update.width]
        assert box.any(axis=1)[[0, -1]].all() and box.any(axis=0)[[0, -1]].all()
        sizes.append(update.width * update.height)
        apply_occupancy_grid_update(subscriber, update)
        assert_array_equal(subscriber, want)
        assert_array_equal(occupancy_grid_values(buffer.message(0.5, (0.0, 0.0), STAMP)), want)
    assert sizes and min(sizes) < 15 * 15


def test_no_update_when_nothing_changed():
    labels = np.zeros((5, 5), dtype=np.uint8)
    buffer = OccupancyGridBuffer(labels.shape)
    buffer.refresh(labels, slice(0, 5), slice(0, 5))
    assert buffer.update_message(labels, slice(1, 4), slice(0, 5), STAMP) is None
    assert buffer.update_message(labels, slice(2, 2), slice(0, 0), STAMP) is None


@pytest.mark.parametrize('x, y, width, height, values, message', [
    (3, 0, 2, 1, 2, 'outside a map'),
    (0, -1, 1, 1, 1, 'outside a map'),
    (0, 0, 2, 2, 3, 'with 3 values'),
])
def test_update_outside_the_map_or_short_is_refused(x, y, width, height, values, message):
    update = OccupancyGridUpdate(x=x, y=y, width=width, height=height,
                                 data=array('b', bytes(values)))
    target = np.zeros((3, 4), dtype=np.int8)
    with pytest.raises(ValueError, match=message):
        apply_occupancy_grid_update(target, update)
    assert not target.any()


@pytest.mark.parametrize('shape, mobile_value, message', [
    ((3, 3), 0, 'mobile_value must be in 1..100'),
    ((3, 3), 101, 'mobile_value must be in 1..100'),
])
def test_buffer_bad_input_raises(shape, mobile_value, message):
    with pytest.raises(ValueError, match=message):
        OccupancyGridBuffer(shape, mobile_value)


def test_buffer_rejects_labels_of_another_shape():
    buffer = OccupancyGridBuffer((3, 4))
    with pytest.raises(ValueError, match='for a buffer of'):
        buffer.refresh(np.zeros((4, 3), dtype=np.uint8), slice(0, 1), slice(0, 1))


def test_twist_round_trip_and_rejection():
    assert twist_to_velocity(velocity_to_twist(0.5, -1.0)) == (0.5, -1.0)
    with pytest.raises(ValueError, match='non-finite'):
        twist_to_velocity(velocity_to_twist(math.nan, 0.0))


def test_markers():
    strip = line_strip_marker([[0.0, 0.0], [1.0, 2.0]], 'planned_path', 0, (1, 0, 0, 1), 0.1,
                              STAMP)
    assert strip.type == Marker.LINE_STRIP and strip.action == Marker.ADD
    assert_array_equal(marker_points(strip), [[0.0, 0.0], [1.0, 2.0]])
    assert (strip.color.r, strip.color.g) == (1.0, 0.0)
    empty = line_strip_marker(np.zeros((0, 2)), 'planned_path', 0, (1, 0, 0, 1), 0.1, STAMP)
    assert empty.action == Marker.DELETE
    goal = sphere_marker((3.0, 4.0), 'goal', 2, (0, 1, 0, 1), 0.4, STAMP)
    assert (goal.pose.position.x, goal.pose.position.y) == (3.0, 4.0)


def test_navigator_markers_built_once_per_change_equal_a_fresh_build():
    # The node's cached markers against navigator_markers on every scan of a run: the path
    # replaced now and then, the trail growing and started over, the goal set and changed.
    from dpn_navigator.ros.navigator_markers import (extend_trail, navigator_markers,
                                                     NavigatorMarkers)
    rng = np.random.default_rng(4)
    cached = NavigatorMarkers('map', min_period=0.0)
    trail, path, goal = [], None, None
    for step in range(120):
        if step % 17 == 3:
            path = rng.uniform(0.0, 20.0, (int(rng.integers(0, 30)), 2))
        if step % 40 == 1:
            goal = tuple(rng.uniform(0.0, 20.0, 2).tolist())
        if step == 70:
            trail = []                                      # a new goal starts it over
        extend_trail(trail, tuple(rng.uniform(0.0, 20.0, 2).tolist()))
        stamp = Time(sec=step, nanosec=7)
        want = navigator_markers(path, trail, goal, stamp)
        got = cached.messages(path, trail, goal, stamp, float(step))
        # Field by field (their CDR bytes differ in the padding, which is not initialised).
        assert got == want


@pytest.mark.parametrize('min_period', [0.0, 0.2])
def test_marker_schedule_sends_every_replan_late_at_most(min_period):
    from dpn_navigator.ros.navigator_markers import markers_due, NavigatorMarkers
    schedule = NavigatorMarkers(min_period=min_period)
    last, sent, replans = -math.inf, [], []
    for step in range(60):
        now = 0.05 * step
        replanned = step % 3 == 0 and step < 40
        if replanned:
            replans.append(now)
        if schedule.due(replanned, False, now):
            schedule.messages(None, [], None, Time(), now)
            sent.append(now)
        if min_period == 0.0:                  # the schedule of markers_due, scan for scan
            assert (sent[-1:] == [now]) == markers_due(replanned, False, now, last)
            last = sent[-1] if sent else last
    gaps = np.diff(sent)
    assert np.all(gaps >= min_period - 1e-9)
    # Every replan goes out, within min_period and one scan.
    assert all(any(replan <= s <= replan + min_period + 0.05 + 1e-9 for s in sent)
               for replan in replans)
