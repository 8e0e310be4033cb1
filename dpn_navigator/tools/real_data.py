"""
The labels measured on real laser recordings: ``python -m dpn_navigator.tools.real_data``.

Runs the navigator's core (the ``dpn`` node's ``NavigatorConfig`` and label grid, ``dpn`` and
``paper`` rule sets) over the recordings of a stationary laser in a folder (by default the
repository's ``../shared/realdata``; see its ``SOURCES.md``), with the laser standing at the
origin of the map frame, and measures the labels against the recordings' ground truth: the
authors' annotated leg clusters (``*_extracted.bag``) or, for a recording without annotation,
the cells hit in at least half of the scans that see them (static). Writes a Markdown table,
the definitions and one picture of the final labelled map per recording and rule set.

The definitions are in `MEASURES` (the page's text) and in the code of `measure_run`.

"""

import argparse
from dataclasses import dataclass, replace
import math
import os
from pathlib import Path
import sys

import numpy as np

from ..benchmark.protocol import NAVIGATORS
from ..core.cell_label import CellLabel, OCCUPANCY_VALUE, ScanInput
from ..core.mapping.label_grid import LabelGrid
from ..core.navigator import Navigator, NavigatorConfig
from ..core.scan_polygon import scan_points

#: The map's cell side [m] (the paper's 0.5 m).
RESOLUTION = 0.5
#: A person's radius around an annotated leg or a walker's hit [m]: half a stride (legs are
#: at most about 0.7 m apart) and about half a person's shoulder width.
PERSON_RADIUS = 0.35
#: A hit belongs to an annotated leg when it lies this close to the leg cluster's position
#: [m] (the authors' clusters: points closer than 0.13 m; legs 0.1-0.2 m wide).
LEG_HIT_DISTANCE = 0.25
#: Legs (or walkers' hits) this close together are one person [m] (a stride).
PERSON_GAP = 0.8
#: A walker seen in a recording without annotation has at least this many hits.
PERSON_MIN_HITS = 3
#: A cell is static when hit (f1) in at least this share of the scans that see it.
STATIC_SHARE = 0.5
#: The rule sets measured: ``--navigator`` overrides of ``NavigatorConfig``.
RULE_SETS = ('paper', 'dpn')
#: Readings of the driver's no-echo codes (finite ranges below ``range_min``).
READINGS = ('as recorded', 'no echo as no return')


@dataclass
class Recording:
    """
    The scans of one recording and their ground truth.

    Attributes
    ----------
    name : str
        The bag's file name without ``.bag``.
    scans : list of tuple
        ``(stamp [s], ranges (L,) float64 [m], angle_min, angle_increment, range_min,
        range_max)`` in the laser frame, in time order.
    legs : list of (K, 2) ndarray or None
        Per scan, the annotated leg clusters' positions [m] in the laser frame, or None where
        the scan has no annotation (always None without an ``_extracted`` bag).
    annotated : bool
        Whether the recording has annotations.

    """

    name: str
    scans: list
    legs: list
    annotated: bool


def _read_messages(path):
    """Yield ``(topic, message)`` of a ROS 1 or ROS 2 bag in log-time order."""
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import get_typestore, Stores
    with AnyReader([Path(path)], default_typestore=get_typestore(Stores.ROS1_NOETIC)) as reader:
        for connection, _, raw in reader.messages():
            yield connection.topic, reader.deserialize(raw, connection.msgtype)


def _stamp_key(header):
    return (int(header.stamp.sec), int(header.stamp.nanosec))


