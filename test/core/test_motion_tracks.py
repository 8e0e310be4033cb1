"""Tests of motion tracks: a moving object stays mobile while it is followed, a pillar never is."""

import math

from changed_cells import assert_box_holds, ChangedCells
from dpn_navigator.core.cell_label import CellLabel
from dpn_navigator.core.mapping.label_grid import LabelGrid, LabelRule
from dpn_navigator.core.mapping.motion_tracks import MotionTracks, TrackConfig
from dpn_navigator.core.navigator import NavigatorConfig
from moving_objects import scan_segments
import numpy as np
from numpy.testing import assert_array_equal
from numpy_label_grid import NumpyExtrasLabelGrid
from numpy_motion_tracks import seen_free_points, segment_summary
import pytest
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, free_pose, hall, RANGE_MAX
from scan_scenes import moving_box_world, RANGE_MIN, ray_cast

S, M = CellLabel.STEADY_OBSTACLE, CellLabel.MOBILE_OBSTACLE

BEAMS = 181
SCAN = {'angle_min': -math.pi / 2, 'angle_increment': math.pi / (BEAMS - 1), 'range_min': 0.1,
        'range_max': 8.0}
DPN = {'free_evidence_radius': 0.6, 'moving_object_size': 0.7}


def disc_scan(laser, centre, radius=0.25):
    """Ranges of a laser at ``laser`` (x, y, yaw) seeing one disc in open space (no returns)."""
    angles = laser[2] + SCAN['angle_min'] + np.arange(BEAMS) * SCAN['angle_increment']
    ux, uy = np.cos(angles), np.sin(angles)
    ox, oy = centre[0] - laser[0], centre[1] - laser[1]
    along = ox * ux + oy * uy
    miss2 = ox * ox + oy * oy - along * along
    inside = radius * radius - miss2
    ranges = np.full(BEAMS, np.inf)
    hit = (inside >= 0.0) & (along > 0.0)
    ranges[hit] = along[hit] - np.sqrt(inside[hit])
    return ranges


def disc_labels(grid, centre, radius=0.25):
    """Labels of the cells within 0.3 m of the disc's rim facing -x (where its hits land)."""
    rr, cc = grid.geometry.world_to_cell(np.array([centre[0] - radius]), np.array([centre[1]]))
    return grid.labels[rr[0], cc[0]]


def run(rule, track, seconds, laser=(1.0, 6.0, 0.0), rate=10.0):
    """Feed scans of a disc at ``track(t)`` to a grid; return the grid after each scan."""
    grid = LabelGrid(width=12.0, height=12.0, rule=rule)
    labels = []
    for step in range(int(seconds * rate) + 1):
        stamp = step / rate
        centre = track(stamp)
        grid.update(laser, disc_scan(laser, centre), safety_radius=0.6, stamp=stamp, **SCAN)
        labels.append(disc_labels(grid, centre))
    return grid, labels


def walking_away(stamp):
    return (4.0 + 0.5 * stamp, 6.0)


def test_object_walking_away_is_steady_without_tracks_and_mobile_with_them():
    # Its back lands where its own body stood: never space seen free, so the free-space
    # evidence alone labels it steady; the place it left is now seen empty, so tracks see it
    # move.
    _, without = run(LabelRule(**DPN), walking_away, 2.0)
    grid, with_tracks = run(LabelRule(**DPN, track_confirm_time=5.0), walking_away, 2.0)
    assert without[-1] == S and set(without) == {S}
    assert with_tracks[0] == S                     # first sight: no motion seen yet
    assert all(label == M for label in with_tracks[-10:])
    assert grid.tracks.positions.shape == (1, 2)


@pytest.mark.parametrize('still_distance', [0.0, 0.08])
def test_object_that_stops_loses_its_track_after_the_confirm_time(still_distance):
    # It walked 0.5 m before it stopped: its track moved, so the still-object rule lets it
    # stand on as the same moving object.
    def walk_then_stand(stamp):
        return walking_away(min(stamp, 1.0))
    grid, labels = run(LabelRule(**DPN, track_confirm_time=2.0,
                                 track_still_distance=still_distance), walk_then_stand, 6.0)
    assert labels[20] == M                         # t = 2 s: followed, standing
    # Last confirmed once the places it left aged out of the history (1.5 s after it
    # stopped), dropped 2 s later: steady from t = 4.5 s on.
    assert labels[-1] == S
    assert grid.tracks.positions.shape == (0, 2)


