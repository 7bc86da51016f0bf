"""`adbgen bench precision`'s machinery on tiny inputs (no timed assertions)."""

from __future__ import annotations

import importlib
import json
import math
import shutil

import figure_checks as fc
import numpy as np
import pytest

from toolchain import require_tool

from benchmarks import baseline as bench_baseline, precision as bp
from benchmarks import precision_charts, precision_curves, precision_sweep
from adbgen.analysis.loading import load_model
from benchmarks.problems import Problem
from adbgen.cli import main


def _require_gcc():
    require_tool(bool(shutil.which("gcc") or shutil.which("cc")), "a C compiler (the compiled engines need gcc)")


@pytest.mark.parametrize("n", [2, 3, 4])
def test_hand_written_baseline_equals_the_generated_rhs(n):
    """thesis Appendix A by hand = the generated rhs at random states and parameters (round-off)."""
    module = importlib.import_module(f"generated.thesis_rotating_n{n}")
    assert bench_baseline.max_difference(module, samples=100, seed=n) < 1e-13


def test_hand_written_baseline_refuses_another_layout():
    with pytest.raises(ValueError, match="hand-written baseline needs"):
        bench_baseline.check_layout(importlib.import_module("generated.two_plane_hill"))


def test_t_dec_from_samples_and_loosest_reliable():
    t = np.linspace(0.0, 20.0, 2001)
    r = 1e-3 * np.exp(-(t - 7.0))  # crosses 1e-3 downwards at t = 7
    assert precision_curves.t_dec_grid(t, r) == pytest.approx(7.0, abs=1e-9)
    assert precision_curves.t_dec_grid(t, np.full_like(t, 1.0)) is None
    assert precision_curves.t_dec_grid(t, np.zeros_like(t)) == 0.0
    rec = {"points": [{"tol": 1e-3, "reliable": False}, {"tol": 1e-4, "reliable": True},
                      {"tol": 1e-5, "reliable": False}, {"tol": 1e-6, "reliable": True}]}
    assert precision_sweep.loosest_reliable(rec)["tol"] == 1e-6  # 1e-5 fails, so 1e-4 does not count
    rec["points"][2]["reliable"] = True
    assert precision_sweep.loosest_reliable(rec)["tol"] == 1e-4


def test_errors_against_a_known_solution(tmp_path):
    """mu = delta = 0: the rotor stays at rest and each ball obeys phi'' = -beta phi', so
    phi(t) = phi(0) + phi'(0) (1 - exp(-beta t)) / beta: the reference and each pathway's error agree with it."""
    _require_gcc()
    beta, t_end = 0.5, 10.0
    pp = bp.PrecisionProblem(Problem("K", "thesis_rotating_n3", {"mu": 0.0, "delta": 0.0, "beta": beta},
                                     {"phi_1": 0.3, "phi_1_dot": 1.0, "phi_2_dot": -0.5}, t_end), 1e-2, "known")
    model = load_model(pp.problem.model)
    exact = model.state({"phi_1": 0.3 + (1 - math.exp(-beta * t_end)) / beta,
                         "phi_2": -0.5 * (1 - math.exp(-beta * t_end)) / beta,
                         "phi_1_dot": math.exp(-beta * t_end), "phi_2_dot": -0.5 * math.exp(-beta * t_end)})
    ref = bp.reference(model, pp, t_end)
    assert np.max(np.abs(ref["y_end"] - exact)) < 1e-12
    assert ref["check_difference"] < 1e-12
    cs = [c for c in precision_curves.curves(model, pp, tmp_path, engines=["cyrk-rk23"], peers=False, lambdify=False)
          if c.name in ("cyrk-rk23", "ivp:handwritten-dop853", "cvode-main")]
    assert len(cs) == 3
    for c in cs:
        pw = c.make(1e-3, t_end)
        out = pw.last = pw.run()
        c.points = [pw]
        rec = precision_sweep.curve_record(c, ref["y_end"], ref["check_difference"])
        err = rec["points"][0]["error"]
        assert err == pytest.approx(float(np.max(np.abs(out["y_end"] - exact))), rel=1e-3, abs=1e-12)
        assert 0 < err < 1e-2


@pytest.fixture(scope="module")
def quick_result():
    _require_gcc()
    return bp.bench_precision(("A",), quick=True, tols=(1e-4, 1e-7), engines=["cyrk-dop853", "cvode-bdf"],
                              peers=False, lambdify=False, t_end=20.0, percall=False)


