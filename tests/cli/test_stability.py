"""`adbgen stability` and `adbgen continue`: the JSON the issue names, and each bad input as one line
on stderr with exit status 2."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import figure_checks as fc
from adbgen.cli import main

from analysis_helpers import CH4, require_auto

pytestmark = pytest.mark.usefixtures("needs_gcc")

PREFIX = "adbgen: error: "
SET = [arg for k, v in CH4.items() for arg in ("--set", f"{k}={v}")]


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def one_line_error(capsys, *argv, match: str = "") -> str:
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == "", (code, out, err)
    assert err.startswith(PREFIX) and err.count("\n") == 1, err
    assert match in err, err
    return err


def test_stability_json_without_scan(capsys):
    code, out, err = run(capsys, "stability", "thesis_rotating_n3", "--set", "Omega=1.8", *SET, "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["classification"] == "unstable" and data["n_unstable"] == 2
    assert data["family_dimension"] == 1 and len(data["neutral_eigenvalues"]) == 1
    assert abs(complex(*data["neutral_eigenvalues"][0])) < 1e-10
    assert len(data["eigenvalues"]) == 9 and data["residual"] < 1e-12
    assert set(data["state"]) == {"x", "y", "phi_1", "phi_2", "phi_3", "x_dot", "y_dot", "phi_1_dot", "phi_2_dot",
                                  "phi_3_dot"}


def test_stability_from_a_closed_form_state_and_from_y0(capsys):
    code, out, _ = run(capsys, "stability", "thesis_rotating_n2", "--set", "Omega=0.5", *SET, "--state", "2-", "--json")
    assert code == 0 and json.loads(out)["classification"] == "stable" and json.loads(out)["state_label"] == "2-"
    code, out, _ = run(capsys, "stability", "thesis_rotating_n2", "--set", "Omega=4", *SET, "--y0", "phi_1=1.6",
                       "--y0", "phi_2=-1.6")
    assert code == 0 and "classification: stable" in out


def test_stability_scan_json(capsys, balanced_scan):
    code, out, err = run(capsys, "stability", "thesis_rotating_n2", *SET, "--scan", "Omega=4:0.5", "--json")
    assert code == 0, err
    data = json.loads(out)
    assert [p["kind"] for p in data["points"]] == ["hopf"] * 3
    for p, b in zip(data["points"], balanced_scan(2).points):
        assert set(p) >= {"kind", "Omega", "frequency", "direction"}
        assert p["Omega"] == pytest.approx(b.value, abs=1e-9) and p["direction"] == b.direction
    assert len(data["stable_intervals"]) == 2
    assert sum(data["stable_intervals"], []) == pytest.approx([1.0296942, 1.0936343, 1.8822393, 4.0], abs=1e-7)


def test_stability_scan_out_writes_the_branch_and_a_plot(capsys, tmp_path, saved_figures):
    code, out, err = run(capsys, "stability", "thesis_rotating_n2", *SET, "--state", "2-", "--scan", "Omega=0.5:1.5",
                         "--out", str(tmp_path))
    assert code == 0, err
    rows = np.loadtxt(tmp_path / "scan.csv", delimiter=",", comments="#", skiprows=4)
    assert rows.shape[1] == 4 and rows[0, 0] == 0.5 and rows[0, 2] == 0 and rows[0, 3] > 0.01
    # scan.png draws the branch of scan.csv: the leading real part (solid where stable, dashed all along) over
    # the rotor amplitude, the fold marked on both panels where the command says it is, and named in the title
    fold = float(re.search(r"fold\s+Omega = ([-\d.e]+)", out).group(1))
    lam, lead, unstable, amp = rows.T
    top, bottom = fc.figure(saved_figures, "scan.png").axes
    for ax, values in ((top, lead), (bottom, amp)):
        fc.assert_line(ax, "unstable", lam, values)
        fc.assert_line(ax, "stable", lam, np.where(unstable == 0, values, np.nan))
        assert fc.vertical_lines(ax) == [pytest.approx(fold, rel=1e-9)]
    fc.assert_legend(top, ["unstable", "stable"])
    fc.assert_labels(top, ylabel="max Re $\\lambda$ (transverse)")
    fc.assert_labels(bottom, xlabel="$\\Omega$", ylabel="$r = \\sqrt{x^2 + y^2}$")
    fc.assert_title(top, "thesis_rotating_n2", "mu = 0.05", f"LP {fold:.6g}")
    assert [t.get_text() for t in top.texts] == [f"LP {fold:.6g}"]


def test_stability_scan_fold_has_null_frequency(capsys):
    code, out, _ = run(capsys, "stability", "thesis_rotating_n2", *SET, "--state", "2-", "--scan", "Omega=0.5:1.5", "--json")
    points = json.loads(out)["points"]
    assert code == 0 and [p["kind"] for p in points] == ["fold"] and points[0]["frequency"] is None


@pytest.mark.parametrize("argv, match", [
    (["thesis_rotating_n9"], "no generated model"),
    (["thesis_rotating_n2", "--set", "Omega_x=1"], "not a parameter"),
    (["thesis_rotating_n2", "--set", "Omega=nan"], "cannot read"),
    (["thesis_rotating_n2", "--y0", "q=1"], "not a state"),
    (["thesis_rotating_n2", "--y0", "x=0", "--state", "start"], "not both"),
    (["thesis_rotating_n2", "--state", "7"], "unknown state label"),
    (["thesis_rotating_n2", "--state", "2+", "--set", "Omega=1.0"], "does not exist"),
    (["thesis_rotating_n2", "--scan", "Omega"], "NAME=FROM:TO"),
    (["thesis_rotating_n2", "--scan", "Omeg=1:2"], "not a parameter"),
    (["thesis_rotating_n2", "--scan", "Omega=2:2"], "empty range"),
    (["thesis_rotating_n2", "--scan", "Omega=1:x"], "cannot read"),
    (["thesis_rotating_n2", "--ds-max", "0"], "--ds-max"),
    (["thesis_rotating_n2", "--out", "x"], "--out needs --scan"),
    (["thesis_rotating_n2", "--bogus"], "unrecognized"),
])
def test_stability_bad_input(capsys, argv, match):
    one_line_error(capsys, "stability", *argv, match=match)


@pytest.mark.parametrize("argv, match", [
    (["thesis_rotating_n2"], "--par"),
    (["thesis_rotating_n2", "--par", "Omegax"], "not a parameter"),
    (["thesis_rotating_n2", "--par", "Omega", "--par2", "mux"], "not a parameter"),
    (["thesis_rotating_n2", "--par", "Omega", "--par2", "Omega"], "must differ"),
    (["thesis_rotating_n2", "--par", "Omega", "--range2", "0:1"], "needs --par2"),
    (["thesis_rotating_n2", "--par", "Omega", "--par2", "mu", "--range2", "1:0"], "LO must be below HI"),
    (["thesis_rotating_n2", "--par", "Omega", "--par2", "mu", "--range2", "1"], "LO:HI"),
    (["thesis_rotating_n2", "--par", "Omega", "--to", "4"], "must differ from the start"),
    (["thesis_rotating_n2", "--par", "Omega", "--set", "mu=inf"], "cannot read"),
    (["thesis_rotating_n2", "--par", "Omega", "--set", "mu=1e999"], "not finite"),
    (["thesis_rotating_n3", "--par", "Omega", "--state", "2-", "--set", "Omega=0.5"], "pin the free angles"),
    (["thesis_rotating_n2", "--par", "Omega", "--state", "9"], "unknown state label"),
])
def test_continue_bad_input(capsys, argv, match):
    if "--to" in argv:
        require_auto()
    one_line_error(capsys, "continue", *argv, match=match)


def test_continue_json(capsys, balanced_scan):
    require_auto()
    code, out, err = run(capsys, "continue", "thesis_rotating_n3", "--par", "Omega", "--to", "0.5", "--json")
    assert code == 0, err
    data = json.loads(out)
    hb = [p for p in data["points"] if p["type"] == "HB"]
    assert [p["label"] for p in data["points"]] == list(range(1, len(data["points"]) + 1))
    assert data["points"][0]["stability"] == "stable" and data["points"][0]["Omega"] == 4.0
    assert [p["Omega"] for p in hb] == pytest.approx([b.value for b in balanced_scan(3).points], abs=1e-6)
    assert all(set(p) >= {"label", "type", "Omega", "stability"} for p in data["points"])


def test_continue_two_parameters_json(capsys):
    require_auto()
    code, out, err = run(capsys, "continue", "thesis_rotating_n2", "--par", "Omega", "--par2", "mu", "--to", "0.5",
                         "--range2", "0.001:0.2", "--json")
    assert code == 0, err
    data = json.loads(out)
    assert {"points", "curves", "special"} <= set(data)
    assert [c["kind"] for c in data["curves"]] == ["hopf", "hopf"]
    assert all(len(pt) == 2 for c in data["curves"] for pt in c["points"])
    assert data["special"] and {s["type"] for s in data["special"]} <= {"BT", "CP", "ZH", "GH", "HH"}
    assert all({"Omega", "mu"} <= set(s) for s in data["special"])
