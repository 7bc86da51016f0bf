"""`adbgen design`: the thesis' ch. 4 advice reproduced as a design (n = 3, Omega = 4, thesis (5.1): the smallest
beta for which the balanced state is stable up to zeta = 0.5, equal to the scan of docs/reproduction.md, 0.2354);
the JSON keys the help names; the output folder; each bad input one line with exit status 2."""

from __future__ import annotations

import json
import math

import pytest

from adbgen.analysis.loading import load_model
from adbgen.cli import build_parser, main
from adbgen.cli.design import BEST_KEYS, JSON_FIELDS, JSON_KEYS
from adbgen.families.single_plane.science.reproduce import _beta_all

PREFIX = "adbgen: error: "
SCAN_STEP = 2.0 ** -10  # the scan's beta bound: 10 bisections of [0, 1], the bracket's upper end


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def design(capsys, zeta_max: float) -> dict:
    code, out, err = run(capsys, "design", "thesis_rotating_n3", "--range", "omega=4:4", "--range",
                         f"zeta=0.001:{zeta_max}", "--vary", "beta=0.01:1", "--json")
    assert code == 0, err
    return json.loads(out)


@pytest.fixture(scope="module")
def scan() -> float:
    return _beta_all(load_model("thesis_rotating_n3"), 4.0)


def test_thesis_ch4_beta_bound_is_the_scan(capsys, scan):
    assert round(scan, 4) == 0.2354
    data = design(capsys, 0.5)
    (low, high), = data["feasible_intervals"]
    assert high == 1.0
    # the design locates the bound to 1e-12; the scan brackets it within 2^-10 below its value
    assert scan - SCAN_STEP <= low <= scan
    assert data["boundaries"] == [{"at": {"beta": low}, "kind": "Hopf", "worst_point": data["boundaries"][0]["worst_point"],
                                   "bracket": None}]
    assert data["boundaries"][0]["worst_point"]["zeta"] == 0.5  # the bound is set at zeta = 0.5
    assert data["feasible"] and data["best"]["margin"] < 0 and data["active_boundary"]["kind"] == "Hopf"
    # negative control: a box up to zeta = 0.4 is a different question, and its bound is outside the scan's bracket
    other = design(capsys, 0.4)
    assert not scan - SCAN_STEP <= other["feasible_intervals"][0][0] <= scan


def test_json_keys_as_documented(capsys, tmp_path):
    code, out, err = run(capsys, "design", "thesis_rotating_n3", "--range", "omega=4:4", "--range", "zeta=0.3:0.5",
                         "--vary", "beta=0.2:0.4", "--json", "--out", str(tmp_path / "d"))
    assert code == 0, err
    data = json.loads(out)
    assert set(data) == set(JSON_FIELDS) - {"balls", "chosen_balls", "balls_choice"}  # the documented keys (no --balls)
    assert set(data["best"]) == set(BEST_KEYS[1:]) | {"beta"}
    assert {p.name for p in (tmp_path / "d").iterdir()} == {"design.json", "report.md", "design.png",
                                                           "design-journal.jsonl"}
    # a rerun into the same folder reads the verification runs from the journal: the same answer
    code, again, err = run(capsys, "design", "thesis_rotating_n3", "--range", "omega=4:4", "--range", "zeta=0.3:0.5",
                           "--vary", "beta=0.2:0.4", "--json", "--out", str(tmp_path / "d"))
    assert code == 0 and json.loads(again)["verification"] == data["verification"] != []
    assert "Boundaries the chart certifies" in (tmp_path / "d" / "report.md").read_text()
    report = (tmp_path / "d" / "report.md").read_text()
    assert "What limits it" in report and "Not covered yet" in report
    # the thesis model has no speed schedule: no run-up of the chosen design, said in one line (no figure)
    assert data["verification_run_up"] is None and "no speed schedule" in data["verification_run_up_note"]
    assert f"Run-up of the chosen design: {data['verification_run_up_note']}." in report.splitlines()
    helps = [a.help for a in build_parser()._subparsers._group_actions[0].choices["design"]._actions]
    assert any(JSON_KEYS in (h or "") for h in helps)


