"""
Read and write ROS ``map_server`` maps: a ``map.yaml`` and its image (PGM, PNG, BMP, ...).

The yaml follows map_server (ROS 1) and nav2_map_server (ROS 2):

``image``
    The image file, relative to the yaml's directory unless absolute. PGM, binary (P5) or
    ASCII (P2), 8 or 16 bit, read here; any other format Pillow reads (PNG, BMP, JPEG, TIFF,
    GIF, ...; nav2_map_server reads them through GraphicsMagick) through `read_map_image`:
    colour converted to grey as nav2_map_server does (``GrayscaleType``: Rec. 601 luma), and
    a pixel with an alpha below full opacity is unknown (nav2_map_server's alpha mask).
``resolution``
    Side of one pixel [m/pixel]; positive.
``origin``
    ``[x, y, yaw]``: map-frame pose of the lower-left pixel's lower-left corner [m, m, rad].
    Rotated maps are not supported: yaw must be 0.
``negate``
    0 (default) when white is free and black occupied, 1 for the reverse.
``occupied_thresh``, ``free_thresh``
    Occupancy probability thresholds (defaults 0.65 and 0.196, map_saver's values);
    ``0 <= free_thresh <= occupied_thresh <= 1``.
``mode``
    ``trinary`` (default), ``scale`` or ``raw``.

A pixel of value ``v`` (maximum ``maxval``) has the occupancy probability
``p = (maxval - v) / maxval``, or ``p = v / maxval`` with ``negate``. In ``trinary`` and
``scale`` mode the cell is occupied when ``p > occupied_thresh`` and free when
``p < free_thresh``; in between it is unknown (trinary) or partly occupied (scale). In ``raw``
mode the pixel value itself is the occupancy in percent, as in nav2_map_server (``negate``
does not apply): ``p = v / 100`` for ``v <= 100``, unknown above. For the simulator only two
facts matter: **occupied** cells (``p > occupied_thresh``) become walls, and **free** cells
(``p < free_thresh``) are where robots may be placed. Unknown and partly occupied cells are
neither: not walls, and not free.

Image row 0 is the top of the map (largest y). The grids this module returns are flipped, so
that row 0 is the bottom (smallest y) and rows run along +y, as in ``nav_msgs/OccupancyGrid``
and ``dpn_navigator.core.GridGeometry``.

"""

from dataclasses import dataclass
import math
from pathlib import Path

from dpn_navigator.core import GridGeometry
import numpy as np
import yaml

from .pgm import read_pgm

#: map_saver's default thresholds, used when the yaml gives none.
DEFAULT_OCCUPIED_THRESH = 0.65
DEFAULT_FREE_THRESH = 0.196
#: The modes of map_server.
MODES = ('trinary', 'scale', 'raw')


@dataclass(frozen=True, eq=False)
class OccupancyMap:
    """
    A map loaded from a map_server yaml.

    Attributes
    ----------
    occupied : (rows, cols) ndarray of bool
        True where the cell is a wall. Row 0 is the bottom of the map (smallest y).
    free : (rows, cols) ndarray of bool
        True where the cell is known free. Same layout.
    resolution : float
        Cell side [m].
    origin : (float, float)
        Map-frame position of the lower-left corner of cell (0, 0) [m].
    yaml_path : pathlib.Path
        The yaml the map came from.

    """

    occupied: np.ndarray
    free: np.ndarray
    resolution: float
    origin: tuple
    yaml_path: Path

    @property
    def geometry(self):
        """Return the grid's `GridGeometry` (cell <-> map-frame conversion)."""
        rows, cols = self.occupied.shape
        return GridGeometry(cols * self.resolution, rows * self.resolution, self.resolution,
                            self.origin)


def classify_pixels(image, maxval, negate=0, occupied_thresh=DEFAULT_OCCUPIED_THRESH,
                    free_thresh=DEFAULT_FREE_THRESH, mode='trinary'):
    """
    Classify image pixels as occupied or free under map_server's rules.

    Parameters
    ----------
    image : (height, width) array_like of int
        Pixel values in ``[0, maxval]``.
    maxval : int
        The image's maximum value.
    negate : int or bool
        Nonzero when black means free (ignored in ``raw`` mode).
    occupied_thresh, free_thresh : float
        Thresholds on the occupancy probability.
    mode : {'trinary', 'scale', 'raw'}
        How pixel values map to occupancy (see the module docstring).

    Returns
    -------
    occupied, free : (height, width) ndarray of bool
        Wall pixels and known-free pixels, in the image's row order. Neither is set for unknown
        (and, in ``scale`` mode, partly occupied) pixels.

    """
    value = np.asarray(image, dtype=np.float64)
    if mode == 'raw':
        percent = np.round(value / maxval * 255.0)
        known = percent <= 100.0
        prob = percent / 100.0
    else:
        prob = value / maxval if negate else (maxval - value) / maxval
        known = np.ones(value.shape, dtype=bool)
    occupied = known & (prob > occupied_thresh)
    free = known & (prob < free_thresh)
    return occupied, free


