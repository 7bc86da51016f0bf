"""Periodic orbits (issue 21 items 1-3): the variational driver, Newton shooting, `adbgen orbit`, branches,
their detectors on systems with known bifurcations, the first Lyapunov coefficient, and AUTO-07p as the
independent method."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from adbgen.analysis.loading import load_model
from adbgen.analysis.orbits import auto_cycles, branches, continuer, hopf, jets, first_lyapunov, orbit
from adbgen.analysis.orbits.cycle import torus_test
from adbgen.analysis.orbits.flow import Flow
from adbgen.analysis.orbits.parameters import ParameterMap
from adbgen.analysis.orbits.shooting import Shooting
from adbgen.analysis.simulate import simulate
from adbgen.cli import main

import orbit_toys as toys
from analysis_helpers import CH4, require_auto

PI = math.pi
FIG54B = {"phi_1": PI / 4, "phi_2": -PI / 4}  # thesis Fig. 5.4(b): the n = 2 run that ends on a limit cycle


@pytest.fixture(scope="module")
def n2():
    return load_model("thesis_rotating_n2")


@pytest.fixture(scope="module")
def fig54b(n2):
    return orbit.find(n2, n2.params(), n2.state(FIG54B), 2000.0)


# ------------------------------------------------------------------------------ the variational driver

def test_variational_equations_match_differences_of_the_flow(n2):
    """Phi and w of the compiled driver against central differences of the end state (every column)."""
    flow = Flow(n2)
    p = n2.params({"Omega": 1.8})
    y = n2.state({"x": 0.01, "phi_1": 1.0, "phi_2": -2.0, "phi_1_dot": 0.1})
    dp = np.eye(n2.n_params)[0]
    X, Phi, W = flow.arcs(y, 0.0, 7.0, p, phi=True, dp=dp)
    h = 1e-6
    fd = np.column_stack([(flow.end(y + h * e, 0.0, 7.0, p) - flow.end(y - h * e, 0.0, 7.0, p)) / (2 * h)
                          for e in np.eye(n2.n_states)])
    assert np.max(np.abs(fd - Phi[0])) < 1e-6 * max(1.0, np.max(np.abs(Phi[0])))
    fdp = (flow.end(y, 0.0, 7.0, p + h * dp) - flow.end(y, 0.0, 7.0, p - h * dp)) / (2 * h)
    assert np.max(np.abs(fdp - W[0])) < 1e-6 * max(1.0, np.max(np.abs(W[0])))
    # negative control: Phi is not the identity's flow of a shorter arc
    _, Phi_short, _ = flow.arcs(y, 0.0, 6.0, p, phi=True)
    assert np.max(np.abs(Phi_short[0] - Phi[0])) > 1e-2


def test_the_driver_entries_refuse_a_wrong_argument(n2):
    """adb_var_arcs and adb_var_sample are typed at load (flow.SIGNATURES): a float where the driver takes a
    pointer, or one argument too few, is refused by ctypes before reaching C; the same call correctly typed runs."""
    import ctypes

    from adbgen.analysis.orbits import flow as flow_module

    flow = Flow(n2)
    lib = flow.lib
    assert len(lib.adb_var_arcs.argtypes) == 17 and len(lib.adb_var_sample.argtypes) == 10
    y = np.ascontiguousarray(n2.state({"x": 0.01, "phi_1": 1.0}))
    p = np.ascontiguousarray(n2.params({"Omega": 1.8}))
    out = np.zeros((1, n2.n_states))
    times = np.array([1.0])
    ptr = flow_module._ptr
    args = [ptr(y), 0.0, ptr(p), 1, ptr(times), 1e-10, 1e-12, flow.method, 100_000, ptr(out)]
    assert lib.adb_var_sample(*args) == 0 and np.all(np.isfinite(out)) and np.any(out != 0)  # the typed call
    with pytest.raises(ctypes.ArgumentError):
        lib.adb_var_sample(1.0, *args[1:])  # a float for the start state's pointer
    with pytest.raises(TypeError):
        lib.adb_var_sample(*args[:-1])  # the output pointer missing
    with pytest.raises(ctypes.ArgumentError):
        lib.adb_var_arcs(1, *([1.0] * 16))


def test_shooting_jacobian_is_exact_with_arcs_and_forcing(tmp_path):
    """The multiple-shooting Jacobian (arcs, period, parameter; a forced model's arcs moving with its
    forcing frequency) against central differences of the residual."""
    m = load_model(toys.duffing_toy(tmp_path))
    flow = Flow(m)
    k = m.param_names.index("w")
    sh = Shooting(m, flow, arcs=3, forcing=k)
    p = m.params({"g": 0.25})
    X = np.array([[1.1, 0.2], [0.7, -0.3], [1.3, 0.1]])
    u = sh.pack(X, 0.0)
    dp = np.eye(m.n_params)[k]
    ev = sh.evaluate(u, p, dp=dp)
    h = 1e-6
    num = np.column_stack([(sh.evaluate(u + h * e, p, jacobian=False).F - sh.evaluate(u - h * e, p, jacobian=False).F)
                           / (2 * h) for e in np.eye(len(u))])
    assert np.max(np.abs(num - ev.A)) < 1e-6
    numk = (sh.evaluate(u, p + h * dp, jacobian=False).F - sh.evaluate(u, p - h * dp, jacobian=False).F) / (2 * h)
    assert np.max(np.abs(numk - ev.Fk)) < 1e-6
    # without the forcing-time term the parameter column is wrong (negative control)
    assert np.max(np.abs(numk - sh.evaluate(u, p, dp=np.eye(m.n_params)[m.param_names.index("g")]).Fk)) > 1e-3


def test_monodromy_of_chained_arcs_is_the_periods_and_the_last_arc_closes_with_the_shift(tmp_path):
    """Three arcs chained end to start: the monodromy matrix Phi_2 Phi_1 Phi_0 is the derivative of the flow
    over the whole period (in that order: the other one differs, negative control), the first residual
    blocks vanish and the last is phi(T; x_0) - x_0 - s, s the windings' shift (shooting.py's F_m)."""
    m = load_model(toys.pd_toy(tmp_path))
    p = m.params({"mu": 0.05})
    flow = Flow(m)
    shift = np.array([2 * PI, 0.0, 0.0, 0.0])
    sh = Shooting(m, flow, arcs=3, shift=shift)
    T = 5.0
    X = [np.array([1.2, 0.1, 0.3, -0.2])]
    for i in range(2):
        X.append(flow.end(X[-1], i * T / 3, T / 3, p))
    ev = sh.evaluate(sh.pack(np.array(X), T), p)
    end, Phi, _ = flow.arcs(X[0], 0.0, T, p, phi=True)
    assert np.max(np.abs(ev.monodromy - Phi[0])) < 1e-8
    assert np.max(np.abs(ev.Phi[0] @ ev.Phi[1] @ ev.Phi[2] - Phi[0])) > 1e-3
    N = m.n_states
    assert np.max(np.abs(ev.F[: 2 * N])) < 1e-10
    assert np.max(np.abs(ev.F[2 * N: 3 * N] - (end[0] - X[0] - shift))) < 1e-10
    assert np.max(np.abs(ev.F[2 * N: 3 * N] - (end[0] - X[0] + shift))) > 1.0


def test_shooting_jacobian_of_a_free_running_orbit_has_the_period_column(tmp_path):
    """Free-running (the period unknown), three arcs: the Jacobian against central differences of the
    residual, the period column d F_i / d T = f(end_i) / m and the phase row included (the column without
    its 1/m is refused, the negative control)."""
    m = load_model(toys.pd_toy(tmp_path))
    p = m.params({"mu": 0.05})
    sh = Shooting(m, Flow(m), arcs=3)
    X = np.array([[1.1, 0.2, 0.1, 0.0], [-0.4, 0.9, 0.0, 0.2], [-0.6, -0.8, -0.1, 0.1]])
    u = sh.pack(X, 6.0)
    ev = sh.evaluate(u, p)
    h = 1e-6
    num = np.column_stack([(sh.evaluate(u + h * e, p, jacobian=False).F - sh.evaluate(u - h * e, p, jacobian=False).F)
                           / (2 * h) for e in np.eye(len(u))])
    assert num.shape == ev.A.shape == (3 * m.n_states + 1,) * 2
    assert np.max(np.abs(num - ev.A)) < 1e-6
    assert np.max(np.abs(3 * num[:-1, -1] - ev.A[:-1, -1])) > 1e-2


def test_multipliers_are_sorted_largest_modulus_first():
    """sort_multipliers: by modulus, largest first; a conjugate pair with its positive imaginary part first."""
    mu = np.array([0.45, -1.5, 0.3 - 0.4j, 2.0, 0.3 + 0.4j, 1.0])
    assert list(orbit.sort_multipliers(mu)) == [2.0, -1.5, 1.0, 0.3 + 0.4j, 0.3 - 0.4j, 0.45]
    assert list(orbit.sort_multipliers(mu[::-1])) == list(orbit.sort_multipliers(mu))


def test_period_doubling_curve_vanishes_where_a_multiplier_is_minus_one(tmp_path):
    """The pd toy's real multipliers -exp(2 pi (mu -+ d)): the period-doubling curve's g = mu_c + 1 is 0 on
    mu = d and 1 - exp(-2 pi d) at mu = 0 (the candidate nearest -1 there)."""
    from adbgen.analysis.orbits.boundary import OrbitFollower
    from adbgen.analysis.orbits.period_doubling import PeriodDoublingCurve

    m = load_model(toys.pd_toy(tmp_path))
    p = m.params({"mu": -0.3})
    o = orbit.refine(m, p, np.array([1.0, 0.0, 0.0, 0.0]), 2 * PI)
    curve = PeriodDoublingCurve(m, ParameterMap(m, p, ["mu", "d"]), OrbitFollower(m, o))
    assert curve.g(curve.x_of(0.1, 0.1)) == pytest.approx(0.0, abs=1e-7)
    assert curve.critical(curve._solve(curve.x_of(0.1, 0.1))[1]).real == pytest.approx(-1.0, abs=1e-7)
    fresh = PeriodDoublingCurve(m, ParameterMap(m, p, ["mu", "d"]), OrbitFollower(m, o))
    assert fresh.g(fresh.x_of(0.0, 0.1)) == pytest.approx(1 - math.exp(-2 * PI * 0.1), abs=1e-7)


# ------------------------------------------------------------------------------ Fig. 5.4(b)

def test_fig54b_limit_cycle(fig54b):
    o = fig54b
    assert o.period == pytest.approx(6.2105202807, rel=1e-9)
    assert o.trivial_multiplier_error < 1e-8
    assert np.all(np.abs(o.nontrivial) < 1.0) and o.stable
    assert o.windings == {"phi_1": 0, "phi_2": 0}
    assert 0.0178 < o.r_min < 0.0180 and 0.1609 < o.r_max < 0.1611


def test_fig54b_period_agrees_with_a_long_simulation(n2, fig54b):
    """The default engine's long run from the thesis' start reaches the same orbit: its returns to the
    orbit's section (t in [4000, 6000], located on the run's own dense output: each step's Taylor
    polynomial, which the engine's steps of order 20 need; a cubic Hermite interpolant between step ends
    was 2.4e-8 off) come every `period` to 1e-8 relative."""
    from scipy.optimize import brentq

    from adbgen.analysis.engines.taylor import TaylorEngine

    o = fig54b
    sim = simulate(n2, n2.params(), n2.state(FIG54B), t_end=6000.0, rtol=1e-12, atol=1e-13)
    t, Y = sim.t, sim.y.T
    assert sim.picked["engine"] == "taylor"
    dense = TaylorEngine(table=[(0.0, sim.picked["order"], sim.picked["step_factor"])])
    f0 = np.asarray(n2.module.rhs(0.0, o.y, o.p))
    D = orbit.wrapped(n2, Y - o.y)
    g = D @ f0

    def section(tt):
        y = dense.dense(n2, n2.params(), sim.t, sim.y, np.array([tt]), 1e-12, 1e-13)[:, 0]
        return orbit.wrapped(n2, (y - o.y)[None])[0] @ f0

    crossings = []
    for i in np.nonzero((g[:-1] < 0) & (g[1:] >= 0) & (t[:-1] > 4000))[0]:
        w = g[i] / (g[i] - g[i + 1])
        if np.linalg.norm(D[i] + w * (D[i + 1] - D[i])) > 0.1:  # a crossing far from the orbit's point
            continue
        crossings.append(brentq(section, t[i], t[i + 1], xtol=1e-13))
    crossings = np.array(crossings)
    assert len(crossings) > 200
    # every return is one period after the previous one (or a whole number of them: steps are long)
    gaps = np.diff(crossings) / o.period
    assert np.max(np.abs(gaps - np.round(gaps))) < 1e-3
    count = int(round((crossings[-1] - crossings[0]) / o.period))
    period = (crossings[-1] - crossings[0]) / count
    assert abs(period - o.period) / o.period < 1e-8
    # one period more or less over the window is far off (the check can fail)
    assert abs((crossings[-1] - crossings[0]) / (count + 1) - o.period) / o.period > 1e-4


def test_fig54b_by_auto_agrees(n2, fig54b):
    """AUTO-07p's collocation from the orbit (as data) to its own solution one small step along the branch:
    the same period (1e-9 relative) and multipliers (1e-5) as Newton shooting at that parameter."""
    require_auto()
    r = auto_cycles.auto_orbit(n2, fig54b, "Omega")
    ours = orbit.refine(n2, n2.params({"Omega": r["Omega"]}), fig54b.y, fig54b.period)
    assert r["Omega"] != 4.0
    assert abs(r["period"] - ours.period) / ours.period < 1e-9
    mu = np.sort(np.abs([complex(a, b) for a, b in r["multipliers"]]))
    assert np.max(np.abs(mu - np.sort(np.abs(ours.multipliers)))) < 1e-5
    assert r["stable"] and ours.stable


# ------------------------------------------------------------------------------ the command

def test_orbit_command_json(capsys):
    code = main(["orbit", "thesis_rotating_n2", "--y0", "phi_1=pi/4", "--y0", "phi_2=-pi/4", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    for key in ("period", "multipliers", "trivial_multiplier_error", "stable", "windings", "r_min", "r_max", "y",
                "residual"):
        assert key in out
    assert all(len(pair) == 2 for pair in out["multipliers"]) and len(out["multipliers"]) == 8
    assert set(out["y"]) == set(load_model("thesis_rotating_n2").state_names)
    assert out["windings"] == {"phi_1": 0, "phi_2": 0} and out["stable"] is True
    # issue 34: what it followed and its margin, certified (the thesis' Fig. 5.4(b) cycle: |mu|max = 0.97)
    assert out["followed_state"] is None and "period 6.21052028" in out["followed_orbit"]
    assert 0 <= out["start_distance"] < 1e-3
    assert out["margin"] == pytest.approx(-0.0300, abs=1e-4) and out["marginal"] is False
    assert out["margin_uncertainty"] >= out["trivial_multiplier_error"]


def test_orbit_state_on_a_forced_model_follows_it_and_an_autonomous_one_refuses(capsys):
    """--state B on the forced two_plane_fixed: the orbit is B (the rotor at rest, a constant solution); on an
    autonomous model a labelled state is a steady state, not an orbit: one line, exit 2."""
    code = main(["orbit", "two_plane_fixed", "--state", "B", "--t-transient", "0", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["followed_state"] == "B" and out["start_distance"] < 1e-12 and out["r_max"] < 1e-12
    code = main(["orbit", "thesis_rotating_n2", "--state", "1"])
    captured = capsys.readouterr()
    assert code == 2 and captured.out == "" and captured.err.count("\n") == 1 and "autonomous" in captured.err


@pytest.mark.parametrize("argv, text", [
    (["--t-transient", "-1"], "--t-transient"),
    (["--arcs", "0"], "--arcs"),
    (["--set", "nope=1"], "'nope' is not a parameter"),
])
def test_orbit_command_bad_input(capsys, argv, text):
    code = main(["orbit", "thesis_rotating_n2", *argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and err[0].startswith("adbgen: error:") and text in err[0]


def test_orbit_on_a_steady_state_is_refused(capsys):
    code = main(["orbit", "thesis_rotating_n2", "--y0", "phi_1=pi/2", "--y0", "phi_2=-pi/2"])
    assert code == 2 and "steady state" in capsys.readouterr().err


# ------------------------------------------------------------------------------ desynchronised orbits

def test_desynchronised_orbit_found_and_continued():
    """thesis Fig. 5.16(a) (n = 3, zeta = 0.25): the balls lap the rotor (each angle loses 2 pi a period);
    the orbit is found, and continued in Omega with its windings."""
    m = load_model("thesis_rotating_n3")
    p = m.params({"zeta": 0.25})
    o = orbit.find(m, p, m.state({"phi_1": PI / 3, "phi_2": -PI / 3, "phi_3": PI}), 3000.0)
    # Two stable desynchronised orbits coexist here: all three balls lapping (period 1.8935742248) and two of
    # them (1.9159166203).  Which one this 3000-long transient reaches depends on the last bits of the
    # engines' sin/cos (glibc's libm gave the first, the pinned SLEEF libm gives the second): the windings
    # must match the period of the orbit found.
    known = {(-1, -1, -1): 1.8935742248, (0, -1, -1): 1.9159166203}
    key = tuple(o.windings[f"phi_{i}"] for i in (1, 2, 3))
    assert key in known, o.windings
    assert o.period == pytest.approx(known[key], rel=1e-8) and o.stable and o.trivial_multiplier_error < 1e-8
    br = branches.from_orbit(m, ParameterMap(m, p, ["Omega"]), o, -1.0,
                             continuer.Settings(ds=0.02, ds_max=0.1, max_points=12, bounds=(3.0, 4.0)))
    j = br.to_json()
    assert j["windings"] == o.windings and len(j["parameter"]) == 12
    assert j["parameter"][-1] < 3.7 and all(np.diff(j["period"]) > 0)
    for pt in br.orbits:  # each a closed orbit modulo 2 pi k
        end = Flow(m).end(pt.arcs[0], 0.0, pt.period, pt.p)
        assert np.max(np.abs(end - pt.arcs[0] - orbit.shift_vector(m, o.windings))) < 1e-7
    # negative control: without the windings the same point is no orbit
    end = Flow(m).end(o.y, 0.0, o.period, o.p)
    assert np.max(np.abs(end - o.y)) > 6.0


# ------------------------------------------------------------------------------ detectors

def _branch(m, lo, hi, start, ds=0.05):
    p = m.params({"mu": start})
    o = orbit.refine(m, p, np.array([1.0, 0.0, 0.0, 0.0]), 2 * PI)
    return branches.from_orbit(m, ParameterMap(m, p, ["mu"]), o, 1.0,
                               continuer.Settings(ds=ds, ds_max=0.1, max_points=60, bounds=(lo, hi)), amplitude=False)


def test_period_doubling_located_exactly(tmp_path):
    """Multipliers -exp(2 pi (mu +- d)): period-doubling at mu = -d and d (d = 0.1)."""
    m = load_model(toys.pd_toy(tmp_path))
    br = _branch(m, -0.3, 0.3, -0.3)
    pd = sorted(s["mu"] for s in br.specials if s["kind"] == "period-doubling")
    assert pd == pytest.approx([-0.1, 0.1], abs=1e-9)
    assert not [s for s in br.specials if s["kind"] != "period-doubling"]
    # negative control: a range without a crossing
    assert not _branch(m, -0.3, -0.15, -0.3).specials


def test_torus_located_exactly_and_neutral_saddle_refused(tmp_path):
    """Multipliers exp(2 pi (mu +- i w2)): a torus point at mu = 0 with angle 2 pi w2 (w2 = 0.3); the
    saddle version (mu + 1, mu - 1) changes the torus test's sign at mu = 0 too, and is no torus."""
    m = load_model(toys.torus_toy(tmp_path))
    br = _branch(m, -0.2, 0.2, -0.2)
    assert [s["kind"] for s in br.specials] == ["torus"]
    assert br.specials[0]["mu"] == pytest.approx(0.0, abs=1e-9)
    assert br.specials[0]["angle"] == pytest.approx(2 * PI * 0.3, abs=1e-7)
    sad = load_model(toys.torus_toy(tmp_path, saddle=True))
    br = _branch(sad, -0.2, 0.2, -0.2)
    assert br.specials == []
    mu0 = br.orbits[0].nontrivial
    mu1 = br.orbits[-1].nontrivial
    assert torus_test(mu0) * torus_test(mu1) < 0  # the test function did change sign


