"""
Run a protocol's episodes in parallel, on local cores or a Ray cluster, into an episode log.

Every episode runs in a worker process (`run_spec`): the lockstep episode of
``dpn_navigator.benchmark.episode``, with no ROS. A worker keeps what episodes of one map and
task share (the scenario, the reference shortest path, the wanderers' clearance grid) for the
next ones, and compiles the core's kernels once. Results come back to this process, which
appends each to ``episodes.csv`` as it arrives (see `EpisodeLog`) and shows progress and the
time left with tqdm.

Ray is optional (``requirements-ray.txt``): `run_protocol` imports it only when given a
``ray_address``. On a cluster every node needs this package and its dependencies installed, and
map yaml paths must exist on every node.

"""

from dataclasses import dataclass
import functools
import multiprocessing
import os
from pathlib import Path
import time

from .baselines.costmap_grid import warm_up_costmap
from .episode import run_episode, task_setup
from .episode_log import EpisodeLog
from ..core.mapping.label_grid import warm_up_label_update
from ..core.planning.astar_search import warm_up_astar
from ..core.planning.planning_masks import warm_up_planning_masks


@dataclass(frozen=True)
class RunStats:
    """
    What one call of `run_protocol` did.

    Attributes
    ----------
    planned : int
        Episodes in the protocol.
    skipped : int
        Episodes already in the log.
    ran : int
        Episodes run and logged now.
    wall_time : float
        Wall-clock time of the call [s].
    simulated_time : float
        Simulated time of the episodes run now, summed [s].
    episode_wall_time : float
        Wall-clock time the workers spent on them, summed [s]: CPU-seconds of work, as each
        worker is one single-threaded process.
    workers : int
        Parallel workers (local processes, or Ray's CPU count).

    """

    planned: int
    skipped: int
    ran: int
    wall_time: float
    simulated_time: float
    episode_wall_time: float
    workers: int

    @property
    def speed_per_core(self):
        """Return simulated seconds per worker wall second (real-time factor per core)."""
        return self.simulated_time / self.episode_wall_time if self.episode_wall_time else 0.0

    @property
    def episodes_per_hour(self):
        """Return episodes finished per wall-clock hour by all workers together."""
        return 3600.0 * self.ran / self.wall_time if self.wall_time else 0.0


@functools.lru_cache(maxsize=8)
def _scenario(map_key, index):
    """Load a scenario once per worker process."""
    from sim_bridge.scenario import load_scenario
    return load_scenario(map_key, index=index)


@functools.lru_cache(maxsize=8)
def _wanderer_grid(map_key, index, agents='p3at'):
    """Build a map's clearance grid for an agent model once per worker process."""
    from sim_bridge.wanderers import AGENT_MODELS
    from sim_bridge.world import wanderer_clearance_grid
    return wanderer_clearance_grid(_scenario(map_key, index), AGENT_MODELS[agents])


@functools.lru_cache(maxsize=24)
def _task_setup(map_key, index, task, agents='p3at'):
    """Compute a task's `TaskSetup` once per worker process."""
    return task_setup(_scenario(map_key, index), task, _wanderer_grid(map_key, index, agents))


#: The kernels an episode runs besides A* and the planning masks, by ``protocol.MAP_MODELS``.
_MAP_MODEL_WARM_UPS = {'labels': (warm_up_label_update,), 'costmap': (warm_up_costmap,),
                       'nav2': (warm_up_costmap,), 'oracle': (), 'foresight': (),
                       'spacetime': ()}


def warm_up_kernels(map_model):
    """
    Compile (or load) the kernels an episode on ``map_model`` runs, before it starts.

    A* and the planning masks (the navigator and the wanderers), and the kernels of the map
    the navigator plans on; nothing of the other maps. Nearly free after the first episode.

    """
    if map_model not in _MAP_MODEL_WARM_UPS:
        raise ValueError(f'unknown map model {map_model!r}; one of {sorted(_MAP_MODEL_WARM_UPS)}')
    for warm_up in (warm_up_astar, warm_up_planning_masks) + _MAP_MODEL_WARM_UPS[map_model]:
        warm_up()


