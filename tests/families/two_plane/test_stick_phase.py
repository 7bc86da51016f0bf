"""The two-plane stick phase emitted and run (issue 37 item 2; two_plane.friction, analysis.engines.hybrid).

The closed-form case, the two-plane twin of tests/analysis/test_hybrid_engine.py's: a braked free rotor (law =
"torque", tau0 < 0, no motor slope, no torsional damping), no imbalance (eps = chi = 0), two equal balls half a
turn apart in each race, the races mirror images (z = +-1), no race damping, started at OMEGA0 with every ball
stuck.  By symmetry the rotor neither moves nor tilts, so ball k's normal force is m R w^2 (w its absolute
speed) and a stuck ball needs F = m R theta_0''.  Stuck: (J_p + 4 m R^2) theta_0'' = tau0 = a (J_p + 4 m R^2),
held while |a| <= mu_s theta_0'^2: released at theta_0' = W = sqrt(|a| / mu_s), slipping forward; then
w = W / (1 + mu_r W tau) and theta_0' = W + tau0 tau / J_p + 4 m R^2 (W - w) / J_p.  Negative control: the
normal force from the race's speed (N = m R theta_0'^2) predicts other speeds.  The model's switching functions
hold the core's accelerations as inputs the driver fills from the rhs (accel_<coordinate>); read with them left
at 0 (the planted error) the stick margin is off.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbgen.analysis.engines import hybrid
from adbgen.analysis.loading import load_model
# the scene of `adbgen verify`'s two-plane stick/slip energy balance: the same bytes, one cached model for both
from adbgen.families.two_plane.science.stick_slip_energy import J_P, MASS, MU_R, MU_S, R, SCENE, TAU0

OMEGA0 = 100.0


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    path = tmp_path_factory.mktemp("two_plane_stick") / "braked.toml"
    path.write_text(SCENE)
    return load_model(scene=path)


def braked(normal: str = "ball"):
    """Release time and (theta_0', w) a time tau after it (module docstring); normal = "race": the planted
    N = m R theta_0'^2, integrated numerically."""
    from scipy.integrate import solve_ivp

    a = TAU0 / (J_P + 4 * MASS * R**2)
    W = math.sqrt(abs(a) / MU_S)
    t_release = (OMEGA0 - W) / abs(a)
    if normal == "ball":
        def state(tau):
            w = W / (1 + MU_R * W * tau)
            return W + TAU0 * tau / J_P + 4 * MASS * R**2 * (W - w) / J_P, w
        return t_release, state

    def rhs(_, u):
        spin, w = u
        N = MASS * R * spin**2
        return [(TAU0 + 4 * R * MU_R * N) / J_P, -MU_R * N / (MASS * R)]

    def state(tau):
        sol = solve_ivp(rhs, (0, tau), [W, W], rtol=1e-12, atol=1e-12)
        return sol.y[0, -1], sol.y[1, -1]
    return t_release, state


def _run(model, tau_after=0.8):
    y0 = np.zeros(model.n_states)
    for k, angle in enumerate((0.0, math.pi, 0.0, math.pi)):
        y0[model.index(f"theta_{k + 1}")] = angle
        y0[model.rate_index(model.index(f"theta_{k + 1}"))] = OMEGA0
    y0[model.rate_index(model.index("theta_0"))] = OMEGA0
    t_release, _ = braked()
    t_end = t_release + tau_after
    return hybrid.run(model, model.params(), y0, 0.0, t_end, rtol=1e-11, atol=1e-13), t_end


def _errors(model, run, t_end, normal):
    t_release, state = braked(normal)
    spin, w = state(t_end - t_release)
    got_spin = run.y_end[model.rate_index(model.index("theta_0"))]
    got_w = run.y_end[model.rate_index(model.index("theta_1"))]
    releases = [t for t, b, mode in run.events if mode == "slip+"]
    return releases, abs(got_spin - spin), abs(got_w - w)


def test_the_model_carries_modes_and_switching_functions(model):
    assert {"stuck_1", "slip_dir_4", "mu_s", "accel_X", "accel_theta_0"} <= set(model.param_names)
    assert {f"{kind}_{k}" for kind in ("normal_force", "slip_rate", "stick_force", "stick_margin")
            for k in range(1, 5)} <= set(model.measures)
    sw = hybrid.switching(model)
    assert len(sw.stuck) == 4 and len(sw.accel_param) == 5
    assert [model.state_names[i] for i in sw.rate_state] == [f"theta_{k}_dot" for k in range(1, 5)]


def test_braked_two_plane_rotor_releases_its_balls_as_the_closed_form_says(model):
    run, t_end = _run(model)
    assert run.status == "success", run.status
    assert run.modes(4) == ("slip+",) * 4, run.events
    assert run.events[:4] == tuple((0.0, k, "stick") for k in range(1, 5))  # at rest on the race at the start
    t_release, _ = braked()
    releases, dspin, dw = _errors(model, run, t_end, "ball")
    assert len(releases) == 4 and max(abs(t - t_release) for t in releases) < 1e-7, (releases, t_release)
    assert dspin < 1e-6 and dw < 1e-6, (dspin, dw)
    vibration = max(abs(run.y_end[model.index(c)]) for c in ("X", "Y", "phi_X", "phi_Y"))
    assert vibration < 1e-9, vibration  # the symmetric rotor stays at rest, as the closed form assumes


def test_a_wrong_normal_force_is_caught(model):
    run, t_end = _run(model)
    _, dspin, dw = _errors(model, run, t_end, "race")
    assert max(dspin, dw) > 1e-3, (dspin, dw)


def test_the_stick_force_needs_the_filled_accelerations(model):
    """At a stuck state the margin read with the core's accelerations filled (hybrid.measure) is the closed
    form's mu_s m R theta_0'^2 - m R |a|; with the inputs left at 0 (the planted error) |F| is 0 instead."""
    y = np.zeros(model.n_states)
    y[model.index("theta_2")] = y[model.index("theta_4")] = math.pi
    for name in ("theta_0", "theta_1", "theta_2", "theta_3", "theta_4"):
        y[model.rate_index(model.index(name))] = 50.0
    p = model.params({f"stuck_{k}": 1.0 for k in range(1, 5)})
    a = TAU0 / (J_P + 4 * MASS * R**2)
    want = MU_S * MASS * R * 50.0**2 - MASS * R * abs(a)
    got = hybrid.measure(model, "stick_margin_1", 0.0, y, p)
    assert got == pytest.approx(want, rel=1e-9), (got, want)
    unfilled = model.measure("stick_margin_1", 0.0, y, p)
    assert abs(unfilled - want) > 1e-3 * abs(want), (unfilled, want)


def test_energy_balance_with_stick_and_slip_and_its_wrong_normal_force():
    """`adbgen verify`'s stick/slip energy balance (two planes) on this module's scene (the same bytes, one cached
    model): holds to its tolerance; the normal force from the race's speed breaks it."""
    from adbgen.families.two_plane.science import stick_slip_energy

    assert stick_slip_energy.check().passed
    assert not stick_slip_energy.check(wrong=True).passed


def test_the_stick_force_with_a_vibrating_core_is_the_derived_one(model):
    """At a stuck state of a rotor that vibrates (eps, chi != 0, every core coordinate and rate non-zero), each
    ball's stick force read through the driver's filling of accel_X, accel_Y, accel_phi_X, accel_phi_Y,
    accel_theta_0 (hybrid.measure) is `model.stick_forces` evaluated with the rhs' accelerations put in by
    coordinate name: the braked case above leaves X'', Y'', phi'' at 0, so it does not see their filling.
    Negative control: X'' and Y'' filled the other way round (`with_accelerations` given a swapped Switching)."""
    import tomllib

    from adbgen.families.two_plane.model import lagrangian, stick_forces
    from adbgen.families.two_plane.scene import TwoPlaneScene

    lag = lagrangian(TwoPlaneScene.from_mapping(tomllib.loads(SCENE)))
    forces = stick_forces(lag)
    rng = np.random.default_rng(3)
    y = rng.normal(0.0, 1e-3, model.n_states)
    for k in range(5):
        y[model.index(f"theta_{k}")] = rng.uniform(0.0, 2 * math.pi)
        y[model.rate_index(model.index(f"theta_{k}"))] = 50.0
    p = model.params({"epsilon": 1e-3, "chi": 0.01, **{f"stuck_{k}": 1.0 for k in range(1, 5)}})
    filled = hybrid.with_accelerations(model, 0.0, y, p)
    f = np.asarray(model.module.rhs(0.0, y, filled))
    core = [model.rate_index(model.index(c)) for c in ("X", "Y", "phi_X", "phi_Y")]
    assert min(abs(f[i]) for i in core) > 1e-6, f[core]  # the core accelerates: its inputs matter
    values = dict(zip(model.param_names, filled))

    def derived(acc):
        subs = {}
        for c in lag.coordinates:
            i = model.rate_index(model.index(c.name))
            subs |= {c.q: y[model.index(c.name)], c.qd: y[i], c.qdd: acc[i]}
        out = []
        for F in forces:
            e = F.xreplace(subs)
            out.append(float(e.xreplace({s: values[str(s)] for s in e.free_symbols})))
        return np.array(out)

    got = np.array([hybrid.measure(model, f"stick_force_{k}", 0.0, y, p) for k in range(1, 5)])
    want = derived(f)
    assert got == pytest.approx(want, rel=1e-9, abs=1e-12), (got, want)
    # the planted filling: the accel parameter of X given Y'' and that of Y given X''
    from dataclasses import replace

    sw = hybrid.switching(model)
    order = list(sw.accel_state)
    x, yy = order.index(core[0]), order.index(core[1])
    order[x], order[yy] = order[yy], order[x]
    wrong = hybrid.with_accelerations(model, 0.0, y, p, replace(sw, accel_state=tuple(order)))
    bad = np.array([model.measure(f"stick_force_{k}", 0.0, y, wrong) for k in range(1, 5)])
    assert np.max(np.abs(bad - want)) > 1e-6 * np.max(np.abs(want)), (bad, want)
