"""
Read and write PGM images (Netpbm graymap), the image format of map_server maps.

Both the binary (P5) and the ASCII (P2) variant are read, 8 or 16 bits deep, with ``#``
comments in the header; maps are written as 8-bit P5, as map_saver does.

"""

from pathlib import Path

import numpy as np

_WHITESPACE = b' \t\n\r\v\f'


def read_pgm(path):
    """
    Read a binary (P5) or ASCII (P2) PGM image.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.

    Returns
    -------
    image : (height, width) ndarray of uint16
        Pixel values; row 0 is the top of the image.
    maxval : int
        The largest possible value (255 for 8-bit images).

    Raises
    ------
    ValueError
        If the file cannot be read or is not a well-formed P2 or P5 PGM.

    """
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise ValueError(f'cannot read PGM image {str(path)!r}: {exc}') from exc
    magic = data[:2]
    if magic not in (b'P5', b'P2'):
        raise ValueError(
            f'{str(path)!r} is not a PGM image (starts with {magic!r}, not P5 or P2); '
            'convert it to PGM, e.g. with map_saver or `convert in.png out.pgm`')
    header, pos = _pgm_tokens(data, 2, 3, path)
    width, height, maxval = header
    if width <= 0 or height <= 0 or not 0 < maxval < 65536:
        raise ValueError(f'{str(path)!r}: bad PGM size {width} x {height} or maxval {maxval}')
    count = width * height
    if magic == b'P5':
        pos += 1  # exactly one whitespace byte ends the header
        dtype = np.dtype(np.uint8) if maxval < 256 else np.dtype('>u2')
        raw = data[pos:pos + count * dtype.itemsize]
        if len(raw) != count * dtype.itemsize:
            raise ValueError(
                f'{str(path)!r}: PGM data is truncated: {len(raw)} of '
                f'{count * dtype.itemsize} bytes')
        image = np.frombuffer(raw, dtype=dtype).astype(np.uint16)
    else:
        values, _ = _pgm_tokens(data, pos, None, path)
        if len(values) != count:
            raise ValueError(
                f'{str(path)!r}: ASCII PGM holds {len(values)} values, expected {count}')
        image = np.asarray(values, dtype=np.int64)
    if image.max(initial=0) > maxval:
        raise ValueError(f'{str(path)!r}: a pixel value exceeds maxval {maxval}')
    return image.astype(np.uint16).reshape(height, width), maxval


def _pgm_tokens(data, pos, count, path):
    """Parse ``count`` (all if None) integer tokens from ``pos``, skipping # comments."""
    tokens = []
    size = len(data)
    while count is None or len(tokens) < count:
        while pos < size and (data[pos] in _WHITESPACE or data[pos] == ord('#')):
            if data[pos] == ord('#'):
                end = data.find(b'\n', pos)
                pos = size if end < 0 else end
            pos += 1
        if pos >= size:
            if count is None:
                break
            raise ValueError(f'{str(path)!r}: PGM header is truncated')
        start = pos
        while pos < size and data[pos] not in _WHITESPACE and data[pos] != ord('#'):
            pos += 1
        token = data[start:pos]
        if not token.isdigit():
            raise ValueError(f'{str(path)!r}: bad PGM token {token[:20]!r}')
        tokens.append(int(token))
    return tokens, pos


def write_pgm(path, image, maxval=255, comment=None):
    """
    Write an 8-bit binary (P5) PGM image.

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write.
    image : (height, width) array_like of int
        Pixel values in ``[0, maxval]``; row 0 is the top of the image.
    maxval : int
        The largest possible value, at most 255.
    comment : str, optional
        One header comment line, such as map_saver's ``CREATOR: ...``.

    """
    image = np.asarray(image)
    if image.ndim != 2 or image.size == 0:
        raise ValueError(f'image must be a non-empty 2-D array, got shape {image.shape}')
    if not 0 < maxval < 256 or image.min() < 0 or image.max() > maxval:
        raise ValueError('pixel values must lie in [0, maxval] with maxval <= 255')
    height, width = image.shape
    header = 'P5\n' + (f'# {comment}\n' if comment else '') + f'{width} {height}\n{maxval}\n'
    Path(path).write_bytes(header.encode('ascii') + image.astype(np.uint8).tobytes())
