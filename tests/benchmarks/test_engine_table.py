"""`adbgen bench auto` (the auto engine's table) and the hand-written heyoka peer of the benchmarks."""

from __future__ import annotations

import json

import numpy as np
import pytest

from toolchain import require_module

from adbgen.analysis.loading import load_model
from benchmarks import engine_table as bench_auto
from benchmarks import peers as bench_peers
from adbgen.cli import main


def _problem(runs: dict, scale: float = 1.0, steps: int = 100) -> dict:
    return {"scale": scale, "runs": {k: {"error": e, "cpu_s": t, "steps": steps} for k, (e, t) in runs.items()}}


def test_choose_keeps_the_fastest_that_reaches_each_tolerance():
    """Per tolerance: the fastest candidate whose error is at most T x scale on every problem, by the
    worse of its time ratios to each problem's fastest; a tolerance nothing reaches has no row."""
    cands = [{"key": k, "engine": "taylor", "order": o, "step_factor": 1.0} for k, o in (("a", 8), ("b", 12))]
    problems = {"A": _problem({"a": (1e-6, 1.0), "b": (1e-9, 3.0)}),
                "B": _problem({"a": (5e-7, 2.0), "b": (1e-10, 2.5)}, scale=10.0)}
    every = 1e-30  # every candidate admissible: the measured errors alone decide
    rows = bench_auto.choose(problems, cands, (1e-5, 1e-7, 1e-9, 1e-12), safety=every)
    assert [(r["rtol"], r["key"]) for r in rows] == [(1e-5, "a"), (1e-7, "b"), (1e-9, "b")]
    assert rows[1]["time_ratio_to_fastest"] == pytest.approx(1.25)  # max(3.0 / 3.0, 2.5 / 2.0)
    only_a = bench_auto.choose({"A": problems["A"]}, cands, (1e-5,), safety=every)
    assert only_a[0]["key"] == "a" and only_a[0]["order"] == 8


def test_choose_takes_only_candidates_whose_step_aims_below_a_tenth_of_the_tolerance():
    """Order 8 with factor 3 aims each step at 3.3e-4 of the weights (`taylor.nominal_error`): though
    fastest and within 1e-6 on the problem, it may not stand for 1e-6; order 20 with factor 1.5 (aim
    6.8e-15) may.  An RK candidate run at a looser rtol than requested may not either."""
    from adbgen.analysis.engines.taylor import nominal_error

    assert nominal_error(8, 3.0) == pytest.approx(3.3e-4, rel=0.05)
    assert nominal_error(20, 1.5) == pytest.approx(6.8e-15, rel=0.05)
    cands = [{"key": "fast", "engine": "taylor", "order": 8, "step_factor": 3.0},
             {"key": "safe", "engine": "taylor", "order": 20, "step_factor": 1.5},
             {"key": "rk", "engine": "cyrk-dop853", "rtol_run": 1e-5}]
    problems = {"A": _problem({"fast": (1e-7, 1.0), "safe": (1e-12, 2.0), "rk": (1e-7, 0.5)})}
    assert [r["key"] for r in bench_auto.choose(problems, cands, (1e-6, 1e-3))] == ["safe", "rk"]
    # without the margin the fastest Taylor candidate stands
    assert bench_auto.choose(problems, cands, (1e-6,), safety=1e-30)[0]["key"] == "fast"
    assert bench_auto.admissible(cands[0], 1e-2) and not bench_auto.admissible(cands[0], 1e-3)


@pytest.fixture(scope="module")
def hy():
    return require_module("heyoka", "the peers extra")