def test_tie_help_says_it_takes_a_varied_name_with_an_example():
    """`design --tie` is NAME=VARIED, a name; `continue --tie` NAME=EXPR (tests/cli/test_orbit.py)."""
    sub = build_parser()._subparsers._group_actions[0].choices["design"]
    tie = next(a for a in sub._actions if "--tie" in a.option_strings)
    assert tie.metavar == "NAME=VARIED"
    assert "the name of a --vary parameter: a name, not an expression" in tie.help
    assert "e.g. --tie c_bt=c_bb" in tie.help and "continue's --tie takes NAME=EXPR" in tie.help


@pytest.mark.parametrize("argv, match", [
    (["--vary", "nope=0:1"], "not a parameter"),
    (["--vary", "beta=1:0"], "LOW 1 is above HIGH 0"),
    (["--vary", "beta=0.1"], "expected LOW:HIGH"),
    (["--vary", "beta=0.2:0.2"], "nothing to vary"),
    (["--vary", "beta=0.1:0.2", "--imbalance=-1:0.01"], "must be >= 0"),
    (["--vary", "beta=0.1:0.2", "--imbalance", "0.02:0.01"], "above HIGH"),
    (["--vary", "beta=0.1:0.2", "--range", "beta=0:1"], "given twice"),
    (["--vary", "beta=0.1:0.2", "--objective", "rmax"], "invalid choice"),
    (["--vary", "beta=0.1:0.2", "--objective", "residual"], "no stick phase"),
    (["--vary", "beta=0.1:0.2", "--objective", "r_max-run-up"], "no run-up"),
    (["--vary", "mu=0.05:0.1", "--objective", "r_max-run-up", "--runs", "two_plane_ramp"], "shares none of the varied"),
    (["--vary", "beta=0.1:0.2", "--workers", "0"], "--workers"),
    (["--vary", "beta=0.1:0.2", "--balls", "2..3"], "--balls needs a scene file"),
    (["--vary", "beta=0.1:0.2", "--balls", "3..2"], "expected 1 <= N1 <= N2"),
    (["--vary", "beta=0.1:0.2", "--balls", "two"], "whole numbers"),
    (["--vary", "beta=0.1:0.2", "--residual-starts", "4"], "only with --objective residual"),
    (["--vary", "beta=0.1:0.2", "--residual-measure", "A"], "only with --objective residual"),
    (["--vary", "beta=0.1:0.2", "--objective", "residual", "--residual-quantile", "1.5"], "expected 0 < Q <= 1"),
    (["--vary", "beta=0.1:0.2", "--objective", "residual", "--residual-starts", "0"], "expected a whole number >= 1"),
])
def test_bad_input_one_line(capsys, argv, match):
    code, out, err = run(capsys, "design", "thesis_rotating_n3", *argv)
    assert code == 2 and out == "", (code, out, err)
    assert err.startswith(PREFIX) and err.count("\n") == 1 and match in err, err


def test_balls_refuse_a_scene_with_values_ball_by_ball(capsys, tmp_path):
    scene = tmp_path / "lists.toml"
    scene.write_text("n = 2\nball_mass = [0.01, 0.012]\n")
    code, out, err = run(capsys, "design", str(scene), "--vary", "beta=0.1:0.2", "--balls", "2..3")
    assert code == 2 and err.startswith(PREFIX) and "ball by ball" in err, err


def test_balls_choose_the_count(capsys, tmp_path):
    """The SI example at two ball counts: each count's design is its own scene's (the counts differ in capacity,
    n mu: 0.02 against 0.03), the chosen count is the one with the better margin."""
    from pathlib import Path

    scene = Path(__file__).resolve().parents[2] / "examples" / "three_ball_si_design.toml"
    code, out, err = run(capsys, "design", str(scene), "--range", "omega=pi:pi", "--imbalance", "0:0.01",
                         "--vary", "beta=0.05:0.3", "--balls", "2..3", "--no-verify", "--json")
    assert code == 0, err
    data = json.loads(out)
    rows = data["balls"]
    assert [r["n"] for r in rows] == [2, 3]
    assert data["best"]["capacity"] == pytest.approx(0.01 * data["chosen_balls"], rel=1e-9)
    feasible = [r for r in rows if r["feasible"]]
    assert data["chosen_balls"] == min(feasible, key=lambda r: r["margin"])["n"]
    assert data["best"]["margin"] == min(r["margin"] for r in feasible)
    # the choice over the counts, from the per-count rows: ranked, with the runner-up and why in one line
    choice = data["balls_choice"]
    assert choice["chosen"] == data["chosen_balls"] and choice["ranking"][0]["n"] == data["chosen_balls"]
    assert [r["value"] for r in choice["ranking"]] == sorted(r["objective_value"] for r in feasible)
    assert choice["why"].startswith(f"n = {data['chosen_balls']} (beta = ") and "\n" not in choice["why"]
    assert all(r["objective_value"] == r["margin"] for r in feasible)

