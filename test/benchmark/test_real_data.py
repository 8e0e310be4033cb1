"""The real-data measure (``dpn_navigator.tools.real_data``): definitions and the recordings."""

import math

from dpn_navigator.core.cell_label import CellLabel
from dpn_navigator.tools import real_data
import numpy as np
import pytest
from realdata_paths import realdata_dir

E, S, M = CellLabel.EXPLORED, CellLabel.STEADY_OBSTACLE, CellLabel.MOBILE_OBSTACLE


def test_measures_count_as_defined():
    # Two scans of a 2 x 3 grid; column 0 static, a walker near column 2 in the first scan.
    static = np.array([[True, False, False], [True, False, False]])
    near = [np.array([[False, False, True], [False, False, True]]), np.zeros((2, 3), bool)]
    walker_cells = [np.array([[False, False, True], [False, False, False]]),
                    np.zeros((2, 3), bool)]
    persons = [[walker_cells[0]], []]
    truth = real_data.GroundTruth(static, np.array([True, True]), near, walker_cells, persons)
    labels = np.array([[[M, E, M], [S, E, E]],        # walker mobile, a static cell too
                       [[M, M, E], [S, E, E]]])       # no walker: both mobile cells false
    visible = np.array([[[True, True, True], [True, True, True]],
                        [[False, True, True], [True, True, True]]])
    counts = real_data.measure_run(truth, labels, visible, np.array([1e-3, 2e-3]))
    assert (counts.mobile_visible, counts.mobile_visible_true) == (3, 1)
    assert (counts.walker_cells, counts.walker_cells_mobile) == (1, 1)
    assert (counts.persons, counts.persons_found) == (1, 1)
    assert (counts.static_seen, counts.static_ever_mobile) == (2, 1)
    # Ghosts: mobile, not static, not near: none in scan 0, (0, 1) in scan 1.
    assert counts.ghosts == 1 and counts.scans == 2
    precision, cells, walkers, static_share, ghosts = counts.ratios()
    assert precision == pytest.approx(1 / 3) and static_share == pytest.approx(50.0)
    assert real_data.Counts().ratios() == (None, None, None, None, None)


def test_no_echo_codes_read_as_no_return_for_the_ground_truth():
    ranges = np.array([0.0, 0.019, 0.5, math.inf, math.nan, -math.inf])
    read = real_data.no_echo_as_no_return(ranges, 0.02)
    np.testing.assert_array_equal(read, [math.inf, math.inf, 0.5, math.inf, math.nan,
                                         -math.inf])


@pytest.fixture
def annotated_bag():
    path = realdata_dir() / 'positive_2.bag'
    if not (path.exists() and path.with_name('positive_2_extracted.bag').exists()):
        pytest.skip(f'no positive_2.bag with its annotation in {realdata_dir()} (set '
                    'DPN_REALDATA_DIR to the real recordings)')
    return path


def test_annotations_pair_with_the_scans_of_their_stamp(annotated_bag):
    recording = real_data.read_recording(annotated_bag)
    assert recording.annotated and len(recording.scans) == 243
    annotated = [k for k, legs in enumerate(recording.legs) if legs is not None]
    assert len(annotated) == 83                      # every /training_scan paired
    for k in annotated:
        legs = recording.legs[k]
        assert legs.shape[1] == 2 and 1 <= legs.shape[0] <= 3
        # A leg cluster is made of the scan's own points: some hit lies within 0.25 m.
        stamp, ranges, angle_min, increment, range_min, range_max = recording.scans[k]
        angles = angle_min + increment * np.arange(ranges.shape[0])
        valid = (ranges >= range_min) & (ranges < range_max)
        x, y = ranges[valid] * np.cos(angles[valid]), ranges[valid] * np.sin(angles[valid])
        for lx, ly in legs:
            assert np.hypot(x - lx, y - ly).min() <= real_data.LEG_HIT_DISTANCE


