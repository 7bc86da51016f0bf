"""Stick and slip as an event-driven hybrid system (issue 37, item 2; adbgen.analysis.engines.hybrid).

The closed-form case: two equal balls half a turn apart on a balanced rotor (eps = 0), no ball drag, a
prescribed speed schedule started at full speed omega with both balls stuck.  By symmetry the rotor's centre
stays at rest (X = Y = 0), so each ball is a point on a race whose speed psi'(t) is prescribed: its normal
force is m R w^2 (w = psi' + phi' its absolute angular speed) and the tangential force a stuck ball needs is
m R psi''.  Hence, for a reduction at rate r to omega_p = omega (1 - depth), a plateau, a recovery at rate
r_c back to omega:

- stuck while r <= mu_s psi'^2: released when psi' = W = sqrt(r / mu_s), slipping forward;
- slipping forward: w' = -mu_r w^2, w = W / (1 + mu_r W tau): stuck again when w = omega_p, at
  tau = (1/omega_p - 1/W) / mu_r (on the plateau, where psi'' = 0 and the margin is positive);
- at the recovery (r_c > mu_s omega_p^2) released backwards: w' = +mu_r w^2, w = omega_p / (1 - mu_r omega_p tau),
  stuck again when w = omega, at tau = (1/omega_p - 1/omega) / mu_r.

The negative control takes the race's speed for the ball's in the normal force (N = m R psi'^2) and shows
that the stick times it predicts are not the engine's.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from adbgen.analysis.engines import hybrid
from adbgen.analysis.loading import load_model

OMEGA, T_RAMP, T_HOLD, DEPTH, RATE, T_PLATEAU, RECOVERY = 100.0, 1.0, 0.1, 0.5, 200.0, 0.5, 200.0
MU_R, MU_S, R, MASS = 0.02, 0.05, 0.05, 0.01
SCENE = f"""n = 2
rotor_mass = 1.0
eccentricity = 0.0
race_radius = {R}
ball_mass = {MASS}
ball_damping = 0.0
stiffness = 1000.0
damping = 1.0
rolling_resistance = {MU_R}
static_friction = {MU_S}
[speed]
law = "schedule"
omega = {OMEGA}
ramp_time = {T_RAMP}
hold_time = {T_HOLD}
reduction_depth = {DEPTH}
reduction_rate = {RATE}
plateau_time = {T_PLATEAU}
recovery_rate = {RECOVERY}
"""


def race_speed(t: float) -> float:
    """psi'(t) of the schedule after the run-up."""
    t_drop = T_RAMP + T_HOLD
    low = OMEGA * (1 - DEPTH)
    t_low = t_drop + (OMEGA - low) / RATE
    t_rec = t_low + T_PLATEAU
    if t <= t_drop:
        return OMEGA
    if t <= t_low:
        return OMEGA - RATE * (t - t_drop)
    if t <= t_rec:
        return low
    return min(OMEGA, low + RECOVERY * (t - t_rec))


def expected_events(normal: str = "ball") -> list[tuple[float, str]]:
    """(time, new mode) of ball 1 after the start.  normal = "ball": N = m R w^2 (right, closed form);
    "race": N = m R psi'^2 (the planted error, its slip integrated by quadrature)."""
    low = OMEGA * (1 - DEPTH)
    W = math.sqrt(RATE / MU_S)
    t_release = T_RAMP + T_HOLD + (OMEGA - W) / RATE
    t_rec = T_RAMP + T_HOLD + (OMEGA - low) / RATE + T_PLATEAU
    if normal == "ball":
        t_stick = t_release + (1 / low - 1 / W) / MU_R
        t_stick2 = t_rec + (1 / low - 1 / OMEGA) / MU_R
    else:
        def w(t, t0, w0, sign):
            return w0 - sign * MU_R * quad(lambda s: race_speed(s) ** 2, t0, t, limit=200)[0]
        t_stick = brentq(lambda t: w(t, t_release, W, 1) - race_speed(t), t_release + 1e-9, t_rec)
        t_stick2 = brentq(lambda t: w(t, t_rec, low, -1) - race_speed(t), t_rec + 1e-9, t_rec + 5)
    return [(t_release, "slip+"), (t_stick, "stick"), (t_rec, "slip-"), (t_stick2, "stick")]


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    path = Path(tmp_path_factory.mktemp("hybrid")) / "stick_slip.toml"
    path.write_text(SCENE)
    return load_model(scene=path)


