"""analysis.design_runs and the transient objectives of analysis.design_transients (issue 39 items 3, 5): a
design interrupted mid-run and run again with the same journal gives the uninterrupted run's answer and reruns
only the unfinished evaluations (negative controls: a planted wrong journal entry is read back and changes the
answer; a line cut by a kill is recomputed); r_max through a run-up equals a direct run of the run model with
the design's values set by name (negative control: the speed left unmapped gives another r_max); residual is
refused where there is no stick phase, and its quantile is None when a run failed."""

from __future__ import annotations

import json

import numpy as np
import pytest

from adbgen.analysis import design_transients as dt
from adbgen.analysis.design import Axis, Design, Problem, assess
from adbgen.analysis.design_runs import JOURNAL, Journal, residual_quantile, run_params, schedule_time
from adbgen.analysis.loading import AnalysisError, load_model
from adbgen.analysis.simulate import simulate
from stick_slip_scene import TORQUE_SCENE


@pytest.fixture(scope="module")
def thesis3():
    return load_model("thesis_rotating_n3")


@pytest.fixture(scope="module")
def candidates(thesis3):
    # thesis (5.1) at Omega = 4 with zeta = 0.3: beta above the thesis' 0.2346 is stable
    pr = Problem(thesis3, thesis3.params({"zeta": 0.3}), [Axis("Omega", 4.0, 4.0)], [Axis("beta", 0.3, 0.6)])
    vs = [assess(pr, [b]) for b in (0.3, 0.45, 0.6)]
    assert all(v.feasible for v in vs)
    return pr, vs