@pytest.mark.parametrize("name", ["thesis_rotating_n2", "thesis_rotating_n3", "thesis_rotating_n4", "two_plane_hill"])
def test_the_hand_written_equations_are_the_models(hy, name):
    """heyoka-hand (Appendix A; the paper's (2), (4) with the Hill run-up and the spin angle as a state)
    equals the generated rhs at random states, parameters and times to 1e-13 (measured <= 5e-15)."""
    model = load_model(name)
    peer = bench_peers.HeyokaHandwritten(model.module)
    rng = np.random.default_rng(3)
    p = np.array(model.module.DEFAULTS) * rng.uniform(0.5, 1.5, model.n_params)
    worst = 0.0
    for t in (0.0, 7.0, 120.0, 450.0):
        y = rng.uniform(-1, 1, model.n_states)
        y[: model.n_states // 2] *= 0.1
        ref = np.asarray(model.module.rhs(t, y, p))
        worst = max(worst, float(np.max(np.abs(peer.rhs(y, p, t) - ref)) / np.max(np.abs(ref))))
    assert worst < 1e-13
    if name == "two_plane_hill":  # negative control: the spin angle off by 0.1 rad is seen
        y = rng.uniform(-1, 1, model.n_states)
        full = peer.full_state(y, 120.0)
        full[-1] += 0.1
        cf = peer.hy.cfunc(peer.outputs, vars=peer.vars)
        off = np.asarray(cf(np.asarray(full), pars=p, time=120.0))[: model.n_states]
        assert np.max(np.abs(off - np.asarray(model.module.rhs(120.0, y, p)))) > 1e-5  # (agreement: 1e-13)


def test_a_model_without_a_hand_written_form_is_refused(hy):
    with pytest.raises(bench_peers.PeerUnavailable, match="no hand-written form"):
        bench_peers.HeyokaHandwritten(load_model("two_plane_rotating").module)


def test_bench_auto_quick(tmp_path, capsys):
    """The quick benchmark on problem A (2 orders x 2 factors, 2 rtols, t_end 200): results, a table
    with rows per problem, and the cost-per-step target line; --table-only remakes the table from the
    stored results, learned with the check scenes it measures (every row passes them)."""
    out, table = tmp_path / "auto.json", tmp_path / "table.json"
    assert main(["bench", "auto", "--quick", "--problems", "A", "--out", str(out), "--table", str(table)]) == 0
    res = json.loads(out.read_text())
    assert res["quick"] and set(res["problems"]) == {"A"} and len(res["candidates"]) == 2 * 2 + 2 * 2
    runs = res["problems"]["A"]["runs"]
    assert all(r["status"] == "success" and r["error"] < 1e-2 for r in runs.values())
    made = json.loads(table.read_text())
    assert set(made["by_problem"]) == {"A"} and made["by_problem"]["A"]["rows"] and made["rows"]
    assert made["by_problem"]["A"]["roles"] == sorted(set(load_model("thesis_rotating_n3").roles))
    cost = res["cost_per_step"][0]
    assert cost["flops_per_step"] > 1000 and 0 < cost["ns_per_flop_scalar"] < 10 and cost["ratio_to_scalar_flop_time"] > 0
    assert "Taylor's cost per step" in capsys.readouterr().out
    # --table-only (not quick) learns with the check scenes; their errors are taken from the table at --table where
    # it records them for every candidate (here the shipped one's: measuring four scenes against real128 references
    # is the benchmark's work, not the suite's (about 60 s); `check_errors` has its own test, on planted runs)
    table.write_text(bench_auto.TABLE_PATH.read_text())
    capsys.readouterr()
    assert main(["bench", "auto", "--table-only", "--problems", "A", "--out", str(out), "--table", str(table)]) == 0
    assert capsys.readouterr().out.count("as recorded in the previous table") == len(bench_auto.CHECK_SCENES)
    remade = json.loads(table.read_text())
    checked = {"scenes": remade["check"]["errors"]}
    assert remade["rows"] == bench_auto.table_of(res, checked)["rows"]
    assert all(bench_auto.passes_check(r, r["rtol"], checked) for r in remade["rows"])


# ------------------------------------------------------------------ issue 35: monotone and admissible table

def _shipped():
    from adbgen.analysis.engines.by_tolerance import TABLE

    table = json.loads(TABLE.read_text())
    measured = json.loads((bench_auto.Path(__file__).resolve().parents[2] / "benchmarks" / "auto.json").read_text())
    return table, measured


def _row_sets(table):
    yield "joint", table["rows"], None
    for label, p in table["by_problem"].items():
        yield label, p["rows"], label


def test_the_shipped_table_is_monotone_in_cost_on_every_learning_problem():
    """Issue 35 item 2: on problems A and B a looser rtol's row never takes more steps x work a step
    (`proxy_cost`, counted from the stored run, not timed) than a tighter rtol's row; also in CPU time."""
    table, measured = _shipped()
    for name, rows, label in _row_sets(table):
        problems = measured["problems"] if label is None else {label: measured["problems"][label]}
        assert bench_auto.monotone_violations(rows, problems, measured["candidates"]) == [], name
        assert bench_auto.monotone_violations(rows, problems, measured["candidates"], cost="cpu") == [], name


def test_a_planted_non_monotone_table_is_caught_and_made_monotone():
    """Negative control: problem A's 1e-6 row swapped for its 1e-12 row (more steps of a higher order) is
    a violation; `make_monotone` gives the looser tolerance a tighter row instead, admissible there."""
    table, measured = _shipped()
    rows = [dict(r) for r in table["by_problem"]["A"]["rows"]]
    tight = next(r for r in rows if r["rtol"] == pytest.approx(1e-12))
    planted = [dict(r) if r["rtol"] != pytest.approx(1e-6) else {**tight, "rtol": 1e-6} for r in rows]
    planted = [{**r, "key": "taylor:o20:f1", "order": 20, "step_factor": 1.0} if r["rtol"] == pytest.approx(1e-6)
               else r for r in planted]
    problems = {"A": measured["problems"]["A"]}
    bad = bench_auto.monotone_violations(planted, problems, measured["candidates"])
    assert bad and all(v["looser"] == pytest.approx(1e-6) for v in bad)
    fixed = bench_auto.make_monotone(planted, problems, measured["candidates"])
    assert bench_auto.monotone_violations(fixed, problems, measured["candidates"]) == []
    by_key = {c["key"]: c for c in measured["candidates"]}
    assert all(bench_auto.admissible(by_key[r["key"]], r["rtol"]) for r in fixed)
    assert next(r for r in fixed if r["rtol"] == pytest.approx(1e-6))["monotone_from"] < 1e-6


def test_every_shipped_row_is_admissible_and_a_planted_aggressive_step_factor_is_caught():
    """Each row's step aims at a tenth of its tolerance or less (`admissible`, the learning's constraint);
    negative control: order 10 with factor 3.5 planted at 1e-8 is refused."""
    table, measured = _shipped()
    for name, rows, _ in _row_sets(table):
        for r in rows:
            assert bench_auto.admissible(r, r["rtol"]), (name, r)
    planted = {"engine": "taylor", "key": "taylor:o10:f3.5", "order": 10, "step_factor": 3.5, "rtol": 1e-8}
    assert not bench_auto.admissible(planted, planted["rtol"])


def test_weighted_error_is_the_promise_at_unit_rtol():
    """`weighted_error` x (1 / rtol) is `tolerance.ratio` at that rtol with atol = rtol x ATOL_RATIO."""
    from benchmarks import tolerance

    y_ref = np.array([8.0, 1e-3, -0.05])
    y = y_ref + [1e-7, 1e-9, 3e-8]
    for rtol in (1e-4, 1e-9):
        assert bench_auto.weighted_error(y, y_ref) / rtol == pytest.approx(
            tolerance.ratio(y, y_ref, rtol, rtol * tolerance.ATOL_RATIO))


def test_the_check_scenes_constrain_the_learning_not_after_it():
    """`choose` with check scenes: the fastest candidate ("fast", within T on the learning problem) whose
    error on a check scene exceeds T (the promise's 10 / CHECK_MARGIN) may not stand for T, the next one
    that passes does; at a T where the check's references cannot tell (floor), the fast one stands.
    Negative control: without the check the fast candidate is chosen at both."""
    cands = [{"key": k, "engine": "taylor", "order": o, "step_factor": f}
             for k, o, f in (("fast", 10, 1.0), ("slow", 20, 1.0))]
    problems = {"A": _problem({"fast": (1e-12, 1.0), "slow": (1e-13, 2.0)})}
    checked = {"scenes": {"long": {"errors": {"fast": 3e-9, "slow": 5e-12}, "floor": 1e-12}}}
    assert not bench_auto.passes_check(cands[0], 1e-9, checked) and bench_auto.passes_check(cands[1], 1e-9, checked)
    assert bench_auto.passes_check(cands[0], 3e-9, checked)  # exactly T: the margin's bound, met
    every = 1e-30
    rows = bench_auto.choose(problems, cands, (1e-6, 1e-9), safety=every, checked=checked)
    assert [r["key"] for r in rows] == ["fast", "slow"]
    assert [r["key"] for r in bench_auto.choose(problems, cands, (1e-6, 1e-9), safety=every)] == ["fast", "fast"]
    floored = {"scenes": {"long": {"errors": {"fast": 3e-9, "slow": 5e-12}, "floor": 2e-9}}}
    assert bench_auto.passes_check(cands[0], 1e-12, floored)  # within 2 x the scene's floor: nothing does better
    failed = {"scenes": {"long": {"errors": {"fast": None, "slow": 5e-12}, "floor": 1e-12}}}
    assert not bench_auto.passes_check(cands[0], 1e-3, failed)  # a failed run never passes


def test_check_errors_grade_by_the_extended_reference_and_floor_at_the_reference_grade_runs(monkeypatch):
    """`check_errors`: each candidate's error against the scene's extended-precision reference, the floor the
    median error of the reference-grade candidates (per-step aim at double's eps, not the factor-1.5 row).  So a
    row whose error is 100x theirs fails the check below its own error, however tight T, while one within twice
    the floor passes at any T."""
    from benchmarks import tolerance

    class Model:
        def params(self, _):
            return [1.0]

        def state(self, _):
            return [0.0, 0.0]

    y_ref = np.array([1.0, 2.0])
    off = {(20, 1.0): 2.2e-9, (20, 1.5): 2.95e-7, (18, 1.0): 4e-9}

    class Engine:
        def __init__(self, table):
            self.key = table[0][1:]

        def run(self, *a, **k):
            return {"status": "success", "y_end": y_ref * (1 + off[self.key])}

    def ext(model, p, y0, t_end):
        return {"y_end": y_ref}, {"y_end": y_ref * (1 + 1e-20)}, {
            "engine": "heyoka", "fp_type": "real128", "tol": 1e-33, "check_tol": 1e-30, "order": 39, "steps": 9,
            "cpu_s": 1.0}

    monkeypatch.setattr(tolerance, "scene_model", lambda scene: Model())
    monkeypatch.setattr(tolerance, "extended_references", ext)
    monkeypatch.setattr("adbgen.analysis.engines.taylor.TaylorEngine", Engine)
    cands = [{"key": f"taylor:o{o}:f{f:g}", "engine": "taylor", "order": o, "step_factor": f} for o, f in off]
    got = bench_auto.check_errors(cands, progress=lambda line: None, scenes=({"name": "s", "y0": {}, "t_end": 1.0},))
    res = got["scenes"]["s"]
    # the floor: the median of the reference-grade runs (order 20 and 18 at factor 1), not of factor 1.5
    assert res["floor"] == pytest.approx((2.2e-9 + 4e-9) / 2 * 2 / 2.01, rel=1e-9) and res["reference"]["fp_type"] == "real128"
    f1, f15, o18 = cands
    assert bench_auto.passes_check(f1, 1e-13, got) and not bench_auto.passes_check(f15, 1e-7, got)
    assert bench_auto.passes_check(f15, 3e-7, got)  # its own error: met
    assert bench_auto.passes_check(o18, 1e-13, got)  # within 2 x the floor
    assert not bench_auto.passes_check(f15, 1e-13, got)  # 100x the floor: its own error must meet T


def test_every_shipped_row_passes_its_check_scenes():
    """The shipped table was learned with the check scenes (its `check` record): each Taylor row's
    recorded error on each scene is within its tolerance (ratio <= 10 / CHECK_MARGIN) or the floor."""
    table, _ = _shipped()
    checked = {"scenes": table["check"]["errors"]}
    assert {s["name"] for s in table["check"]["scenes"]} == {s["name"] for s in bench_auto.CHECK_SCENES}
    for name, rows, _ in _row_sets(table):
        for r in rows:
            assert bench_auto.passes_check(r, r["rtol"], checked), (name, r)
    loose = next(r for r in table["rows"] if r["rtol"] == pytest.approx(1e-3))
    # negative control: the tightest row's candidate at the loosest tolerance passes, the old table's 1e-4
    # row (order 10, factor 2.5: 9.8e-3 on scene 00 of bench tolerance) does not at 1e-4
    assert bench_auto.passes_check(table["rows"][-1], loose["rtol"], checked)
    assert not bench_auto.passes_check({"key": "taylor:o10:f2.5"}, 1e-4, checked)
    # the step-factor cliff: the 1e-4 row learned before the held-in transients (order 13, factor 2; 3.7e3 and
    # 1.2e4 on held-out thesis n = 3 scenes) passes the first two check scenes and is caught by the transients
    cliff = {"key": "taylor:o13:f2"}
    first_two = {"scenes": {k: v for k, v in checked["scenes"].items() if k in ("notebook06_si", "thesis_long")}}
    assert bench_auto.passes_check(cliff, 1e-4, first_two) and not bench_auto.passes_check(cliff, 1e-4, checked)


def test_table_only_reuses_the_recorded_check_scenes_defined_as_now(monkeypatch):
    """`check_and_table` takes a check scene's errors from the previous table's record when the scene is
    recorded as it is defined now and every candidate has an error there; it measures the others.  Negative
    control: a scene recorded with another t_end is measured again."""
    cands = [{"key": "taylor:o20:f1", "engine": "taylor", "order": 20, "step_factor": 1.0}]
    scenes = bench_auto.CHECK_SCENES
    recorded = {"scenes": [bench_auto.json_roundtrip(bench_auto._recorded(s)) for s in scenes],
                "reference": bench_auto.CHECK_REFERENCE,
                "errors": {s["name"]: {"errors": {"taylor:o20:f1": 1e-12}, "floor": 1e-13} for s in scenes}}
    measured = []

    def fake(cands, progress=print, scenes=()):
        measured.extend(s["name"] for s in scenes)
        return {"scenes": {s["name"]: {"errors": {c["key"]: 2e-12 for c in cands}, "floor": 1e-13} for s in scenes}}

    monkeypatch.setattr(bench_auto, "check_errors", fake)
    monkeypatch.setattr(bench_auto, "table_of", lambda result, checked: checked)
    got = bench_auto.check_and_table({"candidates": cands}, progress=lambda line: None, recorded=recorded)
    assert measured == [] and set(got["scenes"]) == {s["name"] for s in scenes}
    recorded["scenes"][-1]["t_end"] *= 2  # negative control: the last scene's record is not the scene now
    got = bench_auto.check_and_table({"candidates": cands}, progress=lambda line: None, recorded=recorded)
    assert measured == [scenes[-1]["name"]] and got["scenes"][scenes[-1]["name"]]["errors"]["taylor:o20:f1"] == 2e-12
    measured.clear()
    got = bench_auto.check_and_table({"candidates": cands + [{"key": "new"}]}, progress=lambda line: None,
                                     recorded={**recorded, "scenes": recorded["scenes"][:-1]})
    assert measured == [s["name"] for s in scenes]  # a candidate without a recorded error: all measured
    measured.clear()  # a record graded by the double references of the tables before: all measured
    bench_auto.check_and_table({"candidates": cands}, progress=lambda line: None,
                               recorded={k: v for k, v in recorded.items() if k != "reference"})
    assert measured == [s["name"] for s in scenes]


def test_the_held_in_transients_are_seeded_and_of_the_held_out_kind():
    """The check scenes added for the step-factor cliff are `tolerance_scenes._thesis` draws from
    `HELD_IN_SEED` (deterministic), thesis n = 3, 4 transients; negative control: another seed draws others."""
    drawn = bench_auto.held_in_transients()
    assert drawn == bench_auto.held_in_transients() and drawn == bench_auto.CHECK_SCENES[-len(drawn):]
    assert all(s["model"].startswith("thesis_rotating_n") and s["t_end"] >= 300 for s in drawn)
    assert bench_auto.held_in_transients(bench_auto.HELD_IN_SEED + 1) != drawn
