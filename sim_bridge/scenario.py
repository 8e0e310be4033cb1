"""
Scenarios: a map_server map plus navigation tasks, listed in an index file.

An index is a YAML file such as ``sim_bridge/scenarios/index.yaml``::

    format: 1
    scenarios:
      - number: 3                     # the map's number in the benchmark set
        name: back_and_forth          # unique; what load_scenario() takes
        family: corridors             # free-form layout class, for grouping results
        map: back_and_forth.yaml      # map_server yaml, relative to the index file
        tasks:                        # map frame: x, y [m], yaw [rad]
          - {start: [2.0, 2.0, 0.0], goal: [2.0, 18.0]}

`load_scenario` takes a name from an index (the built-in one unless told otherwise) or the path
of any map_server yaml; for a bare map it draws tasks from the map's free space, reproducibly
from a seed (see `draw_tasks`).

"""

from dataclasses import dataclass
import math
from pathlib import Path

from dpn_navigator.core import GridGeometry
import numpy as np
import yaml

from .map_io import load_map_yaml
from .tasks import draw_tasks, Task

#: The built-in index.
INDEX_PATH = Path(__file__).resolve().parent / 'scenarios' / 'index.yaml'
#: Index format this module reads.
INDEX_FORMAT = 1
# yaml.safe_load's loader, in C (libyaml, in PyYAML's wheels) when available: the same
# documents, about ten times faster on the 34-map index.
_SAFE_LOADER = getattr(yaml, 'CSafeLoader', yaml.SafeLoader)


@dataclass(frozen=True)
class IndexEntry:
    """
    One scenario of an index file: number, name, family, map yaml path and tasks.

    Attributes
    ----------
    number : int
        The map's number in the benchmark set.
    name : str
        Unique name.
    family : str
        Layout class, e.g. ``corridors``, ``maze``, ``office``.
    map_yaml : pathlib.Path
        The map_server yaml (absolute).
    tasks : tuple of Task
        The map's tasks.

    """

    number: int
    name: str
    family: str
    map_yaml: Path
    tasks: tuple


@dataclass(frozen=True, eq=False)
class Scenario:
    """
    A map and its tasks.

    Attributes
    ----------
    name : str
        The scenario's name.
    occupied : (rows, cols) ndarray of bool
        Wall cells; row 0 is the bottom of the map (smallest y), as in ``GridGeometry``.
    free : (rows, cols) ndarray of bool
        Known-free cells (neither walls nor unknown). Same layout.
    resolution : float
        Cell side [m].
    origin : (float, float)
        Map-frame position of the lower-left corner of cell (0, 0) [m].
    tasks : tuple of Task
        The navigation tasks.
    number : int or None
        Number in the index, None for a bare map.
    family : str or None
        Layout class from the index, None for a bare map.
    map_yaml : pathlib.Path or None
        The map_server yaml the grid came from.

    """

    name: str
    occupied: np.ndarray
    free: np.ndarray
    resolution: float
    origin: tuple
    tasks: tuple
    number: int = None
    family: str = None
    map_yaml: Path = None

    @property
    def geometry(self):
        """Return the grid's `GridGeometry` (cell <-> map-frame conversion)."""
        rows, cols = self.occupied.shape
        return GridGeometry(cols * self.resolution, rows * self.resolution, self.resolution,
                            self.origin)

    @property
    def width(self):
        """Return the extent along x [m]."""
        return self.occupied.shape[1] * self.resolution

    @property
    def height(self):
        """Return the extent along y [m]."""
        return self.occupied.shape[0] * self.resolution


