"""
The benchmark's output files written whole or not at all, and write failures told in one line.

A summary or a figure is first written next to its place under a hidden temporary name and then
renamed over it, so that a full disk, a file-size limit or a kill leaves the old file (or none),
never half of one. `os_error_line` turns any ``OSError`` into the one line ``dpn-benchmark``
prints before it exits with status 2.

"""

import os
from pathlib import Path


def write_file_atomically(path, write):
    """
    Write a file through ``write(temporary_path)``, then rename it to ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write; replaced only when ``write`` succeeded.
    write : callable(pathlib.Path)
        Writes the whole file at the path it is given (same folder and suffix as ``path``).

    Raises
    ------
    OSError
        From ``write`` or the rename; the temporary file is removed then.

    """
    path = Path(path)
    temporary = path.with_name(f'.{path.stem}.{os.getpid()}.tmp{path.suffix}')
    try:
        write(temporary)
        os.replace(temporary, path)
    except BaseException as exc:
        try:
            temporary.unlink()
        except OSError:
            pass
        if isinstance(exc, OSError) and exc.filename is None:
            raise with_filename(exc, path) from exc
        raise


def with_filename(error, path):
    """Return ``error`` as an ``OSError`` of the same kind naming ``path`` (a failed write's)."""
    return type(error)(error.errno, error.strerror or str(error), os.fspath(path))


def write_text_atomically(path, text):
    """Write ``text`` (UTF-8) to ``path`` whole or not at all (`write_file_atomically`)."""
    write_file_atomically(path, lambda temporary: temporary.write_text(text, encoding='utf-8'))


def os_error_line(error):
    """
    Describe an ``OSError`` in one line: what failed, on which file.

    Examples
    --------
    >>> import errno
    >>> os_error_line(OSError(errno.ENOSPC, 'No space left on device', 'out/summary.md'))
    "cannot write 'out/summary.md': No space left on device"

    """
    reason = error.strerror or str(error) or type(error).__name__
    if error.filename is None:
        return reason
    verb = 'read' if isinstance(error, FileNotFoundError) else 'write'
    target = os.fspath(error.filename)
    if error.filename2 is not None:
        target += f' -> {os.fspath(error.filename2)}'
    return f'cannot {verb} {target!r}: {reason}'