def test_forced_duffing_period_doubling(tmp_path):
    """x'' + 0.3 x' - x + x^3 = g cos(1.2 t): the forced response's period-doubling is located on its branch,
    and simulations on either side settle on the orbit of one forcing period and of two."""
    m = load_model(toys.duffing_toy(tmp_path))
    p = m.params({"g": 0.2})
    o = orbit.find(m, p, np.array([1.0, 0.0]), 200.0)
    assert o.forced and o.subharmonic == 1 and o.trivial is None
    br = branches.from_orbit(m, ParameterMap(m, p, ["g"]), o, 1.0,
                             continuer.Settings(ds=0.01, ds_max=0.02, max_points=100, bounds=(0.2, 0.3)))
    pd = [s for s in br.specials if s["kind"] == "period-doubling"]
    assert len(pd) == 1
    g_pd = pd[0]["g"]
    mu = np.array([complex(a, b) for a, b in pd[0]["multipliers"]])
    assert np.min(np.abs(mu + 1)) < 1e-6
    assert orbit.find(m, m.params({"g": g_pd - 0.005}), np.array([1.0, 0.0]), 600.0).subharmonic == 1
    assert orbit.find(m, m.params({"g": g_pd + 0.005}), np.array([1.0, 0.0]), 600.0).subharmonic == 2


