"""AUTO-07p driven from Python on the emitted files (adbgen.analysis.auto07p), against the analysis
layer's own continuation: the Hopf points of the balanced state along Omega agree to 1e-6 for
n = 2, 3, 4 (for n >= 3 through the regularising term of templates/auto/_family.j2), and the
regularised func's Jacobian on the followed state has exactly the transverse spectrum plus -1.

Needs AUTO-07p, gfortran, gcc and make: a failure in CI (CI=true), skipped elsewhere."""

from __future__ import annotations

import ctypes
import subprocess

import numpy as np
import pytest

from adbgen.analysis import auto07p, equilibrium_scan, steady
from adbgen.analysis.starts import labelled_state

from analysis_helpers import CH4, require_auto  # this folder is on sys.path: see conftest.py

TOL = 1e-6


@pytest.fixture(scope="module")
def auto_ok():
    require_auto()


@pytest.fixture(scope="module")
def auto_runs(auto_ok, thesis):
    cache = {}

    def get(n):
        if n not in cache:
            m = thesis[n]
            cache[n] = auto07p.continue_one(m, "Omega", to=0.5)
        return cache[n]
    return get


@pytest.mark.parametrize("n", [2, 3, 4])
def test_auto_hopf_points_equal_the_scan(auto_runs, balanced_scan, thesis, n):
    m = thesis[n]
    assert np.allclose(m.module.START_PARAMETERS, m.params({"Omega": 4.0, **CH4}))
    run = auto_runs(n)
    scan = balanced_scan(n)
    hb = [pt for pt in run.labelled() if pt.kind == "HB"]
    ours = [b for b in scan.points if b.kind == "hopf"]
    assert len(hb) == len(ours) == 3
    assert run.points[0].stable and not auto07p.unlabelled_stability_changes(run.points)
    assert not [pt for pt in run.points if pt.kind in ("BP", "LP")], "a regular branch: no spurious BP/LP"
    rows = {r["label"]: r for r in run.to_json()}
    for pt, b in zip(hb, ours):
        assert abs(pt.values["PAR(1)"] - b.value) < TOL, (pt.values["PAR(1)"], b.value)
        assert abs(rows[pt.label]["frequency"] - b.frequency) < TOL
    print(f"\nn = {n}: AUTO HB {[pt.values['PAR(1)'] for pt in hb]}, scan {[b.value for b in ours]}, "
          f"max difference {max(abs(pt.values['PAR(1)'] - b.value) for pt, b in zip(hb, ours)):.1e}")


def test_auto_from_set_parameters_uses_u_and_par(auto_ok, thesis):
    """A start away from stpnt's parameters (mu = 0.04: another balanced state) through AUTO's U and PAR."""
    m = thesis[3]
    p = m.params({"Omega": 4.0, **CH4, "mu": 0.04})
    y = labelled_state(m, "1", p)
    run = auto07p.continue_one(m, "Omega", p, y, to=1.5)
    hb = [pt.values["PAR(1)"] for pt in run.points if pt.kind == "HB"]
    ours = [b.value for b in equilibrium_scan.scan(m, p, y, "Omega", 4.0, 1.5).points if b.kind == "hopf"]
    assert len(hb) == len(ours) >= 1 and np.max(np.abs(np.array(hb) - ours)) < TOL
    first = next(sol for sol in run.solutions if sol.label == 1)
    assert first.par[3] == 0.04 and np.allclose(first.u[0], y, atol=1e-12), "AUTO started from U, PAR"


HARNESS = r"""
#include "{name}.c"
void h_func(const double *u, const double *par, double *f, double *dfdu, double *dfdp)
{{
    func({ndim}, u, 0, par, 2, f, dfdu, dfdp);
}}
"""


