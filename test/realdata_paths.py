"""
Where the real recordings are: ``<repo>/../shared/realdata`` or ``$DPN_REALDATA_DIR``.

Tests that read them call `real_bags` (or `realdata_dir`), which skips the test with a reason
when the folder or its bags are absent: a fresh clone has no real data, and none is copied in.
"""

import os
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def realdata_dir():
    """Return the real-data folder (the env override or the repo's sibling ``shared/``)."""
    override = os.environ.get('DPN_REALDATA_DIR')
    return Path(override) if override else REPO.parent / 'shared' / 'realdata'


def real_bags():
    """Return the ROS 1 bags of the real-data folder, sorted; skip the test when there are none."""
    folder = realdata_dir()
    bags = sorted(folder.glob('*.bag')) if folder.is_dir() else []
    if not bags:
        pytest.skip(f'no real recordings in {folder} (set DPN_REALDATA_DIR to their folder)')
    return bags


def real_bag_ids():
    """
    Return the real bags' file names, for ``pytest.mark.parametrize`` (``['none']`` if absent).

    Pair with `real_bag`, which skips the ``'none'`` case with a reason.
    """
    folder = realdata_dir()
    names = sorted(p.name for p in folder.glob('*.bag')) if folder.is_dir() else []
    return names or ['none']


def real_bag(name):
    """Return the path of a real bag named by `real_bag_ids`; skip when there is none."""
    if name == 'none':
        real_bags()
    return realdata_dir() / name
