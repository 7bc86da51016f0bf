"""Simulations of the two-plane paper on the generated models (`adbgen.analysis.simulate`) with a named
engine (`ENGINE`, compiled DOP853; not the default, so that the document does not follow a change of the
default): the brute-force diagram of Figure 12(a) (section 4.2) and the run-ups of section 6 (Figures 15
and 16).

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

from ....analysis.loading import AnalysisError, Model, load_model
from ....analysis.simulate import simulate

PLAIN_MASS = 1e-10  # "plain rotor": balls too light for the rotor to feel
RTOL, ATOL = 1e-9, 1e-14


def vibration(model: Model, t, y: np.ndarray, p) -> np.ndarray:
    """A(t): mean of |q_1 + q_2| and |q_1 - q_2| (displacements at z = +-1), states on the rows: the
    generated module's measure "A" (the family declares it once, `two_plane/description.py`)."""
    return model.measure("A", t, y, p)


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


ENGINE = "cyrk-dop853"  # named: the document must not follow a change of the default engine


def engine_for(model: Model, p) -> object:
    """ENGINE, with the rhs symmetrized under the race swap gamma_r where the parameters are gamma_r-symmetric
    (chi = 0, the races' balls alike: the static imbalance of Figure 12(a)), so that the symmetric start stays
    symmetric to the last bit (engines.symmetrized); ENGINE as it is elsewhere (Figure 12(b))."""
    from ....analysis.engines.symmetrized import symmetric_parameters, symmetrized

    sym = next((s for s in model.symmetries if s["kind"] == "race-swap"), None)
    if sym is not None and symmetric_parameters(model, sym, p):
        return symmetrized(ENGINE, model, "race-swap")
    return ENGINE


def settled_vibration(model: Model, values: dict, Omega: float, t_transient: float, periods: int = 20,
                      per_period: int = 64, rtol: float = RTOL) -> Orbit:
    """A_bar after the transient at constant speed Omega (non-autonomous `two_plane_fixed`)."""
    return settled_many(model, values, [Omega], t_transient, periods, per_period, rtol)[0]


def settled_many(model: Model, values: dict, omegas, t_transient: float, periods: int = 20, per_period: int = 64,
                 rtol: float = RTOL, threads: int | None = None) -> list[Orbit]:
    """`settled_vibration` at each Omega: the transients as one batch on the compiled path (`threads` cores),
    each a whole number of periods 2 pi/Omega (so the window's restart at t = 0 keeps the forcing's phase),
    then the windows."""
    from ....analysis.simulate import simulate_many

    omegas = [float(w) for w in omegas]
    P = np.array([model.params(dict(values, Omega=w)) for w in omegas])
    y0 = model.state({"alpha_2": math.pi, "alpha_4": math.pi})
    engine = engine_for(model, P[0])
    ends = []
    for w, p in zip(omegas, P):  # t_end differs per Omega (whole periods): one batch per distinct t_end
        ends.append(math.ceil(t_transient / (2 * math.pi / w)) * (2 * math.pi / w))
    Y = np.zeros((len(omegas), model.n_states))
    for t_end in sorted(set(ends)):
        rows = [i for i, e in enumerate(ends) if e == t_end]
        ens = simulate_many(model, P[rows], np.repeat(y0[None], len(rows), axis=0), t_end=t_end, rtol=rtol, atol=ATOL,
                            engine=engine, threads=threads, measures=False)
        bad = [omegas[i] for i, st in zip(rows, ens.status) if st != "success"]
        if bad:
            raise AnalysisError(f"Figure 12 transient failed at Omega = {bad}")
        Y[rows] = ens.y_end
    out = []
    for w, p, y in zip(omegas, P, Y):
        T = 2 * math.pi / w
        window = simulate(model, p, y, t_end=periods * T, rtol=rtol, atol=ATOL, samples=periods * per_period + 1,
                          engine=engine)
        rates = window.y[[model.rate_index(k) for k in model.role_indices("ball_angle")]]
        out.append(Orbit(w, float(vibration(model, window.t, window.y, p).max()), float(np.abs(rates).max())))
    return out


