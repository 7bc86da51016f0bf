"""`python -m adbgen.cli ...`: the command line (as the `adbgen` script)."""

import sys

from . import main

sys.exit(main())
