"""
``dpn-replay``: run dpn's labelling on a recorded bag and write the maps it makes.

::

    dpn-replay BAG --out DIR [--scan-topic TOPIC] [--pose tf|fixed] [--map-frame FRAME]
               [--params-file FILE] [--navigator dpn|paper] [--animate]

``BAG`` is a rosbag2 folder (MCAP or sqlite3), an ``.mcap`` or ``.db3`` file, or a ROS 1
``.bag`` (``recording.bag_reader``). Each scan of the scan topic (the bag's only
``LaserScan`` topic unless ``--scan-topic`` names one) is placed in the map frame
(``recording.scan_poses``: ``--pose tf``, the default, from the bag's ``/tf`` and
``/tf_static`` at the scan's stamp, map frame ``map`` or else ``odom``; ``--pose fixed``, the
laser at the origin of its own frame) and folded into a ``LabelGrid`` built with the ``dpn``
node's parameters (``ros.params_file``: the node's defaults, the params file's values, and with
``--navigator paper`` the paper's rule set of ``dpn-benchmark --navigator paper`` and
``config/dpn_paper.yaml``). Only the labelling runs: no plan, no commands. The laser pose
comes from TF or is the origin, so the params file's ``laser_x``/``_y``/``_yaw`` and
``laser_frame`` are not used. The grid's size and origin are the scans' extent (hits and laser
positions, 2 m around) unless the params file gives them (``map_width``, ``map_height``,
``origin_x``, ``origin_y``). Outputs: ``recording.replay_output``.

Errors (an unreadable bag, no scan topic or several without ``--scan-topic``, no TF with
``--pose tf``, bad parameters, an output bag that exists) print one line on stderr and exit
with status 2.

"""

import argparse
import dataclasses
from pathlib import Path
import sys
import time

from ..benchmark.protocol import NAVIGATORS
from ..core.mapping.label_grid import LabelGrid, warm_up_label_update
from ..core.mapping.map_values import warm_up_map_values
from ..core.real_laser import real_laser_switch_for, take_real_laser_settings
from ..recording.bag_reader import BagReader, BagReadError, LASER_SCAN
from ..recording.bag_writer import BagPathError, check_bag_path
from ..recording.replay_output import BAG_NAME, ReplayOutput
from ..recording.scan_poses import (grid_box, merge_extents, NoTransformsError, scan_extent,
                                    ScanPoses)
from ..recording.sensor_survey import SensorSurvey
from ..ros.dpn_params import check_grid_size, MAX_FINE_GRID_CELLS
from ..ros.params_file import dpn_parameters, known_parameters, node_values, ParamsFileError

PROG = 'dpn-replay'
#: Params-file names that fix the grid, and the ``grid_box`` keys they set.
GRID_PARAMETERS = {'map_width': 'width', 'map_height': 'height', 'origin_x': 'origin_x',
                   'origin_y': 'origin_y'}


class ReplayError(Exception):
    """A replay cannot run; the message is the one line ``dpn-replay`` prints."""


@dataclasses.dataclass
class ReplaySummary:
    """
    What a replay did.

    Attributes
    ----------
    scan_topic : str
    map_frame : str
    scans : int
        Scans on the topic.
    maps : int
        Scans placed and folded in: one map each.
    skipped : dict of str to int
        Scans not placed, by reason.
    width, height : float
        The grid's size [m].
    origin : (float, float)
        [m]
    update_ms_median : float
        Median label update time [ms].
    hints : list of str
        What the laser did that the parameters given do not cater for
        (`recording.sensor_survey.SensorSurvey.hints`).

    """

    scan_topic: str
    map_frame: str
    scans: int
    maps: int
    skipped: dict
    width: float
    height: float
    origin: tuple
    update_ms_median: float
    hints: list = dataclasses.field(default_factory=list)


def build_parser():
    """Return the argument parser of ``dpn-replay``."""
    parser = argparse.ArgumentParser(
        prog=PROG, description="Run dpn's labelling on a recorded bag: one labelled map per "
        'scan, written as a rosbag2 MCAP bag, with a CSV, a picture and an animation.')
    parser.add_argument('bag', metavar='BAG', help='rosbag2 folder (MCAP or sqlite3), .mcap '
                        'file or ROS 1 .bag')
    parser.add_argument('--out', required=True, metavar='DIR',
                        help='output folder (created if missing): replay/ (the bag), '
                        'replay.csv, replay.png, replay.gif')
    parser.add_argument('--scan-topic', metavar='TOPIC',
                        help="the LaserScan topic; default: the bag's only one")
    parser.add_argument('--pose', choices=('tf', 'fixed'), default='tf',
                        help="tf (default): map frame -> scan frame from the bag's /tf and "
                        '/tf_static at each scan stamp; fixed: the laser at the origin of its '
                        'own frame')
    parser.add_argument('--map-frame', metavar='FRAME',
                        help="with --pose tf: the map frame (default 'map', else 'odom')")
    parser.add_argument('--params-file', metavar='FILE',
                        help='ROS 2 params YAML of the dpn node (e.g. config/dpn.yaml)')
    parser.add_argument('--navigator', choices=('dpn', 'paper'), default='dpn',
                        help="dpn (default): the params as given; paper: the paper's rule set "
                        '(config/dpn_paper.yaml) over them')
    parser.add_argument('--animate', action='store_true', help='also write replay.gif')
    return parser


