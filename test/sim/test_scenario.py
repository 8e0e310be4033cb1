"""
Tests of the scenario side of sim_bridge: PGM and map yaml loading, the index, tasks, free space.

No ROS and no pybullet: everything here is files, numpy and the map_server rules.

"""

import math
from pathlib import Path

from dpn_navigator.core import GridGeometry
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
import numpy as np
from numpy.testing import assert_array_equal
import pytest

from sim_bridge.free_space import clearance_grid, label_components, near_cells
from sim_bridge.map_io import classify_pixels, load_map_yaml
from sim_bridge.pgm import read_pgm, write_pgm
from sim_bridge.scenario import INDEX_PATH, load_index, load_scenario, scenario_names
from sim_bridge.scenarios.generate import write_scenarios
from sim_bridge.tasks import DEFAULT_TASK_CLEARANCE, draw_tasks

# The real maps beside the checkout (../shared/maps), read when present, never shipped.
SHARED_MAPS = next((folder for folder in (Path(__file__).resolve().parents[3] / 'shared' / 'maps',
                                          Path('/work/shared/maps')) if folder.is_dir()),
                   Path('/work/shared/maps'))
SCENARIOS = INDEX_PATH.parent

# A 3 x 4 image, row 0 at the top: black (0) is a wall, white (254) free, grey (205) unknown.
IMAGE = np.array([[0, 254, 254, 205],
                  [254, 254, 0, 205],
                  [254, 254, 254, 254]], dtype=np.uint8)

MAP_YAML = """\
image: tiny.pgm
resolution: 0.5
origin: [-1.0, 2.0, 0.0]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.196
"""


def write_map(directory, yaml_text=MAP_YAML, image=IMAGE):
    """Write ``tiny.pgm`` and ``tiny.yaml``; return the yaml path."""
    write_pgm(directory / 'tiny.pgm', image)
    path = directory / 'tiny.yaml'
    path.write_text(yaml_text)
    return path


# -- PGM ----------------------------------------------------------------------------------


def test_pgm_round_trip_with_comment(tmp_path):
    write_pgm(tmp_path / 'a.pgm', IMAGE, comment='CREATOR: test')
    assert (tmp_path / 'a.pgm').read_bytes().startswith(b'P5\n# CREATOR: test\n4 3\n255\n')
    image, maxval = read_pgm(tmp_path / 'a.pgm')
    assert maxval == 255
    assert_array_equal(image, IMAGE)


def test_pgm_ascii_and_16_bit(tmp_path):
    (tmp_path / 'a.pgm').write_text('P2\n# comment\n3 2\n# another\n15\n0 1 2\n13 14 15\n')
    image, maxval = read_pgm(tmp_path / 'a.pgm')
    assert maxval == 15
    assert_array_equal(image, [[0, 1, 2], [13, 14, 15]])
    (tmp_path / 'b.pgm').write_bytes(b'P5 2 1 65535\n' + np.array([1, 65535], '>u2').tobytes())
    image, maxval = read_pgm(tmp_path / 'b.pgm')
    assert maxval == 65535
    assert_array_equal(image, [[1, 65535]])


@pytest.mark.parametrize('content, match', [
    (b'\x89PNG\r\n', 'not a PGM image'),
    (b'P5\n4 3\n', 'header is truncated'),
    (b'P5\n4 3\n255\n' + bytes(5), 'truncated'),
    (b'P2\n2 1\n255\n1\n', 'holds 1 values, expected 2'),
    (b'P2\n2 1\n9\n1 10\n', 'exceeds maxval'),
    (b'P5\n4 x\n255\n', 'bad PGM token'),
    (b'P5\n0 3\n255\n', 'bad PGM size'),
])
def test_pgm_errors(tmp_path, content, match):
    (tmp_path / 'bad.pgm').write_bytes(content)
    with pytest.raises(ValueError, match=match):
        read_pgm(tmp_path / 'bad.pgm')


def test_pgm_missing_file(tmp_path):
    with pytest.raises(ValueError, match='cannot read PGM'):
        read_pgm(tmp_path / 'none.pgm')


# -- map yaml -----------------------------------------------------------------------------


