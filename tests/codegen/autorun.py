"""AUTO-07p for the tests: the toolchain fixture and asserting wrappers over adbgen.analysis.auto07p
(which builds, runs and reads AUTO's files for users; one implementation of the readers)."""

from __future__ import annotations

from pathlib import Path

import pytest

from adbgen.analysis.auto07p import (AUTO_DIR, BIFURCATIONS, Point, Solution, _number as fortran_number,  # noqa: F401
                                  build_and_run, header_dir as auto_header, missing_tools, read_fort7, read_fort8,
                                  read_multipliers, unlabelled_stability_changes)
from toolchain import require_tool


@pytest.fixture(scope="module")
def auto_toolchain():
    missing = missing_tools()
    require_tool(not missing, ", ".join(missing) + " (Debian packages auto-07p gfortran)")
    return AUTO_DIR


def run_auto(files: dict[str, str], name: str, workdir: Path) -> list[Point]:
    """Build and run with AUTO's make runner, read fort.7."""
    log = build_and_run(files, name, workdir)
    # cmds.make is .IGNORE: a failed compile or run does not change make's exit status
    assert (workdir / f"{name}.exe").is_file(), f"AUTO build failed\n{log}"
    assert (workdir / "fort.7").is_file(), f"AUTO did not run\n{log}"
    assert "Unknown AUTO constant" not in log, log
    points = read_fort7(workdir / "fort.7")
    assert points, f"empty fort.7\n{log}"
    return points