def flickering_post(rule, seconds=3.0):
    """
    Scan a post 4 cm wide 5 m away; return the grid, and per scan its hits and cell label.

    The beams are 1 degree apart and the laser's heading alternates by half a beam, so one
    beam hits the post in every other scan and none in the others.
    """
    grid = LabelGrid(width=12.0, height=12.0, rule=rule)
    post = (6.0, 6.0)
    rr, cc = grid.geometry.world_to_cell(np.array([post[0] - 0.02]), np.array([post[1]]))
    hits, labels = [], []
    for step in range(int(seconds * 10) + 1):
        laser = (1.0, 6.0, 0.0 if step % 2 else 0.5 * SCAN['angle_increment'])
        ranges = disc_scan(laser, post, radius=0.02)
        grid.update(laser, ranges, safety_radius=0.6, stamp=step / 10, **SCAN)
        hits.append(int(np.isfinite(ranges).sum()))
        labels.append(grid.labels[rr[0], cc[0]])
    return grid, hits, labels


@pytest.mark.parametrize('min_hits', [0, 1, 2, 3])
def test_post_thinner_than_the_beam_spacing_is_mobile_only_without_the_thin_thing_rule(
        min_hits):
    # Missed in every other scan, the post's cell is surely seen free in the scans that miss
    # it, and its next hit lands there: evidence of motion. With object_min_hits 2 or more,
    # a one-hit segment shows none and is not followed, so the post stays steady.
    rule = NavigatorConfig(width=1.0, height=1.0, object_min_hits=min_hits).label_rule()
    grid, hits, labels = flickering_post(rule)
    assert hits[0::2] == [0] * len(hits[0::2]) and hits[1::2] == [1] * len(hits[1::2])
    seen = set(labels[1::2])
    if min_hits <= 1:
        assert M in seen and grid.tracks._next_id >= 1
    else:
        assert seen == {S} and grid.tracks._next_id == 0


def test_thin_thing_rule_keeps_a_walking_object_mobile():
    # A P3-AT-sized disc walking away spans six beams: followed as without the rule.
    rule = NavigatorConfig(width=1.0, height=1.0, object_min_hits=3).label_rule()
    _, labels = run(rule, walking_away, 2.0)
    assert all(label == M for label in labels[-10:])


def test_object_min_hits_must_be_a_whole_number():
    for bad in (-1, 2.5, True, math.nan):
        with pytest.raises(ValueError, match='object_min_hits'):
            LabelRule(object_min_hits=bad)
        with pytest.raises(ValueError, match='min_hits'):
            TrackConfig(min_hits=bad)


def test_pillar_passed_by_a_moving_laser_is_never_mobile():
    grid = LabelGrid(width=12.0, height=12.0, rule=LabelRule(**DPN, track_confirm_time=5.0))
    for step in range(41):
        laser = (1.0, 3.0 + 0.1 * step, 0.2 - 0.01 * step)
        grid.update(laser, disc_scan(laser, (4.0, 5.0)), safety_radius=0.6, stamp=step / 10,
                    **SCAN)
    assert np.count_nonzero(grid.labels == S) >= 4
    assert not np.any(grid.labels == M)


@pytest.mark.parametrize('object_in_view', [False, True])
def test_time_going_back_drops_every_track(object_in_view):
    rule = LabelRule(**DPN, track_confirm_time=5.0, mobile_expiry=5.0, trail_distance=1.2)
    grid, _ = run(rule, walking_away, 1.0)
    assert grid.tracks.positions.shape[0] == 1
    laser = (1.0, 6.0, 0.0)
    ranges = (disc_scan(laser, walking_away(1.1)) if object_in_view
              else np.full(BEAMS, np.inf))
    grid.update(laser, ranges, safety_radius=0.6, stamp=0.0, **SCAN)
    # A restarted clock: the tracks start over; the object is not seen to move yet.
    assert grid.tracks.ids.tolist() == []
    assert grid.tracks.hit_ids.shape[0] == np.count_nonzero(np.isfinite(ranges))