def test_map_yaml_orientation_origin_and_trinary(tmp_path):
    grid = load_map_yaml(write_map(tmp_path))
    # Image row 0 (top) is grid row 2: row 0 of the grid is the bottom of the map.
    assert_array_equal(grid.occupied, [[0, 0, 0, 0], [0, 0, 1, 0], [1, 0, 0, 0]])
    assert_array_equal(grid.free, [[1, 1, 1, 1], [1, 1, 0, 0], [0, 1, 1, 0]])
    assert grid.resolution == 0.5
    assert grid.origin == (-1.0, 2.0)
    geometry = grid.geometry
    assert geometry.shape == (3, 4)
    # The top-left wall pixel covers x in [-1, -0.5), y in [3, 3.5).
    rr, cc = geometry.world_to_cell(-0.75, 3.25)
    assert grid.occupied[rr, cc]


def test_map_yaml_negate(tmp_path):
    grid = load_map_yaml(write_map(tmp_path, MAP_YAML.replace('negate: 0', 'negate: 1')))
    # Negated: white (254) is occupied, black free, grey (205 -> p 0.80) occupied as well.
    assert_array_equal(grid.occupied, [[1, 1, 1, 1], [1, 1, 0, 1], [0, 1, 1, 1]])
    assert_array_equal(grid.free, [[0, 0, 0, 0], [0, 0, 1, 0], [1, 0, 0, 0]])


@pytest.mark.parametrize('mode', ['trinary', 'scale'])
def test_thresholds_are_strict(mode):
    # p = (255 - v) / 255: v 89 -> 0.6510 (> 0.65, wall), v 90 -> 0.6471 (not a wall);
    # v 205 -> 0.1961 (not < 0.196, so not free), v 206 -> 0.1922 (free).
    occupied, free = classify_pixels(np.array([[89, 90, 205, 206]]), 255, 0, 0.65, 0.196, mode)
    assert_array_equal(occupied, [[1, 0, 0, 0]])
    assert_array_equal(free, [[0, 0, 0, 1]])


def test_raw_mode_reads_percent():
    # Raw: the value is the occupancy in percent, 101..255 unknown; negate does not apply.
    occupied, free = classify_pixels(np.array([[0, 19, 50, 66, 100, 255]]), 255, 1, 0.65,
                                     0.196, 'raw')
    assert_array_equal(occupied, [[0, 0, 0, 1, 1, 0]])
    assert_array_equal(free, [[1, 1, 0, 0, 0, 0]])


def test_map_yaml_defaults_and_absolute_image(tmp_path):
    write_pgm(tmp_path / 'tiny.pgm', IMAGE)
    path = tmp_path / 'sub' / 'map.yaml'
    path.parent.mkdir()
    path.write_text(f'image: {tmp_path / "tiny.pgm"}\nresolution: 1\norigin: [0, 0, 0]\n')
    grid = load_map_yaml(path)
    assert grid.occupied.sum() == 2 and grid.resolution == 1.0


@pytest.mark.parametrize('text, match', [
    ('resolution: 0.5\norigin: [0, 0, 0]\n', "no 'image' field"),
    ('image: tiny.pgm\norigin: [0, 0, 0]\n', "no 'resolution' field"),
    ('image: tiny.pgm\nresolution: 0.5\n', "no 'origin' field"),
    ('image: tiny.pgm\nresolution: -0.5\norigin: [0, 0, 0]\n', 'resolution must be positive'),
    ('image: tiny.pgm\nresolution: abc\norigin: [0, 0, 0]\n', 'resolution must be a finite'),
    ('image: tiny.pgm\nresolution: .nan\norigin: [0, 0, 0]\n', 'resolution must be a finite'),
    ('image: tiny.pgm\nresolution: 0.5\norigin: [0, 0]\n', r'origin must be \[x, y, yaw\]'),
    ('image: tiny.pgm\nresolution: 0.5\norigin: [0, 0, 0.1]\n', 'only unrotated maps'),
    ('image: tiny.pgm\nresolution: 0.5\norigin: [0, 0, 0]\nnegate: 2\n', 'negate must be'),
    ('image: tiny.pgm\nresolution: 0.5\norigin: [0, 0, 0]\nmode: fancy\n', 'mode must be'),
    ('image: tiny.pgm\nresolution: 0.5\norigin: [0, 0, 0]\nfree_thresh: 0.7\n',
     'free_thresh <= occupied_thresh'),
    ('image: [tiny.pgm]\nresolution: 0.5\norigin: [0, 0, 0]\n', 'image must be a file name'),
    ('image: gone.pgm\nresolution: 0.5\norigin: [0, 0, 0]\n', 'cannot read PGM'),
    ('- just\n- a list\n', 'must be a mapping'),
    ('image: [unclosed\n', 'cannot read map yaml'),
])
def test_map_yaml_errors(tmp_path, text, match):
    with pytest.raises(ValueError, match=match):
        load_map_yaml(write_map(tmp_path, text))


