"""The orbits benchmark's machinery, quick (no timed assertions)."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

from benchmarks.orbits import bench_newton, chart
from benchmarks.report import closing, opening, write

sys.path.insert(0, str(Path(__file__).parents[1] / "codegen"))
from toolchain import require_tool  # noqa: E402


def test_bench_orbits_newton_step(tmp_path):
    """One Newton step of the n = 3 desynchronised orbit: timed, the step small (a point 1e-6 off the orbit)."""
    require_tool(shutil.which("gcc") is not None, "gcc")
    result, started = opening("orbits")
    result["newton"] = r = bench_newton(repeats=2, say=lambda *_: None)
    # a desynchronised orbit: all three balls lapping, or two of them (see tests/analysis/test_orbits.py)
    assert r["windings"] in ({"phi_1": -1, "phi_2": -1, "phi_3": -1}, {"phi_1": 0, "phi_2": -1, "phi_3": -1})
    assert r["states"] == 10
    assert 0 < r["integration_s"] <= r["step_s"] and r["evaluations"] > 10
    assert 1e-7 < r["step_norm"] < 1e-4
    result = closing(result, started)
    path = write(result, tmp_path / "orbits.json")
    assert json.loads(path.read_text())["newton"]["augmented_states"] == 110
    assert chart(result, tmp_path / "orbits.png").is_file()
