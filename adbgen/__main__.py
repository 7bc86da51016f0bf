"""`python -m adbgen ...`: the command line (as the `adbgen` script and `python -m adbgen.cli`)."""

import sys

from .cli import main

sys.exit(main())