def test_map_yaml_missing_file(tmp_path):
    with pytest.raises(ValueError, match='cannot read map yaml'):
        load_map_yaml(tmp_path / 'none.yaml')


# -- built-in scenarios -------------------------------------------------------------------


def test_generator_reproduces_the_shipped_files(tmp_path):
    written = write_scenarios(tmp_path)
    names = sorted(path.name for path in written)
    assert names == sorted(path.name for path in tmp_path.iterdir())
    # Every map (34 yaml + pgm pairs) and the index, byte for byte, and nothing else shipped.
    shipped = sorted(path.name for path in SCENARIOS.iterdir() if path.suffix in ('.pgm', '.yaml'))
    assert names == shipped and len(shipped) == 69
    for path in written:
        assert path.read_bytes() == (SCENARIOS / path.name).read_bytes(), path.name


def test_back_and_forth():
    scenario = load_scenario('back_and_forth')
    assert 'back_and_forth' in scenario_names()
    assert (scenario.number, scenario.family) == (3, 'corridors')
    assert scenario.occupied.shape == (200, 250)
    assert (scenario.width, scenario.height, scenario.origin) == (25.0, 20.0, (0.0, 0.0))
    assert len(scenario.tasks) == 3
    geometry = scenario.geometry

    def wall(x, y):
        return bool(scenario.occupied[geometry.world_to_cell(x, y)])

    # Outer walls, the four inner walls and their gaps on alternate ends.
    assert wall(12.5, 0.1) and wall(12.5, 19.9) and wall(0.1, 10.0) and wall(24.9, 10.0)
    for y, closed_x, gap_x in ((4.0, 2.0, 22.0), (8.0, 22.0, 2.0), (12.0, 2.0, 22.0),
                               (16.0, 22.0, 2.0)):
        assert wall(closed_x, y) and not wall(gap_x, y)
    assert not wall(12.5, 2.0)
    assert scenario.free.sum() + scenario.occupied.sum() == scenario.occupied.size


def test_back_and_forth_tasks_are_feasible():
    scenario = load_scenario('back_and_forth')
    grid = clearance_grid(scenario.free, scenario.geometry, DEFAULT_TASK_CLEARANCE)
    for task in scenario.tasks:
        start = grid.cell_of(*task.start[:2])
        goal = grid.cell_of(*task.goal)
        assert grid.clear[start] and grid.clear[goal]
        assert grid.labels[start] == grid.labels[goal]
        assert math.dist(task.start[:2], task.goal) >= 5.0


def test_unknown_scenario_name():
    with pytest.raises(ValueError, match="unknown scenario 'nowhere'; known: .*back_and_forth"):
        load_scenario('nowhere')


@pytest.mark.parametrize('entry, match', [
    ('- {number: 1, name: a, family: f, map: a.yaml}', 'missing field.*tasks'),
    ('- {number: x, name: a, family: f, map: a.yaml, tasks: []}', 'number must be an integer'),
    ('- {number: 1, name: "", family: f, map: a.yaml, tasks: []}', 'name must be a non-empty'),
    ('- {number: 1, name: a, family: f, map: a.yaml, tasks: [{start: [0, 0], goal: [1, 1]}]}',
     'start must be a list of 3'),
    ('- {number: 1, name: a, family: f, map: a.yaml, tasks: [{start: [0, 0, 0]}]}',
     'exactly start and goal'),
    ('- {number: 1, name: a, family: f, map: a.yaml, tasks: []}\n'
     '- {number: 2, name: a, family: f, map: a.yaml, tasks: []}', r"repeated name\(s\) \['a'\]"),
    ('- 7', 'must be a mapping'),
])
def test_index_errors(tmp_path, entry, match):
    index = tmp_path / 'index.yaml'
    index.write_text('format: 1\nscenarios:\n' + entry + '\n')
    with pytest.raises(ValueError, match=match):
        load_index(index)


