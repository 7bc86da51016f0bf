"""Fixtures of the analysis tests: the committed generated models, a private engine cache."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pytest

# the one helper that turns a missing tool into a failure under CI (tests/codegen/toolchain.py)
sys.path.insert(0, str(Path(__file__).parents[1] / "codegen"))

from toolchain import require_tool  # noqa: E402


@pytest.fixture(autouse=True)
def _needs_gcc():
    """The compiled engines build the generated C library with gcc."""
    require_tool(shutil.which("gcc") is not None, "gcc")


@pytest.fixture(scope="session")
def thesis():
    from adbgen.analysis.loading import load_model

    return {n: load_model(f"thesis_rotating_n{n}") for n in (2, 3, 4)}
