"""Tests of object memory: small objects are forgotten out of view, walls never."""

import dataclasses
import math

from changed_cells import assert_box_holds, ChangedCells
from dpn_navigator.core.cell_label import CellLabel, ScanInput
from dpn_navigator.core.grid_geometry import GridGeometry
from dpn_navigator.core.grid_geometry import squared_radius_bound
from dpn_navigator.core.mapping.label_grid import LabelGrid, LabelRule
from dpn_navigator.core.mapping.object_memory import ObjectMemory
from dpn_navigator.core.navigator import NavigatorConfig
import numpy as np
from numpy.testing import assert_array_equal
from numpy_label_grid import NumpyExtrasLabelGrid
from numpy_object_memory import run_cells
import pytest
from scan_scenes import ANGLE_INCREMENT, ANGLE_MIN, free_pose, hall, RANGE_MAX
from scan_scenes import moving_box_world, RANGE_MIN, ray_cast
from test_motion_tracks import BEAMS, disc_scan, DPN, SCAN

N, E, S, M = (CellLabel.NON_EXPLORED, CellLabel.EXPLORED, CellLabel.STEADY_OBSTACLE,
              CellLabel.MOBILE_OBSTACLE)
TRACKS = {**DPN, 'track_confirm_time': 5.0, 'mobile_expiry': 3.0, 'trail_distance': 1.2}


def wall_and_disc_scan(laser, centre, wall_x=None):
    """Ranges of ``disc_scan`` with a wall along x = ``wall_x`` behind it (None: no wall)."""
    ranges = disc_scan(laser, centre)
    if wall_x is None:
        return ranges
    angles = laser[2] + SCAN['angle_min'] + np.arange(BEAMS) * SCAN['angle_increment']
    along = (wall_x - laser[0]) / np.cos(angles)
    wall = (np.cos(angles) > 0.0) & (along < SCAN['range_max'])
    ranges[wall] = np.minimum(ranges[wall], along[wall])
    return ranges


def look_then_turn_away(rule, centre, seconds_away, laser=(1.0, 6.0, 0.0), wall_x=None):
    """
    See a disc (and a wall) standing still for 1 s, then turn the laser round for a while.

    Returns the grid and the disc's rim cell ``(row, col)``.
    """
    grid = LabelGrid(width=12.0, height=12.0, rule=rule)
    stamp = 0.0
    for _ in range(11):
        grid.update(laser, wall_and_disc_scan(laser, centre, wall_x), safety_radius=0.6,
                    stamp=stamp, **SCAN)
        stamp += 0.1
    away = (laser[0], laser[1], laser[2] + math.pi)
    for _ in range(int(round(seconds_away * 10))):
        grid.update(away, np.full(BEAMS, np.inf), safety_radius=0.6, stamp=stamp, **SCAN)
        stamp += 0.1
    rr, cc = grid.geometry.world_to_cell(np.array([centre[0] - 0.25]), np.array([centre[1]]))
    return grid, (int(rr[0]), int(cc[0]))


def test_object_never_seen_to_move_is_forgotten_out_of_view():
    rule = LabelRule(**TRACKS, object_memory=2.0)
    grid, cell = look_then_turn_away(rule, (4.0, 6.0), 1.5)
    assert grid.labels[cell] == S                  # 1.5 s out of view: still remembered
    grid, cell = look_then_turn_away(rule, (4.0, 6.0), 2.5)
    assert grid.labels[cell] == N                  # never seen free: back to non-explored
    assert not np.any(grid.labels >= S)
    assert grid.object_memory.forgotten >= 4


def test_without_object_memory_it_stays_steady():
    grid, cell = look_then_turn_away(LabelRule(**TRACKS), (4.0, 6.0), 10.0)
    assert grid.labels[cell] == S
    assert grid.object_memory is None