def _kill_and_rerun(argv: list, tmp_path, at_lines: int) -> tuple[dict, dict, int, int]:
    """argv run into tmp_path/whole, and into tmp_path/killed SIGKILLed once its journal holds at_lines lines, then
    run again there: (the whole JSON, the rerun's, the lines kept at the kill, the whole run's lines); the JSON
    without `files`, `evaluations_resumed` moved to `resumed`."""
    import os
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path

    from adbgen.analysis.design_runs import JOURNAL

    argv = [sys.executable, "-m", "adbgen.cli", *argv]
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[2])}

    def json_of(folder):
        done = subprocess.run(argv + ["--out", str(folder)], capture_output=True, text=True, env=env, timeout=900)
        assert done.returncode == 0, done.stderr
        data = json.loads(done.stdout)
        data.pop("files")
        data["resumed"] = data.pop("evaluations_resumed")  # the designs' verdicts read back (issue 39 item 5)
        return data
    whole = json_of(tmp_path / "whole")
    total = len((tmp_path / "whole" / JOURNAL).read_text().splitlines())
    journal = tmp_path / "killed" / JOURNAL
    proc = subprocess.Popen(argv + ["--out", str(tmp_path / "killed")], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, env=env)
    try:
        while proc.poll() is None and not (journal.is_file() and journal.read_text().count("\n") >= at_lines):
            time.sleep(0.05)
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait()
    kept = journal.read_text().count("\n")  # the finished lines (a line cut by the kill is dropped and redone)
    again = json_of(tmp_path / "killed")
    assert len(journal.read_text().splitlines()) == total  # only what was left was computed again
    return whole, again, kept, total


def test_a_killed_design_resumes_to_the_uninterrupted_answer(tmp_path):
    """`adbgen design --objective t_dec --out DIR` killed (SIGKILL) once its journal holds a finished evaluation,
    then run again into DIR (its journal holds the designs' verdicts and the runs): the same JSON as a run never
    killed (the journal read back, not recomputed: the line count grows by what was left only).  Negative
    control: the killed folder's journal was incomplete when killed."""
    whole, again, kept, total = _kill_and_rerun(
        ["design", "thesis_rotating_n3", "--range", "omega=4:4", "--range", "zeta=0.3:0.5", "--vary", "beta=0.3:0.6",
         "--objective", "t_dec", "--workers", "1", "--no-progress", "--json"], tmp_path, 1)
    assert 1 <= kept < total, (kept, total)  # killed with evaluations left to do
    assert whole.pop("resumed") == 0 and again.pop("resumed") >= 1 and again == whole


def test_a_killed_chart_resumes_to_the_uninterrupted_chart(tmp_path):
    """A two-parameter design (the chart: its grid, then its certified rows and columns on the local Dask cluster)
    SIGKILLed once its journal holds more than the grid's 49 verdicts, then run again into the same folder: the
    same chart and best design, the verdicts found before the kill read back.  Negative control: the journal was
    incomplete when killed."""
    whole, again, kept, total = _kill_and_rerun(
        ["design", "thesis_rotating_n3", "--range", "omega=4:4", "--range", "zeta=0.3:0.5", "--vary", "beta=0.1:0.6",
         "--vary", "mu=0.03:0.1", "--no-verify", "--workers", "2", "--no-progress", "--json"], tmp_path, 60)
    assert whole["method"] == "chart" and 60 <= kept < total, (kept, total)
    assert whole.pop("resumed") == 0 and again.pop("resumed") == kept and again == whole

