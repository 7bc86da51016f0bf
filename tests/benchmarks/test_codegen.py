"""The code-generation benchmark runs for tiny n and returns well-formed results (never timings)."""

from __future__ import annotations

import json
import shutil

import pytest

from benchmarks import codegen as bc
from adbgen.cli import main


def test_ops_structure_and_growth():
    result = bc.bench_ops((1, 2, 3), families=("thesis_rotating",))
    rows = result["rows"]
    assert [r["n"] for r in rows] == [1, 2, 3]
    for r in rows:
        assert r["family"] == "thesis_rotating"
        assert r["rhs_ops"] > 0 and r["jac_ops"] > r["rhs_ops"] and r["rhs_statements"] > 0
        # the jac's parts add up, and it reuses the rhs' statements as its shared prefix
        assert r["jac_ops_shared"] + r["jac_ops_derivatives"] + r["jac_ops_column_solves"] == r["jac_ops"]
        assert r["jac_ops_shared"] == r["rhs_ops"]
        assert r["jac_ops_derivatives"] > 0 and r["jac_ops_column_solves"] > 0
    for key in ("rhs_ops", "jac_ops", "rhs_statements", "jac_statements", "jac_ops_derivatives"):
        values = [r[key] for r in rows]
        assert values == sorted(values) and len(set(values)) == len(values), key
    fits = result["fits"]["thesis_rotating"]
    slope = fits["rhs_ops_linear"]["coefficients"][1]
    assert slope > 0
    # the reported residual is the fit's own, recomputed here from the rows and the coefficients
    intercept, _ = fits["rhs_ops_linear"]["coefficients"]
    ns, ops = [r["n"] for r in rows], [r["rhs_ops"] for r in rows]
    residual = max(abs(y - (intercept + slope * n)) / y for n, y in zip(ns, ops))
    assert fits["rhs_ops_linear"]["max_relative_residual"] == pytest.approx(residual, abs=1e-5)
    assert len(fits["jac_ops_quadratic"]["coefficients"]) == 3


def test_polyfit_is_exact_on_a_line():
    fit = bc.polyfit([1, 2, 4, 8], [5, 7, 11, 19], 1)
    assert fit["coefficients"] == pytest.approx([3, 2])
    assert fit["max_relative_residual"] < 1e-9


def test_speed_row_structure(tmp_path):
    row = bc.bench_speed_one("thesis_rotating", 1, tmp_path, target=0.002, repeats=2)
    assert (row["family"], row["n"], row["n_states"]) == ("thesis_rotating", 1, 6)
    keys = ["numba_rhs_loop", "numba_rhs_python", "numba_jac_loop", "numba_jac_python",
            "lambdify_math", "lambdify_numpy"]
    if shutil.which("gcc") or shutil.which("cc"):
        keys += ["c_rhs_loop", "c_jac_loop"]
    for key in keys:
        timing = row[key]
        assert timing["calls"] >= 1 and len(timing["repeats_ns"]) == 2 and timing["ns"] > 0, key
    # lambdify of the closed form computes the same rhs as the generated code
    assert row["lambdify_math"]["relative_difference_to_numba"] < 1e-12
    assert row["closed_form_ops"] > row["rhs_ops"] > 0
    assert "c_rhs_loop/numba_rhs_loop" in row["ratios"] or "c_rhs_loop" not in keys
    assert all(v > 0 for v in row["ratios"].values())
    json.dumps(row)


def test_cli_bench_codegen_writes_json(tmp_path, capsys, monkeypatch):
    calls = {}

    def fake(ops_ns, speed_ns, **kw):  # the CLI's wiring only: the real run is slow
        calls["args"] = (ops_ns, speed_ns)
        return {"benchmark": "codegen", "seconds": 0.0, "ops_n": list(ops_ns)}

    monkeypatch.setattr(bc, "bench_codegen", fake)
    out = tmp_path / "codegen.json"
    assert main(["bench", "codegen", "--out", str(out), "--n", "1", "2", "32"]) == 0
    assert calls["args"] == ((1, 2, 32), (1, 2))  # timings only up to n = 16
    data = json.loads(out.read_text())
    assert data == {"benchmark": "codegen", "seconds": 0.0, "ops_n": [1, 2, 32]}
    assert str(out) in capsys.readouterr().out


def test_forms_rows_and_ratios(tmp_path):
    """Issue 10's comparison on a tiny run: both forms' rows, source sizes and first calls, and the
    loops/unrolled ratios of this run."""
    result = bc.bench_forms((2,), families=("thesis_rotating",), target=0.002, repeats=2)
    rows = {r["form"]: r for r in result["rows"]}
    assert set(rows) == {"loops", "unrolled"}
    for row in rows.values():
        assert row["source_bytes"]["numba"] > 0 and row["numba_first_call_seconds_rhs"] > 0
        assert row["numba_rhs_loop"]["ns"] > 0 and row["numba_jac_loop"]["ns"] > 0
    ratio = result["ratios_loops_over_unrolled"][0]
    assert ratio["n"] == 2 and ratio["numba_rhs_loop loops/unrolled"] > 0
    json.dumps(result)


def test_pipeline_stages_are_timed():
    from benchmarks import derive

    result = derive.bench_pipeline((1,))
    kinds = {r["kind"] for r in result["rows"]}
    assert kinds == {"thesis_rotating", "single_plane_fixed", "flexible_fixed"}  # n = 1: each family's fixed-step kinds
    for r in result["rows"]:
        assert r["form"] == "loops" and r["files"] > 0 and r["bytes"] > 0
        assert r["total_seconds"] >= r["derive_seconds"] + r["emit_seconds"]
        assert r["lowering_errors"]["rhs"] < 1e-12 and all(not c["proportionate"] for c in r["reduction_checks"])