def test_an_interrupted_design_resumes_to_the_uninterrupted_answer(candidates, tmp_path, monkeypatch):
    pr, vs = candidates
    whole = dt.best_by_t_dec(pr, vs, Journal(tmp_path / "whole"), workers=1)
    put, count = Journal.put, {"puts": 0}

    def dies_after_one(self, key, result):
        if count["puts"] == 1:
            raise KeyboardInterrupt  # the kill: the run stops after one finished evaluation
        count["puts"] += 1
        put(self, key, result)
    monkeypatch.setattr(Journal, "put", dies_after_one)
    with pytest.raises(KeyboardInterrupt):
        dt.best_by_t_dec(pr, vs, Journal(tmp_path / "cut"), workers=1)
    monkeypatch.setattr(Journal, "put", put)
    assert len((tmp_path / "cut" / JOURNAL).read_text().splitlines()) == 1
    resumed = dt.best_by_t_dec(pr, vs, Journal(tmp_path / "cut"), workers=1)
    # only the two unfinished evaluations ran again (Dask pickles the task, so they are counted by their lines)
    assert len((tmp_path / "cut" / JOURNAL).read_text().splitlines()) == 3
    assert resumed[1] == whole[1] and resumed[0].design == whole[0].design
    # negative control: the resumed answer is read from the journal: a planted wrong t_dec there changes it
    lines = (tmp_path / "cut" / JOURNAL).read_text().splitlines()
    row = json.loads(lines[0])
    row["result"]["t_dec"] = (row["result"]["t_dec"] or 0.0) + 1.0
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / JOURNAL).write_text("\n".join([json.dumps(row)] + lines[1:]) + "\n")
    assert dt.best_by_t_dec(pr, vs, Journal(tmp_path / "bad"), workers=1)[1] != whole[1]
    # a line cut by a kill mid-write is not read: its evaluation runs again
    (tmp_path / "torn").mkdir()
    (tmp_path / "torn" / JOURNAL).write_text(lines[0][: len(lines[0]) // 2])
    assert dt.best_by_t_dec(pr, vs, Journal(tmp_path / "torn"), workers=1)[1] == whole[1]
    assert len((tmp_path / "torn" / JOURNAL).read_text().splitlines()) == 3  # the torn part dropped


def test_r_max_through_a_run_up_is_the_run_models_run_with_the_designs_values():
    m, ramp = load_model("two_plane_rotating"), load_model("two_plane_ramp")
    pr = Problem(m, m.params({"epsilon": 0.001, "Omega": 3.2}), [Axis("Omega", 3.2, 3.2)], [Axis("c_bb", 1e-5, 1e-3)],
                 ties={"c_bt": "c_bb"})
    v = assess(pr, [3e-4])
    assert v.feasible
    design = dt.by_runs(Design(pr, "interval", None, verdicts=[v]), "r_max-run-up", ramp, run_time=20.0,
                        run_set={"t_ramp": 60.0}, workers=1)
    row = design.objective_runs[0]
    assert row["status"] == "success" and design.best is v and row["t_end"] == 80.0
    values = {n: float(x) for n, x in zip(m.param_names, m.params({"epsilon": 0.001, "Omega": 3.2}))}
    values.update({"c_bb": 3e-4, "c_bt": 3e-4, "t_ramp": 60.0, "Omega_max": 3.2})
    values.pop("Omega")
    y0 = dt.rest_start(ramp)
    direct = simulate(ramp, ramp.params(values), y0, t_end=80.0, threshold=1e-4, keep_trajectory=False)
    assert row["r_max"] == pytest.approx(direct.r_max, rel=1e-12)
    # negative control: the final speed left at the run model's own (3.6) is another run-up
    values["Omega_max"] = float(ramp.params()[ramp.param_names.index("Omega_max")])
    other = simulate(ramp, ramp.params(values), y0, t_end=80.0, threshold=1e-4, keep_trajectory=False)
    assert abs(other.r_max - row["r_max"]) > 1e-6 * row["r_max"]


def test_run_models_without_what_the_objective_needs_are_refused(thesis3, candidates):
    pr, vs = candidates
    with pytest.raises(AnalysisError, match="no stick phase"):
        dt.by_runs(Design(pr, "interval", None, verdicts=vs), "residual", thesis3)
    with pytest.raises(AnalysisError, match="no run-up"):
        schedule_time(thesis3, thesis3.params())
    with pytest.raises(AnalysisError, match="shares none of the varied"):
        run_params(Problem(thesis3, thesis3.params(), [], [Axis("mu", 0.05, 0.1)]), load_model("two_plane_ramp"),
                   [0.06], {"Omega": 4.0})


def test_residual_quantile_counts_no_failed_run():
    ok = [{"residual": x, "status": "success"} for x in np.linspace(0.0, 1.0, 11)]
    assert residual_quantile(ok, 0.9) == pytest.approx(0.9)
    assert residual_quantile(ok[:-1] + [{"residual": None, "status": "max_steps"}]) is None




def test_residual_runs_are_the_stick_slip_engines(tmp_path):
    from adbgen.analysis.design_runs import residual_run, residual_starts
    from adbgen.analysis.engines import hybrid

    path = tmp_path / "torque.toml"
    path.write_text(TORQUE_SCENE)
    model = load_model(scene=str(path))
    p = model.params({"eps": 0.001})
    starts = residual_starts(model, 3)
    assert len({tuple(s) for s in starts}) == 3 and np.all(starts[:, list(model.role_indices("ball_angle"))] >= 0)
    y0 = starts[0].copy()
    y0[list(model.role_indices("ball_angle_rate"))] = 0.0
    y0[list(model.role_indices("spin_angle_rate"))] = 100.0  # the rotor spinning (the braked rotor's start)
    row = residual_run(model, p, y0, 0.5)
    run = hybrid.run(model, p, y0, 0.0, 0.5)
    i, j = model.amplitude_indices[:2]
    assert row["status"] == "success" and row["residual"] == pytest.approx(np.hypot(run.y_end[i], run.y_end[j]), rel=1e-9)
    assert row["modes"] == list(run.modes(2))
    # negative control: the residual is the rotor's displacement, not a ball's angle
    assert row["residual"] != pytest.approx(float(np.hypot(*run.y_end[list(model.role_indices("ball_angle"))])))


def test_the_verification_run_up_is_the_chosen_designs_run_up(tmp_path):
    """The verification's run-up (issue 39 item 4) is design_runs.run_up of the run model with the chosen design's
    values mapped by name: the same r_max, its r(t) on an even grid of the continuous solution at or below r_max and
    ending at r_end; the report gives its numbers and design.json its keys without the trace, run-up.png drawn.
    Negative controls: another design's run-up has another r_max; a model without a speed schedule, or one sharing
    no varied parameter, gives no run but one line saying why."""
    from adbgen.analysis import design_report
    from adbgen.analysis.design_runs import run_up

    m, ramp = load_model("two_plane_rotating"), load_model("two_plane_ramp")
    pr = Problem(m, m.params({"epsilon": 0.001, "Omega": 3.2}), [Axis("Omega", 3.2, 3.2)], [Axis("c_bb", 1e-5, 1e-3)],
                 ties={"c_bt": "c_bb"})
    run, note = dt.verify_run_up(pr, (3e-4,), ramp, run_time=20.0, run_set={"t_ramp": 60.0}, workers=1)
    assert note is None and run["status"] == "success" and run["schedule_end"] == 60.0 and run["t_end"] == 80.0
    q, taken = run_params(pr, ramp, (3e-4,), dt.operating_point(pr), {"t_ramp": 60.0})
    assert {"c_bb", "c_bt", "Omega_max"} <= set(taken) == set(run["mapped"])
    direct = run_up(ramp, q, dt.rest_start(ramp), 20.0)
    assert run["r_max"] == pytest.approx(direct["r_max"], rel=1e-12)
    r = np.array(run["trace"]["r"])
    assert len(r) == 801 and run["trace"]["t"][-1] == pytest.approx(80.0)
    assert r.max() <= run["r_max"] * (1 + 1e-9) and r.max() >= 0.95 * run["r_max"]
    assert r[-1] == pytest.approx(run["r_end"], rel=1e-6)
    assert run["settled"] == (run["t_dec"] is not None and run["r_end"] < run["threshold"])
    # negative control: the run depends on the design (another ball damping, another r_max)
    other, _ = dt.verify_run_up(pr, (1e-4,), ramp, run_time=20.0, run_set={"t_ramp": 60.0}, workers=1)
    assert abs(other["r_max"] - run["r_max"]) > 1e-6 * run["r_max"]
    design = Design(pr, "interval", assess(pr, [3e-4]), verdicts=[assess(pr, [3e-4])])
    design.verification_run_up = run
    files = design_report.write(design, tmp_path, "adbgen design ...")
    data = json.loads((tmp_path / "design.json").read_text())
    assert "trace" not in data["verification_run_up"] and data["verification_run_up"]["r_max"] == run["r_max"]
    assert data["verification_run_up_note"] is None and files["run_up_figure"].endswith("run-up.png")
    assert "run-up on two_plane_ramp" in (tmp_path / "report.md").read_text()
    # negative controls: no speed schedule, or no varied parameter reaching the run model: no run, one line why
    none, why = dt.verify_run_up(pr, (3e-4,), m, workers=1)
    assert none is None and why.startswith("no run-up: two_plane_rotating has no speed schedule") and "\n" not in why
    thesis = load_model("thesis_rotating_n3")
    none, why = dt.verify_run_up(Problem(thesis, thesis.params(), [], [Axis("mu", 0.05, 0.1)]), (0.06,), ramp,
                                 workers=1)
    assert none is None and "shares none of the varied" in why
    design.verification_run_up, design.verification_run_up_note = None, why
    lines = [ln for ln in design_report.report(design, "c").splitlines() if "Run-up of the chosen design" in ln]
    assert lines == [f"Run-up of the chosen design: {why}."]
