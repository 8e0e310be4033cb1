"""
The benchmark protocol: which episodes to run, each with a seed of its own.

The paper's protocol (section 3.2) runs every map of the benchmark set with 3 navigation tasks,
0 to 10 wandering robots and 30 repetitions of each: 34 x 3 x 11 x 30 = 33,660 episodes. A
protocol here is the cross product of maps, task indices, wanderer counts and repetitions; each
episode's world seed is derived from a base seed and the episode's key alone, so an episode
gives the same result whichever worker runs it, in whatever order, and a resumed run continues
the same experiment.

"""

from dataclasses import dataclass
import itertools
from pathlib import Path
import re
import zlib

import numpy as np

from ..core.real_laser import REAL_LASER_SETTINGS

#: The settings of issue 31 (a navigator that does not get stuck: stale obstacles, the honest
#: no-path timer, route commitment and waiting, giving way, exploration with memory), each 0
#: for off. Off in ``paper``, and in the reference navigators, whose rows stay those of the
#: planner they were measured with.
NOT_GETTING_STUCK_OFF = {'stale_obstacle_age': 0.0, 'path_trust_time': 0.0,
                         'route_block_distance': 0.0, 'route_switch_margin': 0.0,
                         'route_review_period': 0.0,
                         'mobile_wait_time': 0.0, 'give_way_time': 0.0,
                         'unknown_cell_cost': 0.0,
                         'forgotten_obstacle_cost': 0.0}

#: ``--navigator`` choices: overrides of ``NavigatorConfig``'s defaults. ``dpn`` is the
#: navigator as shipped; ``paper`` turns off what this project added to the paper's method (the
#: obstacle proximity cost of A*, forgetting unseen obstacles when stuck, the label rules:
#: conservative free space, object-level relabelling and ghost expiry, and the turn sweep).
#: The reference navigators (`MAP_MODELS`) plan on another map with dpn's planner and
#: follower, the turn sweep included; the drive guard only where they take dpn's step
#: (``costmap-bare``, ``oracle-foresight``, ``oracle-bare``): ``costmap`` steps through its
#: recoveries and the sweep alone (0 contacts in 763 held-out episodes without a guard), and
#: ``oracle`` knows the walls and the agents. They forget nothing (the costmap has no decay,
#: the oracle nothing to forget). ``costmap`` is the Nav2-faithful one (recoveries, 1 Hz
#: replanning, NavFn's unknown cost); ``costmap-bare`` the costmap alone, as it ran before
#: 27 November.
#: ``oracle`` plans in space and time on the agents' true future over 8 s and waits where
#: that pays (``baselines.spacetime_oracle``); ``oracle-foresight`` blocks only the agents
#: near the robot, at their constant-velocity forecast over 2 s
#: (``baselines.wanderer_forecast``), the ``oracle`` of 27 November; ``oracle-bare`` every
#: agent where it stands, the oracle before that.
#: ``dpn_no_sweep`` is dpn with the turn sweep off (``NavigatorConfig.turn_sweep_memory``, on
#: by default), as shipped before 25 November; paper turns it off too.
#: ``dpn_real_laser`` is dpn with ``config/dpn_real_laser.yaml``, for a moving robot with a real
#: laser: beams with no return clear nothing (a wall at grazing incidence returns nothing, and
#: its beams would show it empty), mixed pixels and spikes are invalid, veiling hits show no motion
#: (``REAL_LASER``, docs/real_data.md); a hit shows motion only beyond three sigma of the range
#: noise; space is surely free only after 0.5 s without a hit near it (the burn-in), a scan
#: segment narrower than 5 cm shows no motion, and a wall seen at more than 60 deg from its
#: normal next to beams with no return goes on (its unknown cells cost 100 cells more).
REAL_LASER = dict(REAL_LASER_SETTINGS)
NAVIGATORS = {
    'dpn': {},
    'dpn_no_sweep': {'turn_sweep_memory': 0.0},
    'dpn_real_laser': dict(REAL_LASER),
    'paper': {'obstacle_proximity_cost': 0.0, 'forget_obstacles_after': 0.0,
              'free_evidence_radius': 0.0, 'moving_object_size': 0.0, 'object_min_hits': 0,
              'segment_bridge_beams': 0, 'real_laser_switch': 0.0,
              'fine_evidence_resolution': 0.0, 'fine_evidence_radius': 0.0, 'mobile_expiry': 0.0,
              'track_confirm_time': 0.0, 'track_still_distance': 0.0, 'track_exclusive': False,
              'trail_distance': 0.0, 'object_memory': 0.0,
              'object_memory_short_segments': False, 'no_return_reach': 1.0,
              'surface_time': 0.0, 'turn_sweep_memory': 0.0, 'drive_guard_distance': 0.0,
              'map_growth_step': 0.0,
              'free_evidence_renewal': 0.0, **NOT_GETTING_STUCK_OFF},
    'costmap': {'forget_obstacles_after': 0.0, **NOT_GETTING_STUCK_OFF},
    'costmap-bare': {'forget_obstacles_after': 0.0, **NOT_GETTING_STUCK_OFF},
    'oracle': {'forget_obstacles_after': 0.0, **NOT_GETTING_STUCK_OFF},
    'oracle-foresight': {'forget_obstacles_after': 0.0, **NOT_GETTING_STUCK_OFF},
    'oracle-bare': {'forget_obstacles_after': 0.0, **NOT_GETTING_STUCK_OFF},
}

