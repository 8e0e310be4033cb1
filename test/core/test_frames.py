"""
The 3-D transforms and the TF buffer of ``core/frames``, against tf2's documented behaviour.

The expected behaviour is tf2's (geometry2 ``tf2/src/buffer_core.cpp``, ``cache.cpp``,
``static_cache.cpp``; the ROS 2 tf2 concept pages): static transforms hold at all times;
``TimeCache::findClosest`` returns a sample at its exact stamp, the two samples bracketing a
time otherwise, and an extrapolation error before the oldest, after the newest, or for a single
sample at another time; ``TimeCache::interpolate`` is linear in translation and slerp in
rotation; time 0 is ``getLatestCommonTime`` (the earliest of the newest stamps on the path,
static links not counting); ``lookupTransform(target, source)`` gives the pose of ``source`` in
``target``; the cache keeps ``BUFFER_CORE_DEFAULT_CACHE_TIME`` = 10 s behind the newest sample
(``pruneList``) and refuses older data (``TF_OLD_DATA``); NaNs, denormalised quaternions (off by
``QUATERNION_NORMALIZATION_TOLERANCE`` = 0.01), empty names and self transforms are refused.
"""

import doctest
import math

from dpn_navigator.core.frames import (ConnectivityError, ExtrapolationError, FrameLookupError,
                                       InvalidTransformError, TfBuffer, Transform3D)
from dpn_navigator.core.frames import laser_plane as laser_plane_module
from dpn_navigator.core.frames import tf_buffer as tf_buffer_module
from dpn_navigator.core.frames import transform3d as transform3d_module
from dpn_navigator.core.frames.laser_plane import LaserNotLevelError, planar_laser
from dpn_navigator.core.frames.transform3d import quaternion_from_rpy, slerp
from hypothesis import given, strategies as st
import numpy as np
from numpy.testing import assert_allclose
import pytest

IDENTITY_Q = (0.0, 0.0, 0.0, 1.0)
S = 1_000_000_000


def matrix(transform):
    """Return the 4x4 homogeneous matrix of a transform (the independent twin)."""
    m = np.eye(4)
    m[:3, :3] = transform.rotation_matrix()
    m[:3, 3] = transform.translation
    return m


def rpy_matrix(roll, pitch, yaw):
    """Rz(yaw) Ry(pitch) Rx(roll), written out."""
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch),
                              math.sin(pitch), math.cos(yaw), math.sin(yaw))
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


angles = st.floats(-math.pi, math.pi, allow_nan=False)
offsets = st.floats(-10.0, 10.0, allow_nan=False)
poses = st.tuples(offsets, offsets, offsets, angles,
                  st.floats(-1.5, 1.5, allow_nan=False), angles)


def test_the_docstring_examples_run():
    for module in (transform3d_module, tf_buffer_module, laser_plane_module):
        result = doctest.testmod(module)
        assert result.attempted > 0 and result.failed == 0


# --- Transform3D -------------------------------------------------------------------------------

@given(poses)
def test_rotation_matrix_is_rz_ry_rx(pose):
    x, y, z, roll, pitch, yaw = pose
    t = Transform3D.from_xyz_rpy(x, y, z, roll, pitch, yaw)
    assert_allclose(t.rotation_matrix(), rpy_matrix(roll, pitch, yaw), atol=1e-12)
    # getRPY gives back the angles (away from pitch = +-pi/2).
    assert_allclose(rpy_matrix(t.roll, t.pitch, t.yaw), t.rotation_matrix(), atol=1e-9)


@given(poses, poses, st.lists(st.tuples(offsets, offsets, offsets), min_size=1, max_size=5))
def test_compose_inverse_and_apply_agree_with_matrices(a_pose, b_pose, points):
    a = Transform3D.from_xyz_rpy(*a_pose)
    b = Transform3D.from_xyz_rpy(*b_pose)
    assert_allclose(matrix(a @ b), matrix(a) @ matrix(b), atol=1e-9)
    assert_allclose(matrix(a.inverse()), np.linalg.inv(matrix(a)), atol=1e-9)
    assert (a @ a.inverse()).is_close(Transform3D.identity(), atol=1e-9)
    p = np.array(points)
    homogeneous = np.column_stack([p, np.ones(len(p))]) @ matrix(a).T
    assert_allclose(a.apply(p), homogeneous[:, :3], atol=1e-9)
    assert_allclose(a.apply(p[0]), homogeneous[0, :3], atol=1e-9)