# ------------------------------------------------------------------------------ Lyapunov coefficient

@pytest.mark.parametrize("l", [-0.5, 0.7])
def test_first_lyapunov_of_the_normal_form(tmp_path, l):
    """z' = (a + i) z + l |z|^2 z: l1 = 2 l in Kuznetsov's normalisation (<q, q> = 1); sign decides."""
    m = load_model(toys.hopf_toy(tmp_path / str(l), l=l))
    p = m.params({"l": l})
    for kind in ("jet", "differences"):
        l1, info = first_lyapunov.first_lyapunov(m, p, np.zeros(2), derivatives=kind)
        assert l1 == pytest.approx(2 * l, rel=1e-12 if kind == "jet" else 1e-6)
        assert info["frequency"] == pytest.approx(1.0)
    assert first_lyapunov.criticality(2 * l) == ("supercritical" if l < 0 else "subcritical")


def test_jets_equal_differences_of_the_exact_jacobian():
    """B and C from the jet against central differences of the generated Jacobian (random state, complex
    direction), on a thesis and a two-plane model."""
    rng = np.random.default_rng(3)
    for name in ("thesis_rotating_n3", "two_plane_rotating"):
        m = load_model(name)
        y = rng.normal(scale=0.3, size=m.n_states)
        q = rng.normal(size=m.n_states) + 1j * rng.normal(size=m.n_states)
        J = jets.jacobian_jet(m, 0.0, y, m.params(), q)
        D = jets.differences(m, 0.0, y, m.params(), q)
        J0 = m.module.jac(0.0, y, m.params())
        assert np.max(np.abs(J[0] - J0)) <= 1e-14 * np.max(np.abs(J0))  # numba's compiled rounding aside
        for a, b in zip(J[1:], D[1:]):
            assert np.max(np.abs(a - b)) < 1e-6 * np.max(np.abs(a))
        # negative control: the second coefficient is not the first
        assert np.max(np.abs(J[2] - J[1])) > 1e-3


