"""The engineer's 5-ball SI scene of issue 24 end to end (examples/five_ball_si.toml): what the issue
must show.  simulate gives a t_dec and r_max in m and s that mean something (the default threshold a
tenth of the 0.5 mm eccentricity, t_end 636.6 revolutions = 10 s, the transient inside it);
`stability --scan omega=400:100` reaches 100 rad/s (exit 0) or, stopped short, says so (exit 3)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import figure_checks as fc
from adbgen.cli import main

SCENE = str(Path(__file__).resolve().parents[2] / "examples" / "five_ball_si.toml")


def _json(capsys, *argv) -> tuple[int, dict, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, json.loads(out), err


def test_simulate_in_si_units(capsys, tmp_path, saved_figures):
    code, out, _ = _json(capsys, "simulate", "--scene", SCENE, "--y0", "phi_1=1", "--y0", "phi_2=2", "--json",
                         "--out", str(tmp_path))
    assert code == 0
    assert out["t_end"] == pytest.approx(10.0) and out["threshold"] == pytest.approx(5e-5)
    assert out["units"]["r_max"] == "m" and out["units"]["t_dec"] == "s" and out["units"]["parameters"]["omega"] == "rad/s"
    # r_max: the balls start 1 rad apart, the rotor is thrown 10.4 mm; it settles below 50 um after 5.5 s
    assert 0.009 < out["r_max"] < 0.012 and 4.0 < out["t_dec"] < 7.0 < out["t_end"]
    # the figure in the same units: r in m up to r_max (the dense search's peak, above the samples), the
    # threshold at 50 um and t_dec in s where the JSON puts them, t in s to t_end, five ball angles
    top, bottom = fc.figure(saved_figures, "trajectory.png").axes
    fc.assert_peak(top, "$r$", out["r_max"], rel=2e-3)
    r = fc.line(top, "$r$")
    assert np.max(r.get_ydata()) <= out["r_max"] and r.get_xdata()[-1] == out["t_end"]
    fc.assert_hline(top, "threshold 50 \u00b5m (a tenth of eps = 500 \u00b5m)", 5e-5)
    fc.assert_vline(top, f"$t_{{dec}}$ = {out['t_dec']:.4g} s", out["t_dec"])
    fc.assert_labels(top, ylabel="$r$ (m)")
    fc.assert_labels(bottom, xlabel="$t$ (s)")
    fc.assert_legend(bottom, [f"$\\phi_{{{k}}}$" for k in range(1, 6)])
    fc.assert_title(top, "five_ball_si.toml", "$r_{max}$ = 10.4 mm")
    code, again, _ = _json(capsys, "simulate", "--scene", SCENE, "--y0", "phi_1=1", "--y0", "phi_2=2", "--json",
                           "--t-end", "636.6197723675814rev", "--threshold", "0.05mm")
    assert again["t_end"] == pytest.approx(out["t_end"], rel=1e-12) and again["t_dec"] == pytest.approx(out["t_dec"])
    # before issue 24: threshold 1e-3 (1 mm, twice the eccentricity) and t_end 1000 (s): t_dec of the first moment
    code, old, _ = _json(capsys, "simulate", "--scene", SCENE, "--y0", "phi_1=1", "--y0", "phi_2=2", "--json",
                         "--t-end", "1000", "--threshold", "1e-3")
    assert old["t_dec"] < 3.0 < out["t_dec"]


def test_the_scan_reaches_100_rad_s(capsys, tmp_path):
    code, out, err = _json(capsys, "stability", "--scene", SCENE, "--scan", "omega=400:100", "--json",
                           "--out", str(tmp_path))
    assert code == 0 and out["complete"] and out["end"] == "left the range" and out["end_at"] < 100
    hopf = [p for p in out["points"] if p["kind"] == "hopf"]
    assert len(hopf) == 1 and 140 < hopf[0]["omega"] < 165 and hopf[0]["direction"] == "destabilising"
    assert out["stable_intervals"] == [[pytest.approx(hopf[0]["omega"]), 400.0]] and out["units"]["omega"] == "rad/s"


def test_a_scan_stopped_short_says_so(capsys):
    code, out, err = _json(capsys, "stability", "--scene", SCENE, "--scan", "omega=400:100", "--json",
                           "--max-steps", "100")
    assert code == 3 and out["complete"] is False and out["end"] == "step limit" and out["end_at"] > 250
    assert err.startswith("adbgen: ended early: omega reached ") and "rad/s" in err