def test_an_upside_down_laser_mirrors_its_beams():
    # Roll pi: a beam at +30 deg in the laser frame points at -30 deg in the base frame.
    mount = Transform3D.from_xyz_rpy(0.2, 0.0, 0.3, roll=math.pi)
    beam = np.array([[math.cos(math.radians(30)), math.sin(math.radians(30))]])
    assert_allclose(mount.apply(beam), [[0.2 + math.cos(math.radians(30)),
                                         -math.sin(math.radians(30)), 0.3]], atol=1e-12)
    assert mount.yaw == pytest.approx(0.0) and abs(mount.roll) == pytest.approx(math.pi)


def test_planar_points_are_taken_at_z_zero_and_other_shapes_are_refused():
    t = Transform3D((1.0, 2.0, 3.0))
    assert_allclose(t.apply([[0.0, 0.0]]), [[1.0, 2.0, 3.0]])
    with pytest.raises(ValueError, match='points have shape'):
        t.apply([[1.0, 2.0, 3.0, 4.0]])


@pytest.mark.parametrize('rotation, message', [
    ((0.0, 0.0, 0.0), '4 components'),
    ((0.0, 0.0, 0.0, 0.0), 'not of unit length'),
    ((0.0, 0.0, 0.1, 1.0), 'not of unit length'),       # squared norm 1.01: tf2 refuses it
    ((0.0, 0.0, math.nan, 1.0), 'non-finite'),
])
def test_bad_quaternions_are_refused(rotation, message):
    with pytest.raises(ValueError, match=message):
        Transform3D(rotation=rotation)


def test_a_quaternion_within_tf2s_tolerance_is_normalised():
    t = Transform3D(rotation=(0.0, 0.0, 0.0, 1.004))
    assert_allclose(t.rotation, IDENTITY_Q)


def test_bad_translations_are_refused():
    with pytest.raises(ValueError, match='translation'):
        Transform3D((0.0, math.inf, 0.0))
    with pytest.raises(ValueError, match='translation'):
        Transform3D((0.0, 1.0))


def test_slerp_takes_the_shorter_way_and_keeps_unit_length():
    a = quaternion_from_rpy(0.0, 0.0, math.radians(170))
    b = quaternion_from_rpy(0.0, 0.0, math.radians(-170))     # 20 deg away, across +-pi
    middle = Transform3D(rotation=slerp(a, b, 0.5))
    assert abs(middle.yaw) == pytest.approx(math.pi)
    assert np.linalg.norm(slerp(a, b, 0.3)) == pytest.approx(1.0)
    assert_allclose(slerp(a, a, 0.5), a)


# --- TfBuffer: what tf2 does -------------------------------------------------------------------

def robot_tree(cache_duration_ns=None):
    """Return map -> odom (10, 20 s) -> base_link (10, 12, 20 s) -> laser (static)."""
    buffer = TfBuffer(cache_duration_ns)
    buffer.set_transform('map', 'odom', 10 * S, (0.0, 0.0, 0.0), IDENTITY_Q)
    buffer.set_transform('map', 'odom', 20 * S, (1.0, 0.0, 0.0), IDENTITY_Q)
    buffer.set_transform('odom', 'base_link', 10 * S, (0.0, 0.0, 0.0), IDENTITY_Q)
    buffer.set_transform('odom', 'base_link', 12 * S, (2.0, 0.0, 0.0),
                         quaternion_from_rpy(0, 0, math.pi / 2))
    buffer.set_transform('odom', 'base_link', 20 * S, (2.0, 8.0, 0.0),
                         quaternion_from_rpy(0, 0, math.pi / 2))
    buffer.set_transform('base_link', 'laser', 0, (0.5, 0.0, 0.2),
                         quaternion_from_rpy(math.pi, 0, 0), static=True)
    return buffer