def choose_scan_topic(bag, asked):
    """
    Return the scan topic: ``asked`` (with or without its leading ``/``) or the only one.

    Raises
    ------
    ReplayError
        No LaserScan topic, several and none asked, or the asked one is not a LaserScan topic.

    """
    scan_topics = bag.topics_of_type(LASER_SCAN)
    if asked is not None:
        matches = [t for t in bag.topics if t.lstrip('/') == asked.lstrip('/')]
        if not matches:
            raise ReplayError(f'no topic {asked} in {bag.path} (LaserScan topics: '
                              f'{", ".join(scan_topics) or "none"})')
        if matches[0] not in scan_topics:
            raise ReplayError(f'{asked} in {bag.path} is {bag.topics[matches[0]].msg_type}, '
                              'not sensor_msgs/msg/LaserScan')
        return matches[0]
    if not scan_topics:
        raise ReplayError(f'no LaserScan topic in {bag.path} (topics: '
                          f'{", ".join(sorted(bag.topics)) or "none"})')
    if len(scan_topics) > 1:
        raise ReplayError(f'{len(scan_topics)} LaserScan topics in {bag.path} '
                          f'({", ".join(scan_topics)}): choose one with --scan-topic')
    return scan_topics[0]


def parameter_values(params_file, navigator):
    """Return the dpn node's parameter overrides: the file's, then the paper's rule set."""
    values = node_values(params_file) if params_file else {}
    unknown = sorted(set(values) - known_parameters())
    if unknown:
        print(f'{PROG}: warning: the dpn node has no parameter {", ".join(unknown)} '
              '(ignored)', file=sys.stderr)
    if navigator == 'paper':
        values.update(NAVIGATORS['paper'])
    return values


def replay(bag_path, out_dir, scan_topic=None, pose='tf', map_frame=None, params_file=None,
           navigator='dpn', animate=False):
    """
    Replay a bag into labelled maps (see the module); return a `ReplaySummary`.

    Raises
    ------
    ReplayError
        For every error ``dpn-replay`` reports with exit status 2.

    """
    out_dir = Path(out_dir)
    try:
        check_bag_path(out_dir / BAG_NAME)
        values = parameter_values(params_file, navigator)
        params, limits = dpn_parameters(values)
    except (BagPathError, ParamsFileError) as error:
        raise ReplayError(str(error)) from None
    try:
        with BagReader(bag_path) as bag:
            topic = choose_scan_topic(bag, scan_topic)
            try:
                poses = ScanPoses(pose, bag, map_frame)
            except NoTransformsError as error:
                raise ReplayError(str(error)) from None
            return _run(bag, topic, poses, out_dir, params, limits, values, navigator, animate)
    except BagReadError as error:
        raise ReplayError(str(error)) from None


def _placed_scans(bag, topic, poses, max_beams):
    """Yield ``(scan, placed)`` for every scan of ``topic`` that could be placed."""
    for scan in bag.laser_scans(topic):
        if len(scan.ranges) > max_beams:
            poses.skipped[f'more than max_beams {max_beams} beams'] += 1
            continue
        placed = poses.place(scan)
        if placed is not None:
            yield scan, placed