def test_a_wall_is_anchored_and_kept():
    rule = LabelRule(**TRACKS, object_memory=1.0)
    grid, cell = look_then_turn_away(rule, (4.0, 6.0), 3.0, wall_x=7.0)
    wall_col = grid.geometry.world_to_cell(np.array([7.0]), np.array([6.0]))[1][0]
    assert np.all(grid.labels[:, wall_col][grid.object_memory.anchored[:, wall_col]] == S)
    assert np.count_nonzero(grid.labels[:, wall_col] == S) >= 8
    assert grid.labels[cell] == N                  # the disc in front of it is forgotten


def grazing_wall_then_turn_away(rule):
    """
    See a wall along y = 7, 1 m beside the laser, for 1 s, then turn away for 3 s.

    Beyond about 4 m the wall's hits are more than ``segment_gap`` apart: one-hit segments,
    neither long nor small objects. Returns the grid, the label of the wall cell at (6.25,
    6.75) before turning away and that cell.
    """
    grid = LabelGrid(width=12.0, height=12.0, rule=rule)
    laser = (1.0, 6.0, 0.0)
    angles = SCAN['angle_min'] + np.arange(BEAMS) * SCAN['angle_increment']
    with np.errstate(divide='ignore'):
        ranges = np.where(np.sin(angles) > 0.0, 1.0 / np.sin(angles), np.inf)
    ranges[ranges >= SCAN['range_max']] = np.inf
    for step in range(11):
        grid.update(laser, ranges, safety_radius=0.6, stamp=step / 10, **SCAN)
    far_wall = grid.geometry.world_to_cell(np.array([6.25]), np.array([6.75]))
    seen = grid.labels[far_wall][0]
    away = (1.0, 6.0, math.pi)
    for step in range(30):
        grid.update(away, np.full(BEAMS, np.inf), safety_radius=0.6, stamp=1.1 + step / 10,
                    **SCAN)
    return grid, seen, far_wall


def test_a_wall_seen_at_grazing_incidence_is_kept():
    rule = LabelRule(**TRACKS, object_memory=1.0)
    grid, seen, far_wall = grazing_wall_then_turn_away(rule)
    assert seen == S
    assert grid.labels[far_wall][0] == S
    assert grid.object_memory.forgotten == 0


def test_short_segments_list_their_cells_when_the_rule_says_so():
    # The same one-hit segments with object_memory_short_segments: listed, and forgotten out
    # of view as a small object's cells are (the price: a wall glimpsed only at grazing
    # incidence, never anchored, is forgotten too, and found again when seen).
    rule = LabelRule(**TRACKS, object_memory=1.0, object_memory_short_segments=True)
    grid, seen, far_wall = grazing_wall_then_turn_away(rule)
    assert seen == S
    assert grid.labels[far_wall][0] == N
    assert grid.object_memory.forgotten >= 4
    # The near part of the wall, hit by a long segment, is anchored and kept.
    near_wall = grid.geometry.world_to_cell(np.array([2.25]), np.array([6.75]))
    assert grid.object_memory.anchored[near_wall][0] and grid.labels[near_wall][0] == S


def test_short_segments_rule_must_be_a_bool():
    with pytest.raises(ValueError, match='object_memory_short_segments must be a bool'):
        LabelRule(**TRACKS, object_memory=1.0, object_memory_short_segments=1.0)


def test_object_next_to_the_robot_is_kept():
    # Its rim cell 0.75 m from the laser: within twice the safety radius (the robot may turn
    # in place beside it).
    rule = LabelRule(**TRACKS, object_memory=1.0)
    grid, cell = look_then_turn_away(rule, (2.0, 6.0), 3.0)
    assert grid.labels[cell] == S


def test_object_in_view_is_kept():
    rule = LabelRule(**TRACKS, object_memory=0.5)
    grid = LabelGrid(width=12.0, height=12.0, rule=rule)
    laser = (1.0, 6.0, 0.0)
    for step in range(40):
        grid.update(laser, disc_scan(laser, (4.0, 6.0)), safety_radius=0.6, stamp=step / 10,
                    **SCAN)
    assert np.count_nonzero(grid.labels == S) >= 4
    assert grid.object_memory.forgotten == 0