def test_a_static_transform_holds_at_all_times():
    buffer = robot_tree()
    for stamp in (0, 1, 10 * S, 10**18):
        t = buffer.lookup('base_link', 'laser', stamp)
        assert_allclose(t.translation, (0.5, 0.0, 0.2))
    assert buffer.time_range('laser') is None and buffer.is_static('laser')


def test_a_query_at_a_samples_stamp_returns_it():
    t = robot_tree().lookup('odom', 'base_link', 12 * S)
    assert_allclose(t.translation, (2.0, 0.0, 0.0))
    assert t.yaw == pytest.approx(math.pi / 2)


def test_between_two_samples_translation_is_linear_and_rotation_slerp():
    buffer = robot_tree()
    t = buffer.lookup('odom', 'base_link', 11 * S)              # halfway from 10 s to 12 s
    assert_allclose(t.translation, (1.0, 0.0, 0.0), atol=1e-12)
    assert t.yaw == pytest.approx(math.pi / 4)
    t = buffer.lookup('odom', 'base_link', 14 * S)              # a quarter from 12 s to 20 s
    assert_allclose(t.translation, (2.0, 2.0, 0.0), atol=1e-12)
    assert t.yaw == pytest.approx(math.pi / 2)


def test_a_chain_composes_through_every_link():
    buffer = robot_tree()
    stamp = 15 * S
    expected = (buffer.lookup('map', 'odom', stamp) @ buffer.lookup('odom', 'base_link', stamp)
                @ buffer.lookup('base_link', 'laser', stamp))
    got = buffer.lookup('map', 'laser', stamp)
    assert got.is_close(expected)
    # map->odom at 15 s: x 0.5; base at 15 s: (2, 3) facing +y; the laser 0.5 ahead of it.
    assert_allclose(got.translation, (2.5, 3.5, 0.2), atol=1e-12)
    assert buffer.lookup('laser', 'map', stamp).is_close(got.inverse())


def test_siblings_are_looked_up_through_their_common_ancestor():
    buffer = robot_tree()
    buffer.set_transform('base_link', 'camera', 0, (0.0, 1.0, 0.0), IDENTITY_Q, static=True)
    t = buffer.lookup('laser', 'camera', 15 * S)
    expected = buffer.lookup('base_link', 'laser').inverse() @ buffer.lookup('base_link',
                                                                             'camera')
    assert t.is_close(expected)
    # The camera at (0, 1, 0) of the base is at (-0.5, -1, -0.2) of the upside-down laser.
    assert_allclose(t.translation, (-0.5, -1.0, 0.2), atol=1e-12)


@pytest.mark.parametrize('stamp, direction', [(25 * S, 'future'), (5 * S, 'past')])
def test_no_extrapolation(stamp, direction):
    buffer = robot_tree()
    with pytest.raises(ExtrapolationError, match=f'extrapolation into the {direction}') as info:
        buffer.lookup('map', 'laser', stamp)
    assert info.value.stamp_ns == stamp and info.value.frame in ('odom', 'base_link')
    assert not buffer.can_transform('map', 'laser', stamp)


def test_a_single_sample_holds_only_at_its_own_stamp():
    buffer = TfBuffer()
    buffer.set_transform('odom', 'base_link', 5 * S, (1.0, 0.0, 0.0), IDENTITY_Q)
    assert buffer.can_transform('odom', 'base_link', 5 * S)
    for stamp in (5 * S - 1, 5 * S + 1):
        with pytest.raises(ExtrapolationError):
            buffer.lookup('odom', 'base_link', stamp)


