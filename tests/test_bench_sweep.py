"""The sweep benchmark's machinery on a tiny grid (no timed assertions)."""

from __future__ import annotations

import json
import os
import shutil

import pytest

from adbgen import bench
from adbgen.bench_sweep import bench_sweep


def test_bench_sweep_tiny_grid(tmp_path):
    if not (shutil.which("gcc") or shutil.which("cc")):
        if os.environ.get("CI") == "true":
            pytest.fail("gcc is required in CI but missing")
        pytest.skip("no C compiler (the compiled engines need gcc)")
    figure = tmp_path / "basins.png"
    r = bench_sweep(workers=1, grid=["phi_1=0:2*pi*7/8:8", "phi_2=0:2*pi*7/8:8"], t_end=300.0, progress=None,
                    figure=figure, repeats=1)
    assert r["labels_identical"] and r["labels_differing"] == 0
    short, full = r["runs"]["shortcuts"], r["runs"]["full"]
    assert short["points"] == full["points"] == 64
    assert short["integrated"] == 36 and full["integrated"] == 64  # the symmetry: 8 diagonal + 28 pairs
    assert 0 < short["rhs_evaluations"] < full["rhs_evaluations"] and r["rhs_ratio"] > 1.5
    assert sum(short["labels"].values()) == 64 and short["labels"] == full["labels"]
    assert figure.is_file() and len(r["every_run"]) == 2
    path = bench.write(r, tmp_path / "sweep.json")
    assert json.loads(path.read_text())["target"].startswith("under 20 s")