def test_forgetting_widens_the_change_trackers():
    rule = LabelRule(**TRACKS, object_memory=1.0)
    grid, cell = look_then_turn_away(rule, (4.0, 6.0), 0.5)
    tracker = grid.change_tracker()
    tracker.take()
    away = (1.0, 6.0, math.pi)
    for step in range(10):
        grid.update(away, np.full(BEAMS, np.inf), safety_radius=0.6, stamp=2.0 + step / 10,
                    **SCAN)
    assert grid.labels[cell] == N
    rows, cols, _ = tracker.take()
    assert rows.start <= cell[0] < rows.stop and cols.start <= cell[1] < cols.stop


def test_reset_forgets_anchors_and_list():
    rule = LabelRule(**TRACKS, object_memory=1.0)
    grid, _ = look_then_turn_away(rule, (4.0, 6.0), 0.2, wall_x=7.0)
    assert grid.object_memory.anchored.any() and grid.object_memory.provisional.shape[0]
    grid.reset()
    assert not grid.object_memory.anchored.any()
    assert grid.object_memory.provisional.shape[0] == 0


def test_rule_needs_tracks_and_the_hit_clock():
    with pytest.raises(ValueError, match='object_memory needs track_confirm_time'):
        LabelRule(**DPN, object_memory=5.0)
    with pytest.raises(ValueError, match='object_memory needs'):
        LabelRule(**DPN, track_confirm_time=5.0, object_memory=5.0)
    with pytest.raises(ValueError, match='object_memory must be finite'):
        LabelRule(**TRACKS, object_memory=-1.0)


def test_run_cells_expands_half_open_runs():
    assert run_cells(np.array([2, 7, 7]), np.array([5, 7, 9])).tolist() == [2, 3, 4, 7, 8]
    assert run_cells(np.zeros(0, np.int64), np.zeros(0, np.int64)).tolist() == []


class LiteralObjectMemory:
    """The rule of ``object_memory`` written cell by cell, from its docstring."""

    def __init__(self, geometry, memory):
        self.geometry = geometry
        self.memory = memory
        self.anchored = np.zeros(geometry.shape, dtype=bool)
        self.listed = np.zeros(geometry.shape, dtype=bool)

    def update(self, labels, seen_free, last_hit, window, hits_x, hits_y, long, small_object,
               laser_xy, safety_radius, stamp):
        rows, cols, cell_input = window
        bound = squared_radius_bound(safety_radius)
        for r in range(self.geometry.shape[0]):
            for c in range(self.geometry.shape[1]):
                in_window = rows.start <= r < rows.stop and cols.start <= c < cols.stop
                x, y = self.geometry.cell_to_world(r, c)
                near = [(x - hx) ** 2 + (y - hy) ** 2 <= bound for hx, hy in zip(hits_x, hits_y)]
                if in_window and any(n and k for n, k in zip(near, long)):
                    self.anchored[r, c] = True
                if (in_window and any(n and k for n, k in zip(near, small_object))
                        and labels[r, c] == S and not self.anchored[r, c]):
                    self.listed[r, c] = True
                if not self.listed[r, c]:
                    continue
                if labels[r, c] != S or self.anchored[r, c]:
                    self.listed[r, c] = False
                    continue
                unseen = (not in_window
                          or cell_input[r - rows.start, c - cols.start] == ScanInput.NONE)
                far = math.hypot(x - laser_xy[0], y - laser_xy[1]) > 2.0 * safety_radius
                if unseen and far and stamp - last_hit[r, c] >= self.memory:
                    labels[r, c] = E if seen_free[r, c] else N
                    self.listed[r, c] = False


