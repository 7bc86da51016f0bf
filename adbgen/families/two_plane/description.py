"""What the two-plane models say about themselves (`core.description`): roles, units, angles, the paper's
vibration measure A, the symmetries gamma_12, gamma_34 (identical balls in a race) and gamma_r (the race
swap, (13)-(16)), the paper's parameter sets, and its closed-form steady states where exact:

    B    the balanced state of (9) for the symmetric static imbalance (section 3.2.2): the rotor at
         rest, each race's balls at alpha = pi + beta +- arccos(M eps/(4 m R)); given where the set-up
         is the symmetric one (equal balls, R_b = R_t, z_b = -z_t) without couple imbalance (chi = 0) and
         m >= m_c = M eps/(4R).  The rotor is at rest, so no support force acts: it is a steady state of
         the rotating frame and an equilibrium of the forced fixed-frame model alike.
    C3   the undamped C3 state of (29)-(30) with (31)-(32) (rotating frame): top race coincident at pi,
         bottom race at pi +- alpha_hat_34, x = Omega^2 (M eps - 2 m R (cos alpha_hat_34 + 1)) /
         (2k - Omega^2 (M + 4m)), phi_y = x/z, y = phi_x = 0; exact only without bearing damping
         (c_1 = c_2 = 0) in the symmetric set-up (l_1 = l_2, k_1 = k_2) with beta = chi = 0.
"""

from __future__ import annotations

from typing import Mapping

import sympy as sp

from ...core.description import (RACE_SWAP, Candidate, ClosedForm, Description, SteadyState, Symmetry,
                                 ball_exchanges, forcing_parameter, spin_measures)
from ...core.first_order import FirstOrderSystem
from .scene import TwoPlaneScene

_TILTS = ("phi_x", "phi_y", "phi_X", "phi_Y")


def vibration(system: FirstOrderSystem) -> sp.Expr:
    """A: the mean of the rotor's displacement amplitudes at the two points one unit from the midspan,
    |q_1 + q_2| and |q_1 - q_2| with q_1 = X + iY, q_2 = phi_Y - i phi_X (the paper's complex
    coordinates (2); in the rotating frame x, y, phi_x, phi_y, (5)-(6): the same moduli)."""
    q = {c.name: c.q for c in system.coordinates}
    X, Y, pX, pY = (q[n] for n in (("x", "y", "phi_x", "phi_y") if "x" in q else ("X", "Y", "phi_X", "phi_Y")))
    return (sp.sqrt((X + pY) ** 2 + (Y - pX) ** 2) + sp.sqrt((X - pY) ** 2 + (Y + pX) ** 2)) / 2


def race_swap(system: FirstOrderSystem, scene: TwoPlaneScene) -> tuple[Symmetry, ...]:
    """gamma_r of (15)-(16): the races exchanged ball for ball, the tilts reversed; it needs the mirrored
    parameters (R, c_b, bearings) equal, z_b = -z_t and chi = 0 (footnote 1: a misalignment breaks it)."""
    races = [[k for k, r in enumerate(scene.ball_race) if r == race] for race in (0, 1)]
    if len(scene.races) != 2 or len(races[0]) != len(races[1]):
        return ()
    names = {p.name for p in system.parameters}
    balls = [system.coordinates[k].name for k in system.solve.leaves]
    coords = {c.name for c in system.coordinates}
    mapping = {t: (t, -1) for t in _TILTS if t in coords}
    params: dict = {"chi": ("chi", -1)} if "chi" in names else {}
    for a, b in zip(*races):
        mapping[balls[a]], mapping[balls[b]] = (balls[b], 1), (balls[a], 1)
        params[f"m_{a + 1}"], params[f"m_{b + 1}"] = (f"m_{b + 1}", 1), (f"m_{a + 1}", 1)
    pairs = [("R_t", "R_b", 1), ("c_bt", "c_bb", 1), ("z_t", "z_b", -1), ("l_1", "l_2", 1)]
    pairs += [(f"{s}_1{axis}", f"{s}_2{axis}", 1) for s in ("k", "c") for axis in ("", "X", "Y")]
    for a, b, sign in pairs:
        if a in names and b in names:
            params[a], params[b] = (b, sign), (a, sign)
    return (Symmetry("gamma_r: the races exchanged, the tilt reversed (15)-(16)", RACE_SWAP, mapping, params),)