def read_recording(path):
    """
    Read a recording and its annotation (the ``<name>_extracted.bag`` beside it, if any).

    The annotation's ``PoseArray`` messages carry no stamp; each belongs to the
    ``/training_scan`` logged right after it, whose stamp is that of the recording's scan.

    Parameters
    ----------
    path : str or Path
        A ``.bag`` file with one ``LaserScan`` topic.

    Returns
    -------
    Recording

    """
    path = Path(path)
    scans = []
    keys = []
    for _, message in _read_messages(path):
        if not hasattr(message, 'ranges'):
            continue
        stamp = message.header.stamp.sec + 1e-9 * message.header.stamp.nanosec
        scans.append((stamp, np.asarray(message.ranges, dtype=np.float64),
                      float(message.angle_min), float(message.angle_increment),
                      float(message.range_min), float(message.range_max)))
        keys.append(_stamp_key(message.header))
    if not scans:
        raise ValueError(f'{path}: no LaserScan message')
    extracted = path.with_name(path.stem + '_extracted.bag')
    legs = [None] * len(scans)
    if extracted.exists():
        index = {key: k for k, key in enumerate(keys)}
        pending = None
        for topic, message in _read_messages(extracted):
            if topic.endswith('leg_cluster_positions'):
                pending = np.array([(pose.position.x, pose.position.y)
                                    for pose in message.poses], dtype=np.float64).reshape(-1, 2)
            elif hasattr(message, 'ranges') and pending is not None:
                k = index.get(_stamp_key(message.header))
                if k is not None:
                    legs[k] = pending
                pending = None
    return Recording(path.stem, scans, legs, extracted.exists())


def find_recordings(folder):
    """Return the recordings (``*.bag`` but ``*_extracted.bag``) of a folder, by name."""
    folder = Path(folder)
    return sorted(p for p in folder.glob('*.bag') if not p.stem.endswith('_extracted'))


def no_echo_as_no_return(ranges, range_min):
    """Return ``ranges`` with finite readings below ``range_min`` (no-echo codes) as ``+inf``."""
    ranges = ranges.copy()
    ranges[np.isfinite(ranges) & (ranges < range_min)] = math.inf
    return ranges


def grid_config(recording, navigator, **overrides):
    """
    Return the ``NavigatorConfig`` of a rule set on a grid around the standing laser.

    The grid covers ``range_max`` (and a cell) around the origin, where the laser stands.
    """
    reach = max(scan[5] for scan in recording.scans) + RESOLUTION
    side = 2.0 * math.ceil(reach / RESOLUTION) * RESOLUTION
    settings = dict(NAVIGATORS[navigator])
    settings.update(overrides)
    return NavigatorConfig(width=side, height=side, origin=(-side / 2.0, -side / 2.0),
                           resolution=RESOLUTION, **settings)


def run_core(recording, config):
    """
    Run the navigator's core over a recording, the laser standing at the origin.

    Returns
    -------
    labels : (S, H, W) ndarray of uint8
        The labels after each scan.
    visible : (S, H, W) ndarray of bool
        The cells each scan saw (f1 or f2 = 1).
    hit : (S, H, W) ndarray of bool
        The cells within the safety radius of a hit of each scan (f1 = 1).
    seconds : (S,) ndarray of float
        Wall-clock time of each scan's update [s].

    """
    import time
    navigator = Navigator(config)
    grid = navigator.grid
    count = len(recording.scans)
    labels = np.empty((count,) + grid.labels.shape, dtype=grid.labels.dtype)
    visible = np.zeros(labels.shape, dtype=bool)
    hit = np.zeros(labels.shape, dtype=bool)
    seconds = np.empty(count)
    for k, scan in enumerate(recording.scans):
        ranges = scan[1]
        start = time.perf_counter()
        navigator.observe((0.0, 0.0, 0.0), ranges, scan[2], scan[3], scan[4], scan[5],
                          stamp=scan[0])
        seconds[k] = time.perf_counter() - start
        labels[k] = grid.labels
        rows, cols, cell_input = grid.last_window
        visible[k, rows, cols] = cell_input != ScanInput.NONE
        hit[k, rows, cols] = cell_input == ScanInput.HIT
    return labels, visible, hit, seconds


@dataclass
class GroundTruth:
    """
    What the measures compare the labels with, per recording.

    Attributes
    ----------
    static : (H, W) ndarray of bool
        Cells hit (f1) in at least `STATIC_SHARE` of the scans that see them.
    measured : (S,) ndarray of bool
        Scans measured: the annotated ones, or all without annotation.
    near : list of (H, W) ndarray of bool
        Per scan, cells whose centre lies within ``r + PERSON_RADIUS`` of a walker.
    walker_cells : list of (H, W) ndarray of bool
        Per scan, non-static cells within ``r`` of a walker's hit.
    persons : list of list of (H, W) ndarray of bool
        Per scan and person, the cells within ``r`` of that person's hits (persons with hits).

    """

    static: np.ndarray
    measured: np.ndarray
    near: list
    walker_cells: list
    persons: list