def test_tracks_need_a_stamp():
    grid = LabelGrid(width=12.0, height=12.0, rule=LabelRule(**DPN, track_confirm_time=1.0))
    with pytest.raises(ValueError, match='needs a finite scan stamp'):
        grid.update((1.0, 6.0, 0.0), disc_scan((1.0, 6.0, 0.0), (4.0, 6.0)), safety_radius=0.6,
                    **SCAN)


def test_segment_summary_centroids_extents_and_standing():
    laser = (0.0, 0.0)
    # Beam order: a near 3-hit segment, a far wall piece, then a no-return beam.
    hits_x = np.array([2.0, 2.0, 2.0, 5.0, 5.0])
    hits_y = np.array([-0.1, 0.0, 0.1, 1.0, 1.2])
    hit_beams = np.array([3, 4, 5, 6, 7])
    segment, arc = scan_segments(hits_x, hits_y, hit_beams, 0.3)
    assert segment.tolist() == [0, 0, 0, 1, 1]
    centroid_x, centroid_y, extent, open_sides = segment_summary(
        laser, hits_x, hits_y, hit_beams, 10, segment, arc)
    np.testing.assert_allclose(centroid_x, [2.0, 5.0])
    np.testing.assert_allclose(centroid_y, [0.0, 1.1])
    np.testing.assert_allclose(extent, [0.2, 0.2])
    # Segment 0: beam 2 returned nothing, beam 6 is farther: free-standing. Segment 1: beam 5
    # is nearer (it stands behind segment 0), beam 8 returned nothing.
    assert open_sides.tolist() == [2, 1]
    # At the edge of the field of view nothing is known beyond: not free-standing.
    _, _, _, edge = segment_summary(laser, hits_x[:3], hits_y[:3], np.array([0, 1, 2]), 10,
                                    segment[:3], arc[:3])
    assert edge.tolist() == [1]


def test_seen_free_points_needs_every_nearby_beam_to_pass_the_point():
    increment = math.pi / 180
    reach = np.full(181, 8.0)
    reach[100] = 3.0                       # one beam at bearing 10 deg stops at 3 m
    reach[170] = 0.0                       # an invalid beam
    first_angle = -math.pi / 2
    points = np.array([
        [4.0, 0.0],                                          # bearing 0: free
        [4.0 * math.cos(0.1745), 4.0 * math.sin(0.1745)],    # behind the 3 m return
        [2.0 * math.cos(0.1745), 2.0 * math.sin(0.1745)],    # before it: free
        [7.95, 0.0],                                         # within the margin of the end
        [-1.0, 0.0],                                         # behind the laser
        [4.0 * math.cos(1.396), 4.0 * math.sin(1.396)],      # next to the invalid beam
    ])
    free = seen_free_points(points, (0.0, 0.0), first_angle, increment, reach, 0.15)
    assert free.tolist() == [True, False, True, False, False, False]


def test_following_is_off_at_zero_confirm_time():
    tracks = MotionTracks(TrackConfig(confirm_within=0.0))
    moving = np.array([True, True])
    out = tracks.update(0.0, (0.0, 0.0), np.array([2.0, 2.0]), np.array([0.0, 0.1]),
                        np.array([3, 4]), 10, moving, 0.3)
    assert not out.any() and tracks.positions.shape == (0, 2)


@pytest.mark.parametrize('name', ['compact_size', 'gate', 'confirm_within', 'reach',
                                  'half_open_gate', 'still_distance', 'move_distance'])
def test_bad_track_config_raises(name):
    with pytest.raises(ValueError, match=f'{name} must be finite'):
        TrackConfig(**{name: -1.0})
    with pytest.raises(ValueError, match='track_confirm_time must be finite'):
        LabelRule(track_confirm_time=math.inf)
    with pytest.raises(ValueError, match='track_still_distance must be finite'):
        LabelRule(**DPN, track_confirm_time=1.0, track_still_distance=math.nan)