#: The map each ``--navigator`` plans on: ``labels`` (the paper's labelled grid,
#: ``LabelGrid``), ``costmap`` (Nav2's obstacle and inflation layers, ``CostmapGrid``) or
#: ``oracle``, ``foresight`` or ``spacetime`` (the true walls and wanderers, ``OracleGrid``;
#: ``spacetime``: the walls, planned on by ``SpaceTimeOracle``); ``nav2`` is the costmap run by
#: Nav2's default behaviour tree (``baselines.nav2_navigator.Nav2Navigator``: 1 Hz replanning,
#: NavFn's cost of unknown space, the recoveries), ``costmap`` the bare costmap without them.
MAP_MODELS = {'dpn': 'labels', 'dpn_no_sweep': 'labels', 'dpn_real_laser': 'labels',
              'paper': 'labels', 'costmap': 'nav2',
              'costmap-bare': 'costmap', 'oracle': 'spacetime', 'oracle-foresight': 'foresight',
              'oracle-bare': 'oracle'}

#: A ``--maps`` range of map numbers, e.g. ``1-34``.
_NUMBER_RANGE = re.compile(r'\d+-\d+')

#: Largest number of wandering robots an episode may have (the paper's protocol goes to 10).
MAX_WANDERERS = 10


@dataclass(frozen=True)
class Profile:
    """
    A named selection of maps, tasks, wanderer counts and repetitions.

    Attributes
    ----------
    maps : tuple of str or None
        Map selectors (numbers, names or yaml paths); None for every map of the index.
    tasks : tuple of int
        Task indices.
    wanderers : tuple of int
        Wanderer counts.
    repeats : int
        Repetitions of each (map, task, wanderers).

    """

    maps: tuple
    tasks: tuple
    wanderers: tuple
    repeats: int


#: ``--profile`` choices. ``smoke`` runs in minutes on a laptop; ``paper`` is the paper's full
#: protocol.
PROFILES = {
    'smoke': Profile(maps=('3', '15', '27'), tasks=(0,), wanderers=(0, 5, 10), repeats=1),
    'paper': Profile(maps=None, tasks=(0, 1, 2), wanderers=tuple(range(MAX_WANDERERS + 1)),
                     repeats=30),
}


@dataclass(frozen=True)
class EpisodeSpec:
    """
    One episode of a protocol.

    Attributes
    ----------
    map_key : str
        A scenario name of the index, or the absolute path of a map_server yaml.
    task : int
        Index of the map's task.
    wanderers : int
        Number of wandering robots.
    repetition : int
        Repetition number, from 0.
    seed : int
        The world's seed, from `episode_seed`.

    """

    map_key: str
    task: int
    wanderers: int
    repetition: int
    seed: int

    @property
    def key(self):
        """Return ``(map_key, task, wanderers, repetition, seed)``: what identifies a result."""
        return (self.map_key, self.task, self.wanderers, self.repetition, self.seed)