def test_the_optimiser_shows_its_progress(capsys, monkeypatch, tmp_path):
    """More than two varied parameters: COBYLA assesses one design after another (no Dask batch), so the command
    shows the elapsed time on stderr while it runs (adbgen.progress.activity); negative control: not with
    --no-progress."""
    monkeypatch.setenv("ADBGEN_PROGRESS", "1")  # drawn at once, though stderr is not a terminal
    argv = ["design", "thesis_rotating_n3", "--set", "zeta=0.5", "--vary", "Omega=3:5", "--vary", "beta=0.2:1",
            "--vary", "mu=0.03:0.1", "--no-verify"]
    code, out, err = run(capsys, *argv, "--out", str(tmp_path / "a"))
    assert code == 0 and "design optimiser (COBYLA)" in err and "optimiser" in out
    code, out, err = run(capsys, *argv, "--no-progress", "--out", str(tmp_path / "b"))
    assert code == 0 and "design optimiser (COBYLA)" not in err


STICK_SCENE = "n = 2\nrolling_resistance = 0.01\nstatic_friction = 0.02\n[speed]\nomega = 400.0\n"


def test_residual_objective_on_a_stiction_scene(capsys, tmp_path):
    """`--objective residual` with a stiction scene and no --runs: the design on its frictionless twin (the
    balancing state in closed form), the residual runs on the scene's own stiction model with its friction
    (mu_r = 0.01 kept, not the twin's 0); a planted target below the achievable residual is infeasible."""
    scene = tmp_path / "stick.toml"
    scene.write_text(STICK_SCENE)
    argv = ["design", str(scene), "--range", "omega=400:400", "--imbalance", "5e-4:5e-4", "--vary", "D=1e-3:5e-3",
            "--objective", "residual", "--residual-starts", "3", "--run-time", "20", "--no-verify", "--json",
            "--out", str(tmp_path / "d")]
    code, out, err = run(capsys, *argv)
    assert code == 0, err
    data = json.loads(out)
    res = data["residual"]
    assert data["model"] != res["run_model"] and data["feasible"] and res["kept"] == {"mu_r": 0.01}
    assert res["unit"] == "m" and res["starts"] == 3 and res["quantile"] == 0.9 and res["note"] is None
    rows = data["objective_runs"]
    assert all(len(r["residuals"]) == 3 and r["at_rest"] == 3 and "mu_r" not in r["mapped"] for r in rows)
    best = min(rows, key=lambda r: r["residual_quantile"])
    assert data["best"]["D"] == best["design"]["D"] and res["chosen_quantile"] == best["residual_quantile"] > 0
    assert "Residual imbalance r at rest in m" in (tmp_path / "d" / "report.md").read_text()
    # a target below every design's quantile: infeasible, said so (the runs read back from the journal)
    code, out, err = run(capsys, *argv, "--residual-target", f"{0.5 * best['residual_quantile']!r}")
    low = json.loads(out)
    assert code == 0 and not low["feasible"] and low["best"] is None and "no design reaches the target" in low["residual"]["note"]
    assert [r["residuals"] for r in low["objective_runs"]] == [r["residuals"] for r in rows]


def test_a_forced_model_is_designed_on_its_balancing_orbit(capsys):
    # two_plane_fixed: the anisotropic rotor in the fixed frame (analysis/design_orbit.py); docs/design.md's example
    def forced(omega):
        code, out, err = run(capsys, "design", "two_plane_fixed", "--range", f"omega={omega}:{omega}", "--set",
                             "epsilon=0.002", "--vary", "c_bb=1e-4:3e-4", "--tie", "c_bt=c_bb", "--no-verify", "--json")
        assert code == 0, err
        return json.loads(out)
    data = forced(8)
    best = data["best"]
    assert data["feasible"] and best["margin"] < -best["margin_uncertainty"]
    assert best["orbit_period"] == pytest.approx(2 * 3.141592653589793 / 8)
    mu = complex(*best["leading_multiplier"])
    assert abs(mu) < 1 and best["margin"] == pytest.approx(math.log(abs(mu)) / best["orbit_period"], rel=1e-9)
    assert [s["method"] for s in data["sensitivity"]] == ["one-sided finite differences of the worst margin (a forced "
                                                          "model's orbit)"]
    # negative control: at Omega = 4 the anisotropic rotor's balancing orbit is unstable for every c_bb here
    assert not forced(4)["feasible"]
