"""The simulation benchmark's machinery on a tiny problem (no timed assertions, no peers needed)."""

from __future__ import annotations

import json
import math
import shutil

import pytest

import figure_checks as fc
from toolchain import require_tool

from adbgen.analysis.engines import DEFAULT
from benchmarks import pathways, problems, simulate as bs
from benchmarks.report import describe_targets, write
from adbgen.cli import main

TINY = problems.Problem("tiny", "thesis_rotating_n3", {}, dict(problems.PROBLEM_A.y0), t_end=20.0, rtol=1e-6, atol=1e-8)


def _require_gcc():
    require_tool(bool(shutil.which("gcc") or shutil.which("cc")), "a C compiler (the compiled engines need gcc)")


@pytest.fixture(scope="module")
def tiny_result():
    _require_gcc()
    return bs.bench_simulate(TINY, repeats=2, engines=["cyrk-dop853", "cyrk-rk45", "scipy-dop853"], peers=False,
                             sweep_tols=(1e-5, 1e-6), many_n=4, many_repeats=1, floor_target=0.002)


def test_result_has_every_part(tiny_result, tmp_path, monkeypatch):
    r = tiny_result
    for key in ("benchmark", "date", "machine", "versions", "problem", "default_engine", "settings", "reference",
                "engines", "equal_error", "peers", "default_sweep", "baselines", "floor", "symmetry", "many", "targets",
                "seconds"):
        assert key in r, key
    assert r["problem"]["t_end"] == 20.0 and r["default_engine"] == DEFAULT
    assert r["machine"]["load_average_at_start"] is not None
    assert r["default_engine_cold_build_s"] > 0
    json.dumps(r)  # JSON-ready as returned
    path = write(r, tmp_path / "simulate.json")
    assert json.loads(path.read_text())["benchmark"] == "simulate"
    seen = fc.saved_figures(monkeypatch)
    assert bs.chart(r, tmp_path / "simulate.png").is_file()
    ax = fc.figure(seen, "simulate.tmp.png").axes[0]  # (written through a temporary file)
    assert_bars_are_the_walls(ax, r)
    planted = json.loads(json.dumps(r))  # negative control: a wall time drawn that the result does not hold
    planted["engines"][0]["wall_s"] *= 2
    with pytest.raises(AssertionError):
        assert_bars_are_the_walls(ax, planted)


def assert_bars_are_the_walls(ax, r):
    """The chart draws one bar per timed engine and baseline, its width the wall time in ms, labelled with
    its key, sorted by time; the x label and the problem in the title."""
    walls = {e["key"]: e["wall_s"] for e in r["engines"] if e.get("wall_s")}
    walls.update({b["key"].split(":")[1]: b["wall_s"] for b in r.get("baselines", []) if b.get("wall_s")})
    drawn = {tick.get_text(): bar.get_width() for tick, bar in zip(ax.get_yticklabels(), ax.patches)}
    assert set(walls) <= set(drawn), (sorted(walls), sorted(drawn))
    for key, wall in walls.items():
        assert drawn[key] == pytest.approx(1e3 * wall, rel=1e-12), key
    widths = [bar.get_width() for bar in ax.patches]
    assert widths == sorted(widths) and len(widths) == len(ax.get_yticklabels())
    assert ax.get_xscale() == "log" and ax.get_xlim()[0] <= min(widths) and ax.get_xlim()[1] >= max(widths)
    fc.assert_labels(ax, "wall time of the integration [ms] (best of the repeats, log scale)")
    fc.assert_title(ax, f"Problem {r['problem']['label']}", f"t in [0, {r['problem']['t_end']:g}]")


def test_errors_against_a_converged_reference(tiny_result):
    r = tiny_result
    ref = r["reference"]
    assert ref["converged"] and 0 <= ref["check_difference"] < 1e-10
    # runs as accurate as the reference are named, not graded: every other error is 100x above its check
    graded = [e["error"] for e in r["engines"] if e.get("error") and e["name"] not in ref["below_resolution"]]
    assert ref["resolution"] == 100 * ref["check_difference"] and all(e > ref["resolution"] for e in graded)
    assert all(e["error"] <= ref["resolution"] for e in r["engines"] if e["name"] in ref["below_resolution"])
    engines = {e["key"]: e for e in r["engines"]}
    # the default engine is always measured beside the ones asked for
    assert set(engines) == {"cyrk-dop853", "cyrk-rk45", "scipy-dop853", DEFAULT}
    for e in engines.values():
        assert e["status"] == "success"
        assert 0 < e["error"] < 1e-4, e  # rtol 1e-6 over t = 20
        assert e["n_rhs"] > 0 and e["n_steps"] > 0 and len(e["runs_s"]) >= 1 and e["wall_s"] == min(e["runs_s"])
    # CyRK's DOP853 and SciPy's are the same method: the same steps
    assert engines["cyrk-dop853"]["n_steps"] == engines["scipy-dop853"]["n_steps"]
    base = {b["key"]: b for b in r["baselines"]}
    assert set(base) == {"baseline:solve_ivp-dop853", "baseline:ode-dop853"}
    assert base["baseline:solve_ivp-dop853"]["n_steps"] == engines["cyrk-dop853"]["n_steps"]
    assert all(0 < b["error"] < 1e-4 and b["n_rhs"] > 0 for b in base.values())
    # a tighter tolerance gives a smaller error on the default engine's sweep
    curve = r["equal_error"]["curves"][DEFAULT]
    assert [c["tol"] for c in curve] == [1e-5, 1e-6]
    assert curve[1]["error"] < curve[0]["error"]