def load_index(path=None):
    """
    Read a scenario index file.

    Parameters
    ----------
    path : str or pathlib.Path, optional
        The index; the built-in `INDEX_PATH` by default.

    Returns
    -------
    entries : tuple of IndexEntry
        In file order.

    Raises
    ------
    ValueError
        If the file is missing or malformed, or names or numbers repeat.

    """
    path = Path(INDEX_PATH if path is None else path)
    try:
        doc = yaml.load(path.read_text(), Loader=_SAFE_LOADER)
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as exc:
        raise ValueError(f'cannot read scenario index {str(path)!r}: {exc}') from exc
    if not isinstance(doc, dict) or doc.get('format') != INDEX_FORMAT or \
            not isinstance(doc.get('scenarios'), list):
        raise ValueError(f'scenario index {str(path)!r} must be a mapping with format: '
                         f'{INDEX_FORMAT} and a list of scenarios')
    entries = []
    for k, item in enumerate(doc['scenarios']):
        where = f'scenario index {str(path)!r}, entry {k}'
        if not isinstance(item, dict):
            raise ValueError(f'{where}: must be a mapping, got {item!r}')
        missing = [key for key in ('number', 'name', 'family', 'map', 'tasks') if key not in item]
        if missing:
            raise ValueError(f'{where}: missing field(s) {", ".join(missing)}')
        number, name, family, map_name = item['number'], item['name'], item['family'], item['map']
        if isinstance(number, bool) or not isinstance(number, int):
            raise ValueError(f'{where}: number must be an integer, got {number!r}')
        for key, value in (('name', name), ('family', family), ('map', map_name)):
            if not isinstance(value, str) or not value:
                raise ValueError(f'{where}: {key} must be a non-empty string, got {value!r}')
        if not isinstance(item['tasks'], list):
            raise ValueError(f'{where}: tasks must be a list')
        tasks = tuple(_parse_task(task, f'{where} ({name}), task {j}')
                      for j, task in enumerate(item['tasks']))
        entries.append(IndexEntry(number, name, family, (path.parent / map_name).resolve(),
                                  tasks))
    for key in ('number', 'name'):
        values = [getattr(entry, key) for entry in entries]
        repeated = sorted({value for value in values if values.count(value) > 1}, key=str)
        if repeated:
            raise ValueError(f'scenario index {str(path)!r}: repeated {key}(s) {repeated}')
    return tuple(entries)


def _parse_task(task, where):
    """Check one task mapping of an index and return it as a `Task`."""
    if not isinstance(task, dict) or set(task) != {'start', 'goal'}:
        raise ValueError(f'{where}: must be a mapping with exactly start and goal, got {task!r}')
    start, goal = task['start'], task['goal']
    for key, value, size in (('start', start, 3), ('goal', goal, 2)):
        if not isinstance(value, list) or len(value) != size or not all(
                isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                for v in value):
            raise ValueError(f'{where}: {key} must be a list of {size} finite numbers, '
                             f'got {value!r}')
    return Task(tuple(float(v) for v in start), tuple(float(v) for v in goal))


def scenario_names(index=None):
    """Return the scenario names of an index (the built-in one by default), in file order."""
    return tuple(entry.name for entry in load_index(index))


def load_scenario(name_or_path, index=None, n_tasks=3, seed=0):
    """
    Load a scenario by name, or a bare map_server map with drawn tasks.

    Parameters
    ----------
    name_or_path : str or pathlib.Path
        A scenario name from the index, or the path of a map_server yaml (a `Path`, or a
        string ending in ``.yaml``/``.yml`` or holding a path separator).
    index : str or pathlib.Path, optional
        The index to look names up in; the built-in `INDEX_PATH` by default.
    n_tasks : int
        For a bare map: how many tasks to draw.
    seed : int
        For a bare map: seed of the task draw.

    Returns
    -------
    Scenario

    Raises
    ------
    ValueError
        For an unknown name, a missing or malformed index, yaml or image, a task outside the
        map, or a bare map with too little free space for the tasks.

    """
    text = str(name_or_path)
    if isinstance(name_or_path, Path) or text.endswith(('.yaml', '.yml')) or '/' in text:
        grid = load_map_yaml(name_or_path)
        try:
            tasks = draw_tasks(grid.free, grid.geometry, n_tasks, seed)
        except ValueError as exc:
            raise ValueError(f'{text}: {exc}') from None
        return Scenario(Path(text).stem, grid.occupied, grid.free, grid.resolution,
                        grid.origin, tasks, map_yaml=grid.yaml_path)
    entries = {entry.name: entry for entry in load_index(index)}
    if text not in entries:
        raise ValueError(f'unknown scenario {text!r}; known: {", ".join(sorted(entries))} '
                         '(or give the path of a map_server yaml)')
    entry = entries[text]
    grid = load_map_yaml(entry.map_yaml)
    geometry = grid.geometry
    for j, task in enumerate(entry.tasks):
        for x, y in (task.start[:2], task.goal):
            if not geometry.contains_cell(*geometry.world_to_cell(x, y)):
                raise ValueError(f'scenario {text!r} task {j}: ({x}, {y}) lies outside the map')
    return Scenario(entry.name, grid.occupied, grid.free, grid.resolution, grid.origin,
                    entry.tasks, entry.number, entry.family, grid.yaml_path)
