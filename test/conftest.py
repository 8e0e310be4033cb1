"""
Pytest configuration shared by every test of the package.

Loads the hypothesis profile ``dpn``: no example database, so nothing is written into the source
tree; no deadline, since timings on a loaded two-core CI machine are noise; derandomized, so a
run is reproducible. Pass ``--hypothesis-profile`` to use another. What hypothesis still caches
goes under build/ (gitignored), unless HYPOTHESIS_STORAGE_DIRECTORY says otherwise.
"""

import itertools
import os
from pathlib import Path

from hypothesis import settings
import pytest

os.environ.setdefault(
    'HYPOTHESIS_STORAGE_DIRECTORY',
    str(Path(__file__).resolve().parents[1] / 'build' / 'hypothesis'))

settings.register_profile('dpn', database=None, deadline=None, derandomize=True)
settings.load_profile('dpn')


# DDS domains for tests: a block per pytest process, one domain per test that asks for one, so
# that tests never hear each other (or another run on this machine). Valid ids are 0..101.
_DOMAINS = itertools.cycle(range(1 + (os.getpid() % 10) * 10, 11 + (os.getpid() % 10) * 10))


@pytest.fixture
def ros_domain_id():
    """Return a DDS domain id of this test's own; discovery stays on localhost."""
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    return next(_DOMAINS)


@pytest.fixture
def ros_context(ros_domain_id):
    """Yield an initialised rclpy context of this test's own, shut down afterwards."""
    import rclpy
    from rclpy.context import Context
    context = Context()
    rclpy.init(context=context, domain_id=ros_domain_id)
    yield context
    rclpy.try_shutdown(context=context)