def _run(model, t_end=2.6, rtol=1e-11, atol=1e-13):
    y0 = np.zeros(model.n_states)
    y0[model.index("phi_2")] = math.pi
    return hybrid.run(model, model.params(), y0, T_RAMP, t_end, rtol=rtol, atol=atol)


def test_closed_form_stick_slip(model):
    run = _run(model)
    assert run.status == "success", run.status
    ball1 = [(t, mode) for t, b, mode in run.events if b == 1]
    assert ball1[0] == (T_RAMP, "stick")  # decided at the start: held at full speed
    got = ball1[1:]
    want = expected_events("ball")
    assert [m for _, m in got] == [m for _, m in want], got
    errors = [abs(a - b) for (a, _), (b, _) in zip(got, want)]
    assert max(errors) < 1e-8, errors
    ball2 = [(t, mode) for t, b, mode in run.events if b == 2]
    assert [m for _, m in ball2] == [m for _, m in ball1]  # the symmetric ball switches with it
    # the absolute angle travelled while slipping forward, closed form: ln(1 + mu_r W tau) / mu_r
    t_rel, t_st = want[0][0], want[1][0]
    low, W = OMEGA * (1 - DEPTH), math.sqrt(RATE / MU_S)
    race_angle = quad(race_speed, t_rel, t_st, points=[T_RAMP + T_HOLD + (OMEGA - low) / RATE])[0]
    slip_forward = math.log(1 + MU_R * W * (t_st - t_rel)) / MU_R - race_angle
    race_back = quad(race_speed, want[2][0], want[3][0], points=[want[2][0] + (OMEGA - low) / RECOVERY])[0]
    slip_back = -math.log(1 - MU_R * low * (want[3][0] - want[2][0])) / MU_R - race_back
    phi_end = run.y_end[model.index("phi_1")]
    assert abs(phi_end - (slip_forward + slip_back)) < 1e-7, (phi_end, slip_forward + slip_back)
    assert abs(run.y_end[model.index("X")]) < 1e-9 and abs(run.y_end[model.index("Y")]) < 1e-9


def test_a_wrong_normal_force_is_caught(model):
    run = _run(model)
    got = [t for t, b, _ in run.events if b == 1][1:]
    wrong = expected_events("race")
    assert max(abs(a - b) for a, (b, _) in zip(got, wrong)) > 1e-3


def test_events_tighten_with_the_tolerance(model):
    """The event times are located on the interpolant: their error follows the engine's tolerance."""
    want = [t for t, _ in expected_events("ball")]
    errors = []
    for rtol in (1e-6, 1e-11):
        run = _run(model, rtol=rtol, atol=rtol * 1e-2)
        got = [t for t, b, _ in run.events if b == 1][1:]
        errors.append(max(abs(a - b) for a, b in zip(got, want)))
    assert errors[1] < errors[0] and errors[1] < 1e-8, errors


# --- a braked free rotor (law = "torque", tau = tau0 < 0): no speed law, so the model stays small ---
I_Z, TAU0, OMEGA0 = 1e-3, -0.01, 100.0
TORQUE_SCENE = f"""n = 2
rotor_mass = 1.0
eccentricity = 0.0
polar_inertia = {I_Z}
race_radius = {R}
ball_mass = {MASS}
ball_damping = 0.0
stiffness = 1000.0
damping = 1.0
rolling_resistance = {MU_R}
static_friction = {MU_S}
[speed]
law = "torque"
tau0 = {TAU0}
motor_slope = 0.0
"""


