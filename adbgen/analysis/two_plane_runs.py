"""Simulations of the two-plane paper on the generated models with the default engine
(`adbgen.analysis.simulate`): the brute-force diagram of Figure 12(a) (section 4.2) and the run-ups of
section 6 (Figures 15 and 16).

Vibration measure of the paper: A = the average of the rotor's displacement amplitudes at the two
points one unit length from the midspan, |q_1 +- q_2| with q_1 = X + iY, q_2 = phi_Y - i phi_X (the
paper's complex coordinates (2)); A_bar = its maximum over the window looked at.

* **Figure 12(a)** (`two_plane_fixed`, anisotropic supports (43), static imbalance eps/R = m/M = 1e-4,
  chi = 0, c_b/m = 0.01): for each Omega the rotor starts at rest, the balls at rest relative to it on
  opposite sides of each race (alpha = 0, pi); after the transient (a whole number of periods
  2 pi/Omega, so that the restart at t = 0 keeps the forcing's phase) A_bar is the maximum of A over a
  further 20 periods.  The plain rotor is the same model with balls of mass 1e-10 M (the rotor does not
  feel them).  As the paper: "for each value of Omega we let the transients die away".
* **Figures 15, 16** (`two_plane_ramp`, `two_plane_hill`, set-up (10), dynamic imbalance
  eps/R = chi = 5e-5, beta = 1, m/M = eps/R + chi = 1e-4, c_b/m = 0.01 and 0.1): the rotor at rest,
  undeflected, the balls at rest on opposite sides (theta = 0, pi in each race).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .loading import Model, load_model
from .simulate import simulate

PLAIN_MASS = 1e-10  # "plain rotor": balls too light for the rotor to feel
RTOL, ATOL = 1e-9, 1e-14


def vibration(model: Model, y: np.ndarray) -> np.ndarray:
    """A(t): mean of |q_1 + q_2| and |q_1 - q_2| (displacements at z = +-1), states on the rows."""
    X, Y, px, py = (y[model.index(n)] for n in model.module.CORE)
    q1, q2 = X + 1j * Y, py - 1j * px
    return 0.5 * (np.abs(q1 + q2) + np.abs(q1 - q2))


def _ball_values(m: float, ratio: float) -> dict:
    return {**{f"m_{k}": m for k in range(1, 5)}, "c_bt": ratio * m, "c_bb": ratio * m}


# ------------------------------------------------------------------------------ Figure 12(a)

FIG12_EPS = 1e-4
FIG12_RATIO = 0.01


@dataclass
class Orbit:
    Omega: float
    A_bar: float
    drift: float  # max |alpha_k'| over the window: 0 when the balls turn with the rotor


def settled_vibration(model: Model, values: dict, Omega: float, t_transient: float, periods: int = 20,
                      per_period: int = 64, rtol: float = RTOL) -> Orbit:
    """A_bar after the transient at constant speed Omega (non-autonomous `two_plane_fixed`)."""
    T = 2 * math.pi / Omega
    p = model.params(dict(values, Omega=Omega))
    y0 = model.state({"alpha_2": math.pi, "alpha_4": math.pi})
    first = simulate(model, p, y0, t_end=math.ceil(t_transient / T) * T, rtol=rtol, atol=ATOL,
                     keep_trajectory=False)
    window = simulate(model, p, first.y_end, t_end=periods * T, rtol=rtol, atol=ATOL,
                      samples=periods * per_period + 1)
    rates = window.y[[model.index(f"{a}_dot") for a in model.leaves]]
    return Orbit(Omega, float(vibration(model, window.y).max()), float(np.abs(rates).max()))


def figure_12a(omegas, t_transient: float = 4000.0, rtol: float = RTOL) -> dict:
    """A_bar of the balancer and of the plain rotor over the Omega grid."""
    model = load_model("two_plane_fixed")
    common = {"epsilon": FIG12_EPS, "chi": 0.0, "beta": 0.0}
    abb = [settled_vibration(model, {**common, **_ball_values(FIG12_EPS, FIG12_RATIO)}, float(w), t_transient,
                             rtol=rtol) for w in omegas]
    plain = [settled_vibration(model, {**common, **_ball_values(PLAIN_MASS, FIG12_RATIO)}, float(w), t_transient,
                               rtol=rtol) for w in omegas]
    return {"Omega": np.asarray(omegas, float), "abb": abb, "plain": plain, "model": model}


def plain_limit(omegas=(10.0, 20.0, 40.0), t_transient: float = 2000.0) -> dict:
    """A_bar of the plain rotor at high speed (the paper: A_bar -> eps/R as Omega -> infinity)."""
    model = load_model("two_plane_fixed")
    values = {"epsilon": FIG12_EPS, "chi": 0.0, "beta": 0.0, **_ball_values(PLAIN_MASS, FIG12_RATIO)}
    return {float(w): settled_vibration(model, values, float(w), t_transient).A_bar for w in omegas}


def peaks(x: np.ndarray, y: np.ndarray) -> list[float]:
    """Local maxima of y(x), each refined by the parabola through it and its neighbours."""
    out = []
    for i in range(1, len(x) - 1):
        if y[i] > y[i - 1] and y[i] >= y[i + 1]:
            h = x[i + 1] - x[i]
            den = y[i - 1] - 2 * y[i] + y[i + 1]
            out.append(float(x[i] + 0.5 * h * (y[i - 1] - y[i + 1]) / den) if den else float(x[i]))
    return out


# ------------------------------------------------------------------------------ Figures 15, 16

RUNUP_EPS = 5e-5  # eps/R = chi, so m/M = eps/R + chi = 1e-4
RUNUP_MASS = 1e-4
RATIOS = (0.01, 0.1)  # c_b/m of Figures 15(a)/16 left and 15(b)/16 right


@dataclass
class RunUp:
    name: str  # the model
    ratio: float  # c_b/m
    t: np.ndarray
    spin: np.ndarray  # theta_0'(t) = Omega(t)
    ball_speeds: np.ndarray  # theta_k'(t), 4 rows
    angles: np.ndarray  # alpha_k = theta_k - theta_0, 4 rows
    A: np.ndarray
    end_speeds: np.ndarray
    end_spin: float


def spin_law(model: Model, p: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(theta_0, theta_0') of the prescribed run-up: the generated `spin` if the model has one, else
    from the parameters of the ramp (Omega_max t / t_ramp, then constant) or the Hill profile (45)."""
    get = lambda name: p[model.param_names.index(name)]  # noqa: E731
    if "t_ramp" in model.param_names:
        w, tr = get("Omega_max"), get("t_ramp")
        speed = np.where(t < tr, w * t / tr, w)
        angle = np.where(t < tr, 0.5 * w * t**2 / tr, 0.5 * w * tr + w * (t - tr))
        return angle, speed
    w, th, wc = get("Omega_max"), get("t_half"), get("Omega_cyl")
    tb = wc * t
    speed = w * tb**3 / (th**3 + tb**3)  # (45) with n = 3, the exponent of the generated model
    dt = np.diff(t, prepend=t[0])
    angle = np.cumsum(0.5 * (speed + np.r_[speed[0], speed[:-1]]) * dt)  # (for the plots only)
    return angle, speed