def test_index_format_and_missing_file(tmp_path):
    (tmp_path / 'index.yaml').write_text('format: 2\nscenarios: []\n')
    with pytest.raises(ValueError, match='format: 1'):
        load_index(tmp_path / 'index.yaml')
    with pytest.raises(ValueError, match='cannot read scenario index'):
        load_index(tmp_path / 'none.yaml')


def test_custom_index_with_relative_map(tmp_path):
    write_map(tmp_path)
    (tmp_path / 'index.yaml').write_text(
        'format: 1\nscenarios:\n  - number: 7\n    name: tiny\n    family: test\n'
        '    map: tiny.yaml\n    tasks:\n'
        '      - {start: [-0.75, 2.25, 0.5], goal: [0.25, 2.25]}\n')
    scenario = load_scenario('tiny', index=tmp_path / 'index.yaml')
    assert scenario.number == 7 and scenario.map_yaml == (tmp_path / 'tiny.yaml').resolve()
    assert scenario.tasks[0].start == (-0.75, 2.25, 0.5)
    (tmp_path / 'index.yaml').write_text(
        'format: 1\nscenarios:\n  - number: 7\n    name: tiny\n    family: test\n'
        '    map: tiny.yaml\n    tasks:\n      - {start: [-5, 2.25, 0.5], goal: [0.25, 2.25]}\n')
    with pytest.raises(ValueError, match='outside the map'):
        load_scenario('tiny', index=tmp_path / 'index.yaml')


# -- drawn tasks --------------------------------------------------------------------------


def open_room(size=12.0, resolution=0.1):
    """Return a square room of free cells inside a one-cell wall, as (free, geometry)."""
    geometry = GridGeometry(size, size, resolution)
    free = np.ones(geometry.shape, dtype=bool)
    free[[0, -1], :] = free[:, [0, -1]] = False
    return free, geometry


def test_draw_tasks_is_reproducible_and_valid():
    free, geometry = open_room()
    tasks = draw_tasks(free, geometry, 5, seed=3)
    assert tasks == draw_tasks(free, geometry, 5, seed=3)
    assert tasks != draw_tasks(free, geometry, 5, seed=4)
    for task in tasks:
        assert math.dist(task.start[:2], task.goal) >= 5.0
        assert -math.pi <= task.start[2] < math.pi
        for x, y in (task.start[:2], task.goal):
            # At least the clearance from the walls, which are 0.1 m thick.
            assert 0.1 + 0.7 <= x <= 11.9 - 0.7 and 0.1 + 0.7 <= y <= 11.9 - 0.7


def test_draw_tasks_stays_in_one_component():
    free, geometry = open_room()
    free[:, 55:65] = False  # a 1 m wall splits the room into two halves
    for task in draw_tasks(free, geometry, 10, seed=0):
        assert (task.start[0] < 5.5) == (task.goal[0] < 5.5)


def test_draw_tasks_errors():
    free, geometry = open_room(size=4.0)
    assert draw_tasks(free, geometry, 0, seed=0) == ()
    with pytest.raises(ValueError, match='no start and goal 5.0 m apart'):
        draw_tasks(free, geometry, 1, seed=0)
    with pytest.raises(ValueError, match='no free cell with 3.0 m clearance'):
        draw_tasks(free, geometry, 1, seed=0, clearance=3.0)
    with pytest.raises(ValueError, match='n_tasks must be'):
        draw_tasks(free, geometry, -1, seed=0)


def test_bare_map_gets_drawn_tasks(tmp_path):
    free, geometry = open_room()
    image = np.where(free, 254, 0).astype(np.uint8)[::-1]
    write_pgm(tmp_path / 'tiny.pgm', image)
    path = tmp_path / 'room.yaml'
    path.write_text(MAP_YAML.replace('resolution: 0.5', 'resolution: 0.1'))
    scenario = load_scenario(path, n_tasks=2, seed=5)
    assert scenario.name == 'room' and scenario.number is None and len(scenario.tasks) == 2
    assert scenario.tasks == load_scenario(str(path), n_tasks=2, seed=5).tasks


def test_bare_map_without_tasks_names_the_map(tmp_path):
    free, geometry = open_room(size=4.0)
    image = np.where(free, 254, 0).astype(np.uint8)[::-1]
    write_pgm(tmp_path / 'tiny.pgm', image)
    path = tmp_path / 'small_room.yaml'
    path.write_text(MAP_YAML.replace('resolution: 0.5', 'resolution: 0.1'))
    with pytest.raises(ValueError, match=r'small_room\.yaml: could not draw 1 tasks'):
        load_scenario(path, n_tasks=1, seed=0)