def test_time_zero_is_the_latest_common_time():
    buffer = robot_tree()
    buffer.set_transform('odom', 'base_link', 22 * S, (2.0, 10.0, 0.0),
                         quaternion_from_rpy(0, 0, math.pi / 2))
    # map->odom ends at 20 s, odom->base_link at 22 s: the common time is 20 s.
    assert buffer.latest_common_time('map', 'laser') == 20 * S
    assert buffer.latest_common_time('odom', 'laser') == 22 * S
    assert buffer.lookup('map', 'laser').is_close(buffer.lookup('map', 'laser', 20 * S))
    assert buffer.latest_common_time('base_link', 'laser') == 0        # static only
    assert buffer.latest_common_time('base_link', 'base_link') == 22 * S
    assert buffer.latest_common_time('laser', 'laser') == 0
    assert buffer.lookup('laser', 'laser', 123).is_close(Transform3D.identity())


def test_time_zero_can_mean_the_time_zero():
    buffer = TfBuffer()
    buffer.set_transform('odom', 'base_link', 0, (0.0, 0.0, 0.0), IDENTITY_Q)
    buffer.set_transform('odom', 'base_link', S, (1.0, 0.0, 0.0), IDENTITY_Q)
    assert_allclose(buffer.lookup('odom', 'base_link', 0).translation, (1.0, 0.0, 0.0))
    assert_allclose(buffer.lookup('odom', 'base_link', 0, zero_is_latest=False).translation,
                    (0.0, 0.0, 0.0))
    later = TfBuffer()
    later.set_transform('odom', 'base_link', S, (1.0, 0.0, 0.0), IDENTITY_Q)
    assert later.can_transform('odom', 'base_link', 0)
    assert not later.can_transform('odom', 'base_link', 0, zero_is_latest=False)


def test_the_cache_keeps_ten_seconds_by_default():
    buffer = TfBuffer()
    assert buffer.cache_duration_ns == 10 * S
    for second in range(0, 31):
        assert buffer.set_transform('odom', 'base_link', second * S, (second, 0, 0), IDENTITY_Q)
    assert buffer.time_range('base_link') == (20 * S, 30 * S)
    assert not buffer.can_transform('odom', 'base_link', 19 * S)
    assert not buffer.set_transform('odom', 'base_link', 19 * S, (0, 0, 0), IDENTITY_Q)
    assert buffer.set_transform('odom', 'base_link', 25 * S + 1, (0, 0, 0), IDENTITY_Q)


def test_an_unbounded_cache_keeps_everything_in_any_order():
    buffer = TfBuffer(cache_duration_ns=None)
    for second in (30, 0, 15, 5):
        assert buffer.set_transform('odom', 'base_link', second * S, (second, 0, 0), IDENTITY_Q)
    assert buffer.time_range('base_link') == (0, 30 * S)
    assert_allclose(buffer.lookup('odom', 'base_link', 10 * S).translation, (10.0, 0.0, 0.0))
    assert_allclose(buffer.lookup('odom', 'base_link', 2 * S).translation, (2.0, 0.0, 0.0))


def test_a_sample_at_the_same_stamp_replaces_the_first():
    buffer = TfBuffer()
    buffer.set_transform('odom', 'base_link', S, (1.0, 0.0, 0.0), IDENTITY_Q)
    buffer.set_transform('odom', 'base_link', S, (2.0, 0.0, 0.0), IDENTITY_Q)
    assert_allclose(buffer.lookup('odom', 'base_link', S).translation, (2.0, 0.0, 0.0))


def test_a_static_transform_replaces_a_dynamic_history_and_back():
    buffer = robot_tree()
    buffer.set_transform('odom', 'base_link', 0, (7.0, 0.0, 0.0), IDENTITY_Q, static=True)
    assert_allclose(buffer.lookup('odom', 'base_link', 99 * S).translation, (7.0, 0.0, 0.0))
    buffer.set_transform('odom', 'base_link', 3 * S, (1.0, 0.0, 0.0), IDENTITY_Q)
    assert buffer.time_range('base_link') == (3 * S, 3 * S)


