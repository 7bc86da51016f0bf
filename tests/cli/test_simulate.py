"""`adbgen simulate` (adbgen/cli/simulate.py): JSON keys, output files, errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

import figure_checks as fc
from adbgen.cli import main

pytestmark = pytest.mark.usefixtures("needs_gcc")

KEYS = {"model", "engine", "rtol", "atol", "t_end", "status", "r_max", "t_dec", "y_end", "n_rhs", "wall_s", "picked"}


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_simulate_json(capsys):
    code, out, err = run(capsys, "simulate", "thesis_rotating_n2", "--y0", "phi_1=pi/2", "--y0", "phi_2=-pi/2",
                         "--t-end", "1000", "--json")
    assert code == 0 and err == ""
    data = json.loads(out)
    assert KEYS <= set(data)
    assert data["model"] == "thesis_rotating_n2" and data["engine"] == "auto" and data["status"] == "success"
    assert data["picked"]["engine"] in ("taylor", "cyrk-dop853", "cyrk-vern8")  # the auto engine says what it ran
    assert data["rtol"] == 1e-8 and data["atol"] == 1e-10 and data["t_end"] == 1000.0
    assert set(data["y_end"]) == {"x", "y", "phi_1", "phi_2", "x_dot", "y_dot", "phi_1_dot", "phi_2_dot"}
    assert data["r_max"] == pytest.approx(0.0483, rel=5e-3) and data["t_dec"] == pytest.approx(462.42, rel=5e-3)
    assert data["n_rhs"] > 0 and 0 < data["wall_s"] < 10


def test_simulate_not_settled_is_null(capsys):
    code, out, _ = run(capsys, "simulate", "thesis_rotating_n2", "--y0", "phi_1=1", "--t-end", "20", "--json")
    assert code == 0 and json.loads(out)["t_dec"] is None


def test_simulate_table_and_files(capsys, tmp_path, saved_figures):
    code, out, _ = run(capsys, "simulate", "thesis_rotating_n3", "--set", "Omega=3", "--y0", "phi_1=3*pi/4",
                       "--t-end", "50", "--engine", "cvode-adams", "--out", str(tmp_path))
    assert code == 0 and "r_max" in out and "cvode-adams" in out
    data = np.load(tmp_path / "trajectory.npz")
    meta = json.loads(str(data["metadata"]))
    assert meta["parameters"]["Omega"] == 3.0 and data["y"].shape[0] == 10 and data["t"][-1] == 50.0
    lines = (tmp_path / "trajectory.csv").read_text().splitlines()
    assert lines[0].startswith("# model") and any(ln.startswith("t,r,x,y,phi_1") for ln in lines)
    # trajectory.png draws the run: r as in the table (its peak the run's r_max, found between the samples by
    # the dense search, so a little above them), the threshold, no t_dec line (not settled by t = 50), the angles
    table = np.loadtxt(tmp_path / "trajectory.csv", delimiter=",", comments="#", skiprows=len(meta) + 1)
    top, bottom = fc.figure(saved_figures, "trajectory.png").axes
    fc.assert_line(top, "$r$", table[:, 0], table[:, 1])
    fc.assert_peak(top, "$r$", meta["r_max"], rel=1e-3)
    fc.assert_hline(top, "threshold", meta["threshold"])
    assert meta["t_dec"] is None and not any(ln.get_label().startswith("$t_{dec}$") for ln in top.get_lines())
    fc.assert_labels(top, ylabel="$r$")
    fc.assert_title(top, "thesis_rotating_n3", "Omega = 3", "$t_{dec}$ = not settled")
    fc.assert_labels(bottom, xlabel="$t$", ylabel="ball angle (rad, wrapped)")
    fc.assert_legend(bottom, ["$\\phi_{1}$", "$\\phi_{2}$", "$\\phi_{3}$"])
    assert np.nanmax(np.abs(fc.line(bottom, "$\\phi_{1}$").get_ydata())) <= np.pi  # wrapped into (-pi, pi]


@pytest.mark.parametrize("argv, needle", [
    (["simulate", "thesis_rotating_n2", "--set", "Omeg=3"], "'Omeg' is not a parameter"),
    (["simulate", "thesis_rotating_n2", "--y0", "psi=1"], "'psi' is not a state"),
    (["simulate", "thesis_rotating_n2", "--y0", "phi_1=nan"], "cannot read 'nan'"),
    (["simulate", "thesis_rotating_n2", "--set", "mu=inf"], "cannot read 'inf'"),
    (["simulate", "thesis_rotating_n2", "--set", "mu"], "expected NAME=VALUE"),
    (["simulate", "thesis_rotating_n2", "--t-end", "-5"], "must be > 0"),
    (["simulate", "thesis_rotating_n2", "--engine", "euler"], "invalid choice"),
    (["simulate", "no_such_model"], "no generated model 'no_such_model'"),
    (["simulate"], "no model given"),
    (["simulate", "thesis_rotating_n2", "--bogus"], "unrecognized arguments"),
])
def test_bad_input_one_line_exit_2(capsys, argv, needle):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("adbgen: error: ") and needle in err


def test_failed_integration_exit_1(capsys):
    code, out, err = run(capsys, "simulate", "thesis_rotating_n2", "--y0", "phi_1=1", "--max-steps", "20", "--json")
    assert code == 1
    assert json.loads(out)["status"] == "max_steps"
    assert err.startswith("adbgen: error: integration failed at t = ") and "step limit" in err
    code, out, err = run(capsys, "simulate", "thesis_rotating_n2", "--y0", "phi_1=1", "--max-steps", "20")
    assert code == 1 and "not known (the run ended max_steps)" in out and "not settled" not in out


def test_check_tolerance_keeps_every_key_and_adds_the_check(capsys):
    """--check-tolerance: every key of a plain run and label, tolerance_sensitive, tolerance_check; Fig. 5.4(a)
    is robust (a planted flip is flagged in tests/analysis/test_tolerance.py)."""
    argv = ("simulate", "thesis_rotating_n2", "--y0", "phi_1=pi/2", "--y0", "phi_2=-pi/2", "--t-end", "1000")
    code, out, _ = run(capsys, *argv, "--json")
    plain = json.loads(out)
    code, out, _ = run(capsys, *argv, "--json", "--check-tolerance")
    data = json.loads(out)
    assert code == 0 and set(plain) <= set(data)
    assert set(data) - set(plain) == {"label", "tolerance_sensitive", "tolerance_check"}
    assert data["label"] == "balanced 1" and data["tolerance_sensitive"] is False
    check = data["tolerance_check"]
    assert [o["role"] for o in check["outcomes"]] == ["as run", "tighter", "second engine"]
    assert check["outcomes"][1]["rtol"] == pytest.approx(1e-10) and check["disagreements"] == []
    est = check["error_estimate"]  # the global error estimate at t_end: within the bound on this converged case
    assert est["ratio"] <= est["bound"] == 10 and est["exceeded"] is False and est["against"]
    assert est["conditioning"]["ratio"] <= est["conditioning"]["flag_above"] == 2  # well-conditioned: the probe agrees
    assert data["r_max"] == plain["r_max"]  # the run as asked is the plain run
    code, out, _ = run(capsys, *argv, "--check-tolerance", "--quiet")
    assert code == 0 and "robust: balanced 1 (rtol 1e-08" in out and "attractor" in out
    assert "error estimate" in out and "tolerance units at t_end" in out
    assert "conditioning probe" in out