def _cell_centres(geometry):
    x0, y0 = geometry.origin
    res = geometry.resolution
    cx = x0 + (np.arange(geometry.cols) + 0.5) * res
    cy = y0 + (np.arange(geometry.rows) + 0.5) * res
    return np.meshgrid(cx, cy)


def _within(centres, points, radius):
    """Cells whose centre lies within ``radius`` of one of ``points`` ((K, 2) [m])."""
    cx, cy = centres
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if not points.shape[0]:
        return np.zeros(cx.shape, dtype=bool)
    distance2 = ((cx[..., None] - points[:, 0]) ** 2 + (cy[..., None] - points[:, 1]) ** 2)
    return (distance2 <= radius * radius).any(axis=-1)


def _groups(points, gap):
    """Label points by single-link groups of points within ``gap`` [m] of each other."""
    count = points.shape[0]
    group = -np.ones(count, dtype=np.int64)
    current = 0
    for seed in range(count):
        if group[seed] >= 0:
            continue
        group[seed] = current
        stack = [seed]
        while stack:
            k = stack.pop()
            close = np.flatnonzero((group < 0) & (np.hypot(*(points - points[k]).T) <= gap))
            group[close] = current
            stack.extend(close.tolist())
        current += 1
    return group


def ground_truth(recording, safety_radius):
    """
    Build the ground truth of a recording (see `MEASURES`).

    The static cells come from the scans read with no echo as no return (REP 117 with the
    driver's codes decoded), on the paper's f1 and f2: the same for every rule set measured.
    """
    config = grid_config(recording, 'paper')
    grid = LabelGrid(config.width, config.height, config.resolution, config.origin)
    hits = np.zeros(grid.labels.shape, dtype=np.int64)
    seen = np.zeros(grid.labels.shape, dtype=np.int64)
    points = []
    for scan in recording.scans:
        ranges = no_echo_as_no_return(scan[1], scan[4])
        grid.update((0.0, 0.0, 0.0), ranges, scan[2], scan[3], scan[4], scan[5], safety_radius)
        rows, cols, cell_input = grid.last_window
        hits[rows, cols] += cell_input == ScanInput.HIT
        seen[rows, cols] += cell_input != ScanInput.NONE
        found = scan_points((0.0, 0.0, 0.0), ranges, scan[2], scan[3], scan[4], scan[5])
        points.append(np.column_stack((found.hits_x, found.hits_y)))
    static = (seen > 0) & (hits >= STATIC_SHARE * seen)
    centres = _cell_centres(grid.geometry)
    measured = np.array([legs is not None for legs in recording.legs]
                        if recording.annotated else [True] * len(recording.scans))
    rr, cc = grid.geometry.world_to_cell(*np.zeros((2, 0)))
    near, walker_cells, persons = [], [], []
    for k, hit_points in enumerate(points):
        if not measured[k]:
            near.append(None)
            walker_cells.append(None)
            persons.append(None)
            continue
        if recording.annotated:
            legs = recording.legs[k]
            distance = np.hypot(hit_points[:, None, 0] - legs[None, :, 0],
                                hit_points[:, None, 1] - legs[None, :, 1])
            owner = np.where(distance.min(axis=1) <= LEG_HIT_DISTANCE,
                             distance.argmin(axis=1), -1) if legs.shape[0] else \
                -np.ones(hit_points.shape[0], dtype=np.int64)
            leg_person = _groups(legs, PERSON_GAP)
            walker = owner >= 0
            person_of_hit = np.where(walker, leg_person[np.maximum(owner, 0)], -1)
            near.append(_within(centres, legs, safety_radius + PERSON_RADIUS))
        else:
            rr, cc = grid.geometry.world_to_cell(hit_points[:, 0], hit_points[:, 1])
            inside = grid.geometry.contains_cell(rr, cc)
            walker = inside.copy()
            walker[inside] = ~static[rr[inside], cc[inside]]
            person_of_hit = -np.ones(hit_points.shape[0], dtype=np.int64)
            group = _groups(hit_points[walker], PERSON_GAP)
            sizes = np.bincount(group) if group.size else np.zeros(0, dtype=np.int64)
            group = np.where(sizes[group] >= PERSON_MIN_HITS, group, -1) if group.size else group
            person_of_hit[walker] = group
            walker = person_of_hit >= 0
            near.append(_within(centres, hit_points[walker], safety_radius + PERSON_RADIUS))
        walker_cells.append(_within(centres, hit_points[walker], safety_radius) & ~static)
        persons.append([_within(centres, hit_points[person_of_hit == p], safety_radius)
                        for p in np.unique(person_of_hit[person_of_hit >= 0])])
    return GroundTruth(static, measured, near, walker_cells, persons)


