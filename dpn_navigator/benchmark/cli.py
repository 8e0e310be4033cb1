"""
``dpn-benchmark``: run the paper's test protocol without ROS and report it.

Examples::

    dpn-benchmark --profile smoke --out out/smoke
    dpn-benchmark --maps 3 maze /path/to/map.yaml --tasks 0 1 --wanderers 0 5 10 --repeats 2
    dpn-benchmark --profile paper --ray-address auto --out out/paper
    dpn-benchmark --maps back_and_forth --tasks 0 --wanderers 5 --repeats 1 --record out/bags
    dpn-benchmark --profile smoke --laser hokuyo_utm30lx --out out/smoke_utm30lx
    dpn-benchmark --profile smoke --set give_way_time=15 --out out/smoke_give_way_15


Episodes are appended to ``OUT/episodes.csv`` as they finish. Running a command again into the
same OUT resumes: it skips the episodes already logged (each episode is logged once; a log that
holds one twice is refused), so a second run of the same command adds nothing; a second run
while the first still writes is refused (the log is locked). A bag folder of an episode cut
short by a kill (``--record``, no ``metadata.yaml``) is replaced when it runs again. A write
that fails (a full disk, a file-size limit, a read-only OUT) ends the run with one line on
stderr and exit status 2; the log keeps every episode finished before. At the end
``OUT/summary.md`` and ``OUT/success_rate.png`` are written from the whole log, with
``OUT/detection.png`` (the map as a detector against the wanderer count,
``detection_report``), with ``--strip`` a Fig. 9-style strip of one episode and
with ``--animate`` an animated GIF of it. ``--record DIR`` writes every episode run as a
rosbag2 MCAP bag into DIR (docs/recording.md). ``--set NAME=VALUE`` changes a setting of a
built-in navigator (an ablation; ``navigator_overrides``); the reports label such a log
``dpn [NAME=VALUE]``.

"""

import argparse
from dataclasses import dataclass
import json
import math
from pathlib import Path
import sys
import time

from .detection_report import detection_stats, save_detection_figure
from .episode_log import read_log
from .navigator_overrides import parse_overrides, run_label
from .output_files import os_error_line, write_file_atomically, write_text_atomically
from .protocol import MAP_MODELS, NAVIGATORS, plan_episodes, PROFILES, resolve_maps
from .report import save_success_figure, summary_markdown
from .runner import default_workers, run_protocol

#: ``--laser`` choices (``sim_bridge.laser_profiles``), kept here so --help needs no pybullet.
LASER_PROFILE_NAMES = ('ideal', 'sick_lms1xx', 'hokuyo_utm30lx', 'hokuyo_urg04lx', 'rplidar_a2',
                       'lds_01')