def run_spec(spec, index=None, navigator_options=None, detection=True, record_dir=None,
             map_model='labels', episode_options=None):
    """
    Run one episode and return its log row; record it into a bag if asked.

    Parameters
    ----------
    spec : EpisodeSpec
        The episode.
    index : str, optional
        The scenario index (the built-in one by default).
    navigator_options : dict, optional
        ``NavigatorConfig`` overrides (see ``protocol.NAVIGATORS``).
    detection : bool
        Measure the map as a detector (``run_episode``'s ``detection``).
    record_dir : str or os.PathLike, optional
        Write the episode as a rosbag2 MCAP bag into this folder, named by
        ``episode_bag.episode_bag_name`` (``EpisodeBagRecorder``).
    map_model : str
        The map the navigator plans on (``protocol.MAP_MODELS``).
    episode_options : dict, optional
        `EPISODE_OPTIONS` for ``run_episode``: ``agents`` (a name of
        ``sim_bridge.wanderers.AGENT_MODELS``), ``pose_noise`` (``(sigma_xy, sigma_yaw)``),
        ``navigator_class`` (a plug-in's ``'package.module:Class'``) and ``laser`` (a name of
        ``sim_bridge.laser_profiles``; ``ideal`` by default).

    Returns
    -------
    row : dict
        Every column of ``episode_log.COLUMNS``; ``wall_time`` includes the recording.

    """
    started = time.perf_counter()
    scenario = _scenario(spec.map_key, index)
    if not 0 <= spec.task < len(scenario.tasks):
        raise ValueError(f'map {spec.map_key!r} has {len(scenario.tasks)} tasks; there is no '
                         f'task {spec.task}')
    warm_up_kernels(map_model)
    extra = episode_keywords(episode_options)
    agents = (episode_options or {}).get('agents', 'p3at')
    laser = (episode_options or {}).get('laser', 'ideal')
    recorder = None if record_dir is None else _episode_bag(spec, scenario, record_dir, laser)
    try:
        result = run_episode(scenario, spec.task, spec.wanderers, spec.seed,
                             navigator_options=navigator_options, detection=detection,
                             setup=_task_setup(spec.map_key, index, spec.task, agents),
                             recorder=recorder, map_model=map_model, **extra)
    finally:
        if recorder is not None:
            recorder.close()
    row = result.as_row()
    del row['scenario']
    row.update(map=spec.map_key, number=scenario.number, family=scenario.family or '',
               repetition=spec.repetition, wall_time=round(time.perf_counter() - started, 3))
    return row


#: Keys of ``episode_options``.
EPISODE_OPTIONS = ('agents', 'pose_noise', 'navigator_class', 'laser')


def episode_keywords(episode_options):
    """
    Turn ``episode_options`` into ``run_episode`` keywords.

    Raises
    ------
    ValueError
        For an unknown key, agent model or laser profile, or a plug-in that does not load.

    """
    from sim_bridge.laser_profiles import laser_profile
    from sim_bridge.wanderers import AGENT_MODELS
    from .navigator_plugin import load_navigator_class
    options = dict(episode_options or {})
    unknown = set(options) - set(EPISODE_OPTIONS)
    if unknown:
        raise ValueError(f'unknown episode options {sorted(unknown)}; known: {EPISODE_OPTIONS}')
    keywords = {}
    agents = options.get('agents', 'p3at')
    if agents not in AGENT_MODELS:
        raise ValueError(f'unknown agent model {agents!r}; one of {sorted(AGENT_MODELS)}')
    if agents != 'p3at':
        keywords['wanderer_config'] = AGENT_MODELS[agents]
    if options.get('pose_noise'):
        keywords['pose_noise'] = tuple(options['pose_noise'])
    if options.get('navigator_class'):
        keywords['navigator_class'] = load_navigator_class(options['navigator_class'])
    laser = options.get('laser', 'ideal')
    profile = laser_profile(laser)          # an unknown name fails here
    if laser != 'ideal':
        keywords['laser'] = profile.laser
    return keywords


def _episode_bag(spec, scenario, record_dir, laser='ideal'):
    """Return an `EpisodeBagRecorder` for one episode, in ``record_dir``."""
    from .episode_bag import EpisodeBagRecorder, episode_bag_name
    return EpisodeBagRecorder(
        Path(record_dir) / episode_bag_name(spec),
        description={'scenario': scenario.name, 'map': spec.map_key, 'task': spec.task,
                     'wanderers': spec.wanderers, 'repetition': spec.repetition,
                     'seed': spec.seed, 'laser': laser})


def check_bag_folders(specs, record_dir):
    """
    Check that every episode's bag can be written into ``record_dir``, before any runs.

    The episodes are those the log does not hold. A folder of one of them without its
    ``metadata.yaml`` and with only MCAP files in it is the bag of an episode that was in
    flight when a run was killed (`is_partial_bag`): it is removed, and the episode records it
    again. Any other folder there is refused.

    Returns
    -------
    list of pathlib.Path
        The partial bag folders removed.

    Raises
    ------
    dpn_navigator.recording.bag_writer.BagPathError
        When a complete bag folder (or anything else) exists already or ``record_dir`` cannot
        be written.

    """
    import shutil
    from ..recording.bag_writer import check_bag_path
    from .episode_bag import episode_bag_name
    removed = []
    for spec in specs:
        path = Path(record_dir) / episode_bag_name(spec)
        if is_partial_bag(path):
            shutil.rmtree(path)
            removed.append(path)
        check_bag_path(path)
    return removed


def is_partial_bag(path):
    """
    Tell whether ``path`` is a bag folder cut short: MCAP files only, no ``metadata.yaml``.

    A bag writer writes ``metadata.yaml`` when it closes the bag; a kill before that leaves the
    folder with its MCAP file alone. Nothing else is taken for one (an empty folder, a folder
    holding any other file or a sub-folder is not).

    """
    path = Path(path)
    if not path.is_dir() or path.is_symlink():
        return False
    entries = list(path.iterdir())
    return bool(entries) and all(entry.is_file() and not entry.is_symlink()
                                 and entry.suffix == '.mcap' for entry in entries)