def episode_seed(base_seed, map_key, task, wanderers, repetition):
    """
    Derive an episode's world seed from the base seed and the episode's key.

    Parameters
    ----------
    base_seed : int
        The run's ``--seed``, non-negative.
    map_key : str
        The map's name or yaml path.
    task, wanderers, repetition : int
        The rest of the episode's key.

    Returns
    -------
    seed : int
        In ``[0, 2**31)``; the same for the same arguments on every machine and Python run
        (``numpy.random.SeedSequence`` over the key, with a CRC-32 of the map key).

    """
    sequence = np.random.SeedSequence(
        [base_seed, zlib.crc32(map_key.encode('utf-8')), task, wanderers, repetition])
    return int(sequence.generate_state(1, np.uint32)[0] & 0x7FFFFFFF)


def resolve_maps(selectors, entries):
    """
    Turn map selectors into map keys.

    Parameters
    ----------
    selectors : sequence of str, or None
        Map numbers (``'15'``), ranges of numbers (``'1-34'``), names (``'maze'``) or paths of
        map_server yaml files (ending in ``.yaml``/``.yml`` or holding a ``/``). None selects
        every map of the index.
    entries : sequence of sim_bridge.scenario.IndexEntry
        The scenario index.

    Returns
    -------
    map_keys : tuple of str
        Index names, and absolute paths for yaml files, in the order given, without repeats.

    Raises
    ------
    ValueError
        For an unknown number or name, or a yaml path that does not exist.

    """
    if selectors is None:
        return tuple(entry.name for entry in entries)
    by_number = {str(entry.number): entry.name for entry in entries}
    names = {entry.name for entry in entries}
    keys = []
    for selector in selectors:
        text = str(selector).strip()
        if text.endswith(('.yaml', '.yml')) or '/' in text:
            path = Path(text).expanduser().resolve()
            if not path.is_file():
                raise ValueError(f'map yaml {text!r} does not exist')
            key = str(path)
        elif text in by_number:
            key = by_number[text]
        elif _NUMBER_RANGE.fullmatch(text):
            low, high = (int(part) for part in text.split('-'))
            missing = [str(n) for n in range(low, high + 1) if str(n) not in by_number]
            if low > high or missing:
                raise ValueError(f'map range {text!r} holds no map number '
                                 f'{", ".join(missing) or text}; the index numbers its maps '
                                 f'{min(e.number for e in entries)} to '
                                 f'{max(e.number for e in entries)}')
            keys.extend(by_number[str(n)] for n in range(low, high + 1)
                        if by_number[str(n)] not in keys)
            continue
        elif text in names:
            key = text
        else:
            known = ', '.join(f'{entry.number} {entry.name}' for entry in entries)
            raise ValueError(f'unknown map {text!r}: give a number or name of the index '
                             f'({known}) or the path of a map_server yaml')
        if key not in keys:
            keys.append(key)
    return tuple(keys)


def plan_episodes(map_keys, tasks, wanderers, repeats, base_seed):
    """
    List a protocol's episodes.

    Parameters
    ----------
    map_keys : sequence of str
        From `resolve_maps`.
    tasks : sequence of int
        Task indices, non-negative.
    wanderers : sequence of int
        Wanderer counts in ``[0, MAX_WANDERERS]``.
    repeats : int
        Repetitions, positive.
    base_seed : int
        Non-negative.

    Returns
    -------
    specs : list of EpisodeSpec
        Map by map, then task, wanderers and repetition, without repeats.

    Raises
    ------
    ValueError
        For a negative task, a wanderer count out of range, ``repeats < 1`` or a negative seed.

    """
    tasks = _unique_ints(tasks, 'task', 0, None)
    wanderers = _unique_ints(wanderers, 'wanderer count', 0, MAX_WANDERERS)
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 1:
        raise ValueError(f'repeats must be a positive integer, got {repeats!r}')
    if isinstance(base_seed, bool) or not isinstance(base_seed, int) or base_seed < 0:
        raise ValueError(f'the seed must be a non-negative integer, got {base_seed!r}')
    return [EpisodeSpec(map_key, task, count, repetition,
                        episode_seed(base_seed, map_key, task, count, repetition))
            for map_key, task, count, repetition in itertools.product(
                map_keys, tasks, wanderers, range(repeats))]


def _unique_ints(values, what, low, high):
    """Check a list of integers against ``[low, high]`` and drop repeats, keeping order."""
    checked = []
    for value in values:
        if isinstance(value, bool) or not isinstance(value, int) or value < low or (
                high is not None and value > high):
            bound = f'from {low}' if high is None else f'in [{low}, {high}]'
            raise ValueError(f'each {what} must be an integer {bound}, got {value!r}')
        if value not in checked:
            checked.append(value)
    return tuple(checked)