# -- free space ---------------------------------------------------------------------------


def near_cells_twin(mask, clearance):
    """Brute force: the least distance between two unit squares, cell by cell."""
    rows, cols = mask.shape
    near = mask.copy()
    for r, c in zip(*np.nonzero(mask)):
        for i in range(rows):
            for j in range(cols):
                gap = math.hypot(max(abs(i - r) - 1, 0), max(abs(j - c) - 1, 0))
                near[i, j] |= gap < clearance
    return near


@settings(max_examples=60)
@given(mask=hnp.arrays(bool, st.tuples(st.integers(1, 9), st.integers(1, 9))),
       clearance=st.floats(0.0, 5.0))
def test_near_cells_matches_brute_force(mask, clearance):
    assert_array_equal(near_cells(mask, clearance), near_cells_twin(mask, clearance))


def test_label_components_is_4_connected():
    mask = np.array([[1, 1, 0, 1],
                     [0, 1, 0, 0],
                     [1, 0, 1, 1]], dtype=bool)
    labels, count = label_components(mask)
    assert count == 4
    assert_array_equal(labels, [[1, 1, 0, 2], [0, 1, 0, 0], [3, 0, 4, 4]])


def test_clearance_grid_cells_keep_the_clearance():
    free, geometry = open_room(size=6.0, resolution=0.05)
    grid = clearance_grid(free, geometry, 0.5)
    assert grid.factor == 4 and grid.geometry.resolution == pytest.approx(0.2)
    rr, cc = np.nonzero(grid.clear)
    # Coarse cells are 0.2 m; the walls end 0.05 m in from the edge; every corner of a clear
    # cell is at least 0.5 m from them.
    x, y = grid.geometry.cell_to_world(rr, cc)
    assert x.min() - 0.1 >= 0.55 - 1e-9 and x.max() + 0.1 <= 5.45 + 1e-9
    assert y.min() - 0.1 >= 0.55 - 1e-9 and y.max() + 0.1 <= 5.45 + 1e-9
    assert len(np.unique(grid.labels[rr, cc])) == 1
    assert grid.is_clear(3.0, 3.0) and not grid.is_clear(0.2, 3.0) and not grid.is_clear(-1, 3)


# -- the shared real maps -----------------------------------------------------------------

# Free / occupied fractions from /work/shared/maps/SOURCES.md (map_server trinary semantics).
SHARED_FRACTIONS = {
    'depot': (0.968, 0.032), 'warehouse': (0.845, 0.018), 'tb3_sandbox': (0.054, 0.006),
    'smoothers_world': (0.882, 0.118), 'willow-2010-02-18-0.10': (0.317, 0.002),
    'intel': (0.283, 0.017), 'aces': (0.255, 0.014), 'tb3_office_raw': (0.389, 0.031),
    'room-64-64-8': (0.789, 0.211), 'maze-128-128-2': (0.663, 0.337),
    'den312d': (0.464, 0.536), 'Berlin_1_256': (0.725, 0.275),
}


@pytest.mark.parametrize('name', sorted(SHARED_FRACTIONS))
def test_shared_maps_load(name):
    path = SHARED_MAPS / f'{name}.yaml'
    if not path.exists():
        pytest.skip(f'{path} is not present')
    grid = load_map_yaml(path)
    image, _ = read_pgm(SHARED_MAPS / f'{name}.pgm')
    assert grid.occupied.shape == image.shape
    free_fraction, occupied_fraction = SHARED_FRACTIONS[name]
    assert grid.free.mean() == pytest.approx(free_fraction, abs=0.0006)
    assert grid.occupied.mean() == pytest.approx(occupied_fraction, abs=0.0006)


@pytest.mark.parametrize('name', ['depot', 'intel', 'warehouse'])
def test_shared_maps_give_tasks(name):
    path = SHARED_MAPS / f'{name}.yaml'
    if not path.exists():
        pytest.skip(f'{path} is not present')
    scenario = load_scenario(path, n_tasks=3, seed=0)
    grid = clearance_grid(scenario.free, scenario.geometry, DEFAULT_TASK_CLEARANCE)
    for task in scenario.tasks:
        assert grid.is_clear(*task.start[:2]) and grid.is_clear(*task.goal)