def _func(m, tmp_path):
    user = (m.folder / "auto" / f"{m.name}.c").read_text()
    (tmp_path / f"{m.name}.c").write_text(user)
    (tmp_path / "harness.c").write_text(HARNESS.format(name=m.name, ndim=m.n_states))
    r = subprocess.run(["gcc", "-std=gnu99", "-O1", "-Wall", "-Wextra", "-Werror", "-fPIC", "-shared", "-I",
                        str(auto07p.header_dir()), "-o", "h.so", "harness.c", "-lm"], cwd=tmp_path, capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    lib = ctypes.CDLL(str(tmp_path / "h.so"))
    ptr = lambda a: a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))  # noqa: E731

    def call(u, p):
        par = np.zeros(36)
        par[: p.size] = p
        f, dfdu, dfdp = np.zeros(m.n_states), np.zeros(m.n_states**2), np.zeros(m.n_states * 36)
        lib.h_func(ptr(np.ascontiguousarray(u, float)), ptr(par), ptr(f), ptr(dfdu), ptr(dfdp))
        return f, dfdu.reshape(m.n_states, m.n_states).T
    return call


def _match(a, b):
    rest, worst = list(b), 0.0
    for z in a:
        k = int(np.argmin([abs(z - w) for w in rest]))
        worst = max(worst, abs(z - rest.pop(k)))
    return worst


@pytest.mark.parametrize("n", [3, 4])
def test_regularised_func_has_the_transverse_spectrum_and_minus_one(auto_ok, thesis, tmp_path, n):
    """On the followed state dF/dU = J - T E^T: its eigenvalues are the transverse spectrum (the
    analysis layer's) and -1 (n - 2 times), so AUTO's Hopf points and stability are the deflated
    spectrum's.  Off the state, func = rhs + the term, and dfdu is its exact derivative."""
    m = thesis[n]
    func = _func(m, tmp_path)
    y = np.array(m.module.START)
    for omega in (4.0, 1.88, 1.3):
        p = m.params({"Omega": omega, **CH4})
        f, J_auto = func(y, p)
        assert np.max(np.abs(f)) < 1e-14
        transverse = steady.transverse_spectrum(steady.jacobian(m, y, p), steady.balanced_family_tangent(m, y))
        assert _match(np.linalg.eigvals(J_auto), np.r_[transverse, -np.ones(n - 2)]) < 1e-10
        assert np.linalg.cond(J_auto) < 1e8, "regular"
    rng = np.random.default_rng(12)
    p = m.params({"Omega": 2.0, **CH4})
    free = list(m.angle_indices)[2:]
    for _ in range(5):
        u = y + 0.05 * rng.standard_normal(m.n_states)
        f, J_auto = func(u, p)
        h = u[free] - y[free]
        assert np.max(np.abs(f - steady.residual(m, u, p))) > 1e-4 * np.max(np.abs(h)), "the term is there off the state"
        fd = np.empty_like(J_auto)
        for j in range(m.n_states):
            e = np.zeros(m.n_states)
            e[j] = 1e-6
            fd[:, j] = (func(u + e, p)[0] - func(u - e, p)[0]) / 2e-6
        assert np.max(np.abs(fd - J_auto)) < 1e-7 * max(1.0, np.max(np.abs(J_auto)))


def test_two_parameter_hopf_curves_are_hopf_points_of_the_analysis_layer(auto_ok, thesis):
    """n = 2 in (Omega, mu): every curve starts at a Hopf point of the one-parameter run; sampled points
    of each curve are Hopf points of the balanced state (3.6) at that (Omega, mu) by the analysis
    layer's own spectrum; the codimension-two points are reported once."""
    m = thesis[2]
    res = auto07p.continue_two(m, "Omega", "mu", to=0.5, range2=(0.001, 0.2))
    assert [c.kind for c in res.curves] == ["hopf", "hopf"], "H2 and H3 lie on one closed curve"
    assert res.curves[1].also_from == [pytest.approx(1.0296942, abs=1e-6)]
    out = res.to_json()
    assert {"curves", "special"} <= set(out) and out["special"]
    assert all(s["type"] in auto07p.CODIM2 for s in out["special"])
    keys = {(s["type"], round(s["Omega"], 5), round(s["mu"], 5)) for s in out["special"]}
    assert len(keys) == len(out["special"]), "each special point once"
    for curve in res.curves:
        assert any(abs(a - curve.origin) < 1e-6 and abs(b - 0.05) < 1e-9 for a, b in curve.points)
        pts = np.array(curve.points)
        for a, b in pts[np.linspace(0, len(pts) - 1, 8).astype(int)]:
            if b < 0.0051:  # at mu_c = delta/2 the balanced state meets the coincident one (pitchfork)
                continue
            p = m.params({**CH4, "Omega": a, "mu": b})
            s = steady.analyse(m, p, labelled_state(m, "1", p))
            near = s.transverse[np.argsort(np.abs(s.transverse.real))[:2]]
            assert np.all(np.abs(near.real) < 1e-6) and np.all(np.abs(near.imag) > 1e-3), (a, b, near)


