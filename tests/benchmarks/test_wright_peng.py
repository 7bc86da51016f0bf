"""The Wright and Peng reproduction (benchmarks/wright_peng.py, issue 37 item 5): the labels from t_dec and a run's
status, the comparison of two cases, the verdicts, and the study scene's values.  The tiny version on the model
(3 x 3 starts) runs with the study, `python3 -m benchmarks.wright_peng --check`, not here: its model is the
stick/slip model of speed_reduction_scene.toml, whose first generation is minutes (test_speed_reduction.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from benchmarks import friction_studies as fs
from benchmarks import wright_peng as wp

B, N, U, F = wp.BALANCED, wp.NOT_BALANCED, wp.UNDECIDED, wp.FAILED


def test_labels_are_decided_only_with_the_confirmation_window():
    t_end = 20.0
    t_dec = np.array([5.0, math.nan, 19.0, 18.0, 5.0])
    failed = np.array([False, False, False, False, True])
    assert wp.labels(t_dec, failed, t_end, confirm=2.0).tolist() == [B, N, U, B, F]
    # negative control: without the window a late fall below the threshold would pass for balanced
    assert wp.labels(t_dec, failed, t_end, confirm=0.0).tolist()[2] == B


def test_differ_counts_only_starts_decided_in_both():
    a = np.array([B, B, N, U, F, N])
    b = np.array([B, N, N, B, B, B])
    d = wp.differ(a, b)
    assert d == {"compared": 4, "differ": 2, "fraction": 0.5, "left_out": 2}
    assert wp.differ(a, a)["differ"] == 0
    # an undecided start never counts as agreeing or differing
    assert wp.differ(np.array([U]), np.array([B]))["compared"] == 0
    assert wp.differ(np.array([U]), np.array([B]))["fraction"] is None


def _versus(fraction, left_out=0, compared=100):
    """`differ`'s counts with `fraction` of `compared` starts differing (None: nothing compared)."""
    if fraction is None:
        return {"compared": 0, "differ": 0, "fraction": None, "left_out": left_out}
    return {"compared": compared, "differ": round(fraction * compared), "fraction": fraction, "left_out": left_out}


def _result(fast, slow, ref, dips):
    cases = [{"name": "constant", "counts": {"balanced": 9}, "vs_constant": wp.differ(np.ones(9), np.ones(9))}]
    for t, frac in ((min(wp.RAMPS), fast), (max(wp.RAMPS), slow)):
        cases.append({"name": f"ramp {t:g} s", "counts": {"balanced": 0}, "vs_constant": _versus(frac)})
    cases.append({"name": f"ramp {wp.REFERENCE:g} s", "counts": {"balanced": ref}, "vs_constant": {"fraction": 0.3}})
    cases += [{"name": f"dip {i}", "counts": {"balanced": k}, "vs_constant": {"fraction": 0.3}}
              for i, k in enumerate(dips)]
    return {"cases": cases}


def test_verdicts():
    v = wp.verdicts(_result(0.0, 0.6, 10, (12, 11)))
    assert v["acceleration_may_be_ignored"] and v["acceleration_matters"] and v["dip_enlarges_basin"]
    assert v["best_dip"] == "dip 0"
    # negative controls: a fast ramp that differs, a slow one that does not, dips no better than the ramp
    v = wp.verdicts(_result(0.2, 0.1, 12, (12, 11)))
    assert v["acceleration_may_be_ignored"] is False and v["acceleration_matters"] is False
    assert v["dip_enlarges_basin"] is False
    assert wp.verdicts(_result(None, None, 1, (2,)))["acceleration_matters"] is None


def test_cases_constant_is_a_step_with_the_balls_at_rest_on_the_disc():
    base = fs.scene_values(wp.SCENE)
    cs = wp.cases(base)
    const = cs[0]
    assert const["values"]["t_ramp"] == wp.STEP and const["values"]["depth"] == 0.0
    assert const["y0"] == [f"phi_1_dot={base['omega']!r}", f"phi_2_dot={base['omega']!r}"]
    assert [c["values"]["t_ramp"] for c in cs[1:1 + len(wp.RAMPS)]] == list(wp.RAMPS)
    assert all(c["values"]["depth"] > 0 for c in cs if "dip" in c["name"])
    assert base["mu_r"] == 0.0 and base["mu_s"] == 0.0  # the paper's balls: viscous drag only


