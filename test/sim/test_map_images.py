"""map_server maps in any image format Nav2's map_server reads: PGM, PNG, BMP, with alpha."""

import numpy as np
from numpy.testing import assert_array_equal
from PIL import Image
import pytest
from sim_bridge.map_io import load_map_yaml, read_map_image
from sim_bridge.pgm import write_pgm

YAML = 'image: {image}\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n' \
       'occupied_thresh: 0.65\nfree_thresh: 0.196\n'


def grey_map():
    """Return a 6 x 8 grey image: black walls around, white inside, a grey unknown patch."""
    image = np.full((6, 8), 254, dtype=np.uint8)
    image[0, :] = image[-1, :] = image[:, 0] = image[:, -1] = 0
    image[2:4, 3:5] = 205
    return image


def load(tmp_path, name, save):
    save(tmp_path / name)
    (tmp_path / f'{name}.yaml').write_text(YAML.format(image=name))
    return load_map_yaml(tmp_path / f'{name}.yaml')


@pytest.mark.parametrize('name, mode', [('map.png', 'L'), ('map.bmp', 'L'), ('rgb.png', 'RGB'),
                                        ('map.tif', 'L'), ('map.gif', 'L')])
def test_every_format_reads_as_the_pgm(tmp_path, name, mode):
    image = grey_map()
    reference = load(tmp_path, 'map.pgm', lambda path: write_pgm(path, image))
    other = load(tmp_path, name, lambda path: Image.fromarray(image).convert(mode).save(path))
    assert_array_equal(other.occupied, reference.occupied)
    assert_array_equal(other.free, reference.free)
    assert reference.occupied.sum() == 24 and reference.free.sum() == 20


def test_transparent_pixels_are_unknown(tmp_path):
    image = grey_map()
    rgba = np.dstack([image] * 3 + [np.full(image.shape, 255, dtype=np.uint8)])
    rgba[0, 0, 3] = 0                                    # a transparent wall pixel
    rgba[1, 1, 3] = 128                                  # a half-transparent free pixel
    loaded = load(tmp_path, 'alpha.png', lambda path: Image.fromarray(rgba, 'RGBA').save(path))
    # Row 0 of the image is the top of the map: the last row of the grids.
    assert not loaded.occupied[-1, 0] and not loaded.free[-2, 1]
    assert loaded.occupied[-1, 1] and loaded.free[-2, 2]


def test_sixteen_bit_and_bad_images(tmp_path):
    image = (grey_map().astype(np.uint16) * 257)
    Image.fromarray(image).save(tmp_path / 'deep.png')
    grey, maxval, opaque = read_map_image(tmp_path / 'deep.png')
    assert maxval == 65535 and opaque is None and grey.max() == 254 * 257
    (tmp_path / 'junk.png').write_bytes(b'not an image')
    with pytest.raises(ValueError, match='cannot read map image'):
        read_map_image(tmp_path / 'junk.png')
    with pytest.raises(ValueError, match='cannot read map image'):
        read_map_image(tmp_path / 'missing.png')