def test_leading_slashes_are_stripped_on_input_and_refused_in_lookups():
    buffer = TfBuffer()
    buffer.set_transform('/odom', '/base_link', S, (1.0, 0.0, 0.0), IDENTITY_Q)
    assert buffer.frames == {'odom', 'base_link'}
    with pytest.raises(FrameLookupError, match="cannot start with a '/'"):
        buffer.lookup('/odom', 'base_link', S)


@pytest.mark.parametrize('target, source, message', [
    ('map', 'nowhere', "source frame 'nowhere' does not exist"),
    ('', 'laser', 'cannot be empty'),
])
def test_unknown_frames(target, source, message):
    with pytest.raises(FrameLookupError, match=message):
        robot_tree().lookup(target, source, 15 * S)


def test_two_trees_are_not_connected():
    buffer = robot_tree()
    buffer.set_transform('world', 'other', 0, (0, 0, 0), IDENTITY_Q, static=True)
    with pytest.raises(ConnectivityError, match="'other' and 'laser'"):
        buffer.lookup('other', 'laser', 15 * S)
    assert not buffer.can_transform('other', 'laser', 15 * S)


@pytest.mark.parametrize('parent, child, translation, rotation, message', [
    ('odom', 'odom', (0, 0, 0), IDENTITY_Q, 'to itself'),
    ('', 'odom', (0, 0, 0), IDENTITY_Q, 'parent frame is empty'),
    ('map', '/', (0, 0, 0), IDENTITY_Q, 'child frame is empty'),
    ('map', 'odom', (math.nan, 0, 0), IDENTITY_Q, 'translation'),
    ('map', 'odom', (0, 0, 0), (0, 0, math.nan, 1), 'non-finite'),
    ('map', 'odom', (0, 0, 0), (0, 0, 0, 1.1), 'not of unit length'),
    ('elsewhere', 'base_link', (0, 0, 0), IDENTITY_Q, "already has the parent 'odom'"),
    ('laser', 'map', (0, 0, 0), IDENTITY_Q, 'would close a loop'),
])
def test_malformed_transforms_are_refused(parent, child, translation, rotation, message):
    buffer = robot_tree()
    before = buffer.lookup('map', 'laser', 15 * S)
    with pytest.raises(InvalidTransformError, match=message):
        buffer.set_transform(parent, child, 15 * S, translation, rotation)
    assert buffer.lookup('map', 'laser', 15 * S).is_close(before)


def test_a_bad_cache_duration_is_refused():
    with pytest.raises(ValueError, match='cache_duration_ns'):
        TfBuffer(-1)


@given(st.lists(poses, min_size=2, max_size=2), st.lists(poses, min_size=2, max_size=2),
       poses, st.floats(0.0, 1.0))
def test_lookups_match_matrices_of_the_interpolated_links(odom_poses, base_poses, mount,
                                                          fraction):
    """An independent twin: each link interpolated by hand, the chain as 4x4 matrices."""
    buffer = TfBuffer(cache_duration_ns=None)
    stamps = (1 * S, 3 * S)
    for stamp, pose in zip(stamps, odom_poses):
        buffer.set_transform('map', 'odom', stamp, pose[:3], quaternion_from_rpy(*pose[3:]))
    for stamp, pose in zip(stamps, base_poses):
        buffer.set_transform('odom', 'base_link', stamp, pose[:3],
                             quaternion_from_rpy(*pose[3:]))
    buffer.set_transform('base_link', 'laser', 0, mount[:3], quaternion_from_rpy(*mount[3:]),
                         static=True)
    stamp = stamps[0] + int(fraction * (stamps[1] - stamps[0]))
    ratio = (stamp - stamps[0]) / (stamps[1] - stamps[0])

    def link(pose_pair):
        a, b = (Transform3D.from_xyz_rpy(*p) for p in pose_pair)
        m = np.eye(4)
        m[:3, 3] = a.translation + ratio * (b.translation - a.translation)
        m[:3, :3] = Transform3D(rotation=slerp(a.rotation, b.rotation, ratio)).rotation_matrix()
        return m

    expected = link(odom_poses) @ link(base_poses) @ matrix(Transform3D.from_xyz_rpy(*mount))
    assert_allclose(matrix(buffer.lookup('map', 'laser', stamp)), expected, atol=1e-9)
    assert_allclose(matrix(buffer.lookup('laser', 'map', stamp)), np.linalg.inv(expected),
                    atol=1e-9)