def figure_12a(omegas, t_transient: float = 4000.0, rtol: float = RTOL, with_plain: bool = True,
               dynamic: bool = False) -> dict:
    """A_bar of the balancer and (with_plain) of the plain rotor over the Omega grid: the static imbalance of
    Figure 12(a), or (dynamic) the dynamic imbalance of Figure 12(b) (eps/R = chi = 5e-5, beta = 1,
    m/M = eps/R + chi)."""
    model = load_model("two_plane_fixed")
    if dynamic:
        common, mass = {"epsilon": FIG12_EPS / 2, "chi": FIG12_EPS / 2, "beta": 1.0}, FIG12_EPS
    else:
        common, mass = {"epsilon": FIG12_EPS, "chi": 0.0, "beta": 0.0}, FIG12_EPS
    abb = settled_many(model, {**common, **_ball_values(mass, FIG12_RATIO)}, omegas, t_transient, rtol=rtol)
    plain = settled_many(model, {**common, **_ball_values(PLAIN_MASS, FIG12_RATIO)}, omegas, t_transient,
                         rtol=rtol) if with_plain else []
    return {"Omega": np.asarray(omegas, float), "abb": abb, "plain": plain, "model": model}


def plain_limit(omegas=(10.0, 20.0, 40.0), t_transient: float = 2000.0) -> dict:
    """A_bar of the plain rotor at high speed (the paper: A_bar -> eps/R as Omega -> infinity)."""
    model = load_model("two_plane_fixed")
    values = {"epsilon": FIG12_EPS, "chi": 0.0, "beta": 0.0, **_ball_values(PLAIN_MASS, FIG12_RATIO)}
    return {float(w): settled_vibration(model, values, float(w), t_transient).A_bar for w in omegas}


def balanced_orbit(model: Model, values: dict) -> np.ndarray:
    """B of `two_plane_fixed` (static imbalance, two equal balls a race): the rotor at rest, the balls at
    alpha = pi +- arccos(m_c/m), m_c = M eps/(4R) ((9)); a constant state, so a periodic orbit of the forced
    system with any period (no support force acts)."""
    p = model.params(values)
    get = lambda name: p[model.param_names.index(name)]  # noqa: E731
    a = math.acos(get("M") * get("epsilon") / (4 * get("R_t") * get("m_1")))
    return model.state(dict(zip(model.leaves, (math.pi + a, math.pi - a, math.pi + a, math.pi - a))))


def balanced_state(model: Model, values: dict, tol: float = 1e-13) -> np.ndarray:
    """B of `two_plane_fixed` for any imbalance (static, or dynamic: chi != 0, Figure 12(b)): the rotor at rest,
    the balls at the constant angles alpha_k where the balls' centrifugal forces and moments cancel the
    imbalance's ((9), both planes), so that no support force acts at any speed.  Solved (scipy fsolve) for the
    ball angles from the rotor's accelerations at t = 0 (two complex balance conditions, four real equations;
    the forcing turns with Omega t, so t = 0 stands for every t), starting from the static closed form
    (`balanced_orbit` with the whole imbalance as eps/R); raises AnalysisError where the balls cannot balance."""
    from scipy.optimize import fsolve

    if values.get("chi", 0.0) == 0.0:
        return balanced_orbit(model, values)
    p = model.params(dict(values, Omega=1.0))
    rotor = [model.state_names.index(n + "_dot") for n in model.state_names[:4]]
    guess = balanced_orbit(model, dict(values, epsilon=values["epsilon"] + values["chi"], chi=0.0))
    scale = 1.0 / max(abs(values["epsilon"]), abs(values["chi"]))

    def residual(a):
        return np.asarray(model.module.rhs(0.0, model.state(dict(zip(model.leaves, a))), p))[rotor] * scale

    a = fsolve(residual, [guess[model.index(k)] for k in model.leaves], xtol=1e-14, full_output=True)[0]
    if np.abs(residual(a)).max() > tol:
        raise AnalysisError(f"B not found for {values}: the balance conditions leave {np.abs(residual(a)).max():.1e}")
    return model.state(dict(zip(model.leaves, a)))


