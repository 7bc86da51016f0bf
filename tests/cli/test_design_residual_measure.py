"""`adbgen design --objective residual` on a two-plane stiction scene reads the residual imbalance the run model
names for itself (its RESIDUAL_MEASURE: A for two planes, two_plane.description; analysis/loading.py's
Model.residual_measure), not r of the rotor's centre: the design on the paper's rotating-frame model
two_plane_rotating (set (10), the balanced state B of (9) in closed form), the residual runs on the stiction
scene below (its fixed-frame stick/slip model, constant speed Omega = 3, above both critical speeds), the
paper's values mapped onto it by name.  The smallest design that still decides: one varied value (both races'
ball damping, tied), two starts, a short run (every run ends at rest).

Negative controls: an explicit --residual-measure r wins and reads other values (r, not A); a name the model
does not have is refused in one line; a module that names a residual measure it does not have is refused in
one line (a planted RESIDUAL_MEASURE)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from adbgen.analysis.loading import AnalysisError, load_scene_text
from adbgen.cli import main

PREFIX = "adbgen: error: "
# the two-plane stick/slip structure of two_plane_rotating (2 + 2 balls, isotropic bearings, constant speed); its
# shared values come from the design, mu_r and mu_s are its own
SCENE = """eccentricity = 0.01
misalignment = 0.0
rolling_resistance = 0.002
static_friction = 0.004
races = [{z = 2.0, radius = 1.0, masses = [0.003, 0.003], damping = 0.01},
         {z = -2.0, radius = 1.0, masses = [0.003, 0.003], damping = 0.01}]
[speed]
law = "constant"
omega = 3.0
"""


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    path = tmp_path_factory.mktemp("scene") / "two_plane_stick.toml"
    path.write_text(SCENE)
    return path


def argv(scene, out, *more):
    return ["design", "two_plane_rotating", "--range", "Omega=3:3", "--imbalance", "0.01:0.01",
            "--vary", "c_bt=0.005:0.01", "--tie", "c_bb=c_bt", "--objective", "residual", "--runs", str(scene),
            "--residual-starts", "2", "--run-time", "100", "--no-verify", "--json", "--out", str(out), *more]


def test_the_residual_is_the_run_models_own_measure(capsys, scene, tmp_path):
    runs = load_scene_text(SCENE)
    assert runs.residual_measure == "A" and "A" in runs.measures
    code, out, err = run(capsys, *argv(scene, tmp_path / "a"))
    assert code == 0, err
    data = json.loads(out)
    res, rows = data["residual"], data["objective_runs"]
    assert res["measure"] == "A" and res["note"] is None and res["chosen_quantile"] is not None, res
    assert rows and all(len(r["residuals"]) == 2 and r["failed"] == 0 for r in rows)
    assert res["designs_decided"] >= 1 and res["chosen_quantile"] == min(
        r["residual_quantile"] for r in rows if r["residual_quantile"] is not None)
    # explicit r wins (the negative control of the default: the same runs, another measure, other values)
    code, out, err = run(capsys, *argv(scene, tmp_path / "r", "--residual-measure", "r"))
    assert code == 0, err
    r_data = json.loads(out)
    assert r_data["residual"]["measure"] == "r"
    a = np.array([r["residuals"] for r in rows], dtype=float)
    r = np.array([row["residuals"] for row in r_data["objective_runs"]], dtype=float)
    assert a.shape == r.shape and np.nanmax(np.abs(a - r)) > 1e-3 * np.nanmax(np.abs(a))
    # and the report says which measure it is
    assert "Residual imbalance A at rest" in (tmp_path / "a" / "report.md").read_text()


def test_a_wrong_measure_name_is_refused_in_one_line(capsys, scene, tmp_path):
    code, out, err = run(capsys, *argv(scene, tmp_path / "x", "--residual-measure", "B"))
    assert code == 2 and out == "" and err.startswith(PREFIX) and err.count("\n") == 1, err
    assert f"--residual-measure: 'B' is not a measure of {load_scene_text(SCENE).name}; its measures: " in err


def test_a_planted_wrong_residual_measure_in_the_module_is_refused(monkeypatch):
    runs = load_scene_text(SCENE)
    monkeypatch.setattr(runs.module, "RESIDUAL_MEASURE", "B")
    with pytest.raises(AnalysisError, match="names 'B' as its residual imbalance") as info:
        runs.residual_measure
    assert "\n" not in str(info.value)
