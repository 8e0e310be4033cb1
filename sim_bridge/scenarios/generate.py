"""
Generate the built-in synthetic maps: ``python -m sim_bridge.scenarios.generate [DIR]``.

``back_and_forth`` stands in for scenario 3 of the paper's benchmark set (its Fig. 9): a
25 m x 20 m rectangle closed by walls, split into five lanes (3.7 to 3.8 m wide) by four long
parallel walls that leave a 5.8 m gap alternately at the right and at the left end, so that a
robot going from the bottom lane to the top one must zig-zag through all of them. Walls are
0.2 m thick; the map has 0.1 m cells. The lanes and gaps leave a Husky (0.99 m x 0.67 m) with
a 0.6 m safety radius plenty of room, and ten Pioneer 3-ATs room to pass it.

The generated files are committed under ``sim_bridge/scenarios/``; a test checks that this
module still writes them byte for byte.

"""

import argparse
from pathlib import Path

from dpn_navigator.core import GridGeometry
import numpy as np

from sim_bridge.pgm import write_pgm

#: Map size [m] and resolution [m/cell] of back_and_forth.
BACK_AND_FORTH_SIZE = (25.0, 20.0)
BACK_AND_FORTH_RESOLUTION = 0.1
#: Wall rectangles of back_and_forth, ``(x_min, y_min, x_max, y_max)`` in the map frame [m].
BACK_AND_FORTH_WALLS = (
    (0.0, 0.0, 25.0, 0.2),     # outer walls: bottom, top, left, right
    (0.0, 19.8, 25.0, 20.0),
    (0.0, 0.0, 0.2, 20.0),
    (24.8, 0.0, 25.0, 20.0),
    (0.2, 3.9, 19.0, 4.1),     # inner walls, gap on the right
    (6.0, 7.9, 24.8, 8.1),     # gap on the left
    (0.2, 11.9, 19.0, 12.1),   # gap on the right
    (6.0, 15.9, 24.8, 16.1),   # gap on the left
)

# Pixel values as map_saver writes them.
_FREE_PIXEL = 254
_OCCUPIED_PIXEL = 0

_MAP_YAML = """\
image: {image}
mode: trinary
resolution: {resolution}
origin: [0.0, 0.0, 0.0]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.196
"""


def rasterize_walls(walls, size, resolution):
    """
    Rasterize wall rectangles into a PGM image.

    Parameters
    ----------
    walls : sequence of (float, float, float, float)
        Rectangles ``(x_min, y_min, x_max, y_max)`` in the map frame [m]; a cell is a wall
        when its centre lies inside one.
    size : (float, float)
        Map width and height [m]; the origin is ``(0, 0)``.
    resolution : float
        Cell side [m].

    Returns
    -------
    image : (rows, cols) ndarray of uint8
        254 for free and 0 for wall pixels; row 0 is the top of the map, as in a PGM.

    """
    geometry = GridGeometry(size[0], size[1], resolution)
    xs, ys = geometry.cell_to_world(*np.indices(geometry.shape))
    wall = np.zeros(geometry.shape, dtype=bool)
    for x_min, y_min, x_max, y_max in walls:
        wall |= (xs > x_min) & (xs < x_max) & (ys > y_min) & (ys < y_max)
    image = np.where(wall, _OCCUPIED_PIXEL, _FREE_PIXEL).astype(np.uint8)
    return image[::-1]


def write_back_and_forth(directory):
    """
    Write ``back_and_forth.pgm`` and ``back_and_forth.yaml`` into a directory.

    Parameters
    ----------
    directory : str or pathlib.Path
        Where to write; must exist.

    Returns
    -------
    paths : tuple of pathlib.Path
        The yaml and the image written.

    """
    directory = Path(directory)
    image = rasterize_walls(BACK_AND_FORTH_WALLS, BACK_AND_FORTH_SIZE, BACK_AND_FORTH_RESOLUTION)
    pgm = directory / 'back_and_forth.pgm'
    write_pgm(pgm, image, comment='CREATOR: sim_bridge.scenarios.generate 0.100 m/pix')
    map_yaml = directory / 'back_and_forth.yaml'
    map_yaml.write_text(_MAP_YAML.format(image=pgm.name, resolution=BACK_AND_FORTH_RESOLUTION))
    return map_yaml, pgm


def main(argv=None):
    """Write the generated maps into a directory (this package's by default)."""
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('directory', nargs='?', default=str(Path(__file__).resolve().parent),
                        help='output directory (default: %(default)s)')
    args = parser.parse_args(argv)
    write_back_and_forth(args.directory)
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