# --- laser_plane: a 3-D mount as the planar scan the core takes -------------------------------

def beam_headings(plane, beams):
    """Return the map-plane heading of each beam in the order of `PlanarLaser.ranges`."""
    index = plane.ranges(np.arange(beams))
    return index, plane.pose[2] + plane.angle_min + np.arange(beams) * plane.angle_increment


@pytest.mark.parametrize('roll, increment', [(0.0, 0.1), (math.pi, 0.1), (0.0, -0.1),
                                             (math.pi, -0.1), (-math.pi, 0.1)])
def test_each_beam_keeps_its_true_heading(roll, increment):
    beams, angle_min = 11, (-0.5 if increment > 0 else 0.5)
    mount = Transform3D.from_xyz_rpy(1.0, -2.0, 0.3, roll=roll, yaw=0.7)
    plane = planar_laser(mount, angle_min, increment, beams)
    assert plane.angle_increment > 0.0
    assert plane.angle_max == pytest.approx(plane.angle_min + (beams - 1) * increment * np.sign(
        increment))
    index, headings = beam_headings(plane, beams)
    for i, heading in zip(index, headings):
        # The true direction of beam i, through the 3-D rotation.
        angle = angle_min + i * increment
        direction = mount.rotation_matrix() @ np.array([math.cos(angle), math.sin(angle), 0.0])
        assert math.cos(heading - math.atan2(direction[1], direction[0])) == pytest.approx(1.0)
    assert plane.pose[:2] == pytest.approx((1.0, -2.0))
    assert plane.upside_down == (abs(roll) > 1.0)


def test_a_slightly_tilted_laser_is_taken_as_planar_and_a_steep_one_refused():
    plane = planar_laser(Transform3D.from_xyz_rpy(pitch=math.radians(5)), -1.0, 0.1, 21)
    assert plane.tilt == pytest.approx(math.radians(5)) and not plane.reverse
    with pytest.raises(LaserNotLevelError, match='tilted 30.0 deg'):
        planar_laser(Transform3D.from_xyz_rpy(roll=math.radians(30)), -1.0, 0.1, 21)


@pytest.mark.parametrize('args, message', [((-1.0, 0.0, 5), 'must not be 0'),
                                           ((math.nan, 0.1, 5), 'angle_min must be finite'),
                                           ((-1.0, 0.1, 0), 'at least one beam')])
def test_malformed_scans_are_refused(args, message):
    with pytest.raises(ValueError, match=message):
        planar_laser(Transform3D.identity(), *args)


def test_sample_step_tells_how_far_apart_the_samples_around_a_stamp_lie():
    buffer = TfBuffer()
    buffer.set_transform('odom', 'base_link', 1_000_000_000, (0.0, 0.0, 0.0),
                         quaternion_from_rpy(0.0, 0.0, 0.0))
    buffer.set_transform('odom', 'base_link', 1_400_000_000, (0.3, 0.4, 0.0),
                         quaternion_from_rpy(0.0, 0.0, 0.5))
    buffer.set_transform('base_link', 'laser', 0, (0.2, 0.0, 0.1), (0.0, 0.0, 0.0, 1.0),
                         static=True)
    duration, distance, turn = buffer.sample_step('base_link', 1_100_000_000)
    assert duration == pytest.approx(0.4)
    assert distance == pytest.approx(0.5) and turn == pytest.approx(0.5)
    assert buffer.sample_step('base_link', 1_400_000_000) == (0.0, 0.0, 0.0)
    assert buffer.sample_step('base_link', 1_500_000_000) is None      # beyond the samples
    assert buffer.sample_step('laser', 1_100_000_000) is None          # static
    assert buffer.sample_step('odom', 1_100_000_000) is None           # a root
    with pytest.raises(FrameLookupError):
        buffer.sample_step('wheel', 1_100_000_000)
