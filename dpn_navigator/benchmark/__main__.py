"""``python -m dpn_navigator.benchmark``: the same as ``dpn-benchmark``."""

import sys

from .cli import main

sys.exit(main())
