"""
Pytest configuration shared by every test of the package.

Loads the hypothesis profile ``dpn``: no example database, so nothing is written into the source
tree; no deadline, since timings on a loaded two-core CI machine are noise; derandomized, so a
run is reproducible. Pass ``--hypothesis-profile`` to use another. What hypothesis still caches
goes under build/ (gitignored), unless HYPOTHESIS_STORAGE_DIRECTORY says otherwise.
"""

import os
from pathlib import Path

from hypothesis import settings

os.environ.setdefault(
    'HYPOTHESIS_STORAGE_DIRECTORY',
    str(Path(__file__).resolve().parents[1] / 'build' / 'hypothesis'))

settings.register_profile('dpn', database=None, deadline=None, derandomize=True)
settings.load_profile('dpn')