def test_double_hopf_points_of_n3_are_two_pairs_on_the_axis(auto_ok, thesis):
    """n = 3, (Omega, mu): the Hopf curve crosses itself where two pairs of different frequency are on
    the imaginary axis (thesis: two H1 curves intersect, Fig. 4.5); checked on a fresh steady state."""
    from adbgen.analysis.starts import follower as _follower

    m = thesis[3]
    res = auto07p.continue_two(m, "Omega", "mu", to=0.5, range2=(0.001, 0.2))
    y = np.array(m.module.START)
    hh = auto07p.double_hopf_points(m, res.curves, res.one.p, "Omega", "mu", _follower(m, y))
    assert len(hh) >= 1
    for point in hh:
        p = m.params({**CH4, "Omega": point["Omega"], "mu": point["mu"]})
        state = labelled_state(m, "1", p)
        s = steady.analyse(m, p, state)
        pairs = s.transverse[s.transverse.imag > 0]
        near = pairs[np.argsort(np.abs(pairs.real))[:2]]
        assert np.all(np.abs(near.real) < 1e-8), near
        assert abs(near[0].imag - near[1].imag) > 1e-2
        assert sorted(near.imag) == pytest.approx(point["frequencies"], rel=1e-7)
    assert any(abs(pt["Omega"] - 1.5978798) < 1e-6 and abs(pt["mu"] - 0.0282608) < 1e-6 for pt in hh)


def test_fold_curve_of_the_coincident_state_passes_the_wedge_tip(auto_ok, thesis):
    """n = 2 from 2- at Omega = 0.5: the fold's curve in (Omega, mu) reaches its lowest mu at the wedge
    tip (4.1), (mu_c, Omega_c) = (delta/2, 1/sqrt(1 + 2 mu_c)) (to the curve's sampling)."""
    m = thesis[2]
    p = m.params({**CH4, "Omega": 0.5})
    res = auto07p.continue_two(m, "Omega", "mu", p, labelled_state(m, "2-", p), to=1.5, range2=(0.001, 0.2))
    assert [c.kind for c in res.curves] == ["fold"]
    pts = np.array(res.curves[0].points)
    tip = pts[np.argmin(pts[:, 1])]
    mu_c = CH4["delta"] / 2
    assert abs(tip[1] - mu_c) < 1e-6 and abs(tip[0] - 1 / np.sqrt(1 + 2 * mu_c)) < 1e-3, tip


def test_zeta_limit_of_n4_at_omega_3(auto_ok, thesis):
    """Fig. 4.13(b): at Omega = 3 the balanced state of n = 4 is stable only for zeta below about 0.1;
    the scan and AUTO-07p (started at Omega = 3 through U and PAR, the free angles pinned) agree."""
    from adbgen.analysis.starts import pinned_start as _pinned_start

    m = thesis[4]
    p = m.params({**CH4, "Omega": 3.0})
    scan = equilibrium_scan.scan(m, p, m.module.START, "zeta", 0.01, 0.2)
    assert [b.kind for b in scan.points] == ["hopf"] and scan.points[0].direction == "destabilising"
    assert scan.stable_intervals == [pytest.approx((0.01, scan.points[0].value))]
    run = auto07p.continue_one(m, "zeta", p, _pinned_start(m, p), to=0.2)
    hb = [pt.values["PAR(5)"] for pt in run.points if pt.kind == "HB"]
    assert len(hb) == 1 and abs(hb[0] - scan.points[0].value) < TOL
    assert 0.09 < hb[0] < 0.1