def post_and_passer(rule, grid_class=LabelGrid, seconds=10.0):
    """
    Scan a post (a 0.1 m disc at (4, 6)) that a disc of 0.3 m passes 0.8 m behind at 0.5 m/s.

    Returns the grid and, after each scan, the labels of the post's and the passer's hit
    cells.
    """
    grid = grid_class(width=12.0, height=12.0, rule=rule)
    laser = (1.0, 6.0, 0.0)
    post = (4.0, 6.0)
    post_cell = grid.geometry.world_to_cell(post[0] - 0.1, post[1])
    post_labels, passer_labels = [], []
    for step in range(int(seconds * 10) + 1):
        stamp = step / 10
        passer = (4.8, 4.0 + 0.5 * stamp)
        ranges = np.minimum(disc_scan(laser, passer, 0.3), disc_scan(laser, post, 0.1))
        grid.update(laser, ranges, safety_radius=0.6, stamp=stamp, **SCAN)
        post_labels.append(grid.labels[post_cell])
        passer_labels.append(disc_labels(grid, passer, 0.3))
    return grid, post_labels, passer_labels


@pytest.mark.parametrize(('still_distance', 'post_mobile'), [(0.08, False), (0.0, True)])
@pytest.mark.parametrize('exclusive', [False, True])
def test_post_a_moving_object_passes_is_not_mobile_with_the_still_object_rule(
        still_distance, post_mobile, exclusive):
    # The places the passer left, within 1.2 m of the post and now seen empty, showed the
    # post moving, and its track lived on 5 s after that; the post stands where it stood.
    rule = LabelRule(**DPN, track_confirm_time=5.0, track_still_distance=still_distance,
                     track_exclusive=exclusive)
    _, post_labels, passer_labels = post_and_passer(rule)
    assert set(post_labels) == ({S, M} if post_mobile else {S})
    assert all(label == M for label in passer_labels[10:])


def test_a_track_started_on_a_post_is_not_continued_by_it_once_it_stands_still():
    tracks = MotionTracks(TrackConfig(confirm_within=5.0, still_distance=0.08))
    post_x, post_y = np.array([3.0, 3.0, 3.0]), np.array([-0.05, 0.0, 0.05])
    beams = np.array([10, 11, 12])
    moving = np.array([True, True, True])
    tracks.update(0.0, (0.0, 0.0), post_x, post_y, beams, 30, moving, 0.3)
    assert tracks.ids.tolist() == [0] and tracks.moved.tolist() == [False]
    followed = [tracks.update(0.1 * step, (0.0, 0.0), post_x, post_y, beams, 30, ~moving, 0.3)
                for step in range(1, 11)]
    # Continued until the centroid of 0.8 s ago (still_age) shows it standing where it stood.
    assert [bool(out.all()) for out in followed] == [True] * 7 + [False] * 3
    assert tracks.ids.tolist() == [0]
    assert_array_equal(tracks.origins, [[3.0, 0.0]])


@pytest.mark.parametrize('exclusive', [False, True])
def test_exclusive_tracks_let_one_segment_per_scan_continue_a_track(exclusive):
    tracks = MotionTracks(TrackConfig(confirm_within=5.0, exclusive=exclusive))
    laser = (0.0, 0.0)
    tracks.update(0.0, laser, np.full(3, 3.0), np.array([-0.05, 0.0, 0.05]),
                  np.array([15, 16, 17]), 40, np.ones(3, dtype=bool), 0.3)
    # Two compact free-standing segments 0.25 m either side of the track, no evidence: the
    # first in beam order takes it; the second is 0.5 m from it then, within the gate.
    hits_y = np.array([-0.3, -0.25, -0.2, 0.2, 0.25, 0.3])
    followed = tracks.update(0.1, laser, np.full(6, 3.0), hits_y,
                             np.array([10, 11, 12, 20, 21, 22]), 40, np.zeros(6, dtype=bool),
                             0.3)
    assert followed.tolist() == [True] * 3 + [not exclusive] * 3
    assert tracks.hit_ids.tolist() == [0] * 3 + [-1 if exclusive else 0] * 3
    assert_array_equal(tracks.positions, [[3.0, -0.25 if exclusive else 0.25]])