def build_parser():
    """Return the argument parser of ``dpn-benchmark``."""
    parser = argparse.ArgumentParser(
        prog='dpn-benchmark', description=__doc__.strip().splitlines()[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Options left out take the profile's value: "
               + '; '.join(f'{name}: maps {" ".join(p.maps) if p.maps else "all"}, tasks '
                           f'{" ".join(map_str(p.tasks))}, wanderers '
                           f'{" ".join(map_str(p.wanderers))}, repeats {p.repeats}'
                           for name, p in PROFILES.items()) + '.')
    parser.add_argument('--profile', choices=sorted(PROFILES), default='smoke',
                        help='preset selection (default: %(default)s)')
    parser.add_argument('--maps', nargs='+', metavar='MAP',
                        help='index numbers, names or map_server yaml paths')
    parser.add_argument('--tasks', nargs='+', type=int, metavar='K', help='task indices')
    parser.add_argument('--wanderers', nargs='+', type=int, metavar='N',
                        help='wanderer counts, 0 to 10')
    parser.add_argument('--repeats', type=int, help='repetitions of each configuration')
    parser.add_argument('--navigator', type=navigator_choice, default='dpn',
                        metavar='{' + ','.join(sorted(NAVIGATORS)) + '} or package.module:Class',
                        help='dpn: as shipped; dpn_no_sweep: dpn with the turn sweep off '
                             '(docs/safety.md); dpn_real_laser: dpn with '
                             'config/dpn_real_laser.yaml, for real lasers (docs/real_data.md); '
                             "paper: without this project's additions "
                             '(A* proximity cost, forgetting unseen obstacles when stuck, the '
                             'label rules of docs/detection.md); costmap: a Nav2-style '
                             "obstacle + inflation costmap run by Nav2 Jazzy's default "
                             "behaviour tree (1 Hz replanning, NavFn's cost of unknown space, "
                             'the recoveries); costmap-bare: the costmap without them; '
                             "oracle: the true walls and every agent's true future over 8 s, "
                             'planned on in space and time (it waits where that pays); '
                             'oracle-foresight: the agents near the robot at a constant-'
                             'velocity forecast over 2 s; oracle-bare: every agent where it '
                             "stands; the references with dpn's planner and follower "
                             '(docs/benchmark.md); package.module:Class: your own navigator, '
                             'a class implementing the protocol of '
                             'dpn_navigator.benchmark.navigator_plugin (default: %(default)s)')
    parser.add_argument('--set', action='append', default=[], metavar='NAME=VALUE',
                        dest='overrides',
                        help='change a setting of a built-in navigator, e.g. '
                             'give_way_time=15 (repeatable; the names and ranges of '
                             'docs/ros_reference.md, which the node takes as parameters): an '
                             'ablation on the same episodes; recorded in run.json, and the '
                             'reports label the log "dpn [give_way_time=15.0]"')
    parser.add_argument('--seed', type=int, default=0,
                        help='base seed of the episode seeds (default: %(default)s)')
    parser.add_argument('--out', default='benchmark_out', type=Path,
                        help='output folder; a run into it resumes episodes.csv there: the '
                             'episodes logged are skipped, never logged twice, and a second '
                             'run while one is writing is refused. A failed write ends the '
                             'run with one line and exit status 2, keeping every logged '
                             'episode (default: %(default)s)')
    parser.add_argument('--workers', type=int,
                        help=f'local worker processes (default: the CPUs, {default_workers()} '
                             'here)')
    parser.add_argument('--ray-address', metavar='ADDRESS',
                        help="run on Ray: 'local' starts an instance here, else an address "
                             "for ray.init, e.g. 'auto' (needs requirements-ray.txt)")
    parser.add_argument('--index', type=Path,
                        help='scenario index yaml (default: the one sim_bridge ships)')
    parser.add_argument('--strip', action='store_true',
                        help="also rerun the first map's first task with the most wanderers and "
                             'draw strip.png, a Fig. 9-style strip of map snapshots')
    parser.add_argument('--animate', action='store_true',
                        help='also rerun that episode (the one --strip draws) and write '
                             'episode.gif, an animation of it in the same style')
    parser.add_argument('--record', metavar='DIR', type=Path,
                        help='write every episode run (not those already in the log) as a '
                             'rosbag2 MCAP bag into DIR: what the nodes would have published '
                             '(docs/recording.md); choose the episodes with --maps, --tasks, '
                             '--wanderers and --repeats. A complete bag is never overwritten; '
                             'the bag of an episode cut short by a kill (no metadata.yaml) is '
                             'replaced when the episode runs again')
    parser.add_argument('--no-detection', action='store_true',
                        help='skip the detection measures (about 8-10 %% of episode time; see '
                             'docs/detection.md): their columns are left empty')
    parser.add_argument('--no-progress', action='store_true', help='no progress bar')
    add_world_options(parser)
    return parser


def navigator_choice(text):
    """Return a ``--navigator`` value: a built-in name or ``package.module:Class``."""
    if text in NAVIGATORS or (':' in text and all(text.partition(':')[::2])):
        return text
    raise argparse.ArgumentTypeError(
        f'invalid choice {text!r}: one of {", ".join(sorted(NAVIGATORS))}, or '
        'package.module:Class')


def add_world_options(parser):
    """Add the options of the agents, the pose noise (issue 30) and the laser to the parser."""
    from sim_bridge.wanderers import AGENT_MODELS
    parser.add_argument('--agents', choices=sorted(AGENT_MODELS), default='p3at',
                        help='the moving agents: p3at, the wandering Pioneer 3-ATs that stop '
                             'for the Husky; pedestrians, people of 0.3 m radius at 0.8-1.4 '
                             'm/s who do not stop for it but slow down or stand where they '
                             'would meet it within 1 s (a velocity obstacle); '
                             'pedestrians-ignoring, the same people blind to the Husky; mixed, '
                             'P3-ATs and pedestrians half and half (docs/benchmark.md) '
                             '(default: %(default)s)')
    parser.add_argument('--pose-noise', nargs=2, type=float, metavar=('SIGMA_XY', 'SIGMA_YAW'),
                        help='Gaussian noise on the pose the navigator is given [m, rad], per '
                             'scan (the benchmark judges the true pose)')
    parser.add_argument('--laser', default='ideal', metavar='PROFILE',
                        help="the world's laser: "
                             f'{", ".join(LASER_PROFILE_NAMES)}; ideal is the paper\'s perfect '
                             'laser, the others are modelled on data sheets, with noise, lost '
                             'returns and mixed pixels (docs/simulator.md) (default: '
                             '%(default)s)')


def run_settings(args):
    """
    Return what must be the same for every episode of one log, for ``run.json``.

    The navigator; its setting overrides (``--set``), the agent model, the pose noise and the
    laser only when not the defaults, so that the ``run.json`` of a default run reads as
    before.
    """
    settings = {'navigator': args.navigator}
    overrides = navigator_settings(args)
    if overrides:
        settings['settings'] = overrides
    if args.agents != 'p3at':
        settings['agents'] = args.agents
    if args.pose_noise:
        settings['pose_noise'] = list(args.pose_noise)
    if args.laser != 'ideal':
        settings['laser'] = args.laser
    return settings


def episode_options(args):
    """
    Return the ``episode_options`` of ``run_protocol`` the arguments ask for (None: defaults).

    Raises
    ------
    ValueError
        For negative pose noise, an unknown laser, a plug-in navigator that does not load, or
        one with ``--record``.

    """
    from .navigator_plugin import load_navigator_class
    options = {}
    if args.agents != 'p3at':
        options['agents'] = args.agents
    if args.pose_noise:
        if min(args.pose_noise) < 0.0 or not all(map(math.isfinite, args.pose_noise)):
            raise ValueError(f'--pose-noise must be finite and >= 0, got {args.pose_noise}')
        options['pose_noise'] = tuple(args.pose_noise)
    if args.laser not in LASER_PROFILE_NAMES:
        raise ValueError(f'unknown --laser {args.laser!r}: choose one of '
                         f'{", ".join(LASER_PROFILE_NAMES)}')
    if args.laser != 'ideal':
        options['laser'] = args.laser
    if args.navigator not in NAVIGATORS:
        if getattr(args, 'record', None):
            raise ValueError('--record needs a built-in navigator (a bag holds its map)')
        load_navigator_class(args.navigator)               # fail here, not in a worker
        options['navigator_class'] = args.navigator
    return options or None


def navigator_settings(args):
    """
    Return the ``--set`` overrides of the navigator's settings, a dict (empty: none).

    Raises
    ------
    ValueError
        For a bad pair (`parse_overrides`), or overrides with a plug-in navigator.

    """
    if not args.overrides:
        return {}
    if args.navigator not in NAVIGATORS:
        raise ValueError('--set needs a built-in navigator; a plug-in takes its own settings')
    return parse_overrides(args.overrides, NAVIGATORS[args.navigator])


def navigator_options(args):
    """Return the ``NavigatorConfig`` overrides of a built-in navigator with ``--set``'s."""
    return {**NAVIGATORS.get(args.navigator, {}), **navigator_settings(args)}


def map_str(values):
    """Return the values as strings (for help texts)."""
    return [str(value) for value in values]


def main(argv=None):
    """Run ``dpn-benchmark``; return the exit status (2 with one line on stderr for an error)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return run_benchmark(parser, args)
    except OSError as exc:
        parser.exit(2, f'dpn-benchmark: error: {os_error_line(exc)} (the episodes finished '
                       f'are in {args.out / "episodes.csv"}; run the command again to '
                       'resume)\n')


def run_benchmark(parser, args):
    """Run the episodes and write the reports of ``args``; return the exit status."""
    from sim_bridge.scenario import load_index
    if args.laser not in LASER_PROFILE_NAMES:        # before the output folder is made
        parser.error(f'unknown --laser {args.laser!r}: choose one of '
                     f'{", ".join(LASER_PROFILE_NAMES)}')
    profile = PROFILES[args.profile]
    try:
        entries = load_index(args.index)
        map_keys = resolve_maps(args.maps if args.maps else profile.maps, entries)
        specs = plan_episodes(map_keys, args.tasks or profile.tasks,
                              args.wanderers if args.wanderers is not None else
                              profile.wanderers, args.repeats or profile.repeats, args.seed)
        navigator_settings(args)                        # before the output folder is made
        args.out.mkdir(parents=True, exist_ok=True)
        options = episode_options(args)
        check_run_settings(args.out / 'run.json', run_settings(args))
        log_path = args.out / 'episodes.csv'
        print(f'dpn-benchmark: {len(specs)} episodes ({len(map_keys)} maps) into {log_path}',
              flush=True)
        stats = run_protocol(specs, log_path, workers=args.workers,
                             ray_address=args.ray_address, index=args.index,
                             progress=not args.no_progress,
                             navigator_options=navigator_options(args),
                             detection=not args.no_detection, record_dir=args.record,
                             map_model=MAP_MODELS.get(args.navigator, 'labels'),
                             episode_options=options)
    except ValueError as exc:
        parser.exit(2, f'dpn-benchmark: error: {exc}\n')
    except KeyboardInterrupt:
        print('dpn-benchmark: interrupted; finished episodes are in the log, run the same '
              'command again to resume', file=sys.stderr)
        return 130
    print(f'ran {stats.ran} episodes ({stats.skipped} already logged) in '
          f'{stats.wall_time:.1f} s on {stats.workers} workers: '
          f'{stats.simulated_time:.0f} s simulated, {stats.speed_per_core:.1f}x real time per '
          f'worker, {stats.episodes_per_hour:.0f} episodes per hour')
    rows = read_log(log_path)
    label = run_label(run_settings(args))
    title = f'dpn benchmark, {label} navigator'
    if args.laser != 'ideal':
        title += f', {args.laser} laser'
    summary = summary_markdown(rows, title=title, navigator=args.navigator)
    write_text_atomically(args.out / 'summary.md', summary)
    if rows:
        write_file_atomically(args.out / 'success_rate.png', lambda path: save_success_figure(
            path, rows, title=f'Success rate per map, {label} navigator'))
    print(f'wrote {args.out / "summary.md"} and {args.out / "success_rate.png"}')
    if detection_stats(rows) is not None:
        write_file_atomically(args.out / 'detection.png', lambda path: save_detection_figure(
            path, {label: rows},
            title=f'Detection against wanderer count, {label} navigator'))
        print(f'wrote {args.out / "detection.png"}')
    if (args.strip or args.animate) and specs and args.navigator in NAVIGATORS:
        showcase = rerun_showcase(specs, args.index, navigator_options=navigator_options(args),
                                  map_model=MAP_MODELS[args.navigator],
                                  episode_options=episode_options(args))
        if args.strip:
            write_file_atomically(args.out / 'strip.png',
                                  lambda path: write_strip(path, showcase))
            print(f'wrote {args.out / "strip.png"}')
        if args.animate:
            write_file_atomically(args.out / 'episode.gif',
                                  lambda path: write_animation(path, showcase))
            print(f'wrote {args.out / "episode.gif"}')
    return 0


def check_run_settings(path, settings):
    """
    Record a run's settings next to its log, or check them against the recorded ones.

    Parameters
    ----------
    path : pathlib.Path
        ``run.json`` in the output folder.
    settings : dict
        What must be the same for every episode of one log (the navigator variant).

    Raises
    ------
    ValueError
        If the folder's log was written with other settings.

    """
    if path.is_file():
        try:
            recorded = json.loads(path.read_text())
        except ValueError as exc:
            raise ValueError(f'{path} is not valid JSON ({exc}); remove it or use another '
                             '--out') from exc
        if recorded != settings:
            raise ValueError(f'{path.parent} holds a run with {recorded}, not {settings}: '
                             'use another --out')
    else:
        write_text_atomically(path, json.dumps(settings, sort_keys=True) + '\n')


@dataclass(frozen=True)
class Showcase:
    """
    One episode rerun with an `EpisodeRecorder`, for the strip and the animation.

    Attributes
    ----------
    spec : EpisodeSpec
        The episode.
    scenario : sim_bridge.scenario.Scenario
        Its map and tasks.
    result : EpisodeResult
        What it measured.
    recorder : EpisodeRecorder
        Its snapshots, finished.
    wall_time : float
        Wall-clock time of the rerun [s].

    """

    spec: object
    scenario: object
    result: object
    recorder: object
    wall_time: float

    @property
    def title(self):
        """Return the figure title: the episode and its outcome."""
        spec, result = self.spec, self.result
        outcome = 'success' if result.success else result.failure
        return (f'{self.scenario.name}, task {spec.task}, {spec.wanderers} wanderers, seed '
                f'{spec.seed}: {outcome} at t = {result.time:.0f} s')


def rerun_showcase(specs, index=None, navigator_options=None, period=1.0, map_model='labels',
                   episode_options=None):
    """
    Rerun one episode of a protocol with an `EpisodeRecorder`.

    The episode is the first spec's map and task with the largest wanderer count of ``specs``,
    repetition 0.

    Parameters
    ----------
    specs : sequence of EpisodeSpec
        The protocol; at least one.
    index : str or os.PathLike, optional
        The scenario index.
    navigator_options : dict, optional
        ``NavigatorConfig`` overrides (see ``protocol.NAVIGATORS``).
    map_model : str
        The map the navigator plans on (``protocol.MAP_MODELS``).
    period : float
        Simulated time between snapshots [s].
    episode_options : dict, optional
        As for ``run_protocol`` (the agents, the pose noise, the laser).

    Returns
    -------
    Showcase

    """
    from sim_bridge.scenario import load_scenario
    from .episode import run_episode
    from .runner import episode_keywords
    from .snapshots import EpisodeRecorder
    first = specs[0]
    spec = max((s for s in specs if (s.map_key, s.task, s.repetition) ==
                (first.map_key, first.task, 0)), key=lambda s: s.wanderers)
    scenario = load_scenario(spec.map_key, index=index)
    recorder = EpisodeRecorder(period=period)
    started = time.perf_counter()
    result = run_episode(scenario, spec.task, spec.wanderers, spec.seed, recorder=recorder,
                         navigator_options=navigator_options, map_model=map_model,
                         **episode_keywords(episode_options))
    recorder.finish()
    return Showcase(spec, scenario, result, recorder, time.perf_counter() - started)


def write_strip(path, showcase, panels=4):
    """
    Draw the Fig. 9-style strip of a rerun episode into a PNG.

    Parameters
    ----------
    path : str or os.PathLike
        The PNG to write.
    showcase : Showcase
        The episode (`rerun_showcase`).
    panels : int
        Snapshots in the strip.

    """
    from .snapshots import pick_snapshots, save_strip_figure
    recorder = showcase.recorder
    save_strip_figure(
        path, pick_snapshots(recorder.snapshots, panels), recorder.geometry.resolution,
        recorder.geometry.origin, goal=showcase.scenario.tasks[showcase.spec.task].goal,
        title=f'{showcase.title} ({showcase.wall_time:.0f} s wall)')


def write_animation(path, showcase, fps=8.0):
    """
    Write the animated GIF of a rerun episode: one frame per snapshot.

    Parameters
    ----------
    path : str or os.PathLike
        The GIF to write.
    showcase : Showcase
        The episode (`rerun_showcase`).
    fps : float
        Frames per second: with a snapshot every simulated second, ``fps`` times real time.

    """
    from .animation import save_animation
    recorder = showcase.recorder
    save_animation(path, recorder.snapshots, recorder.geometry.resolution,
                   recorder.geometry.origin,
                   goal=showcase.scenario.tasks[showcase.spec.task].goal,
                   title=showcase.title, fps=fps)
