"""Suite-wide: the toolchain helper and the figure checks (figure_checks.py, fixture `saved_figures`) on
sys.path, and every skip of the run recorded: for
tests/test_no_skips.py, which runs last and fails under CI if any test was skipped, and (with
pytest-xdist, where that test sees only its worker's skips) for the controller, which lists them
and fails the run under CI."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

# pytest runs with --import-mode=importlib (no test folder on sys.path): the one helper that turns a
# missing tool or package into a failure under CI lives in tests/codegen/toolchain.py
sys.path.insert(0, str(Path(__file__).parent / "codegen"))
# and the figure checks every test folder shares (tests/figure_checks.py)
sys.path.append(str(Path(__file__).parent))

import figure_checks  # noqa: E402
import toolchain  # noqa: E402

FINAL_TEST = "test_no_test_was_skipped_under_ci"


@pytest.fixture
def saved_figures(monkeypatch) -> dict:
    """{file name: Figure} of each figure the test's commands save (figure_checks.saved_figures)."""
    return figure_checks.saved_figures(monkeypatch)


def pytest_runtest_logreport(report):
    if report.skipped and not hasattr(report, "wasxfail"):
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else str(report.longrepr)
        toolchain.SKIPS_SEEN.append((report.nodeid, reason))


# The files holding the suite's longest tests (--durations of the fresh-clone run of 2026-11-29: 60-180 s each),
# run first: with pytest-xdist a long test left for the end keeps one worker busy while the other idles.  Whole
# files move, so that a module's fixtures (the site build) stay shared by its tests.
LONG_FIRST = ("codegen/test_regenerate.py", "docsite/test_site.py", "benchmarks/test_engine_table.py",
              "test_derive_notebooks.py", "test_install.py", "plugins/test_toy_family_and_target.py",
              "benchmarks/test_rk_ensemble.py")


def _long_rank(item) -> int:
    path = item.nodeid.split("::", 1)[0].removeprefix("tests/")
    return LONG_FIRST.index(path) if path in LONG_FIRST else len(LONG_FIRST)


def pytest_collection_modifyitems(session, config, items):
    """The files of the longest tests first (LONG_FIRST), the rest in collection order; the skip check goes
    last, so that it sees every other test's outcome."""
    last = [item for item in items if item.name == FINAL_TEST]
    rest = sorted((item for item in items if item.name != FINAL_TEST), key=_long_rank)  # stable: order kept
    items[:] = rest + last


def _controller(config) -> bool:
    return not hasattr(config, "workerinput")


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    if _controller(config) and toolchain.SKIPS_SEEN:
        terminalreporter.section(f"{len(toolchain.SKIPS_SEEN)} skipped" + (" under CI: the run fails" if toolchain.in_ci() else ""))
        for node, reason in toolchain.SKIPS_SEEN:
            terminalreporter.line(f"{node}: {reason}")


def pytest_sessionfinish(session, exitstatus):
    """Under CI a run with a skip fails, also when the skips happened on xdist workers."""
    if _controller(session.config) and toolchain.in_ci() and toolchain.SKIPS_SEEN and exitstatus == 0:
        session.exitstatus = pytest.ExitCode.TESTS_FAILED