def test_n3_in_mu_the_balanced_branch_turns_at_mu_c(auto_ok, thesis):
    """n = 3, Omega = 1.5, mu from 0.05 down: stable below a Hopf point, and at mu_c = delta/3 (phi_3 = pi,
    phi_1 = phi_2 = pi: the thesis' pitchfork PF1,2) the branch turns into its mirror copy without a
    change of stability; scan and AUTO-07p agree on both points."""
    m = thesis[3]
    p = m.params({**CH4, "Omega": 1.5})
    scan = equilibrium_scan.scan(m, p, m.module.START, "mu", 0.05, 0.002)
    kinds = [(b.kind, b.direction) for b in scan.points]
    assert kinds == [("hopf", "stabilising"), ("fold", None), ("hopf", "destabilising")]
    fold = scan.points[1]
    assert abs(fold.value - CH4["delta"] / 3) < 1e-10
    assert scan.stable_intervals == [pytest.approx((CH4["delta"] / 3, scan.points[0].value), abs=1e-10)]
    run = auto07p.continue_one(m, "mu", p, m.module.START, to=0.002)
    lp = [pt.values["PAR(4)"] for pt in run.points if pt.kind == "LP"]
    hb = [pt.values["PAR(4)"] for pt in run.points if pt.kind == "HB"]
    assert lp and all(abs(v - fold.value) < TOL for v in lp)
    assert hb and all(abs(v - scan.points[0].value) < TOL for v in hb)


def test_two_plane_rotor_hopf_point_from_the_scan_and_auto(auto_ok):
    """The same layer on the two-plane rotating model (16 states, 4 balls on two races): the state B
    of its START loses stability at a Hopf point going down from Omega = 3; scan and AUTO-07p agree."""
    from adbgen.analysis.loading import load_model

    m = load_model("two_plane_rotating")
    p = np.array(m.module.START_PARAMETERS)
    scan = equilibrium_scan.scan(m, p, m.module.START, "Omega", 3.0, 2.5)
    assert [(b.kind, b.direction) for b in scan.points] == [("hopf", "destabilising")]
    run = auto07p.continue_one(m, "Omega", to=2.5)
    hb = [pt.values[run.column()] for pt in run.points if pt.kind == "HB"]
    assert len(hb) == 1 and abs(hb[0] - scan.points[0].value) < TOL
    assert abs(scan.points[0].value - 2.731992) < 1e-6


def test_a_bifurcation_row_carries_where_auto_may_have_placed_it():
    """`location_tolerance` is LCSPAE's stopping rule EPSS (1 + sqrt|DS DSMAX|) with the model's own EPSS (its c.
    file); `AutoRun.to_json` gives HB / LP / BP rows that plus fort.7's printed digits, and no other row."""
    from adbgen.analysis.loading import load_model

    model = load_model("thesis_rotating_n2")
    epss = auto07p.constant((model.folder / "auto" / "c.thesis_rotating_n2").read_text(), "EPSS")
    assert epss == 1e-8 and auto07p.constant("NTST = 20, NCOL = 4", "EPSS") is None
    tol = auto07p.location_tolerance(epss, 0.0025, 0.005)
    assert tol == pytest.approx(1e-8 * (1 + np.sqrt(0.0025 * 0.005)), rel=1e-15)
    col = f"PAR({auto07p.auto_parameter(model.param_names.index('Omega'))})"
    points = [auto07p.Point(1, -5, ty, lab, {col: 1.5}) for ty, lab in ((3, 1), (2, 2), (1, 3), (-4, 4), (9, 5))]
    rows = auto07p.AutoRun(model, "Omega", points, [], np.zeros(model.n_params), tol).to_json()
    assert [r["type"] for r in rows if "location_uncertainty" in r] == ["HB", "LP", "BP"]
    assert rows[0]["location_uncertainty"] == pytest.approx(tol + 1.5 * auto07p.PRINTED_RELATIVE, rel=1e-15)
    # a run whose tolerance is unknown says nothing about where its points are
    assert all("location_uncertainty" not in r for r in auto07p.AutoRun(model, "Omega", points, [], None).to_json())