def run_up(name: str, ratio: float, t_end: float, m: float = RUNUP_MASS, samples: int = 30001,
           rtol: float = RTOL) -> RunUp:
    model = load_model(name)
    p = model.params({"epsilon": RUNUP_EPS, "chi": RUNUP_EPS, "beta": 1.0, **_ball_values(m, ratio)})
    y0 = model.state({"theta_2": math.pi, "theta_4": math.pi})
    sim = simulate(model, p, y0, t_end=t_end, rtol=rtol, atol=ATOL, samples=samples)
    angle, spin = spin_law(model, p, sim.t)
    speeds = sim.y[[model.index(f"{a}_dot") for a in model.leaves]]
    thetas = sim.y[[model.index(a) for a in model.leaves]]
    _, end_spin = spin_law(model, p, np.array([t_end]))
    return RunUp(name, ratio, sim.t, spin, speeds, thetas - angle, vibration(model, sim.y),
                 sim.y_end[[model.index(f"{a}_dot") for a in model.leaves]], float(end_spin[0]))


def synchronised_from(run: RunUp, tol: float = 1e-3) -> float | None:
    """The time from which every ball turns with the rotor (|theta_k' - Omega| <= tol Omega to the end);
    None if they do not by the end."""
    lag = np.max(np.abs(run.ball_speeds - run.spin), axis=0)
    bad = np.nonzero(lag > tol * np.maximum(run.spin, 1e-12))[0]
    if not bad.size:
        return float(run.t[0])
    if bad[-1] == len(run.t) - 1:
        return None
    return float(run.t[bad[-1] + 1])
