"""
Figures of labelled maps, drawn like the paper's Fig. 9 (matplotlib, no display needed).

Explored cells white, steady obstacles black, mobile obstacles grey, non-explored cells shaded,
the planned path red, the executed path yellow, wanderers as red circles.

"""

import matplotlib

matplotlib.use('Agg')

from matplotlib import pyplot  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402
import numpy as np  # noqa: E402

from ..core.cell_label import (OCCUPANCY_FREE, OCCUPANCY_MOBILE_OBSTACLE,  # noqa: E402
                               OCCUPANCY_STEADY_OBSTACLE, OCCUPANCY_UNKNOWN)

#: Colour per OccupancyGrid value, in the order of ``_VALUES``.
_VALUES = (OCCUPANCY_UNKNOWN, OCCUPANCY_FREE, OCCUPANCY_MOBILE_OBSTACLE,
           OCCUPANCY_STEADY_OBSTACLE)
_COLOURS = ('#c8d3e0', '#ffffff', '#8c8c8c', '#000000')


def draw_map(axes, values, resolution, origin, planned=None, executed=None, wanderers=None,
             wanderer_radius=0.36, goal=None, title=None):
    """
    Draw a labelled map with paths on matplotlib axes.

    Parameters
    ----------
    axes : matplotlib.axes.Axes
        Where to draw.
    values : (H, W) ndarray of int8
        OccupancyGrid values (-1, 0, 70, 100), row 0 at the bottom.
    resolution : float
        Cell side [m].
    origin : (float, float)
        Map-frame position of cell (0, 0)'s lower-left corner [m].
    planned, executed : (N, 2) array_like of float, optional
        Planned (red) and executed (yellow) paths in the map frame [m].
    wanderers : (K, 2) array_like of float, optional
        Wanderer positions [m], drawn as circles of ``wanderer_radius`` [m].
    wanderer_radius : float
        [m]
    goal : (float, float), optional
        Drawn as a green star [m].
    title : str, optional
        Title of the axes.

    """
    index = np.searchsorted(np.array(_VALUES), np.asarray(values))
    height, width = index.shape
    extent = (origin[0], origin[0] + width * resolution, origin[1],
              origin[1] + height * resolution)
    axes.imshow(index, origin='lower', extent=extent, cmap=ListedColormap(_COLOURS),
                vmin=0, vmax=len(_VALUES) - 1, interpolation='nearest')
    for points, colour, width_pt, label in ((executed, '#ffd400', 2.5, 'executed path'),
                                            (planned, '#e00000', 1.5, 'planned path')):
        if points is not None and len(points) >= 2:
            points = np.asarray(points, dtype=float)
            axes.plot(points[:, 0], points[:, 1], color=colour, linewidth=width_pt, label=label)
    for x, y in np.asarray(wanderers if wanderers is not None else [], dtype=float).reshape(-1, 2):
        axes.add_patch(Circle((x, y), wanderer_radius, facecolor='#d62728', edgecolor='black',
                              linewidth=0.5, alpha=0.8))
    if goal is not None:
        axes.plot([goal[0]], [goal[1]], marker='*', markersize=12, color='#00a000',
                  markeredgecolor='black', linestyle='none', label='goal')
    axes.set_xlim(extent[0], extent[1])
    axes.set_ylim(extent[2], extent[3])
    axes.set_aspect('equal')
    axes.set_xlabel('x [m]')
    axes.set_ylabel('y [m]')
    if title:
        axes.set_title(title)


def save_map_figure(path, values, resolution, origin, **drawing):
    """Draw one labelled map (see ``draw_map``) into a PNG file at ``path``."""
    height, width = np.shape(values)
    aspect = (height / width) if width else 1.0
    figure, axes = pyplot.subplots(figsize=(8.0, max(3.0, 8.0 * aspect) + 0.8))
    draw_map(axes, values, resolution, origin, **drawing)
    if axes.get_legend_handles_labels()[0]:         # no empty legend box (a laser standing still)
        axes.legend(loc='upper right', fontsize=8, framealpha=0.9)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    pyplot.close(figure)