@pytest.mark.slow
def test_the_tool_writes_the_page_and_the_real_sensor_rules_help(annotated_bag, tmp_path):
    data = tmp_path / 'data'
    data.mkdir()
    for name in ('positive_2.bag', 'positive_2_extracted.bag'):
        (data / name).symlink_to(annotated_bag.with_name(name))
    out = tmp_path / 'page'
    assert real_data.main(['--data', str(data), '--out', str(out), '--no-cost']) == 0
    page = (tmp_path / 'page.md').read_text()
    assert '| stationary laser, annotated walkers, as recorded | paper |' in page
    assert (out / 'positive_2.png').stat().st_size > 0
    # Read with the no-echo codes as no return, the rules for real lasers raise dpn's
    # precision of mobile and keep static cells from turning mobile.
    recording = real_data.read_recording(annotated_bag)
    truth = real_data.ground_truth(recording, 0.6)
    ratios = {}
    for name, overrides in (('before', {'no_return_reach': 1.0, 'surface_time': 0.0}),
                            ('after', {})):
        config = real_data.grid_config(recording, 'dpn', no_echo_below_range_min=True,
                                       **overrides)
        labels, visible, _, seconds = real_data.run_core(recording, config)
        ratios[name] = real_data.measure_run(truth, labels, visible, seconds).ratios()
    assert ratios['after'][0] > ratios['before'][0]
    assert ratios['after'][3] <= ratios['before'][3]


def test_no_recordings_exit_2(tmp_path, capsys):
    assert real_data.main(['--data', str(tmp_path), '--out', str(tmp_path / 'x')]) == 2
    assert 'no recordings' in capsys.readouterr().err


def _walker_recording(scans=12, beams=181):
    """Return a synthetic standing laser: a wall at 4 m, a box walking across in front."""
    angle_min, increment = -0.5 * np.pi, np.pi / (beams - 1)
    angles = angle_min + increment * np.arange(beams)
    records = []
    for k in range(scans):
        ranges = np.full(beams, 4.0)
        centre = -0.6 + 0.1 * k                               # the walker's bearing [rad]
        ranges[np.abs(angles - centre) < 0.08] = 2.0
        records.append((0.1 * k, ranges, angle_min, increment, 0.05, 10.0))
    return real_data.Recording('walker', records, [None] * scans, False)


def test_update_cost_times_labels_ready_and_the_whole_update_of_every_rule_set():
    cost = real_data.update_cost(_walker_recording(), beams=241, rounds=1)
    assert set(cost) == {name for name, _, _ in real_data.TABLE_RULES}
    for ready, whole in cost.values():
        assert 0.0 < ready <= whole
    lines = []
    real_data.write_page_cost(lines, [('walker, 241 beams', cost)])
    rows = [line for line in lines if line.startswith('| walker, 241 beams |')]
    assert len(rows) == 2                                     # to the labels, whole
    paper_whole = cost['paper'][1]
    for row, index in zip(rows, (0, 1)):
        cells = [cell.strip() for cell in row.strip('|').split('|')]
        assert float(cells[1]) == pytest.approx(1e3 * cost['paper'][index], abs=6e-4)
        last = real_data.TABLE_RULES[-1][0]                    # the last column's rule set
        assert float(cells[-1]) == pytest.approx(cost[last][index] / paper_whole, abs=0.051)