def symmetries(system: FirstOrderSystem, scene: TwoPlaneScene) -> tuple[Symmetry, ...]:
    """gamma_12, gamma_34 (each race's balls exchanged with their masses; more balls: the generators of
    every permutation within the race) and gamma_r."""
    balls = [system.coordinates[k].name for k in system.solve.leaves]
    out: tuple = ()
    for race, tag in ((0, "top race"), (1, "bottom race")):
        members = [k for k, r in enumerate(scene.ball_race) if r == race]
        out += ball_exchanges([balls[k] for k in members], {balls[k]: (f"m_{k + 1}",) for k in members},
                              tag=f" ({tag})")
    return out + race_swap(system, scene)


def _symmetric_guards(p: dict, exact_bearings: bool = False) -> tuple:
    eq = lambda a, b: sp.Eq(a, b, evaluate=False)  # noqa: E731  (a positive symbol == another stays a test)
    guards = [eq(p["chi"], 0)] + [eq(p[f"m_{k}"], p["m_1"]) for k in (2, 3, 4)]
    guards += [eq(p["R_b"], p["R_t"]), eq(p["z_b"], -p["z_t"])]
    if exact_bearings:
        guards += [eq(p["beta"], 0), eq(p["c_1"], 0), eq(p["c_2"], 0), eq(p["l_2"], p["l_1"]), eq(p["k_2"], p["k_1"])]
    return tuple(guards)


def balanced_form(system: FirstOrderSystem) -> ClosedForm:
    """B of (9), symmetric static imbalance: alpha_{1,3} = pi + beta + alpha_hat, alpha_{2,4} = pi + beta -
    alpha_hat, alpha_hat = arccos(M eps/(4 m R)) (section 3.2.2), the rotor at rest."""
    p = {q.name: q.symbol for q in system.parameters}
    ratio = p["M"] * p["epsilon"] / (4 * p["m_1"] * p["R_t"])
    guards = _symmetric_guards(p) + (sp.Gt(p["m_1"], 0, evaluate=False), sp.Gt(p["R_t"], 0, evaluate=False),
                                     sp.Ge(1 - ratio**2, 0))
    a = sp.acos(ratio)
    mean = sp.pi + p["beta"]
    balls = [system.coordinates[k].name for k in system.solve.leaves]
    return ClosedForm("B", (), (Candidate(guards, dict(zip(balls, (mean + a, mean - a, mean + a, mean - a)))),))


def c3_form(system: FirstOrderSystem) -> ClosedForm:
    """C3 of (29)-(30): the undamped symmetric set-up, top race coincident (alpha_1 = alpha_2 = pi), the
    bottom race's centre at rest ((26): phi_y = x/z, phi_x = -y/z = 0), cos alpha_hat_34 from (31)-(32)."""
    p = {q.name: q.symbol for q in system.parameters}
    M, eps, m, R, z, k, l = (p[n] for n in ("M", "epsilon", "m_1", "R_t", "z_t", "k_1", "l_1"))
    W, Jt, Jp = p["Omega"], p["J_t"], p["J_p"]
    den_x = 2 * k - W**2 * (M + 4 * m)
    den_t = 2 * k * l**2 - W**2 * (Jt + 4 * m * z**2 - Jp)
    kappa = z**2 * den_x / den_t
    cos_a = (M * eps / (2 * m * R) - (1 - kappa)) / (kappa + 1)
    ne = lambda e: sp.Ne(e, 0, evaluate=False)  # noqa: E731
    guards = _symmetric_guards(p, exact_bearings=True) + (
        sp.Gt(m, 0, evaluate=False), sp.Gt(R, 0, evaluate=False), ne(z), ne(den_x), ne(den_t), ne(kappa + 1),
        sp.Ge(1 - cos_a**2, 0))
    a = sp.acos(cos_a)
    x = W**2 * (M * eps - 2 * m * R * (cos_a + 1)) / den_x
    names = [c.name for c in system.coordinates]
    balls = [system.coordinates[j].name for j in system.solve.leaves]
    values = {"x": x, "phi_y": x / z} if "x" in names else {}
    values.update(dict(zip(balls, (sp.pi, sp.pi, sp.pi + a, sp.pi - a))))
    return ClosedForm("C3", (), (Candidate(guards, values),))


