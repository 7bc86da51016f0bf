"""Suite-wide: the toolchain helper on sys.path, and every skip of the run recorded for
tests/test_no_skips.py, which runs last and fails under CI if any test was skipped."""

from __future__ import annotations

import sys
from pathlib import Path

# pytest runs with --import-mode=importlib (no test folder on sys.path): the one helper that turns a
# missing tool or package into a failure under CI lives in tests/codegen/toolchain.py
sys.path.insert(0, str(Path(__file__).parent / "codegen"))

import toolchain  # noqa: E402

FINAL_TEST = "test_no_test_was_skipped_under_ci"


def pytest_runtest_logreport(report):
    if report.skipped and not hasattr(report, "wasxfail"):
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else str(report.longrepr)
        toolchain.SKIPS_SEEN.append((report.nodeid, reason))


def pytest_collection_modifyitems(session, config, items):
    """The skip check goes last, so that it sees every other test's outcome."""
    last = [item for item in items if item.name == FINAL_TEST]
    items[:] = [item for item in items if item.name != FINAL_TEST] + last
