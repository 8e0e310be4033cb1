"""The episode animation: an animated GIF, one frame per snapshot, drawn like the strip."""

from dpn_navigator.benchmark.animation import save_animation
from dpn_navigator.benchmark.snapshots import Snapshot
import numpy as np
from PIL import Image
import pytest


def _snapshots(count):
    values = np.full((8, 10), -1, dtype=np.int8)
    snapshots = []
    for k in range(count):
        values = values.copy()
        values[:, :k + 2] = 0           # explored grows to the right
        values[0, :] = 100              # a wall
        values[4, k + 1] = 70           # a mobile obstacle that moves
        executed = np.array([[0.25, 2.0], [0.25 + 0.5 * k + 0.1, 2.0]])
        snapshots.append(Snapshot(
            time=float(k), values=values, planned=np.array([[0.5 * k, 2.0], [4.5, 3.5]]),
            executed=executed, wanderers=np.array([[0.5 * k + 0.5, 2.25]])))
    return snapshots


def test_one_frame_per_snapshot(tmp_path):
    path = tmp_path / 'episode.gif'
    save_animation(path, _snapshots(4), 0.5, (0.0, 0.0), goal=(4.5, 3.5), title='test',
                   fps=4.0)
    with Image.open(path) as gif:
        assert gif.format == 'GIF' and gif.n_frames == 4
        assert gif.info['duration'] == 250      # [ms] at 4 frames per second
        frames = []
        for k in range(gif.n_frames):
            gif.seek(k)
            frames.append(np.asarray(gif.convert('RGB')))
    # The map changes between frames, and a frame holds the strip's black walls and grey
    # mobile obstacles.
    assert all(not np.array_equal(a, b) for a, b in zip(frames, frames[1:]))
    colours = {tuple(c) for c in frames[-1].reshape(-1, 3)}
    assert (0, 0, 0) in colours and (0x8c, 0x8c, 0x8c) in colours


@pytest.mark.parametrize(('snapshots', 'fps', 'message'), [
    ([], 8.0, 'no snapshots to animate'),
    (_snapshots(1), 0.0, 'fps must be positive'),
    (_snapshots(1), float('nan'), 'fps must be positive'),
])
def test_bad_input_is_refused(tmp_path, snapshots, fps, message):
    with pytest.raises(ValueError, match=message):
        save_animation(tmp_path / 'a.gif', snapshots, 0.5, (0.0, 0.0), fps=fps)
    assert not (tmp_path / 'a.gif').exists()