@pytest.mark.parametrize('seed', range(6))
def test_object_memory_equals_its_literal_twin(seed):
    rng = np.random.default_rng(seed)
    geometry = GridGeometry(6.0, 5.0, 0.5)
    fast = ObjectMemory(geometry, memory=1.0)
    twin = LiteralObjectMemory(geometry, memory=1.0)
    labels = rng.choice([N, E, S, M], size=geometry.shape, p=[0.2, 0.2, 0.5, 0.1]).astype(
        np.uint8)
    twin_labels = labels.copy()
    seen_free = rng.random(geometry.shape) < 0.3
    last_hit = np.zeros(geometry.shape)
    for step in range(30):
        stamp = 0.3 * step
        r0, c0 = rng.integers(0, 6, 2)
        window = (slice(int(r0), int(r0) + 5), slice(int(c0), int(c0) + 6))
        cell_input = rng.choice([ScanInput.NONE, ScanInput.INSIDE, ScanInput.HIT],
                                size=(5, 6)).astype(np.uint8)
        cell_input = cell_input[:window[0].stop - window[0].start,
                                :min(window[1].stop, geometry.shape[1]) - window[1].start]
        window = (slice(window[0].start, window[0].start + cell_input.shape[0]),
                  slice(window[1].start, window[1].start + cell_input.shape[1]))
        count = int(rng.integers(0, 12))
        hits_x = rng.uniform(0.0, 6.0, count)
        hits_y = rng.uniform(0.0, 5.0, count)
        kind = rng.integers(0, 3, count)             # long, small object, or neither
        hit = np.zeros(geometry.shape, dtype=bool)
        hit[window[0], window[1]] = cell_input == ScanInput.HIT
        last_hit[hit] = stamp
        # Some labels change between scans, as the FSM would change them.
        flip = rng.random(geometry.shape) < 0.05
        labels[flip] = twin_labels[flip] = rng.choice([E, S, M], size=int(flip.sum()))
        laser_xy = tuple(rng.uniform(0.0, 5.0, 2))
        args = ((window[0], window[1], cell_input), hits_x, hits_y, kind == 0, kind == 1,
                laser_xy, 0.6, stamp)
        fast.update(labels, seen_free, last_hit, *args)
        twin.update(twin_labels, seen_free, last_hit, *args)
        assert_array_equal(labels, twin_labels)
        assert_array_equal(fast.anchored, twin.anchored)
    assert fast.forgotten > 0


def crossing_boxes(resolution, seed, steps):
    """
    Return the side of a hall [m] and its scans: four wanderer-sized boxes crossing it.

    A 30 m hall with 10 standing boxes at 0.5 m cells, else 12 m with 3; the laser somewhere
    free at every scan, scans 0.1-0.4 s apart. Yields ``(LabelGrid.update arguments, stamp)``.
    """
    rng = np.random.default_rng(seed)
    size = 30.0 if resolution == 0.5 else 12.0
    static = hall(size, 10 if resolution == 0.5 else 3, rng)

    def scans():
        stamp = 0.0
        for step in range(steps):
            world = moving_box_world(static, step, seed, boxes=4)
            pose = free_pose(world, rng)
            ranges = ray_cast(world, pose)
            stamp += rng.choice([0.1, 0.2, 0.4])
            yield (pose, ranges, ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, 0.6), stamp
    return size, scans()


@pytest.mark.parametrize(('memory', 'resolution', 'seed'), [
    (5.0, 0.5, 0), (1.0, 0.5, 1), (0.5, 0.5, 2), (0.3, 0.1, 3), (0.3, 0.1, 4)])
