"""External tools the code-generation tests build with (gcc, SUNDIALS, AUTO-07p, gfortran).

In CI (CI=true) a missing tool is a failure, so that a broken image cannot turn the tests into
skips; elsewhere the test is skipped with the reason.
"""

from __future__ import annotations

import os
import shutil

import pytest

# The flags for the emitted C: every target must compile cleanly with them.
STRICT_CFLAGS = ("-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic")


def which(tool: str) -> str | None:
    """Full path of `tool` on PATH, or None."""
    return shutil.which(tool)


def require_tool(ok: bool, what: str) -> None:
    """Fail (in CI) or skip (elsewhere) unless `ok`; `what` names the missing tool."""
    if ok:
        return
    if os.environ.get("CI") == "true":
        pytest.fail(f"{what} is required in CI but missing")
    pytest.skip(f"{what} not available")