def floquet(model: Model, values: dict, Omega: float, rtol: float = 1e-11) -> tuple[np.ndarray, np.ndarray]:
    """Floquet multipliers and eigenvectors of B (`balanced_state`) at constant speed Omega: the monodromy matrix
    over T = 2 pi/Omega of Phi' = J(t) Phi, J the generated jac along the (constant) orbit (scipy DOP853)."""
    from scipy.integrate import solve_ivp

    p = model.params(dict(values, Omega=Omega))
    y = balanced_state(model, values)
    n = model.n_states
    jac = model.module.jac
    sol = solve_ivp(lambda t, z: (np.asarray(jac(t, y, p)) @ z.reshape(n, n)).ravel(), (0.0, 2 * math.pi / Omega),
                    np.eye(n).ravel(), method="DOP853", rtol=rtol, atol=rtol * 1e-2)
    return np.linalg.eig(sol.y[:, -1].reshape(n, n))


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
    radius: float = 1.0  # the races' radius R (the balls' inertia m R^2: `reproduce.following_lag`)


def spin_law(model: Model, p: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(theta_0, theta_0') of the prescribed run-up at the times t: the generated module's measures
    "spin_angle" and "spin_rate" (the run-up law the family derived the model with: the ramp, or the
    Hill profile (45)); they depend on t and p only."""
    t = np.atleast_1d(np.asarray(t, float))
    y = np.zeros((model.n_states, len(t)))
    return model.measure("spin_angle", t, y, p), model.measure("spin_rate", t, y, p)


def run_up(name: str, ratio: float, t_end: float, m: float = RUNUP_MASS, samples: int = 30001,
           rtol: float = RTOL, phase: float = 0.0, offset: float = 0.0, mass_spread: float = 0.0) -> RunUp:
    """The run-up from rest, the balls of each race at `phase` and `phase` + pi (+ `offset`: the second ball of
    each race moved, a start that is not exactly opposite, as no physical start is; `mass_spread`: the second
    ball of each race heavier by that fraction, balls that are not exactly alike)."""
    model = load_model(name)
    values = {"epsilon": RUNUP_EPS, "chi": RUNUP_EPS, "beta": 1.0, **_ball_values(m, ratio)}
    if mass_spread:
        values.update(m_2=m * (1 + mass_spread), m_4=m * (1 + mass_spread))
    p = model.params(values)
    y0 = model.state({"theta_1": phase, "theta_2": phase + math.pi + offset, "theta_3": phase,
                      "theta_4": phase + math.pi + offset})
    sim = simulate(model, p, y0, t_end=t_end, rtol=rtol, atol=ATOL, samples=samples, engine=ENGINE)
    angle, spin = spin_law(model, p, sim.t)
    balls = list(model.role_indices("ball_angle"))
    rates = [model.rate_index(k) for k in balls]
    _, end_spin = spin_law(model, p, np.array([t_end]))
    return RunUp(name, ratio, sim.t, spin, sim.y[rates], sim.y[balls] - angle, vibration(model, sim.t, sim.y, p),
                 sim.y_end[rates], float(end_spin[0]), float(p[model.param_names.index("R_t")]))


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


# ------------------------------------------------------------------ after the ramp: constant speed

def to_rotating(fixed: Model, y: np.ndarray, theta0: float, omega: float, rotating: Model) -> np.ndarray:
    """A state of a fixed-frame run-up model (X, Y, phi_X, phi_Y, theta_k and rates) as a state of the
    rotating-frame model at spin angle theta0 and speed omega: r = q e^{-i theta0} ((5)-(6)), alpha_k =
    theta_k - theta0."""
    v = dict(zip(fixed.state_names, y))
    turn = np.exp(-1j * theta0)
    q1, q1d = v["X"] + 1j * v["Y"], v["X_dot"] + 1j * v["Y_dot"]
    q2, q2d = v["phi_Y"] - 1j * v["phi_X"], v["phi_Y_dot"] - 1j * v["phi_X_dot"]
    r1, r2 = q1 * turn, q2 * turn
    r1d, r2d = (q1d - 1j * omega * q1) * turn, (q2d - 1j * omega * q2) * turn
    out = {"x": r1.real, "y": r1.imag, "phi_y": r2.real, "phi_x": -r2.imag,
           "x_dot": r1d.real, "y_dot": r1d.imag, "phi_y_dot": r2d.real, "phi_x_dot": -r2d.imag}
    for k, name in enumerate(fixed.leaves):
        out[rotating.leaves[k]] = v[name] - theta0
        out[rotating.leaves[k] + "_dot"] = v[name + "_dot"] - omega
    return rotating.state(out)


def coincident_from(run: RunUp) -> float | None:
    """The time from which the two balls of each race have exactly the same angle (to the last bit)."""
    same = (run.angles[0] == run.angles[1]) & (run.angles[2] == run.angles[3])
    bad = np.nonzero(~same)[0]
    if bad.size and bad[-1] == len(run.t) - 1:
        return None
    return float(run.t[bad[-1] + 1]) if bad.size else float(run.t[0])


def after_ramp(ratio: float, t_more: float = 6000.0, kick: float = 1e-9, rtol: float = RTOL) -> dict:
    """The ramp of Figure 15 continued at the constant speed Omega_max in the rotating frame
    (`two_plane_rotating`, autonomous there): the end state's steady state and spectrum (Newton), and the
    run from it as it is, then from where that settled with balls 1 and 3 (one in each race) moved by
    `kick` rad."""
    from ....analysis.steady import refine

    fixed = load_model("two_plane_ramp")
    rotating = load_model("two_plane_rotating")
    run = run_up("two_plane_ramp", ratio, 6000.0, rtol=rtol)
    theta0, _ = spin_law(fixed, fixed.params(), np.array([6000.0]))
    omega = float(run.spin[-1])
    values = {"Omega": omega, "epsilon": RUNUP_EPS, "chi": RUNUP_EPS, "beta": 1.0, **_ball_values(RUNUP_MASS, ratio)}
    p = rotating.params(values)
    y = to_rotating(fixed, _end_state(fixed, ratio, rtol), float(theta0[0]), omega, rotating)
    out = {"coincident_from": coincident_from(run), "A_end_ramp": float(run.A[-1]), "kick": kick, "omega": omega}
    sim = simulate(rotating, p, y, t_end=t_more, rtol=rtol, atol=ATOL, samples=int(t_more) + 1, engine=ENGINE)
    A = vibration(rotating, sim.t, sim.y, p)
    out["as_is"] = {"A_end": float(A[-1]), "t": sim.t, "A": A}
    try:  # where the run settled: a steady state of the rotating frame?
        st = refine(rotating, p, sim.y_end)
        out.update(unstable=st.n_unstable, leading=[complex(z) for z in st.transverse[:2]],
                   moved=float(np.abs(st.y - sim.y_end).max()))
    except AnalysisError as exc:
        out.update(unstable=None, leading=[], moved=None, newton=str(exc))
    y1 = sim.y_end.copy()
    y1[[rotating.index(rotating.leaves[0]), rotating.index(rotating.leaves[2])]] += kick  # one ball a race
    sim = simulate(rotating, p, y1, t_end=t_more, rtol=rtol, atol=ATOL, samples=int(t_more) + 1, engine=ENGINE)
    A = vibration(rotating, sim.t, sim.y, p)
    out["kicked"] = {"A_end": float(A[-1]), "t": sim.t, "A": A}
    return out


def _end_state(fixed: Model, ratio: float, rtol: float) -> np.ndarray:
    p = fixed.params({"epsilon": RUNUP_EPS, "chi": RUNUP_EPS, "beta": 1.0, **_ball_values(RUNUP_MASS, ratio)})
    y0 = fixed.state({"theta_2": math.pi, "theta_4": math.pi})
    return simulate(fixed, p, y0, t_end=6000.0, rtol=rtol, atol=ATOL, keep_trajectory=False, engine=ENGINE).y_end
