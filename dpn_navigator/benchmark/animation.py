"""
An animated GIF of an episode, frame by frame in the style of the paper's Fig. 9.

Each frame is one `snapshots.Snapshot` drawn by ``dpn_navigator.tools.figures.draw_map``, as in the
strip: explored white, steady obstacles black, mobile obstacles grey, non-explored shaded, the
planned path red, the executed path yellow, the wanderers red circles, with the simulated time
in the title. Written with matplotlib's Pillow writer (Pillow comes with matplotlib).

"""

import math


def save_animation(path, snapshots, resolution, origin, goal=None, wanderer_radius=0.36,
                   title=None, fps=8.0, width_inches=5.0, dpi=72):
    """
    Draw snapshots as the frames of an animated GIF.

    Parameters
    ----------
    path : str or os.PathLike
        The GIF to write.
    snapshots : sequence of Snapshot
        The frames, in time order; at least one.
    resolution : float
        The maps' cell side [m].
    origin : (float, float)
        Map-frame position of the maps' cell (0, 0) lower-left corner [m].
    goal : (float, float), optional
        Marked on every frame [m].
    wanderer_radius : float
        Circle radius of the wanderers [m].
    title : str, optional
        First title line of every frame; the second is the simulated time.
    fps : float
        Frames per second of the GIF, positive.
    width_inches : float
        Figure width [in]; the height follows the map's aspect ratio.
    dpi : int
        Pixels per inch: the GIF is about ``width_inches * dpi`` pixels wide.

    Raises
    ------
    ValueError
        With no snapshots, or a frame rate that is not positive and finite.

    """
    from matplotlib.animation import PillowWriter
    from ..tools import figures  # selects the Agg backend before pyplot is imported
    if not snapshots:
        raise ValueError('no snapshots to animate')
    if not (math.isfinite(fps) and fps > 0.0):
        raise ValueError(f'fps must be positive and finite, got {fps!r}')
    pyplot = figures.pyplot
    height, width = snapshots[0].values.shape
    figure, axes = pyplot.subplots(
        figsize=(width_inches, width_inches * height / width + 0.9))
    writer = PillowWriter(fps=fps)
    try:
        with writer.saving(figure, str(path), dpi):
            for snapshot in snapshots:
                axes.clear()
                label = f't = {snapshot.time:5.1f} s'
                figures.draw_map(axes, snapshot.values, resolution, origin,
                                 planned=snapshot.planned, executed=snapshot.executed,
                                 wanderers=snapshot.wanderers, wanderer_radius=wanderer_radius,
                                 goal=goal, title=f'{title}\n{label}' if title else label)
                axes.title.set_fontsize(8)
                if axes.get_legend_handles_labels()[0]:
                    axes.legend(loc='upper right', fontsize=6, framealpha=0.9)
                figure.tight_layout()
                writer.grab_frame()
    finally:
        pyplot.close(figure)