def test_quick_run_records_curves_reference_and_targets(quick_result, tmp_path):
    r = quick_result
    for key in ("benchmark", "date", "machine", "versions", "settings", "problems", "targets", "seconds"):
        assert key in r, key
    json.dumps(r)
    a = r["problems"]["A"]
    assert a["problem"]["t_end"] == 20.0 and a["reference"]["check_difference"] < 1e-10
    names = {c["name"] for c in a["curves"]}
    assert {"cyrk-dop853", "cvode-bdf", "ivp:numba-dop853", "ivp:handwritten-dop853", "cvode-main"} <= names
    for c in a["curves"]:
        run = [q for q in c["points"] if q["status"] == "success"]
        assert run or c["skipped"], c
        if len(run) == 2:  # tighter tolerance, smaller error
            assert run[1]["tol"] < run[0]["tol"] and run[1]["error"] < run[0]["error"], c["name"]
        for q in run:
            assert q["wall_s"] == min(q["runs_s"]) and 0 < q["error"] < 1e-2
            assert q["cpu_s"] == min(q["runs_cpu_s"]) > 0
            assert "reliable" in q and q["t_dec_how"] != "not available", (c["name"], q)
    assert set(a["loosest_reliable"]) == names
    assert [t["target"] for t in r["targets"]][0].startswith("A, error 1e-8")

def test_quick_run_charts_draw_its_curves(quick_result, tmp_path, monkeypatch):
    """The work-precision chart draws each pathway's successful points (CPU time, error), tightest last;
    the reliability chart a bar of -log10 of each pathway's loosest reliable tolerance."""
    r = quick_result
    seen = fc.saved_figures(monkeypatch)
    assert precision_charts.chart(r, "A", tmp_path / "p_A.png").is_file()
    assert precision_charts.chart_reliable(r, tmp_path / "rel.png").is_file()
    ax = fc.figure(seen, "p_A.tmp.png").axes[0]
    assert_curves_drawn(ax, r)
    planted = json.loads(json.dumps(r))  # negative control: one point's error changed
    next(q for c in planted["problems"]["A"]["curves"] for q in c["points"] if q.get("error"))["error"] *= 3
    with pytest.raises(AssertionError):
        assert_curves_drawn(ax, planted)
    bars = fc.figure(seen, "rel.tmp.png").axes[0]
    drawn = {tick.get_text(): bar.get_width() for tick, bar in zip(bars.get_yticklabels(), bars.patches)}
    loosest = r["problems"]["A"]["loosest_reliable"]
    assert drawn == {k: (-math.log10(v["tol"]) if v["tol"] else 0.0) for k, v in loosest.items()}
    notes = [x.get_text() for x in bars.texts]  # each bar's tolerance, or why it has none
    assert sorted(notes) == sorted(f"{v['tol']:g}" if v["tol"] else (v.get("why") or "none") for v in loosest.values())


def assert_curves_drawn(ax, r):
    prob = r["problems"]["A"]
    drawn = 0
    for c in prob["curves"]:
        pts = sorted(((q[precision_charts.TIME], q["error"], q["tol"]) for q in c["points"]
                      if q.get(precision_charts.TIME) and q.get("error") and q["error"] <= 1.0
                      and q.get("status") == "success"), key=lambda v: -v[2])
        if not pts:
            continue
        label = f"{c['name']} (default)" if c["name"] == r["default_engine"] else c["name"]
        fc.assert_line(ax, label, [v[0] for v in pts], [v[1] for v in pts])
        drawn += 1
    assert drawn >= 2 and ax.get_xscale() == ax.get_yscale() == "log"
    fc.assert_labels(ax, "CPU time of the integration [s] (best of the repeats, log)",
                     "global error: max |y(t_end) - y_ref(t_end)| (log)")


def test_sweep_skips_a_pathway_predicted_too_slow():
    """The probe predicts the full run; over the cap, every tolerance is recorded as skipped with the reason."""
    from benchmarks.pathways import Pathway

    def make(tol, t_end):
        return Pathway(f"slow@{tol:g}", "ivp", "slow", tol, lambda: {"wall_s": t_end * 1e-3, "y_end": None,
                                                                     "status": "success"})

    c = precision_curves.Curve("slow", "ivp", "", make, False)
    precision_sweep.sweep(None, None, [c], (1e-3, 1e-4), t_end=100.0, repeats=1, max_run_s=0.05, budget_s=10.0)
    assert not c.points and [s["tol"] for s in c.skipped] == [1e-3, 1e-4]
    assert "predicted" in c.skipped[0]["reason"]
    assert c.skipped[0]["last_measured_s"] == pytest.approx(100.0 * precision_sweep.PROBE_FRACTION * 1e-3)


def test_cli_bench_precision_rejects_bad_input(tmp_path, capsys):
    out = tmp_path / "p.json"
    assert main(["bench", "precision", "--out", str(out), "--problems", "Z"]) == 2
    assert "unknown problem 'Z'" in capsys.readouterr().err
    assert main(["bench", "precision", "--out", str(out), "--max-run", "0"]) == 2
    assert not out.exists()


