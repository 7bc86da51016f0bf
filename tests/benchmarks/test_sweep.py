"""The sweep benchmark's machinery on a tiny grid (no timed assertions)."""

from __future__ import annotations

import json
import os
import shutil

import pytest

from benchmarks.report import write
from benchmarks.sweep import bench_sweep


def test_bench_sweep_tiny_grid(tmp_path):
    if not (shutil.which("gcc") or shutil.which("cc")):
        if os.environ.get("CI") == "true":
            pytest.fail("gcc is required in CI but missing")
        pytest.skip("no C compiler (the compiled engines need gcc)")
    figure = tmp_path / "basins.png"
    # t_end 2000 as the benchmark's: trajectories reach the basin regions, so the shortcuts are taken
    r = bench_sweep(workers=1, grid=["phi_1=0:2*pi*5/6:6", "phi_2=0:2*pi*5/6:6"], t_end=2000.0, progress=None,
                    figure=figure, repeats=1)
    assert r["labels_identical"] and r["labels_differing"] == 0 and r["full_map_asymmetric_points"] == 0
    short, full = r["runs"]["shortcuts"], r["runs"]["full"]
    assert short["points"] == full["points"] == 36
    # the symmetry: 6 diagonal points + 15 pairs, a pair's second point only where the label is uncertain
    assert 21 <= short["integrated"] < 30 and full["integrated"] == 36
    assert 0 < short["rhs_evaluations"] < full["rhs_evaluations"] and r["rhs_ratio"] > 2.0
    assert sum(short["labels"].values()) == 36 and short["labels"] == full["labels"]
    assert set(short["timing"]["tasks_cpu_s"]) == {"regions", "integrate", "classify"}
    assert r["cpu_target_met"] in (True, False) and r["check_dt"] == 10.0 and r["stop_region"] == "lyapunov"
    assert figure.is_file() and len(r["every_run"]) == 2
    path = write(r, tmp_path / "sweep.json")
    assert json.loads(path.read_text())["target"].startswith("under 20 s")