def test_floor_symmetry_many_and_targets(tiny_result):
    r = tiny_result
    floor = r["floor"]
    assert floor["basis"] == "C" and floor["c_rhs_loop"]["min_ns"] > 0 and floor["numba_rhs_loop"]["min_ns"] > 0
    for key in ("cyrk-dop853", "scipy-dop853"):
        assert floor["ratio"][key] > 0 and floor["floor_s"][key] > 0
    # paired ratios for the fast Runge-Kutta engines only (not SciPy's)
    assert set(floor["paired"]) == {"cyrk-dop853", "cyrk-rk45"}
    assert all(len(v["ratios"]) == 2 and v["median"] > 0 for v in floor["paired"].values())
    # the generated rhs evaluates every ball alike; the compiled default keeps identical balls together
    assert r["symmetry"]["rhs_symmetric_fraction"]["generated numba rhs"] == 1.0
    assert r["symmetry"]["runs"]["cyrk-dop853"]["bitwise_equal"] is True
    many = r["many"]
    assert many["n_trajectories"] == 4 and set(many["threads"]) == {"1", "2"} and many["speedup"]["2"] > 0
    assert many["identical_across_threads"] and many["statuses"] == ["success"]
    assert many["control"]["speedup"]["2"] > 0 and len(many["control"]["threads"]["2"]["runs_s"]) == 1
    targets = {t["target"]: t for t in r["targets"]}
    assert len(targets) == 4
    assert targets["default engine vs JiTCODE dop853"]["passed"] is None  # peers off: not measured
    rk = targets["a Runge-Kutta engine within 1.5x of its floor"]
    assert rk["passed"] in (True, False) and rk["measured_ratio"] > 0
    assert all(line.split()[0] in ("PASS", "FAIL", "n/a") for line in describe_targets(r))


def test_time_at_error_interpolates_log_log():
    pts = [(1e-6, 1.0), (1e-8, 4.0)]
    mid = pathways.time_at_error(pts, 1e-7)
    assert mid["how"] == "interpolated" and mid["time_s"] == pytest.approx(2.0)
    out = pathways.time_at_error(pts, 1e-9)
    assert out["how"] == "extrapolated" and out["time_s"] == pytest.approx(8.0)
    # a dominated point (less accurate and slower than another) is ignored
    assert pathways.time_at_error(pts + [(1e-5, 3.0)], 1e-7)["time_s"] == pytest.approx(2.0)
    assert pathways.time_at_error([], 1e-7) is None and pathways.time_at_error([(None, 1.0)], 1e-7) is None


def test_error_and_symmetry_records():
    assert pathways.error([1.0, 2.0], [1.0, 2.5]) == pytest.approx(0.5)
    assert pathways.error([math.nan, 2.0], [1.0, 2.0]) is None
    from adbgen.analysis.loading import load_model

    model = load_model("thesis_rotating_n3")
    y = model.state({"x": 0.1285, "y": -0.0083, "phi_1": 3.0772, "phi_2": 3.0772, "phi_3": 3.0772})
    rec = problems.symmetry_record(model, y)
    assert rec["bitwise_equal"] and rec["ends_at_2minus"] and rec["angle_spread"] == 0.0
    y[model.index("phi_3")] = math.nextafter(3.0772, 4.0)
    rec = problems.symmetry_record(model, y)
    assert not rec["bitwise_equal"] and rec["ends_at_2minus"]


def test_cli_bench_simulate_wiring(tmp_path, capsys, monkeypatch):
    calls = {}

    def fake(**kw):  # the CLI's wiring only: the real run takes minutes
        calls.update(kw)
        return {"benchmark": "simulate", "seconds": 0.0, "targets": [], "problem": {}}

    monkeypatch.setattr(bs, "bench_simulate", fake)
    monkeypatch.setattr(bs, "chart", lambda result, path: path)
    out = tmp_path / "sim.json"
    assert main(["bench", "simulate", "--out", str(out), "--repeats", "2", "--engines", "cyrk-dop853",
                 "--no-peers"]) == 0
    assert calls["repeats"] == 2 and calls["engines"] == ["cyrk-dop853"] and calls["peers"] is False
    assert json.loads(out.read_text())["benchmark"] == "simulate"
    assert str(out) in capsys.readouterr().out
    assert main(["bench", "simulate", "--out", str(out), "--repeats", "0"]) == 2
    assert main(["bench", "simulate", "--out", str(out), "--engines", "no-such-engine"]) == 2
    assert "no-such-engine" in capsys.readouterr().err
