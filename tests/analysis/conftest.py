"""Fixtures of the analysis tests (analysis_fixtures.py): gcc for the compiled engines, the committed
generated models, and the scans of the balanced state along Omega at the parameters of thesis ch. 4."""

from __future__ import annotations

import sys
from pathlib import Path

# the one helper that turns a missing tool into a failure under CI (tests/codegen/toolchain.py), and
# this folder's own helpers (analysis_helpers.py): pytest runs with --import-mode=importlib
sys.path.insert(0, str(Path(__file__).parents[1] / "codegen"))
sys.path.insert(0, str(Path(__file__).parent))

# the fixtures the command tests (tests/cli) share
from analysis_fixtures import _needs_gcc, balanced_scan, thesis  # noqa: E402,F401