def test_only_percall_replaces_the_percall_part_and_keeps_the_rest(tmp_path, monkeypatch):
    """`--only-percall` swaps in a new per-call part (and its targets) and keeps the work-precision part."""
    from benchmarks import percall as bench_percall

    row = {"n": 2, "numba_rhs_loop": {"ns": 100.0}, "handwritten_rhs_loop": {"ns": 95.0},
           "lambdify_math": {"ns": 60000.0}, "numba_rhs_python": {"ns": 900.0}}
    monkeypatch.setattr(bench_percall, "bench_percall", lambda ns, quick=False, progress=None: {"rows": [row]})
    previous = {"benchmark": "precision", "problems": {"A": {"what": "kept"}},
                "targets": [{"target": "per call: old", "passed": False}, {"target": "problem A: kept", "passed": True}]}
    result = bp.rerun_percall(previous, (2,))
    assert result["problems"] == {"A": {"what": "kept"}} and result["percall"]["rows"][0]["n"] == 2
    names = [t["target"] for t in result["targets"]]
    assert "per call: old" not in names and "problem A: kept" in names
    assert any(name.startswith("per call: generated numba rhs within 1.2x") for name in names)
    assert result["percall_date"]


def test_only_percall_refuses_a_foreign_results_file(tmp_path, capsys):
    out = tmp_path / "sweep.json"
    out.write_text('{"benchmark": "sweep"}\n')
    before = out.read_bytes()
    assert main(["bench", "precision", "--only-percall", "--out", str(out)]) == 2
    assert "holds no `adbgen bench precision` result" in capsys.readouterr().err
    assert out.read_bytes() == before


def test_the_reference_is_computed_in_extended_precision_where_the_problem_allows():
    """The known problem of the test above over t = 200 (the balls' rates decay, their angles grow to ~2):
    the extended-precision reference (heyoka in long double on the hand-written equations, checked on the
    generated statements) is within 1e-15 of the closed form, its two formulations within 1e-16 of each
    other.  Negative control: a problem that asks for no extended reference (as the stiff C) keeps CyRK's
    Vern8 in double."""
    from toolchain import require_module

    require_module("heyoka", "the peers extra")
    beta, t_end = 0.5, 200.0
    pp = bp.PrecisionProblem(Problem("K", "thesis_rotating_n3", {"mu": 0.0, "delta": 0.0, "beta": beta},
                                     {"phi_1": 0.3, "phi_1_dot": 1.0, "phi_2_dot": -0.5}, t_end), 1e-2, "known")
    model = load_model(pp.problem.model)
    decay = math.exp(-beta * t_end)
    exact = model.state({"phi_1": 0.3 + (1 - decay) / beta, "phi_2": -0.5 * (1 - decay) / beta,
                         "phi_1_dot": decay, "phi_2_dot": -0.5 * decay})
    ref = bp.reference(model, pp, t_end)
    assert ref["method"].startswith("heyoka adaptive Taylor in extended precision"), ref.get("extended_fallback_because")
    assert np.max(np.abs(ref["y_end"] - exact)) < 1e-15 and ref["check_difference"] < 1e-16
    plain = bp.reference(model, bp.PrecisionProblem(pp.problem, 1e-2, "known", extended_reference=False), t_end)
    assert plain["method"].startswith("cyrk-vern8") and "double_reference_difference" not in plain


def test_auto_targets_count_a_level_above_the_defaults_curve():
    """At an error the default's loosest run already beats, its time there is its cheapest run reaching
    it (an upper bound); at an error the peer never reaches, the default is ahead by note; elsewhere the
    curves are interpolated.  A slower default fails."""
    def curve(name, pts):
        return {"name": name, "points": [{"error": e, precision_sweep.TIME: t, "status": "success"} for e, t in pts]}

    auto = curve("auto", [(3e-7, 0.002), (1e-9, 0.003), (1e-14, 0.008)])
    hand = curve("peer:heyoka-hand", [(1e-5, 0.004), (1e-8, 0.006), (1e-11, 0.012)])
    prob = {"A": {"curves": [auto, hand]}}
    out = precision_sweep.auto_targets(prob, "auto")
    rows = {round(-math.log10(r["error"])): r for r in prob["A"]["auto_vs_heyoka_hand"]}
    assert rows[6]["default_s"] == 0.002 and "cheapest run" in rows[6]["note"] and rows[6]["ratio"] > 1
    assert "ratio" in rows[9] and "peer does not reach" in rows[12]["note"]
    assert out[0]["passed"] and "not covered" not in out[0]["detail"]
    slow = curve("auto", [(3e-7, 0.02), (1e-14, 0.08)])
    assert precision_sweep.auto_targets({"A": {"curves": [slow, hand]}}, "auto")[0]["passed"] is False