@dataclass
class Counts:
    """Pooled counts of the measures over one or more recordings (see `MEASURES`)."""

    mobile_visible: int = 0
    mobile_visible_true: int = 0
    walker_cells: int = 0
    walker_cells_mobile: int = 0
    persons: int = 0
    persons_found: int = 0
    static_seen: int = 0
    static_ever_mobile: int = 0
    ghosts: int = 0
    scans: int = 0
    update_seconds: float = 0.0
    updates: int = 0

    def add(self, other):
        """Return the sum of two counts."""
        return Counts(*(getattr(self, name) + getattr(other, name)
                        for name in self.__dataclass_fields__))

    def ratios(self):
        """Return (precision, walker-cell recall, person recall, static %, ghosts / scan)."""
        def ratio(num, den):
            return num / den if den else None
        static = ratio(self.static_ever_mobile, self.static_seen)
        return (ratio(self.mobile_visible_true, self.mobile_visible),
                ratio(self.walker_cells_mobile, self.walker_cells),
                ratio(self.persons_found, self.persons),
                None if static is None else 100.0 * static,
                ratio(self.ghosts, self.scans))


def measure_run(truth, labels, visible, seconds):
    """Count the measures of one run of the core over a recording."""
    counts = Counts()
    static_seen = np.zeros(truth.static.shape, dtype=bool)
    static_mobile = np.zeros(truth.static.shape, dtype=bool)
    for k in np.flatnonzero(truth.measured):
        mobile = labels[k] == CellLabel.MOBILE_OBSTACLE
        near = truth.near[k]
        shown = mobile & visible[k]
        counts.mobile_visible += int(shown.sum())
        counts.mobile_visible_true += int((shown & near).sum())
        counts.walker_cells += int(truth.walker_cells[k].sum())
        counts.walker_cells_mobile += int((truth.walker_cells[k] & mobile).sum())
        counts.persons += len(truth.persons[k])
        counts.persons_found += sum(bool((cells & mobile).any()) for cells in truth.persons[k])
        static_seen |= truth.static & visible[k]
        static_mobile |= truth.static & shown & ~near
        counts.ghosts += int((mobile & ~truth.static & ~near).sum())
        counts.scans += 1
    counts.static_seen = int(static_seen.sum())
    counts.static_ever_mobile = int(static_mobile.sum())
    counts.update_seconds = float(seconds.sum())
    counts.updates = int(seconds.shape[0])
    return counts


def _format(value, digits=2, suffix=''):
    return '-' if value is None else f'{value:.{digits}f}{suffix}'


def draw_maps(path, panels, config, legs=None):
    """
    Draw final labelled maps side by side into a PNG file.

    Parameters
    ----------
    path : Path
    panels : list of (str, (H, W) ndarray of uint8)
        Title and labels of each map.
    config : NavigatorConfig
        The grid's resolution and origin.
    legs : (K, 2) ndarray, optional
        Every annotated leg position of the recording [m], drawn as red dots.

    """
    from matplotlib import pyplot
    from .figures import draw_map
    figure, axes = pyplot.subplots(1, len(panels), figsize=(6.0 * len(panels), 6.4))
    for ax, (title, labels) in zip(np.atleast_1d(axes), panels):
        draw_map(ax, OCCUPANCY_VALUE[labels], config.resolution, config.origin, title=title)
        if legs is not None and legs.shape[0]:
            ax.plot(legs[:, 0], legs[:, 1], '.', color='#d62728', markersize=2,
                    label='annotated legs')
        ax.plot([0.0], [0.0], '^', color='#1f77b4', markersize=8, label='laser')
        ax.legend(loc='upper right', fontsize=8, framealpha=0.9)
    figure.tight_layout()
    figure.savefig(path, dpi=80)
    pyplot.close(figure)