def _run(bag, topic, poses, out_dir, params, limits, values, navigator, animate):
    # Pass 1: where the scans are, for the grid's extent.
    extent, scans, placed_count, first_stamp = None, bag.topics[topic].count, 0, None
    for scan, placed in _placed_scans(bag, topic, poses, limits.max_beams):
        extent = merge_extents(extent, scan_extent(placed))
        placed_count += 1
        first_stamp = scan.stamp_ns if first_stamp is None else first_stamp
    if placed_count == 0:
        reasons = '; '.join(f'{n} x {why}' for why, n in poses.skipped.most_common(3))
        raise ReplayError(f'no scan of {topic} in {bag.path} could be placed'
                          f'{" (" + reasons + ")" if reasons else ""}')
    config = params.navigator
    given = {key: float(values[name]) for name, key in GRID_PARAMETERS.items() if name in values}
    width, height, origin = grid_box(extent, config.resolution, given)
    try:
        check_grid_size(width, height, config.resolution)
        if config.fine_evidence_resolution > 0.0:
            check_grid_size(width, height, config.fine_evidence_resolution, MAX_FINE_GRID_CELLS,
                            'fine_evidence_resolution')
        config = dataclasses.replace(config, width=width, height=height, origin=origin,
                                     laser_offset=(0.0, 0.0, 0.0))
    except ValueError as error:
        raise ReplayError(f'{error}; give map_width, map_height, origin_x and origin_y in a '
                          '--params-file') from None
    x_min, x_max, y_min, y_max = extent
    if given and not (origin[0] <= x_min and x_max <= origin[0] + width
                      and origin[1] <= y_min and y_max <= origin[1] + height):
        print(f'{PROG}: warning: the grid of the params file, {width:g} x {height:g} m at '
              f'({origin[0]:g}, {origin[1]:g}), does not hold the extent of the scans, x '
              f'{x_min:.1f}..{x_max:.1f}, y {y_min:.1f}..{y_max:.1f} m: what lies outside is '
              'not mapped', file=sys.stderr)
    # Pass 2: the labelling, as the node's Navigator builds its grid.
    warm_up_label_update()
    warm_up_map_values()
    grid = LabelGrid(config.width, config.height, config.resolution, config.origin,
                     config.label_rule())
    real_laser = real_laser_switch_for(config, grid)
    real_laser_due, switch_note = False, None
    poses.skipped.clear()
    update_ms = []
    survey = SensorSurvey()
    custom = {'replayed_bag': str(bag.path), 'scan_topic': topic, 'pose': poses.mode,
              'map_frame': str(poses.map_frame), 'navigator': navigator}
    output = ReplayOutput(out_dir, grid, poses.map_frame, topic, params.map_mobile_value,
                          animate, custom, with_transforms=poses.mode == 'tf')
    try:
        if poses.mode == 'tf':
            output.write_transforms(bag.transforms(), first_stamp)
        for scan, placed in _placed_scans(bag, topic, poses, limits.max_beams):
            started = time.perf_counter()
            if real_laser_due:
                # As the node's Navigator does (core.real_laser): the map starts again.
                config, taken = take_real_laser_settings(config, grid)
                switch_note = real_laser.describe(taken, (scan.stamp_ns - first_stamp) * 1e-9)
                real_laser_due = False
            try:
                grid.update(placed.pose, **placed.fields(), safety_radius=config.safety_radius,
                            stamp=scan.stamp_ns * 1e-9)
                grid.settle()
            except ValueError as error:
                poses.skipped[f'rejected by the label update: {str(error)[:60]}'] += 1
                continue
            elapsed_ms = 1e3 * (time.perf_counter() - started)
            if real_laser is not None and real_laser.switched_at is None:
                real_laser_due = real_laser.watch(placed.pose[:2], scan.ranges,
                                                  scan.range_min, scan.range_max)
            survey.add(scan.ranges, scan.range_min, scan.range_max, placed.pose[:2])
            output.add(scan, placed.pose[:2], elapsed_ms)
            update_ms.append(elapsed_ms)
        if not update_ms:
            raise ReplayError(f'no scan of {topic} in {bag.path} could be folded into the map')
        output.close(f'{Path(bag.path).name} ({navigator})')
    finally:
        output.__exit__(None, None, None)
    update_ms.sort()
    return ReplaySummary(topic, poses.map_frame, scans, output.maps, dict(poses.skipped),
                         width, height, origin, update_ms[len(update_ms) // 2],
                         ([switch_note] if switch_note else [])
                         + survey.hints(values, files=navigator != 'paper'))


def main(argv=None):
    """Run ``dpn-replay``; return its exit status (0, or 2 on an error)."""
    args = build_parser().parse_args(argv)
    try:
        summary = replay(args.bag, args.out, args.scan_topic, args.pose, args.map_frame,
                         args.params_file, args.navigator, args.animate)
    except ReplayError as error:
        print(f'{PROG}: error: {error}', file=sys.stderr)
        return 2
    skipped = sum(summary.skipped.values())
    reasons = ''.join(f'\n  skipped {n}: {why}' for why, n in sorted(summary.skipped.items()))
    print(f'{PROG}: {summary.maps} maps from {summary.scans} scans of {summary.scan_topic} '
          f'({skipped} skipped) in frame {summary.map_frame}; grid {summary.width:g} x '
          f'{summary.height:g} m at ({summary.origin[0]:g}, {summary.origin[1]:g}); median '
          f'label update {summary.update_ms_median:.2f} ms; wrote {args.out}{reasons}')
    for hint in summary.hints:
        print(f'{PROG}: note: {hint}', file=sys.stderr)
    return 0


if __name__ == '__main__':
    sys.exit(main())