@pytest.mark.slow
def test_compiled_object_memory_equals_the_numpy_one_on_hall_sequences(
        memory, resolution, seed):
    # Boxes the size of a wanderer cross the hall: they are listed, anchored where they stand
    # by a wall, forgotten once out of view. Every array, the list, the counter, the replan
    # flag and the change trackers, after every scan.
    rule = dataclasses.replace(NavigatorConfig(width=1.0, height=1.0).label_rule(),
                               object_memory=memory)
    size, scans = crossing_boxes(resolution, seed, 90)
    fast = LabelGrid(size, size, resolution, rule=rule)
    reference = NumpyExtrasLabelGrid(size, size, resolution, rule=rule)
    trackers = (fast.change_tracker(), reference.change_tracker())
    changed = (ChangedCells(fast.labels), ChangedCells(reference.labels))
    middle = fast.labels.shape[0] // 2
    path = np.array([[middle, c] for c in range(2 * middle)])
    for args, stamp in scans:
        assert fast.update(*args, path=path, stamp=stamp) == reference.update(
            *args, path=path, stamp=stamp)
        assert_array_equal(fast.labels, reference.labels)
        assert_array_equal(fast.object_memory.anchored, reference.object_memory.anchored)
        assert_array_equal(fast.object_memory.provisional,
                           reference.object_memory.provisional)
        assert fast.object_memory.forgotten == reference.object_memory.forgotten
        for tracker, cells in zip(trackers, changed):     # a literal diff, not each other
            assert_box_holds(tracker.take(), cells.take())
    assert fast.object_memory.forgotten > 0
    assert fast.object_memory.anchored.any()


@pytest.mark.parametrize(('resolution', 'seed'), [(0.5, 0), (0.1, 1)])
def test_deferred_evidence_gives_the_same_grid_on_hall_sequences(resolution, seed):
    # The navigator's rule (tracks, trails, object memory, fine evidence) on boxes crossing a
    # hall: a grid that marks its free evidence after each update, as the node does once the
    # map is out, labels every scan as one that marks it in the update, and ends equal. A
    # short memory, so that cells are forgotten.
    rule = dataclasses.replace(NavigatorConfig(width=1.0, height=1.0).label_rule(),
                               object_memory=1.0)
    size, scans = crossing_boxes(resolution, seed, 60)
    now, deferred = (LabelGrid(size, size, resolution, rule=rule) for _ in range(2))
    trackers = (now.change_tracker(), deferred.change_tracker())
    changed = (ChangedCells(now.labels), ChangedCells(deferred.labels))
    moving = stale_entries = 0
    for step, (args, stamp) in enumerate(scans):
        assert now.update(*args, stamp=stamp) == deferred.update(*args, stamp=stamp,
                                                                 defer_evidence=True)
        assert_array_equal(deferred.labels, now.labels)
        assert_array_equal(deferred.last_hit, now.last_hit)
        assert_array_equal(deferred.cell_track, now.cell_track)
        for tracker, cells in zip(trackers, changed):     # a literal diff, not each other
            assert_box_holds(tracker.take(), cells.take())
        if step % 3:
            deferred.settle()
            assert_array_equal(deferred.seen_free, now.seen_free)
            assert_array_equal(deferred.fine_evidence.seen_free, now.fine_evidence.seen_free)
            memory = deferred.object_memory
            assert_array_equal(memory.anchored, now.object_memory.anchored)
            # The list in the same order, but for cells this scan anchored (dropped at the
            # next update).
            listed = memory.provisional
            stale = memory.anchored.ravel()[listed]
            assert_array_equal(listed[~stale], now.object_memory.provisional)
            stale_entries += int(stale.sum())
        moving += int((now.labels == CellLabel.MOBILE_OBSTACLE).sum())
    assert moving > 0                       # the boxes were seen to move
    assert now.seen_free.any() and now.fine_evidence.seen_free.any()
    assert now.object_memory.forgotten > 0
    assert deferred.object_memory.forgotten == now.object_memory.forgotten
    assert stale_entries > 0                # a listed cell anchored later came up


def test_the_literal_change_oracle_catches_a_box_too_small():
    labels = np.zeros((4, 5), dtype=np.uint8)
    cells = ChangedCells(labels)
    labels[1, 3] = 2
    changed = cells.take()
    assert_box_holds((slice(1, 2), slice(3, 4), False), changed)
    with pytest.raises(AssertionError, match='1 changed cells outside'):
        assert_box_holds((slice(0, 1), slice(0, 5), False), changed)
    assert cells.take()[0].size == 0                  # taken: nothing changed since
