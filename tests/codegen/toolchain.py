"""External tools the code-generation tests build with (gcc, SUNDIALS, AUTO-07p, gfortran).

In CI (any truthy CI: "true", "1", "yes", ...) a missing tool or package is a failure, so that a broken
image cannot turn the tests into skips; elsewhere the test is skipped with the reason.  This is the
one helper for that: every test that needs a tool or an optional package calls `require_tool` or
`require_module` (tests/test_no_skips.py lists the skips of a run and fails under CI if any).
"""

from __future__ import annotations

import importlib
import os
import shutil

import pytest

# The flags for the emitted C: every target must compile cleanly with them (the proofs before
# writing use the same, one definition)
from adbgen.codegen.compiler import STRICT_CFLAGS  # noqa: E402,F401


def which(tool: str) -> str | None:
    """Full path of `tool` on PATH, or None."""
    return shutil.which(tool)


# skips seen in this run, (test id, reason): filled by tests/conftest.py, read by tests/test_no_skips.py
SKIPS_SEEN: list[tuple[str, str]] = []


def in_ci() -> bool:
    """CI set to anything but empty, 0, false, no or off (GitHub sets "true", others "1" or "True")."""
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no", "off")


def require_tool(ok: bool, what: str) -> None:
    """Fail (in CI) or skip (elsewhere) unless `ok`; `what` names the missing tool."""
    if ok:
        return
    if in_ci():
        pytest.fail(f"{what} is required in CI but missing")
    pytest.skip(f"{what} not available")


def require_module(name: str, what: str):
    """The imported module `name`, or fail (in CI) / skip (elsewhere) naming `what` provides it."""
    try:
        return importlib.import_module(name)
    except ImportError:
        require_tool(False, f"Python package {name} ({what})")