def test_hopf_cycle_amplitude_grows_as_predicted(n2):
    """n = 2, H1 at Omega = 1.8822 (thesis (5.1)'s other parameters): supercritical; near it the cycle's
    r_max^2 grows linearly in the distance from the Hopf point, with the slope -4 s Re lambda' / (w l1)
    predicted by l1 (s the largest squared rotor part of Re(e^(i theta) q))."""
    from adbgen.analysis import equilibrium_scan

    p = n2.params({"Omega": 4.0, **CH4})
    sc = equilibrium_scan.scan(n2, p, n2.module.START, "Omega", 4.0, 1.5)
    b = sc.points[0]
    pm = ParameterMap(n2, p, ["Omega"])
    hp = hopf.HopfPoint.at(n2, pm, b.y, b.value)
    l1d, _ = first_lyapunov.first_lyapunov(n2, hp.p, hp.y, derivatives="differences")
    assert hp.l1 == pytest.approx(l1d, rel=1e-5) and hp.criticality == "supercritical"
    br = branches.from_hopf(n2, pm, hp, continuer.Settings(ds=0.002, ds_max=0.004, max_points=8, bounds=(1.5, 4.0)))
    lam = np.array([o.p_value for o in br.orbits[1:]])
    r2 = np.array([o.r_max ** 2 for o in br.orbits[1:]])
    slope, icpt = np.polyfit(lam - hp.lam, r2, 1)
    assert np.max(np.abs(np.polyval([slope, icpt], lam - hp.lam) - r2)) < 0.02 * r2.max()  # linear
    # the prediction
    ev = lambda lam_: first_lyapunov.hopf_vectors(np.asarray(n2.module.jac(0.0, hp.y, pm(lam_))), hp.omega)[0]  # noqa: E731
    dre = (ev(hp.lam + 1e-6).real - ev(hp.lam - 1e-6).real) / 2e-6
    th = np.linspace(0, 2 * PI, 721)
    s = max(float(np.sum(np.real(np.exp(1j * a) * hp.q[:2]) ** 2)) for a in th)
    predicted = -4 * s * dre / (hp.omega * hp.l1)
    assert slope == pytest.approx(predicted, rel=0.05)
    assert all(o.stable for o in br.orbits[1:])  # supercritical: the small cycles are stable


