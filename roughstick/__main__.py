"""``python -m roughstick``: the console script (as ``roughstick`` and ``python -m roughstick.cli``)."""

import sys

from .cli import main

sys.exit(main())