def test_trail_out_of_view_goes_back_to_explored_once_its_object_is_seen_far_away():
    rule = LabelRule(**DPN, track_confirm_time=5.0, mobile_expiry=5.0, trail_distance=1.2)
    grid, labels = run(rule, walking_away, 1.0)
    assert labels[-1] == M
    (track,) = grid.tracks.ids
    behind_laser = (1, 1)                         # out of view, far from the object
    in_its_shadow = grid.geometry.world_to_cell(5.25, 6.0)   # out of view, 1 m behind it
    for cell in (behind_laser, in_its_shadow):
        grid.labels[cell] = M
        grid.cell_track[cell] = track
        grid.last_hit[cell] = 1.0                 # recent: the 5 s expiry keeps it
        # As if the object's hits had marked it (the grid lists the cells it marked).
        grid._marked = np.append(grid._marked, cell[0] * grid.geometry.cols + cell[1])
    laser = (1.0, 6.0, 0.0)
    grid.update(laser, disc_scan(laser, walking_away(1.1)), safety_radius=0.6, stamp=1.1,
                **SCAN)
    rows, cols, cell_input = grid.last_window
    assert cell_input[in_its_shadow[0] - rows.start, in_its_shadow[1] - cols.start] == 0
    assert grid.labels[behind_laser] == CellLabel.EXPLORED
    assert grid.cell_track[behind_laser] == -1
    assert grid.labels[in_its_shadow] == M        # within 1.2 m of it: may be it
    # The object's own hit cells carry its track.
    assert np.all(grid.cell_track[rows, cols][cell_input == 2] == track)


def test_trails_are_off_at_zero_distance_and_need_tracks():
    grid, _ = run(LabelRule(**DPN, track_confirm_time=5.0), walking_away, 0.5)
    assert grid.cell_track is None
    with pytest.raises(ValueError, match='trail_distance needs track_confirm_time'):
        LabelRule(**DPN, trail_distance=1.0)
    with pytest.raises(ValueError, match='track_confirm_time needs moving_object_size'):
        LabelRule(free_evidence_radius=0.6, track_confirm_time=1.0)


@pytest.mark.parametrize(('half_open_gate', 'label'), [(0.35, M), (0.0, S)])
def test_followed_object_partly_hidden_on_one_side_stays_mobile_within_the_tight_gate(
        half_open_gate, label):
    grid, labels = run(LabelRule(**DPN, track_confirm_time=5.0), walking_away, 1.0)
    assert labels[-1] == M
    grid.tracks.config = TrackConfig(confirm_within=5.0, half_open_gate=half_open_gate)
    laser = (1.0, 6.0, 0.0)
    for step in range(11, 21):
        stamp = step / 10
        centre = walking_away(stamp)
        # A thin post 1.5 m ahead hides the object's left edge: one end of its segment is
        # closed by a nearer return.
        ranges = np.minimum(disc_scan(laser, centre), disc_scan(laser, (2.5, 6.15), 0.08))
        grid.update(laser, ranges, safety_radius=0.6, stamp=stamp, **SCAN)
        assert disc_labels(grid, centre) == label


def assert_same_tracks(fast, reference):
    for name in ('positions', 'ids', 'last_seen', 'last_confirmed', 'origins', 'moved',
                 'hit_ids', 'hit_long', 'hit_object', '_history_xy', '_history_stamp',
                 '_next_id'):
        assert_array_equal(getattr(fast, name), getattr(reference, name), err_msg=name)


def assert_same_grids(fast, reference):
    assert_same_tracks(fast.tracks, reference.tracks)
    assert_array_equal(fast.labels, reference.labels)
    if reference.cell_track is not None:
        assert_array_equal(fast.cell_track, reference.cell_track)
        assert_array_equal(np.unique(fast._marked), np.unique(reference._marked))