def _passer_by_recording(scans=20, beams=181):
    """
    Return a synthetic annotated standing laser with a passer-by outside the annotation.

    A wall at 4 m; a pillar at 1.5 m, 60 deg; a dark surface at 3 m, -50 deg, that returns
    in a third of the scans only (no echo written as 0.0); a passer-by at 2 m, 40 deg, in
    scans 5-9 (outside the annotated region); an annotated walker at 2 m straight ahead in
    scans 12-17 (inside the region).
    """
    angle_min, increment = -0.5 * np.pi, np.pi / (beams - 1)
    angles = angle_min + increment * np.arange(beams)
    records, legs = [], []
    for k in range(scans):
        ranges = np.full(beams, 4.0)
        ranges[np.abs(angles - np.radians(60.0)) < 0.05] = 1.5
        dark = np.abs(angles - np.radians(-50.0)) < 0.05
        ranges[dark] = 3.0 if k % 3 == 0 else 0.0
        if 5 <= k <= 9:
            ranges[np.abs(angles - np.radians(40.0)) < 0.06] = 2.0
        walking = 12 <= k <= 17
        if walking:
            ranges[np.abs(angles) < 0.06] = 2.0
        records.append((0.1 * k, ranges, angle_min, increment, 0.02, 10.0))
        legs.append(np.array([[2.05, 0.0]]) if walking else np.zeros((0, 2)))
    return real_data.Recording('passer_by', records, legs, True)


def test_people_the_annotation_leaves_out_are_found_in_front_of_the_background():
    recording = _passer_by_recording()
    background = real_data.background_ranges(recording)
    angles = np.degrees(recording.scans[0][2] + recording.scans[0][3] * np.arange(181))
    assert background[np.argmin(np.abs(angles - 60.0))] == pytest.approx(1.5)
    assert background[np.argmin(np.abs(angles - 40.0))] == pytest.approx(4.0)
    # The dark surface returns in a third of the scans: no background, so never a person.
    assert np.isnan(background[np.argmin(np.abs(angles + 50.0))])
    people = real_data.unannotated_people(recording)
    bearing = math.radians(40.0)
    for k, points in enumerate(people):
        if 5 <= k <= 9:
            assert points.shape[0] >= real_data.PERSON_MIN_HITS
            np.testing.assert_allclose(np.hypot(points[:, 0], points[:, 1]), 2.0)
            assert np.abs(np.arctan2(points[:, 1], points[:, 0]) - bearing).max() < 0.07
        else:                       # the annotated walker, the pillar, the dark surface: no
            assert points.shape == (0, 2)
    # Scans of different layouts have no common background: no one is found.
    shifted = list(recording.scans)
    stamp, ranges, angle_min, increment, range_min, range_max = shifted[3]
    shifted[3] = (stamp, ranges[:-1], angle_min, increment, range_min, range_max)
    odd = real_data.Recording('odd', shifted, recording.legs, True)
    assert real_data.background_ranges(odd) is None
    assert all(points.shape == (0, 2) for points in real_data.unannotated_people(odd))


def test_cells_near_the_people_the_annotation_leaves_out_count_only_when_asked():
    recording = _passer_by_recording()
    truth = real_data.ground_truth(recording, 0.6)
    config = real_data.grid_config(recording, 'paper')
    labels, visible, _, seconds = real_data.run_core(recording, config)
    scan = 7
    centres = real_data._cell_centres(real_data.Navigator(config).grid.geometry)
    passer_by = (2.0 * math.cos(math.radians(40.0)), 2.0 * math.sin(math.radians(40.0)))
    cell = np.unravel_index(np.argmin(np.hypot(centres[0] - passer_by[0],
                                               centres[1] - passer_by[1])), centres[0].shape)
    assert truth.near_unannotated[scan][cell] and not truth.near[scan][cell]
    # Mark that cell mobile and visible in that scan only, with nothing else mobile.
    labels = np.full(labels.shape, CellLabel.EXPLORED, dtype=labels.dtype)
    labels[scan][cell] = M
    visible[scan][cell] = True
    plain = real_data.measure_run(truth, labels, visible, seconds)
    counted = real_data.measure_run(truth, labels, visible, seconds, unannotated=True)
    assert (plain.mobile_visible, plain.mobile_visible_true) == (1, 0)
    assert (counted.mobile_visible, counted.mobile_visible_true) == (1, 1)
    assert counted.ghosts == plain.ghosts - int(not truth.static[cell])
    assert counted.walker_cells == plain.walker_cells       # the recalls: annotated only
