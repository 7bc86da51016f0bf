"""Energy balance over a run with stick and slip (issue 37, "What must be shown"; the hybrid engine
adbgen.analysis.engines.hybrid on an emitted single-plane friction model with stiction).

A braked free rotor (law = "torque", tau = tau0 < 0) with an eccentric disc and two balls, started with both
balls stuck: they release and slip.  Along the run

    E(0) - E(t) = int_0^t ( 2 F + sum_i R mu_r N_i |phi_i'| - tau0 psi' ) dt

with E = T + V and F the Rayleigh function from the family's own energies (2.7)-(2.9) (model.lagrangian), N_i
the emitted measure normal_force_i along the run, and the motor's work tau0 psi'.  A stuck ball does no work
(phi_i' = 0).  The integral is by Gauss-Legendre on each smooth piece between events (the run's output at the
nodes, a second identical run), so the balance holds to the integrator's tolerance.  Negative controls: the
friction's work counted twice, and the normal force taken from the race's speed (m R psi'^2), are caught.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from adbgen.analysis.engines import hybrid
from adbgen.families.single_plane.model import lagrangian
from adbgen.families.single_plane.scene import Scene
from stick_slip_scene import braked_model

SCENE = {"n": 2, "rotor_mass": 1.0, "eccentricity": 2e-3, "polar_inertia": 1e-3, "race_radius": 0.05,
         "ball_mass": 0.01, "ball_damping": 1e-5, "stiffness": 1000.0, "damping": 1.0, "rolling_resistance": 0.02,
         "static_friction": 0.05, "speed": {"law": "torque", "tau0": -0.01, "motor_slope": 0.0}}
# the shared scene has eps = 0 and no ball drag: every value is a parameter, set here to SCENE's
OVERRIDES = {"eps": SCENE["eccentricity"], "D": SCENE["ball_damping"]}
T_END, RTOL, ATOL = 1.0, 1e-11, 1e-13
NODES, PIECE = 8, 0.01  # Gauss-Legendre nodes per piece of at most PIECE seconds


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    """The shared stick/slip scene's model (tests/stick_slip_scene.py), run at SCENE's values (OVERRIDES)."""
    return braked_model(tmp_path_factory)


@pytest.fixture(scope="module")
def energies():
    """E = T + V and 2 F, from (2.7)-(2.9), with their arguments (q..., q'...) and the states' names."""
    lag = lagrangian(Scene.from_mapping(SCENE))
    coords = lag.coordinates
    args = [c.q for c in coords] + [c.qd for c in coords]
    names = [c.name for c in coords] + [f"{c.name}_dot" for c in coords]
    return names, args, sum((term.T + term.V for term in lag.terms), sp.S.Zero), 2 * lag.rayleigh()


def _lambdified(expr, args, values: dict):
    """expr with the model's parameter values put in (by name), as a function of args."""
    return sp.lambdify(args, expr.xreplace({s: values[str(s)] for s in expr.free_symbols if str(s) in values}),
                       "numpy")


def _modes_along(model, p, events, times) -> list[np.ndarray]:
    """The parameters with each ball's mode (stuck_k, slip_dir_k) as the events set them, at each time: the
    measures' accelerations (X'', Y'' from the model's solve) depend on the mode."""
    out, k, current = [], 0, np.array(p, float)
    for t in times:
        while k < len(events) and events[k][0] <= t:
            _, ball, mode = events[k]
            current = current.copy()
            current[model.param_names.index(f"stuck_{ball}")] = 1.0 if mode == "stick" else 0.0
            if mode != "stick":
                current[model.param_names.index(f"slip_dir_{ball}")] = 1.0 if mode == "slip+" else -1.0
            k += 1
        out.append(current)
    return out


def _run(model, t_eval=None):
    y0 = np.zeros(model.n_states)
    y0[model.index("phi_1")], y0[model.index("phi_2")] = 0.3, math.pi
    y0[model.index("psi_dot")] = 16.0  # released near sqrt(|a| / mu_s) = 13.8 rad/s
    p = model.params(OVERRIDES)
    return hybrid.run(model, p, y0, 0.0, T_END, t_eval=t_eval, rtol=RTOL, atol=ATOL), p


def _balance(model, energies, friction_factor=1.0, normal="model"):
    """max over the pieces' ends of |E(0) - E(t) - W(t)| / E(0), the share of E(0) friction took, the events."""
    names, args, energy, dissipation = energies
    first, p = _run(model)
    assert first.status == "success", first.status
    ends = sorted({0.0, T_END, *(t for t, _, _ in first.events if 0.0 < t < T_END)})
    x, w = np.polynomial.legendre.leggauss(NODES)
    times, weights, marks = [], [], []
    for a, b in zip(ends[:-1], ends[1:]):
        pieces = max(1, math.ceil((b - a) / PIECE))
        edges = np.linspace(a, b, pieces + 1)
        for lo, hi in zip(edges[:-1], edges[1:]):
            times += list((hi + lo) / 2 + (hi - lo) / 2 * x)
            weights += list((hi - lo) / 2 * w)
        times.append(b)
        weights.append(0.0)
        marks.append(len(times))  # its index once 0.0 is put first
    times, weights = np.array([0.0] + times), np.array([0.0] + weights)
    second, _ = _run(model, times)
    assert len(second.t) == len(times) and second.events == first.events
    Y = second.y.T
    values = dict(zip(model.param_names, p))
    f_energy, f_damping = (_lambdified(e, args, values) for e in (energy, dissipation))
    states = [Y[model.index(n)] for n in names]
    modes = _modes_along(model, p, first.events, times)
    R, mu_r, m, tau0 = values["R"], values["mu_r"], values["m"], values["tau0"]
    friction = 0.0
    for k in (1, 2):
        if normal == "model":
            N = np.array([model.measure(f"normal_force_{k}", t, y, q) for t, y, q in zip(times, Y.T, modes)])
        else:  # the planted error: the race's speed in place of the ball's, no rotor acceleration
            N = m * R * Y[model.index("psi_dot")] ** 2
        friction = friction + friction_factor * R * mu_r * N * np.abs(Y[model.index(f"phi_{k}_dot")])
    power = f_damping(*states) + friction - tau0 * Y[model.index("psi_dot")]
    work = np.cumsum(weights * power)
    E = f_energy(*states)
    error = max(abs(E[0] - E[i] - work[i]) for i in marks) / abs(E[0])
    friction_share = float(np.sum(weights * friction)) / abs(E[0])
    return error, friction_share, first.events


def test_energy_balance_with_stick_and_slip(model, energies):
    error, share, events = _balance(model, energies)
    modes = [mode for _, _, mode in events]
    assert "stick" in modes and any(mode.startswith("slip") for mode in modes), events
    assert share > 1e-3, share
    assert error < 1e-8, (error, events)


def test_friction_counted_twice_is_caught(model, energies):
    error, share, _ = _balance(model, energies, friction_factor=2.0)
    assert error > 1e-4, (error, share)


def test_a_wrong_normal_force_is_caught(model, energies):
    error, _, _ = _balance(model, energies, normal="race")
    assert error > 1e-6, error
