"""Stick and slip as an event-driven hybrid system (issue 37, item 2; adbgen.analysis.engines.hybrid).

The closed-form case: a braked free rotor (law = "torque", constant torque tau0 < 0, no motor slope) with two
equal balls half a turn apart, a balanced rotor (eps = 0) and no ball drag, started at OMEGA0 with both balls
stuck.  By symmetry the rotor's centre stays at rest (X = Y = 0), so each ball's normal force is m R w^2 (w
= psi' + phi' its absolute angular speed) and the tangential force a stuck ball needs is m R psi''; the
motion is in closed form (`braked`).  The negative control takes the race's speed for the ball's in the
normal force (N = m R psi'^2) and shows that the engine's run is not that motion.  (A prescribed speed
schedule with a temporary reduction has a closed form too, four events, docs/friction.md, but its model
takes over ten minutes to generate: not a test yet.)
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbgen.analysis.engines import hybrid
from stick_slip_scene import I_Z, MASS, MU_R, MU_S, R, TAU0, braked_model

# --- a braked free rotor (law = "torque", tau = tau0 < 0): no speed law, so the model stays small ---
OMEGA0 = 100.0


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
    """The scene's model, from the scene cache (shared with the other stick/slip tests)."""
    return braked_model(tmp_path_factory)


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


def test_braked_rotor_events_tighten_with_the_tolerance(torque_model):
    """The release is located on the step's interpolant: its error follows the engine's tolerance."""
    errors = []
    for rtol in (1e-6, 1e-11):
        run, t_end = _braked_run(torque_model, rtol=rtol, atol=rtol * 1e-2)
        errors.append(_braked_errors(torque_model, run, t_end, "ball")[1])
    assert errors[1] < 1e-3 * errors[0] and errors[1] < 1e-9, errors
