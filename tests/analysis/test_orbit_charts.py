"""Two-parameter curves and stability charts (issue 21 item 4) and scans that miss nothing (item 5)."""

from __future__ import annotations

import dataclasses
import json
import math
import types

import numpy as np
import pytest

from adbgen.analysis import equilibrium_scan, steady
from adbgen.analysis.loading import AnalysisError, load_model
from adbgen.analysis.orbits import auto_cycles, charts, describe, orbit
from adbgen.analysis.orbits.boundary import OrbitFollower
from adbgen.analysis.orbits.parameters import ParameterMap
from adbgen.cli import main

from analysis_helpers import require_auto

ALPHA = math.acos(0.25)  # B with m/M = eps/R (paper's charts): cos alpha_hat = m_c/m = 1/4
B = {"alpha_1": math.pi + ALPHA, "alpha_2": math.pi - ALPHA, "alpha_3": math.pi + ALPHA, "alpha_4": math.pi - ALPHA}
TIES_STATIC = ["m_1=epsilon*M/R_t", "m_2=m_1", "m_3=m_1", "m_4=m_1", "c_bt=0.01*m_1", "c_bb=c_bt"]


# ------------------------------------------------------------------------------ item 5: scans

def test_scan_finds_the_window_inside_one_step(capsys):
    """n = 2 just above the mu where the two Hopf points near Omega = 1.066 meet (mu = 0.034): the stable
    window [1.06558, 1.06656] (width 1e-3) lies inside one default step (0.01); the bounded steps find both
    Hopf points, and the scan says what it resolved.  Negative control: the plain stepping misses them."""
    code = main(["stability", "thesis_rotating_n2", "--set", "mu=0.034", "--set", "Omega=1.0", "--scan",
                 "Omega=1.0:1.15", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    hopf = [p["Omega"] for p in out["points"] if p["kind"] == "hopf"]
    assert hopf == pytest.approx([1.065577215, 1.066561046], abs=1e-8)
    assert all(p["criticality"] in ("supercritical", "subcritical") and "first_lyapunov" in p for p in out["points"])
    assert len(out["stable_intervals"]) == 1
    assert out["stable_intervals"][0] == pytest.approx([1.065577215, 1.066561046], abs=1e-8)
    res = out["resolution"]
    assert set(res) >= {"largest_step", "step_near_axis", "ds_floor", "extremum_checks"} and res["largest_step"] <= 0.0101
    m = load_model("thesis_rotating_n2")
    p = m.params({"mu": 0.034, "Omega": 1.0})
    y = steady.refine(m, p, m.module.START).y
    plain = equilibrium_scan.scan(m, p, y, "Omega", 1.0, 1.15, watch=False)
    assert plain.points == []


def test_extremum_check_catches_a_dip_the_step_bound_alone_would_not():
    """The continuer's parabola check (the one the equilibrium scans use): three points whose test function
    dips below zero inside the last step get a point inserted at the dip; a monotone one gets none."""
    from adbgen.analysis.orbits import continuer

    class Line:  # the curve y = lambda with one test function of lambda
        size, test_names = 2, ("dip",)

        def __init__(self, g):
            self.g = g

        def parameter(self, x):
            return float(x[-1])

        def evaluate(self, x):
            return np.array([x[0] - x[1]]), np.array([[1.0, -1.0]])

        def data(self, x):
            return None

        def tests(self, x, data):
            return np.array([self.g(float(x[-1]))])

    def check(g):
        curve, s = Line(g), continuer.Settings(fold_test=False)
        corr = continuer._Corrector(curve, s)
        t = np.array([1.0, 1.0]) / np.sqrt(2)
        pts = [continuer.Point(np.array([v, v]), None, curve.tests(np.array([v, v]), None), t, v * np.sqrt(2))
               for v in (0.0, 1.0, 2.0)]
        branch = continuer.Branch(pts[:2], [], "", 0.0)
        return continuer._check_extrema(curve, corr, branch, pts[2], ["dip"], s)
    # (lam - 1.5)^2 - 0.01 sampled at 0, 1, 2: 2.24, 0.24, 0.24, positive at the ends, negative inside (1.4, 1.6)
    (mid,) = check(lambda lam: (lam - 1.5) ** 2 - 0.01)
    assert mid.x[-1] == pytest.approx(1.5) and mid.tests[0] < 0
    assert check(lambda lam: 3.0 - lam) == []  # monotone: nothing to check


def test_zeta_scan_finds_the_instability_near_zero(capsys):
    """n = 3, Omega = 4, beta = 0.25: stable down to zeta = 2.70e-4, unstable below (a scan of zeta from 0.0025
    on cannot see it, and the thesis' "stable in the whole range 0 < zeta < 0.5" does not hold there)."""
    code = main(["stability", "thesis_rotating_n3", "--set", "Omega=4", "--set", "beta=0.25", "--set", "zeta=0.5",
                 "--scan", "zeta=0.5:1e-6", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    assert [p["kind"] for p in out["points"]] == ["hopf"]
    assert out["points"][0]["zeta"] == pytest.approx(2.6998e-4, rel=1e-3)
    assert out["points"][0]["direction"] == "destabilising"


def test_par2_defaults_find_the_thesis_hopf_curves(capsys):
    """`continue --par2` without --to runs over the model's own AUTO range (UZSTOP: Omega down to 0.5) and
    meets the Hopf points of n = 2 (H1 at 1.88 included); --to 2 (the old default, half the start) does not."""
    require_auto()
    code = main(["continue", "thesis_rotating_n2", "--par", "Omega", "--par2", "mu", "--range2", "0.001:0.2", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    assert len([c for c in out["curves"] if c["kind"] == "hopf"]) == 2
    code = main(["continue", "thesis_rotating_n2", "--par", "Omega", "--par2", "mu", "--range2", "0.001:0.2",
                 "--to", "2", "--json"])
    assert not [c for c in json.loads(capsys.readouterr().out)["curves"] if c["kind"] == "hopf"]


# ------------------------------------------------------------------------------ item 4: charts

def test_forcing_frequency_is_the_modules_own():
    """The forcing frequency is the module's FORCING_FREQUENCY, not guessed (two_plane_fixed at its defaults
    has Omega = l_1 = l_2 = 3: a guess by the rhs' period could pick either); a time-dependent model that
    declares none (a run-up) is refused, and so is a module whose declaration is removed (negative control)."""
    m = load_model("two_plane_fixed")
    assert m.param_names[describe.forcing_parameter(m)] == "Omega"
    assert describe.forcing_parameter(load_model("thesis_rotating_n2")) is None
    with pytest.raises(AnalysisError, match="not periodically forced"):
        describe.forcing_parameter(load_model("two_plane_hill"))
    bare = dataclasses.replace(m, module=types.SimpleNamespace(
        **{k: v for k, v in vars(m.module).items() if k != "FORCING_FREQUENCY"}))
    with pytest.raises(AnalysisError, match="FORCING_FREQUENCY"):
        describe.forcing_parameter(bare)


def test_hopf_chart_with_ties_is_exact_on_its_curves():
    """two_plane_rotating, dynamic imbalance (Fig. 14(a)): eps/R = chi, m/M = eps/R + chi, c_b/m = 0.01, beta = 1
    by ties; the chart's Hopf curves are Hopf points of the followed state (a pair within 1e-7 of the axis at
    sampled points), and the shaded region is where the grid found B stable."""
    m = load_model("two_plane_rotating")
    ties = ["chi=epsilon/R_t", "m_1=M*2*epsilon/R_t", "m_2=m_1", "m_3=m_1", "m_4=m_1", "c_bt=0.01*m_1", "c_bb=c_bt"]
    pm = ParameterMap(m, m.params({"Omega": 4.0, "beta": 1.0, "epsilon": 0.005}), ["Omega", "epsilon"], ties)
    from adbgen.analysis.orbits.equilibrium import homotopy

    p = pm((4.0, 0.005))
    y = homotopy(m, m.module.START, m.module.START_PARAMETERS, p)
    chart = charts.compute(m, pm, y, (2.0, 4.0), (1e-4, 0.02), log2=True, n1=21, n2=5)
    hopf = [c for c in chart.curves if c.kind == "hopf"]
    assert hopf and chart.stable.max() == 1 and chart.stable.min() == 0
    for c in hopf:
        for lam in c.points[:: max(1, len(c.points) // 5)]:
            q = pm(lam)
            ys = steady.newton(m, q, y)[0]
            ev = steady.analyse(m, q, ys).transverse
            assert np.min(np.abs(ev[ev.imag > 1e-6].real)) < 1e-7
    j = chart.to_json()
    assert j["ties"] == ties and j["log2"] and len(j["grid"]["stable"]) == 5 and "resolution" in j
    # the reproduction's copy leaves the wall time out (it must come out byte-identical run to run)
    assert j["wall_s"] > 0 and chart.to_json(timing=False) == {k: v for k, v in j.items() if k != "wall_s"}


def test_torus_curve_of_the_forced_model_against_auto():
    """two_plane_fixed (anisotropic (43)) at its defaults: AUTO-07p's TR points of the forced response in Omega
    (its own detection on the oscillator extension) are points of our torus curve: a multiplier pair of B on
    the unit circle there (to AUTO's 6 printed digits in Omega); and between them B's stability changes."""
    require_auto()
    m = load_model("two_plane_fixed")
    p = m.params()
    tr = [pt for pt in auto_cycles.auto_forced_bifurcations(m, "Omega", p, 2.2, 3.0) if pt["type"] == "TR"]
    assert len(tr) >= 2
    start = orbit.refine(m, p, m.steady_state("B", p), None)
    f = OrbitFollower(m, start)
    k = m.param_names.index("Omega")
    for pt in tr[:2]:
        q = p.copy()
        q[k] = pt["Omega"]
        _, mu = f.solve(q)
        pair = mu[mu.imag > 1e-9]
        assert np.min(np.abs(np.abs(pair) - 1)) < 1e-4
        # negative control: 0.01 away in Omega the pair is off the circle
        q[k] = pt["Omega"] + 0.01
        _, mu2 = f.solve(q)
        assert np.min(np.abs(np.abs(mu2[mu2.imag > 1e-9]) - 1)) > 1e-4


def test_chart_command_writes_the_figure_and_its_data(tmp_path, capsys):
    """The forced model's chart from the command line with ties and a log axis: figure + curves as data."""
    argv = ["continue", "two_plane_fixed", "--par", "Omega", "--par2", "epsilon", "--set", "Omega=2.5",
            "--set", "epsilon=1e-4", *sum((["--y0", f"{k}={v}"] for k, v in B.items()), []),
            *sum((["--tie", t] for t in TIES_STATIC), []), "--to", "2.7", "--range2", "3e-5:3e-4", "--log2",
            "--grid", "6:3", "--plot", str(tmp_path / "chart.png"), "--json"]
    code = main(argv)
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and (tmp_path / "chart.png").is_file() and (tmp_path / "chart.json").is_file()
    saved = json.loads((tmp_path / "chart.json").read_text())
    assert saved["curves"] == out["curves"] and out["parameter2"] == "epsilon" and out["ties"] == TIES_STATIC
    assert any(c["kind"] == "torus" for c in out["curves"])


def test_the_critical_member_of_a_pair_does_not_depend_on_the_sort():
    """A complex pair ties in the real part: whichever member a sort puts first (numpy's SIMD sorts and its
    portable one break the tie differently, the pinned environment of `adbgen reproduce` switches the
    former off), the curves are given the member with the positive imaginary part; the Hopf curve tracks
    the candidates above the axis, and the conjugate made it follow another eigenvalue (no curve found)."""
    pair = [complex(-1e-3, 2.0), complex(-1e-3, -2.0)]
    others = [complex(-0.5, 0.1), complex(-0.5, -0.1), complex(-2.0, 0.0)]
    for ev in (pair + others, pair[::-1] + others, others + pair[::-1]):
        assert charts._critical(np.array(ev), False, 0) == complex(-1e-3, 2.0)
    mult = [complex(0.3, 0.9), complex(0.3, -0.9), complex(0.2, 0.0)]
    for ev in (mult, [mult[1], mult[0], mult[2]]):
        assert charts._critical(np.array(ev), True, 0) == complex(0.3, 0.9)


def test_a_chart_in_the_pinned_environment_finds_the_curves_it_finds_unpinned():
    """Fig. 10(a) on a 21 x 7 grid in a child with `adbgen reproduce`'s pinned environment (numpy's SIMD
    loops off, OpenBLAS Prescott): the same curves as here (before the fix: none there, four here)."""
    import os
    import subprocess
    import sys

    from adbgen.analysis.reproduction import pinned_environment

    code = ("from adbgen.families.two_plane.charts import CHARTS\n"
            "from adbgen.analysis.loading import load_model\n"
            "from adbgen.analysis.orbits import charts\n"
            "from adbgen.analysis.orbits.parameters import ParameterMap\n"
            "case = CHARTS[0]\n"
            "m = load_model(case.model)\n"
            "pm = ParameterMap(m, m.params(case.sets), ['Omega', 'epsilon'], case.ties)\n"
            "c = charts.compute(m, pm, charts.chart_start(m, pm, (3.0, 1e-3)), case.range1, case.range2, log2=True,"
            " n1=21, n2=7, lam1_0=3.0, lam2_0=1e-3)\n"
            "print(sorted(cv.kind for cv in c.curves), int((c.stable == 1).sum()))\n")
    env = pinned_environment({k: v for k, v in os.environ.items() if k != "GLIBC_TUNABLES"})
    pinned = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600)
    plain = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert pinned.returncode == 0 and plain.returncode == 0, pinned.stderr[-500:] + plain.stderr[-500:]
    assert pinned.stdout == plain.stdout and "hopf" in pinned.stdout


def test_the_default_title_with_the_fig14a_ties_fits_the_figure():
    """`--par2 ... --tie ... --plot`'s title: the paper's Fig. 14(a) ties broken onto lines inside the figure
    (one line, as before, overran both edges; the control below measures that)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ties = ["chi=epsilon/R_t", "m_2=M*2*epsilon/R_t", "m_3=m_2", "m_4=m_2", "m_1=m_2", "c_bt=0.01*m_2", "c_bb=c_bt"]
    fig = plt.figure(figsize=charts.FIGSIZE)
    width = fig.bbox.width

    def extent(text):
        t = fig.suptitle(text, fontsize=charts.TITLE_FONTSIZE)
        fig.canvas.draw()
        return t.get_window_extent()

    box = extent(charts.default_title("two_plane_rotating", ties))
    assert 0 <= box.x0 and box.x1 <= width
    assert charts.default_title("two_plane_rotating", ties).startswith("two_plane_rotating: stable region shaded\n")
    one_line = extent("two_plane_rotating: stable region shaded; tied: " + ", ".join(ties))
    assert one_line.x0 < 0 and one_line.x1 > width  # control: the old title did not fit
    assert charts.default_title("m", []) == "m: stable region shaded"
    plt.close(fig)
