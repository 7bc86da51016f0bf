"""Fixtures of the command tests: those of the analysis tests (tests/analysis/analysis_fixtures.py) for the
commands over generated models, which request gcc explicitly (`needs_gcc`)."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parents[1] / "analysis"))

from toolchain import require_tool  # noqa: E402

from analysis_fixtures import balanced_scan, thesis  # noqa: E402,F401


@pytest.fixture
def needs_gcc():
    """The compiled engines build the generated C library with gcc."""
    require_tool(shutil.which("gcc") is not None, "gcc")
