"""Energy balance over a run with stick and slip (issue 37, "What must be shown"), a check of `adbgen verify`
(`REGISTERED`, listed by the family's `checks()`) run on the emitted stick/slip model through the hybrid engine
(adbgen.analysis.engines.hybrid).

A braked free rotor (law = "torque", tau = tau0 < 0) with an eccentric disc and two balls, started with both
balls stuck: they release and slip.  Along the run

    E(0) - E(t) = int_0^t ( 2 F + sum_i R mu_r N_i |phi_i'| - tau0 psi' ) dt

with E = T + V and F the Rayleigh function from the family's energies (2.7)-(2.9) (model.lagrangian), N_i the
emitted measure normal_force_i along the run (in each piece's modes), and the motor's work tau0 psi'.  A stuck
ball does no work (phi_i' = 0).  The integral is by Gauss-Legendre on each smooth piece between events (the
run's output at the nodes, from a second identical run), so the balance holds to the integrator's tolerance.
Wrong variants: the normal force taken from the race's speed (N = m R psi'^2, the registered one), and the
friction's work counted twice (a test).

`SCENE` is the one stick/slip scene the tests generate as well (tests/stick_slip_scene.py), so its model is
generated once per machine: every value in it is a parameter, and the run sets its own (`VALUES`).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import sympy as sp

from ....analysis.engines import hybrid
from ....analysis.loading import load_scene_text
from ....core.checks import DERIVED, CheckResult, Registered, timed
from ..model import lagrangian
from ..scene import Scene

MU_R, MU_S, R, MASS = 0.02, 0.05, 0.05, 0.01
I_Z, TAU0 = 1e-3, -0.01
SCENE = f"""n = 2
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
VALUES = {"eps": 2e-3, "D": 1e-5}  # the run's rotor: an eccentric disc, ball drag (the scene has neither)
START = {"phi_1": 0.3, "phi_2": math.pi, "psi_dot": 16.0}  # released near sqrt(|a| / mu_s) = 13.8 rad/s
T_END, RTOL, ATOL = 1.0, 1e-11, 1e-13
NODES, PIECE = 8, 0.01  # Gauss-Legendre nodes per piece of at most PIECE seconds
TOLERANCE = 1e-8  # of E(0); measured 8.0e-15 (the wrong normal force: 1.2e-3)


def stick_slip_model():
    """SCENE's model, from the scene cache (`load_model(scene=...)`: keyed by the scene's bytes)."""
    return load_scene_text(SCENE)


@lru_cache(maxsize=1)
def energies():
    """E = T + V and 2 F, from (2.7)-(2.9), with their arguments (q..., q'...) and the states' names."""
    lag = lagrangian(Scene.from_mapping({**_scene_mapping(), "eccentricity": VALUES["eps"],
                                         "ball_damping": VALUES["D"]}))
    coords = lag.coordinates
    args = [c.q for c in coords] + [c.qd for c in coords]
    names = [c.name for c in coords] + [f"{c.name}_dot" for c in coords]
    return names, args, sum((term.T + term.V for term in lag.terms), sp.S.Zero), 2 * lag.rayleigh()


def _scene_mapping() -> dict:
    import tomllib

    return tomllib.loads(SCENE)


def _lambdified(expr, args, values: dict):
    """expr with the model's parameter values put in (by name), as a function of args."""
    return sp.lambdify(args, expr.xreplace({s: values[str(s)] for s in expr.free_symbols if str(s) in values}),
                       "numpy")


def _run(model, t_eval=None):
    y0 = np.zeros(model.n_states)
    for name, value in START.items():
        y0[model.index(name)] = value
    p = model.params(VALUES)
    return hybrid.run(model, p, y0, 0.0, T_END, t_eval=t_eval, rtol=RTOL, atol=ATOL), p


def balance(model, friction_factor: float = 1.0, normal: str = "model") -> tuple[float, float, tuple]:
    """max over the pieces' ends of |E(0) - E(t) - W(t)| / E(0), the share of E(0) friction took, the events.
    normal = "race": the planted error, N = m R psi'^2 (the race's speed in place of the ball's, no rotor
    acceleration)."""
    names, args, energy, dissipation = energies()
    first, p = _run(model)
    if first.status != "success":
        raise RuntimeError(f"the stick/slip run failed: {first.status} at t = {first.t_end}")
    ends = sorted({0.0, T_END, *(t for t, _, _ in first.events if 0.0 < t < T_END)})
    times, weights, marks = hybrid.gauss_nodes(ends, NODES, PIECE)
    second, _ = _run(model, times)
    if len(second.t) != len(times) or second.events != first.events:
        raise RuntimeError("the second run differs from the first")
    Y = second.y.T
    values = dict(zip(model.param_names, p))
    f_energy, f_damping = (_lambdified(e, args, values) for e in (energy, dissipation))
    states = [Y[model.index(n)] for n in names]
    modes = hybrid.modes_along(model, p, first.events, times)
    radius, mu_r, m, tau0 = values["R"], values["mu_r"], values["m"], values["tau0"]
    friction = 0.0
    for k in (1, 2):
        if normal == "model":
            N = np.array([model.measure(f"normal_force_{k}", t, y, q) for t, y, q in zip(times, Y.T, modes)])
        else:
            N = m * radius * Y[model.index("psi_dot")] ** 2
        friction = friction + friction_factor * radius * mu_r * N * np.abs(Y[model.index(f"phi_{k}_dot")])
    power = f_damping(*states) + friction - tau0 * Y[model.index("psi_dot")]
    work = np.cumsum(weights * power)
    E = f_energy(*states)
    error = max(abs(E[0] - E[i] - work[i]) for i in marks) / abs(E[0])
    friction_share = float(np.sum(weights * friction)) / abs(E[0])
    return float(error), friction_share, first.events


def check(wrong: bool = False) -> CheckResult:
    """The balance over a run with stick and slip to TOLERANCE of E(0); the run must hold both a stick and a
    slip phase and friction must take more than 1e-3 of E(0).  wrong: N = m R psi'^2."""
    def run():
        error, share, events = balance(stick_slip_model(), normal="race" if wrong else "model")
        modes = [mode for _, _, mode in events]
        phases = "stick" in modes and any(mode.startswith("slip") for mode in modes)
        ok = error <= TOLERANCE and phases and share > 1e-3
        return ok, (f"E(0) - E(t) = work of damping, friction and motor to {error:.1e} of E(0) at every event and "
                    f"t = {T_END:g} s ({len(events)} events, stick and slip: {phases}; friction took {share:.2%} of "
                    f"E(0); tol {TOLERANCE:g}; hybrid-dop853 at rtol {RTOL:g})")
    return timed("stick/slip energy balance, n=2", "(2.7)-(2.9) with stick and slip (issue 37)", run)


REGISTERED = Registered("stick/slip energy balance", DERIVED, check,
                        "the normal force from the race's speed (m R psi'^2)")