# ------------------------------------------------------------------------------ AUTO: the same branch

def test_cycle_branch_agrees_with_auto(n2):
    """The n = 2 branch from H1 by Newton shooting and by AUTO-07p's collocation (IPS = 2 from the HB label,
    NTST = 60, NCOL = 4): at AUTO's points our orbits refined there have the same period at AUTO's parameter
    value, or (where the branch runs more in the period) the same parameter value at AUTO's period, to 1e-9
    relative (AUTO prints 11 digits), and the torus point is the same to 1e-6 in Omega."""
    require_auto()
    from adbgen.analysis import equilibrium_scan

    p = n2.params({"Omega": 4.0, **CH4})
    sc = equilibrium_scan.scan(n2, p, n2.module.START, "Omega", 4.0, 1.7)
    pm = ParameterMap(n2, p, ["Omega"])
    hp = hopf.HopfPoint.at(n2, pm, sc.points[0].y, sc.points[0].value)
    ours = branches.from_hopf(n2, pm, hp, continuer.Settings(ds=0.01, ds_max=0.05, max_points=40, bounds=(1.7, 4.0)),
                              amplitude=False)
    theirs = auto_cycles.auto_branches(n2, "Omega", p, [hp.lam], 1.7, nmx=60)[0]
    cmp = auto_cycles.compare(ours, theirs, pm)
    assert len(cmp["points"]) >= 6 and cmp["unrefined"] == 0 and max(cmp["period_rel"], cmp["parameter_rel"]) < 1e-9
    assert all(r["rel"] is not None and r["rel"] < 1e-9 for r in cmp["points"])
    tr = [s["Omega"] for s in ours.specials if s["kind"] == "torus"]
    assert tr and auto_cycles.nearest_special(theirs["points"], "torus", tr[0], "Omega") < 1e-6