def test_study_scenes_are_read_and_a_scene_of_another_structure_is_refused(tmp_path):
    v = fs.scene_values(wp.SCENE)
    assert v["k"] == 1.0e4 and v["omega"] == 400.0 and v["D"] == 5e-3 and v["t_ramp"] == 1.0
    assert fs.schedule_end({**v, "t_hold": 1.0, "depth": 0.5, "drop_rate": 100.0, "t_plateau": 2.0,
                            "recovery_rate": 200.0}) == pytest.approx(1.0 + 1.0 + 2.0 + 2.0 + 1.0)
    bad = tmp_path / "bad.toml"
    bad.write_text(wp.SCENE.read_text().replace("n = 2 ", "n = 3 "))
    with pytest.raises(ValueError, match="n = 3"):
        fs.scene_values(bad)
    const = tmp_path / "const.toml"
    const.write_text("n = 2\nrolling_resistance = 0.0\nstatic_friction = 0.0\n[speed]\nlaw = \"constant\"\n")
    with pytest.raises(ValueError, match="speed law"):
        fs.scene_values(const)


def test_the_studies_command_line(tmp_path, capsys):
    """friction_studies.main: --check's exit code follows the failures; a bad --side is refused in one line; a run
    writes the figure and the JSON with wall_s (planted study, check and draw: no model)."""
    def study(side, workers, progress):
        return {"starts": side * side}, []

    def draw(result, runs, path):
        path.write_text("figure")
        return path

    args = dict(default_side=2, study=study, draw=draw, figure="x.png", summary=lambda r: f"{r['starts']} starts")
    assert fs.main("x", "d", ["--check"], check=lambda workers: [], **args) == 0
    assert fs.main("x", "d", ["--check"], check=lambda workers: ["planted failure"], **args) == 1  # negative control
    assert "x: check failed: planted failure" in capsys.readouterr().err
    assert fs.main("x", "d", ["--side", "1"], check=None, **args) == 2
    assert capsys.readouterr().err.strip() == "x: --side must be >= 2, got 1"
    assert fs.main("x", "d", ["--side", "3", "--out", str(tmp_path)], check=None, **args) == 0
    import json
    data = json.loads((tmp_path / "x.json").read_text())
    assert data["starts"] == 9 and "wall_s" in data and (tmp_path / "x.png").read_text() == "figure"


def test_a_dip_is_not_said_to_enlarge_the_basin_on_undecided_starts():
    """Undecided or failed starts that could change the dip's verdict leave it open (None), never decide it."""
    def result(ref, dip):
        r = _result(0.0, 0.6, 0, (0,))
        r["cases"][3]["counts"] = ref
        r["cases"][4]["counts"] = dip
        return r

    # the ramp's 5 undecided starts could be balanced: 12 against 10 is not decided (the old check said True)
    assert wp.verdicts(result({"balanced": 10, "undecided": 5}, {"balanced": 12}))["dip_enlarges_basin"] is None
    assert wp.verdicts(result({"balanced": 10, "failed": 1}, {"balanced": 12}))["dip_enlarges_basin"] is True
    # the dip's failed starts could lift it above the ramp: not decided False either
    assert wp.verdicts(result({"balanced": 10}, {"balanced": 9, "failed": 3}))["dip_enlarges_basin"] is None
    assert wp.verdicts(result({"balanced": 10}, {"balanced": 9, "failed": 1}))["dip_enlarges_basin"] is False


def test_the_acceleration_verdicts_take_the_left_out_starts_both_ways():
    """Starts undecided or failed in either case could differ or not: a verdict they could change is None."""
    r = _result(0.0, 0.6, 10, (12,))
    by = {c["name"]: c for c in r["cases"]}
    fast, slow = by[f"ramp {min(wp.RAMPS):g} s"], by[f"ramp {max(wp.RAMPS):g} s"]
    fast["vs_constant"] = _versus(0.0, left_out=3)  # 0 of 100 differ, 3 left out: at most 3 / 103 <= 5 %
    slow["vs_constant"] = _versus(0.3, left_out=3)  # 30 of 103 even if none of the 3 differ: >= 25 %
    v = wp.verdicts(r)
    assert v["acceleration_may_be_ignored"] is True and v["acceleration_matters"] is True
    # negative controls: enough starts left out to cross either criterion leave the verdict open (the old check,
    # on the compared starts only, said True for both)
    fast["vs_constant"] = _versus(0.0, left_out=40)
    slow["vs_constant"] = _versus(0.3, left_out=60, compared=40)
    v = wp.verdicts(r)
    assert v["acceleration_may_be_ignored"] is None and v["acceleration_matters"] is None