def describe(system: FirstOrderSystem, scene: TwoPlaneScene, parameter_sets: Mapping | None = None,
             steady: tuple[str, ...] = (), forcing: str | None = None, measures: Mapping | None = None) -> Description:
    """A two-plane model's description; `steady`: which closed forms it gets ("B", "C3"); `forcing`: the
    forcing frequency's parameter as declared (None: found in the equations, for a scene's model); `measures`:
    more measures (a stiction model's switching functions, `friction.measures`)."""
    coords = [c.name for c in system.coordinates]
    rotor = ("x", "y") if "x" in coords else ("X", "Y")
    roles = {c: ("translation" if c in rotor else "tilt" if c in _TILTS else "spin_angle" if c == "theta_0"
                 else "ball_angle") for c in coords}
    units = {c: ("rad" if c not in rotor else "m" if scene.si else "1") for c in coords}
    names = {p.name for p in system.parameters}
    speed = next((s for s in ("Omega", "Omega_max") if s in names), None)
    forms, states = [], []
    if "B" in steady:
        forms.append(balanced_form(system))
        p = {q.name: q.symbol for q in system.parameters}
        states.append(SteadyState("B", "balanced state B of (9), symmetric static imbalance (section 3.2.2): the "
                                       "rotor at rest, alpha = pi + beta +- arccos(M eps/(4 m R)); given where "
                                       "m_k = m, R_b = R_t, z_b = -z_t, chi = 0 and m >= m_c = M eps/(4R)", "B", (),
                                  sp.And(*_symmetric_guards(p), sp.Ge(p["m_1"], p["M"] * p["epsilon"] / (4 * p["R_t"])))))
    if "C3" in steady:
        forms.append(c3_form(system))
        states.append(SteadyState("C3", "C3 of (29)-(30) with (31)-(32): top race coincident at pi, bottom race at "
                                        "pi +- alpha_hat_34, phi_y = x/z; exact only undamped (c_1 = c_2 = 0) in the "
                                        "symmetric set-up (m_k = m, R, l, k equal, z_b = -z_t, beta = chi = 0): "
                                        "None elsewhere, where C3 may still exist", "C3"))
    return Description(
        time_unit="s" if scene.si else "1", units=units, roles=roles, angles=tuple(c for c in coords if roles[c].endswith("angle")),
        amplitude=rotor, measures={"A": vibration(system), **spin_measures(system.solve.eom), **(measures or {})},
        forcing_frequency=forcing_parameter(system.solve.eom) if forcing is None else forcing, symmetries=symmetries(system, scene),
        parameter_sets=dict(parameter_sets or {}),
        scales={"eccentricity": "epsilon", **({"speed": speed} if speed else {})},
        closed_forms=tuple(forms), steady_states=tuple(states),
        # the residual imbalance is A, not r: (9) asks forces and moments in equilibrium, and a couple leaves the
        # centre at rest (r = 0) with the rotor tilted (docs/friction.md, Residual imbalance over starts (two planes))
        residual="A")


def _ball_values(m: float, ratio: float, n: int = 4) -> dict:
    return {**{f"m_{k}": m for k in range(1, n + 1)}, "c_bt": ratio * m, "c_bb": ratio * m}


# the paper's named sets beyond a model's defaults (section 6 run-ups; Figure 12(a), section 4.2)
RUN_UP_SETS = {f"paper section 6 (Figures 15, 16): eps/R = chi = 5e-5, beta = 1, m = 1e-4, c_b/m = {r:g}":
               {"epsilon": 5e-5, "chi": 5e-5, "beta": 1.0, **_ball_values(1e-4, r)} for r in (0.01, 0.1)}
FIGURE_12A_SET = {"paper Figure 12(a) (section 4.2): eps/R = m/M = 1e-4, chi = 0, c_b/m = 0.01":
                  {"epsilon": 1e-4, "chi": 0.0, "beta": 0.0, **_ball_values(1e-4, 0.01)}}


def defaults(system: FirstOrderSystem) -> dict:
    return {q.name: q.default for q in system.parameters}