@pytest.mark.parametrize('seed', range(4))
@pytest.mark.parametrize('still_rules', [True, False])
@pytest.mark.slow
def test_compiled_tracks_equal_the_numpy_ones_on_hall_sequences(seed, still_rules):
    # A laser that stands still for ten scans at a time among boxes that walk; the numpy
    # tracks (and trail marks) of commit 1d9ead7 are the oracle, after every scan. The
    # shipped rule, and the one before still objects and exclusive tracks; seeds 2 and 3
    # lose 3 % of the returns.
    before = {} if still_rules else {'track_still_distance': 0.0, 'track_exclusive': False,
                                     'object_min_hits': 0}
    rule = NavigatorConfig(width=1.0, height=1.0, segment_bridge_beams=2 if seed >= 2 else 0,
                           **before).label_rule()
    rng = np.random.default_rng(seed)
    static = hall(30.0, 10, rng)
    fast = LabelGrid(30.0, 30.0, 0.5, rule=rule)
    reference = NumpyExtrasLabelGrid(30.0, 30.0, 0.5, rule=rule)
    trackers = (fast.change_tracker(), reference.change_tracker())
    changed = (ChangedCells(fast.labels), ChangedCells(reference.labels))
    path = np.array([[30, c] for c in range(60)])
    stamp = 0.0
    followed = started = 0
    for step in range(120):
        world = moving_box_world(static, step, seed, boxes=5)
        if step % 10 == 0:
            pose = free_pose(world, rng)
        ranges = ray_cast(world, pose)
        if seed >= 2:           # lost returns, and segments that go on across two of them
            ranges[rng.random(ranges.shape[0]) < 0.03] = np.inf
        # Mostly forward by a scan period; once back in time (a restarted simulation).
        stamp = 0.5 if step == 80 else stamp + 0.1
        args = (pose, ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, 0.6)
        assert fast.update(*args, path=path, stamp=stamp) == reference.update(
            *args, path=path, stamp=stamp)
        assert_same_grids(fast, reference)
        for tracker, cells in zip(trackers, changed):     # a literal diff, not each other
            assert_box_holds(tracker.take(), cells.take())
        followed += np.count_nonzero(fast.tracks.hit_ids >= 0)
        started = max(started, fast.tracks._next_id)
    assert followed > 0 and started > 1


@pytest.mark.parametrize('half_open_gate', [0.35, 0.0])
@pytest.mark.parametrize(('still_distance', 'exclusive'), [(0.0, False), (0.08, True)])
def test_compiled_tracks_equal_the_numpy_ones_on_a_walking_disc(half_open_gate, still_distance,
                                                                exclusive):
    rule = LabelRule(**DPN, track_confirm_time=2.0, mobile_expiry=5.0, trail_distance=1.2)
    grids = (LabelGrid(width=12.0, height=12.0, rule=rule),
             NumpyExtrasLabelGrid(width=12.0, height=12.0, rule=rule))
    for grid in grids:
        grid.tracks.config = TrackConfig(confirm_within=2.0, half_open_gate=half_open_gate,
                                         still_distance=still_distance, exclusive=exclusive)
    laser = (1.0, 6.0, 0.0)
    for step in range(70):
        stamp = step / 10
        centre = (4.0 + 0.5 * min(stamp, 2.0), 6.0 + 0.3 * math.sin(stamp))
        ranges = np.minimum(disc_scan(laser, centre), disc_scan(laser, (2.5, 6.15), 0.08))
        for grid in grids:
            grid.update(laser, ranges, safety_radius=0.6, stamp=stamp, **SCAN)
        assert_same_grids(*grids)
    assert grids[0].tracks._next_id >= 1


@pytest.mark.parametrize('still_distance', [0.0, 0.08])
@pytest.mark.parametrize('exclusive', [False, True])
def test_compiled_tracks_equal_the_numpy_ones_on_a_post_and_its_passer(still_distance,
                                                                       exclusive):
    rule = LabelRule(**DPN, track_confirm_time=5.0, track_still_distance=still_distance,
                     track_exclusive=exclusive, mobile_expiry=3.0, trail_distance=1.2)
    fast = post_and_passer(rule, LabelGrid, 8.0)
    reference = post_and_passer(rule, NumpyExtrasLabelGrid, 8.0)
    assert_same_grids(fast[0], reference[0])
    assert fast[1:] == reference[1:]