def braked(normal: str = "ball"):
    """Release time and (psi', w) a time tau after it, for the braked rotor started at OMEGA0 with both balls
    stuck.  Stuck: (I_z + 2 m R^2) psi'' = tau0 = a (I_z + 2 m R^2), the ball needs F = m R a, held while
    |a| <= mu_s psi'^2: released at psi' = W = sqrt(|a| / mu_s), slipping forward.  Slipping:
    m R^2 w' = -mu_r N, I_z psi'' = tau0 + 2 R mu_r N.  normal = "ball": N = m R w^2 (right): w = W / (1 +
    mu_r W tau), psi' = W + tau0 tau / I_z + 2 m R^2 (W - w) / I_z; "race": N = m R psi'^2 (the planted
    error), integrated numerically."""
    from scipy.integrate import solve_ivp

    a = TAU0 / (I_Z + 2 * MASS * R**2)
    W = math.sqrt(abs(a) / MU_S)
    t_release = (OMEGA0 - W) / abs(a)
    if normal == "ball":
        def state(tau):
            w = W / (1 + MU_R * W * tau)
            return W + TAU0 * tau / I_Z + 2 * MASS * R**2 * (W - w) / I_Z, w
        return t_release, state

    def rhs(_, u):
        psid, w = u
        N = MASS * R * psid**2
        return [(TAU0 + 2 * R * MU_R * N) / I_Z, -MU_R * N / (MASS * R)]

    def state(tau):
        sol = solve_ivp(rhs, (0, tau), [W, W], rtol=1e-12, atol=1e-12)
        return sol.y[0, -1], sol.y[1, -1]
    return t_release, state


@pytest.fixture(scope="module")
def torque_model(tmp_path_factory):
    path = Path(tmp_path_factory.mktemp("hybrid_torque")) / "braked.toml"
    path.write_text(TORQUE_SCENE)
    return load_model(scene=path)


def _braked_run(model, tau_after=0.8, rtol=1e-11, atol=1e-13):
    y0 = np.zeros(model.n_states)
    y0[model.index("phi_2")] = math.pi
    y0[model.rate_index(model.index("psi"))] = OMEGA0
    t_release, _ = braked()
    return hybrid.run(model, model.params(), y0, 0.0, t_release + tau_after, rtol=rtol, atol=atol), t_release + tau_after


def _braked_errors(model, run, t_end, normal):
    t_release, state = braked(normal)
    psid, w = state(t_end - t_release)
    ball1 = [(t, mode) for t, b, mode in run.events if b == 1]
    y = run.y_end
    got_psid = y[model.rate_index(model.index("psi"))]
    got_w = got_psid + y[model.rate_index(model.index("phi_1"))]
    return ball1, abs(ball1[1][0] - t_release) if len(ball1) > 1 else math.inf, abs(got_psid - psid), abs(got_w - w)


def test_braked_rotor_releases_its_balls_as_the_closed_form_says(torque_model):
    run, t_end = _braked_run(torque_model)
    assert run.status == "success", run.status
    ball1, dt, dpsid, dw = _braked_errors(torque_model, run, t_end, "ball")
    assert [m for _, m in ball1] == ["stick", "slip+"], ball1
    assert dt < 1e-8 and dpsid < 1e-7 and dw < 1e-7, (dt, dpsid, dw)
    assert [m for t, b, m in run.events if b == 2] == ["stick", "slip+"]


def test_braked_rotor_a_wrong_normal_force_is_caught(torque_model):
    run, t_end = _braked_run(torque_model)
    _, _, dpsid, dw = _braked_errors(torque_model, run, t_end, "race")
    assert max(dpsid, dw) > 1e-3, (dpsid, dw)
