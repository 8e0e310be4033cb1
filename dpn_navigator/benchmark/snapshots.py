"""
Snapshots of an episode's map, and the paper's Fig. 9 strip of them.

`EpisodeRecorder` is a ``recorder`` for `run_episode`: it keeps the executed path at every scan
and a `Snapshot` of the labelled map, planned path and wanderers every ``period`` simulated
seconds (and at the last scan). `save_strip_figure` draws a few of them side by side, coloured
as in the paper's Fig. 9 (see ``dpn_navigator.tools.figures``).

"""

from dataclasses import dataclass
import math

import numpy as np

from ..core import OCCUPANCY_VALUE


@dataclass(frozen=True)
class Snapshot:
    """
    The navigator's view at one moment of an episode.

    Attributes
    ----------
    time : float
        Simulated time [s].
    values : (H, W) ndarray of int8
        The map as OccupancyGrid values (-1, 0, 70, 100), row 0 at the bottom.
    planned : (N, 2) ndarray of float or None
        Planned path in the map frame [m].
    executed : (K, 2) ndarray of float
        The Husky's positions so far, one per scan [m].
    wanderers : (W, 2) ndarray of float
        Wanderer positions [m].

    """

    time: float
    values: np.ndarray
    planned: np.ndarray
    executed: np.ndarray
    wanderers: np.ndarray


class EpisodeRecorder:
    """
    Record an episode for figures: call it as ``recorder(world, navigator)`` once per scan.

    Parameters
    ----------
    period : float
        Simulated time between snapshots [s], positive.

    Attributes
    ----------
    snapshots : list of Snapshot
        One at the first scan and then every ``period``; `finish` adds the last scan's.
    executed : list of (float, float)
        The Husky's position at every scan [m].
    geometry : GridGeometry or None
        The navigator's grid, once a scan has been recorded.

    """

    def __init__(self, period=1.0):
        if not (math.isfinite(period) and period > 0.0):
            raise ValueError(f'period must be positive and finite, got {period!r}')
        self.period = period
        self.snapshots = []
        self.executed = []
        self._next_time = 0.0
        self._last = None
        self.geometry = None

    def __call__(self, world, navigator):
        """Note the Husky's position; take a snapshot when one is due."""
        x, y = world.husky_pose[:2]
        self.executed.append((float(x), float(y)))
        self._last = (world, navigator)
        self.geometry = navigator.grid.geometry
        if world.time >= self._next_time - 1e-9:
            self.snapshots.append(self._snapshot(world, navigator))
            self._next_time = world.time + self.period

    def finish(self):
        """Add a snapshot of the last scan recorded, unless it is already the last one."""
        if self._last is not None and (
                not self.snapshots or self.snapshots[-1].time < self._last[0].time):
            self.snapshots.append(self._snapshot(*self._last))

    def _snapshot(self, world, navigator):
        """Copy what a snapshot holds out of the world and the navigator."""
        planned = navigator.path_xy
        return Snapshot(
            time=float(world.time), values=OCCUPANCY_VALUE[navigator.grid.labels],
            planned=None if planned is None else np.array(planned, dtype=float),
            executed=np.array(self.executed, dtype=float),
            wanderers=np.array(world.wanderer_positions, dtype=float).reshape(-1, 2))


def pick_snapshots(snapshots, count):
    """
    Pick ``count`` snapshots evenly spread in time, always including the first and the last.

    Parameters
    ----------
    snapshots : sequence of Snapshot
        In time order, at least one.
    count : int
        How many, at least 1.

    Returns
    -------
    picked : list of Snapshot
        Without repeats, in time order; all of them when there are at most ``count``.

    """
    if not snapshots:
        raise ValueError('no snapshots to pick from')
    if count < 1:
        raise ValueError(f'count must be at least 1, got {count!r}')
    times = np.array([snapshot.time for snapshot in snapshots])
    targets = np.linspace(times[0], times[-1], count)
    chosen = sorted({int(np.argmin(np.abs(times - target))) for target in targets})
    return [snapshots[k] for k in chosen]


def save_strip_figure(path, snapshots, resolution, origin, goal=None, wanderer_radius=0.36,
                      title=None):
    """
    Draw snapshots side by side (the paper's Fig. 9, right column) into a PNG file.

    Parameters
    ----------
    path : str or os.PathLike
        The PNG to write.
    snapshots : sequence of Snapshot
        What to draw, left to right; at least one.
    resolution : float
        The maps' cell side [m].
    origin : (float, float)
        Map-frame position of the maps' cell (0, 0) lower-left corner [m].
    goal : (float, float), optional
        Marked on every panel [m].
    wanderer_radius : float
        Circle radius of the wanderers [m].
    title : str, optional
        Figure title.

    """
    from ..tools import figures  # selects the Agg backend before pyplot is imported
    pyplot = figures.pyplot
    if not snapshots:
        raise ValueError('no snapshots to draw')
    height, width = snapshots[0].values.shape
    panel = 4.0
    figure, axes = pyplot.subplots(
        1, len(snapshots), figsize=(panel * len(snapshots), panel * height / width + 1.2),
        squeeze=False)
    for ax, snapshot in zip(axes[0], snapshots):
        figures.draw_map(ax, snapshot.values, resolution, origin, planned=snapshot.planned,
                         executed=snapshot.executed, wanderers=snapshot.wanderers,
                         wanderer_radius=wanderer_radius, goal=goal,
                         title=f't = {snapshot.time:.0f} s')
    axes[0][0].legend(loc='upper right', fontsize=7, framealpha=0.9)
    if title:
        figure.suptitle(title)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    pyplot.close(figure)