def test_continue_orbits_json(capsys):
    """`continue --from-hopf`: the HB points carry first_lyapunov and criticality; `orbits` holds one branch of
    arrays (parameter, period, stable, amplitude) starting at that Hopf point; `orbit_points` the torus."""
    require_auto()
    code = main(["continue", "thesis_rotating_n2", "--par", "Omega", "--to", "1.8", "--from-hopf", "1.88",
                 "--max-points", "25", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    hb = [pt for pt in out["points"] if pt["type"] == "HB"]
    assert hb and all(pt["criticality"] == "supercritical" and pt["first_lyapunov"] < 0 for pt in hb)
    (br,) = out["orbits"]
    assert {"parameter", "period", "stable", "amplitude"} <= set(br) and len(br["parameter"]) == 25
    assert br["from"]["Omega"] == pytest.approx(1.8822393490, abs=1e-8) and br["stable"][1] is True
    assert br["period"][0] == pytest.approx(2 * PI / 0.7431172783, rel=1e-8)
    tr = [pt for pt in out["orbit_points"] if pt["kind"] == "torus"]
    assert tr and tr[0]["Omega"] == pytest.approx(1.867449636, abs=1e-8) and len(tr[0]["multipliers"]) == 8


def test_orbit_code_names_no_family_or_model():
    """analysis/orbits reads models through their self-description: no family's or model's name in it (the
    negative control: the family folders do name them)."""
    import re
    from pathlib import Path

    import adbgen

    root = Path(adbgen.__file__).parent
    pattern = re.compile(r"thesis_rotating|single_plane|two_plane|single-plane|two-plane|scene_two", re.I)
    files = sorted((root / "analysis" / "orbits").glob("*.py")) + [root / "analysis" / "engines" / "variational_driver.c"]
    assert len(files) > 15
    assert [f.name for f in files if pattern.search(f.read_text())] == []
    assert pattern.search((root / "families" / "two_plane" / "science" / "periodic_orbits.py").read_text())