def _run_spec_star(args):
    """Run `run_spec` on a tuple of its arguments (for ``Pool.imap_unordered``)."""
    return run_spec(*args)


def default_workers():
    """Return the number of CPUs this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def run_protocol(specs, log_path, workers=None, ray_address=None, index=None, progress=True,
                 navigator_options=None, detection=True, record_dir=None, map_model='labels',
                 episode_options=None):
    """
    Run the episodes a log does not hold yet and append their rows to it.

    Parameters
    ----------
    specs : sequence of EpisodeSpec
        The protocol (`plan_episodes`).
    log_path : str or os.PathLike
        ``episodes.csv``; created when missing, resumed when present.
    workers : int, optional
        Local worker processes (default: the CPUs available); 1 runs in this process. Ignored
        with ``ray_address``.
    ray_address : str, optional
        Run on Ray instead: ``'local'`` starts a Ray instance on this machine, anything else is
        passed to ``ray.init(address=...)`` (e.g. ``'auto'`` or ``'ray://head:10001'``).
    index : str, optional
        Scenario index for map names (the built-in one by default).
    progress : bool
        Show a tqdm progress bar with the time left on stderr.
    navigator_options : dict, optional
        ``NavigatorConfig`` overrides for every episode (see ``protocol.NAVIGATORS``).
    detection : bool
        Measure the map as a detector in every episode (the detection columns).
    record_dir : str or os.PathLike, optional
        Record every episode run now (not those already in the log) as a bag in this folder.
    map_model : str
        The map every episode's navigator plans on (``protocol.MAP_MODELS``).
    episode_options : dict, optional
        As for `run_spec` (agents, pose noise, a plug-in navigator, the laser), for every
        episode.

    Returns
    -------
    RunStats

    Raises
    ------
    ValueError
        If ``workers`` is not positive, ``episode_options`` are bad or the log belongs to
        another version; a
        ``BagPathError`` if an episode's bag exists already or cannot be written.
    ImportError
        If ``ray_address`` is given and Ray is not installed.

    """
    from tqdm import tqdm
    episode_keywords(episode_options)   # bad options (a laser, an agent model) fail here
    if workers is None:
        workers = default_workers()
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f'workers must be a positive integer, got {workers!r}')
    started = time.perf_counter()
    index = None if index is None else os.fspath(index)
    with EpisodeLog(log_path) as log:
        done = log.done_keys()
        pending = [spec for spec in specs if spec.key not in done]
        skipped = len(specs) - len(pending)
        if record_dir is not None:
            record_dir = os.fspath(record_dir)
            check_bag_folders(pending, record_dir)
        simulated = spent = 0.0
        ran = 0
        with tqdm(total=len(specs), initial=skipped, unit='episode', disable=not progress,
                  dynamic_ncols=True, smoothing=0.05) as bar:
            if ray_address is not None:
                results, workers = _ray_results(pending, ray_address, index,
                                                navigator_options, detection, record_dir,
                                                map_model, episode_options)
            else:
                results = _local_results(pending, workers, index, navigator_options, detection,
                                         record_dir, map_model, episode_options)
            for row in results:
                log.append(row)
                ran += 1
                simulated += row['time']
                spent += row['wall_time']
                bar.set_postfix_str(f'{simulated / spent:.0f}x real time per worker',
                                    refresh=False)
                bar.update(1)
    return RunStats(planned=len(specs), skipped=skipped, ran=ran,
                    wall_time=time.perf_counter() - started, simulated_time=simulated,
                    episode_wall_time=spent, workers=workers)


def _local_results(pending, workers, index, navigator_options, detection, record_dir,
                   map_model, episode_options=None):
    """Yield the rows of pending episodes from local worker processes, as they finish."""
    if workers == 1 or len(pending) <= 1:
        for spec in pending:
            yield run_spec(spec, index, navigator_options, detection, record_dir, map_model,
                           episode_options)
        return
    # spawn: each worker starts clean (its own pybullet client, no forked state).
    context = multiprocessing.get_context('spawn')
    with context.Pool(min(workers, len(pending))) as pool:
        yield from pool.imap_unordered(
            _run_spec_star,
            [(spec, index, navigator_options, detection, record_dir, map_model,
              episode_options) for spec in pending])


def _ray_results(pending, address, index, navigator_options, detection, record_dir,
                 map_model, episode_options=None):
    """Start the pending episodes on Ray; return a generator of rows and Ray's CPU count."""
    import ray
    if not ray.is_initialized():
        ray.init(address=None if address == 'local' else address, include_dashboard=False,
                 log_to_driver=False)
    cpus = max(1, int(ray.cluster_resources().get('CPU', 1)))
    remote = ray.remote(num_cpus=1)(run_spec)

    def rows():
        waiting = [remote.remote(spec, index, navigator_options, detection, record_dir,
                                 map_model, episode_options)
                   for spec in pending]
        while waiting:
            finished, waiting = ray.wait(waiting, num_returns=1)
            yield ray.get(finished[0])
    return rows(), cpus
