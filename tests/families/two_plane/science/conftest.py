"""The family's science runs generated models on the compiled engines, which gcc builds."""

from __future__ import annotations

import shutil

import pytest
from toolchain import require_tool


@pytest.fixture(autouse=True)
def _needs_gcc():
    require_tool(shutil.which("gcc") is not None, "gcc")