def load_map_yaml(path):
    """
    Load a map_server ``map.yaml`` and its image.

    Parameters
    ----------
    path : str or pathlib.Path
        The yaml file.

    Returns
    -------
    OccupancyMap
        Walls and free cells with row 0 at the bottom, resolution and origin.

    Raises
    ------
    ValueError
        If the yaml or the image is missing or malformed, a field is missing or out of range,
        or the origin's yaw is not 0.

    """
    path = Path(path)
    try:
        doc = yaml.safe_load(path.read_text())
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as exc:
        raise ValueError(f'cannot read map yaml {str(path)!r}: {exc}') from exc
    if not isinstance(doc, dict):
        raise ValueError(f'map yaml {str(path)!r} must be a mapping with image, resolution, '
                         f'origin, ...; got {type(doc).__name__}')
    for key in ('image', 'resolution', 'origin'):
        if key not in doc:
            raise ValueError(f'map yaml {str(path)!r} has no {key!r} field')
    image_name = doc['image']
    if not isinstance(image_name, str) or not image_name:
        raise ValueError(f'map yaml {str(path)!r}: image must be a file name, got {image_name!r}')
    resolution = _number(doc, 'resolution', path)
    if resolution <= 0.0:
        raise ValueError(f'map yaml {str(path)!r}: resolution must be positive, got {resolution}')
    origin = doc['origin']
    if not isinstance(origin, list) or len(origin) != 3:
        raise ValueError(f'map yaml {str(path)!r}: origin must be [x, y, yaw], got {origin!r}')
    x0, y0, yaw = (_number({'origin': value}, 'origin', path) for value in origin)
    if yaw != 0.0:
        raise ValueError(
            f'map yaml {str(path)!r}: origin yaw is {yaw} rad; only unrotated maps (yaw 0) are '
            'supported: rotate the image and set yaw to 0')
    negate = doc.get('negate', 0)
    if negate not in (0, 1):  # True and False compare equal to 1 and 0
        raise ValueError(f'map yaml {str(path)!r}: negate must be 0 or 1, got {negate!r}')
    occupied_thresh = _number(doc, 'occupied_thresh', path, DEFAULT_OCCUPIED_THRESH)
    free_thresh = _number(doc, 'free_thresh', path, DEFAULT_FREE_THRESH)
    if not 0.0 <= free_thresh <= occupied_thresh <= 1.0:
        raise ValueError(
            f'map yaml {str(path)!r}: need 0 <= free_thresh <= occupied_thresh <= 1, got '
            f'free_thresh {free_thresh} and occupied_thresh {occupied_thresh}')
    mode = doc.get('mode', 'trinary')
    if mode not in MODES:
        raise ValueError(f'map yaml {str(path)!r}: mode must be one of {MODES}, got {mode!r}')
    image, maxval, opaque = read_map_image(path.parent / image_name)
    occupied, free = classify_pixels(image, maxval, negate, occupied_thresh, free_thresh, mode)
    if opaque is not None:
        occupied &= opaque
        free &= opaque
    return OccupancyMap(np.ascontiguousarray(occupied[::-1]), np.ascontiguousarray(free[::-1]),
                        resolution, (x0, y0), path)


def read_map_image(path):
    """
    Read a map image: PGM here, any other format through Pillow.

    Parameters
    ----------
    path : pathlib.Path
        The image file.

    Returns
    -------
    image : (H, W) ndarray of int
        Grey values, row 0 at the top.
    maxval : int
        Their maximum (255, or 65535 for a 16-bit grey image).
    opaque : (H, W) ndarray of bool, or None
        For an image with an alpha channel, the fully opaque pixels (the others are unknown);
        None without one.

    Raises
    ------
    ValueError
        When the file cannot be read or is no image Pillow knows.

    """
    path = Path(path)
    if path.suffix.lower() == '.pgm':
        image, maxval = read_pgm(path)
        return image, maxval, None
    try:
        with open(path, 'rb') as stream:
            magic = stream.read(2)
    except OSError as exc:
        raise ValueError(f'cannot read map image {str(path)!r}: {exc}') from exc
    if magic in (b'P5', b'P2'):
        image, maxval = read_pgm(path)
        return image, maxval, None
    from PIL import Image, UnidentifiedImageError
    try:
        with Image.open(path) as picture:
            picture.load()
            if picture.mode in ('I;16', 'I;16B', 'I;16L', 'I'):
                grey = np.asarray(picture, dtype=np.int64)
                return grey, 65535, None
            has_alpha = 'A' in picture.getbands() or 'transparency' in picture.info
            converted = picture.convert('LA' if has_alpha else 'L')
    except (OSError, UnidentifiedImageError) as exc:
        raise ValueError(f'cannot read map image {str(path)!r}: {exc}') from exc
    pixels = np.asarray(converted, dtype=np.int64)
    if has_alpha:
        return pixels[..., 0], 255, pixels[..., 1] == 255
    return pixels, 255, None


def _number(doc, key, path, default=None):
    """Return ``doc[key]`` as a finite float (``default`` when absent and given)."""
    value = doc.get(key, default)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or \
            not math.isfinite(value):
        raise ValueError(f'map yaml {str(path)!r}: {key} must be a finite number, got {value!r}')
    return float(value)
