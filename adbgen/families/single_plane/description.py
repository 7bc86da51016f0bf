"""What the single-plane models say about themselves (`core.description`): roles, units, angles, the
exchange symmetries of identical balls, the thesis' parameter sets, and the closed-form steady states
of ch. 3 rendered from `steady_states` (thesis (3.6), (3.9), (3.10)), with the thesis' existence
criteria (3.14), (3.16), (3.18) as the independent check of where each is given.

Labels (as the thesis and `adbgen stability --state` use them):

    1              balanced state (3.6), phi_3.. = pi (thesis ch. 4's choice); where that leaves no
                   solution, pi, 0, pi, ... (pairs cancelling); else j balls at pi after such pairs
    2+, 2-         coincident states (3.9)
    3(k)+, 3(k)-   in-line states (3.10): k = n - m balls opposite the m coincident ones (1 <= k <= n - 1;
                   the thesis' 3 (n = 2), 3+- (n = 3), 3A = 3(2)+, 3B+- = 3(1)+- (n = 4))
"""

from __future__ import annotations

from typing import Mapping

import sympy as sp

from ...core.description import (BALL, Candidate, ClosedForm, Description, Equilibria, SteadyState, ball_exchanges,
                                 forcing_parameter, spin_measures)
from ...core.first_order import FirstOrderSystem
from . import steady_states as ss
from .symbols import Omega, delta, mu, zeta

# the in-line states' arguments: m balls at phi_1 (the rest opposite), the sign of the arccosine
ARG_M = sp.Symbol("arg_m", integer=True, positive=True)
ARG_SIGN = sp.Symbol("arg_sign", integer=True)

THESIS_5_1 = {"mu": 0.05, "Omega": 4.0, "zeta": 0.01, "beta": 0.01, "delta": 0.01}
THESIS_SETS = {
    "thesis (5.1)": THESIS_5_1,
    "thesis (5.1), beta = 0.25 (Figures 5.15(b)-5.17(b))": {**THESIS_5_1, "beta": 0.25},
    "thesis (5.1), zeta = 0.25 (Figures 5.16(a), 5.17(a))": {**THESIS_5_1, "zeta": 0.25},
}


def _positive(symbol: sp.Symbol) -> sp.Basic:
    """symbol > 0 as a guard (the symbols are declared positive, so SymPy would call it True)."""
    return sp.Gt(symbol, 0, evaluate=False)


def _balanced_candidate(n: int, A: sp.Expr, balls: sp.Expr | None) -> Candidate:
    """(3.6) with the free balls placed so that A = -delta/mu - sum cos phi_3.. (and B = 0): phi_1,2 =
    alpha +- arccos(|A|/2), where |A| <= 2; the rotor at rest (its coordinates 0).  alpha = atan2(B, A)
    = pi or 0: with free balls (all at pi or 0) B = -sum sin phi_i is 0, but it rounds to a tiny negative
    number (sin of the double pi is +1.2e-16), so with A < 0 the numbers (as the analysis layer computed
    them before these were emitted) have alpha = -pi for n >= 3: kept so (-atan2(0, A)), the same state
    either way."""
    alpha = (1 if n == 2 else -1) * sp.atan2(0, A)
    gamma = sp.acos(sp.sqrt(A**2) / 2)
    return Candidate((_positive(mu), sp.Ge(4 - A**2, 0)), {"phi_1": alpha + gamma, "phi_2": alpha - gamma}, balls)


def balanced_form(n: int) -> ClosedForm:
    """The balanced state 1 (3.6): the free angles phi_3..phi_n at pi (the thesis' ch. 4), else the
    pattern pi, 0, pi, ... (pairs cancel, so A = (n - 2) mod 2 - delta/mu), else the first n - 2 - j
    free balls in that pattern and the last j at pi with j the largest of n's parity <= delta/mu + 2
    (A = j - delta/mu): one of them exists wherever mu >= delta/n (3.14)."""
    # the same three candidates for every n (the emitted code does not grow with n; for n = 2 the
    # second is the first and the third never applies)
    alternating = sp.pi * (1 + (-1) ** BALL) / 2  # pi for phi_3 (index 2), 0 for phi_4, ...
    J = sp.floor(delta / mu) + 2
    j = J - (1 - (-1) ** (J - n)) / 2
    last = _balanced_candidate(n, -delta / mu + j, sp.Piecewise((alternating, BALL < n - j), (sp.pi, True)))
    candidates = [_balanced_candidate(n, -delta / mu + (n - 2), sp.pi),
                  _balanced_candidate(n, -delta / mu + (n - 2) % 2, alternating),
                  Candidate(last.guards + (sp.Ge(n - 2 - j, 0),), last.values, last.balls)]
    return ClosedForm("balanced", (), tuple(candidates))


def inline_form(n: int) -> ClosedForm:
    """The in-line states (3.10) (m = n: the coincident states (3.9)) for m = arg_m balls at phi_1:
    the arccosine's argument within [-1, 1]; zeta, Omega, delta > 0 (the thesis' assumption, ch. 2.2)."""
    x, y, phi1 = ss.inline_parts(n, ARG_M, ARG_SIGN)
    guards = (_positive(Omega), _positive(zeta), _positive(delta), sp.Ge(1 - ss.arccos_argument(n, ARG_M) ** 2, 0))
    return ClosedForm("inline", (ARG_M, ARG_SIGN),
                      (Candidate(guards, {"x": x, "y": y}, sp.Piecewise((phi1, BALL < ARG_M), (phi1 + sp.pi, True))),))


def thesis_steady_states(n: int) -> tuple[tuple[ClosedForm, ...], tuple[SteadyState, ...]]:
    """The closed forms and labels of ch. 3 for n balls (`closed_forms` of the analysis, emitted)."""
    forms = (balanced_form(n),) if n >= 2 else ()
    forms += (inline_form(n),)
    states = []
    if n >= 2:
        states.append(SteadyState("1", "balanced state (3.6): x = y = 0; phi_3.. = pi where that has a solution "
                                       "(thesis ch. 4), else pi, 0, pi, ...; exists where mu >= delta/n (3.14)",
                                  "balanced", (), sp.Ge(mu, delta / n)))
    exists_where = sp.And(_positive(zeta), _positive(delta))
    for sign, tag in ((1, "+"), (-1, "-")):
        states.append(SteadyState(f"2{tag}", f"coincident state 2{tag} (3.9): every ball at phi_1; exists where "
                                             "(3.16) holds (needs zeta > 0)", "inline", (n, sign),
                                  sp.And(exists_where, ss.inline_condition(n, n))))
    for k in range(1, n):
        for sign, tag in ((1, "+"), (-1, "-")):
            states.append(SteadyState(f"3({k}){tag}", f"in-line state 3({k}){tag} (3.10): {n - k} ball(s) at phi_1, {k} "
                                                      "opposite; exists where (3.18) holds (needs zeta > 0)",
                                      "inline", (n - k, sign), sp.And(exists_where, ss.inline_condition(n, n - k))))
    return forms, tuple(states)


# the thesis' names of its steady states (ch. 3): balanced 1 (3.6), coincident 2+- (3.9), in-line 3(n-m)+- (3.10)
THESIS_NAMES = {"rest": "balanced 1", "together": "coincident 2", "opposed": "in-line 3({n}-{m})"}


def _balls(system: FirstOrderSystem) -> list[str]:
    return [system.coordinates[k].name for k in system.solve.leaves]


def _own_parameters(system: FirstOrderSystem, balls: list[str]) -> Mapping[str, tuple[str, ...]] | None:
    """Each ball's own parameters (unequal balls: m_i, D_i, and mu_r_i with friction), None when they
    share theirs."""
    names = {p.name for p in system.parameters}
    if "m_1" not in names:
        return None
    return {b: tuple(f"{stem}_{k + 1}" for stem in ("m", "D", "mu_r") if f"{stem}_{k + 1}" in names)
            for k, b in enumerate(balls)}


def balanced_manifold(system: FirstOrderSystem) -> Equilibria:
    """Thesis (3.6): the balanced states x = y = 0, sum cos phi_i = -delta/mu, sum sin phi_i = 0 (identical
    balls; dimensionless rotating frame), a manifold of dimension n - 2 (n >= 3)."""
    phis = [system.coordinates[k].q for k in system.solve.leaves]
    return Equilibria("balanced states (3.6)", ("x", "y"),
                      (sp.Add(*map(sp.cos, phis)) + delta / mu, sp.Add(*map(sp.sin, phis))))


def rotor_balance(system: FirstOrderSystem, rotor: tuple[str, str]) -> Equilibria | None:
    """The balanced states of any rotating-frame model with the rotor at rest: the rotor's generalised
    forces vanish (thesis (3.6), in the model's own parameters and ball masses: M q'' = f with every rate
    and the rotor's displacement 0, where the balls' rows of f vanish too).  None where f there depends
    on time (a driven spin)."""
    eom = system.solve.eom
    at_rest = {c.q: 0 for c in eom.coordinates if c.name in rotor} | {c.qd: 0 for c in eom.coordinates}
    rows = tuple(sp.sympify(eom.forcing[eom.index(name)]).xreplace(at_rest) for name in rotor)
    if any(eom.time in r.free_symbols for r in rows):
        return None
    return Equilibria("balanced states (3.6): the rotor's generalised forces at rest vanish", rotor, rows)


def describe(system: FirstOrderSystem, *, rotating: bool, dimensionless: bool, thesis_states: bool = False,
             parameter_sets: Mapping | None = None, forcing: str | None = None,
             equilibria: Equilibria | None = None) -> Description:
    """A single-plane model's description: rotor coordinates x, y (rotating frame) or X, Y, the spin
    angle psi under a torque, ball angles phi_i; thesis_states: the closed forms of ch. 3 (the
    dimensionless rotating frame (2.25)-(2.27) only)."""
    coords = [c.name for c in system.coordinates]
    balls = _balls(system)
    rotor = ("x", "y") if rotating else ("X", "Y")
    length = "1" if dimensionless else "m"
    units = {c: (length if c in rotor else "rad") for c in coords}
    roles = {c: ("translation" if c in rotor else "spin_angle" if c == "psi" else "ball_angle") for c in coords}
    angles = tuple(c for c in coords if c not in rotor)
    params = {p.name for p in system.parameters}
    scales = {k: v for k, v in (("eccentricity", "delta" if dimensionless else "eps"),
                                ("speed", "Omega" if dimensionless else "omega")) if v in params}
    forms, states = thesis_steady_states(len(balls)) if thesis_states else ((), ())
    names = THESIS_NAMES if thesis_states else {}
    return Description(
        time_unit="1" if dimensionless else "s", units=units, roles=roles, angles=angles, amplitude=rotor,
        measures=spin_measures(system.solve.eom), forcing_frequency=forcing_parameter(system.solve.eom) if forcing is None else forcing,
        symmetries=ball_exchanges(balls, _own_parameters(system, balls)),
        parameter_sets=dict(parameter_sets or {}), scales=scales, closed_forms=forms, steady_states=states,
        steady_state_names=names,
        equilibria=equilibria if equilibria is not None or not rotating else rotor_balance(system, rotor))


def thesis_rotating(system: FirstOrderSystem) -> Description:
    """thesis_rotating_n*: (2.25)-(2.27), dimensionless, autonomous; the closed forms of ch. 3."""
    return describe(system, rotating=True, dimensionless=True, thesis_states=True, parameter_sets=THESIS_SETS,
                    forcing="", equilibria=balanced_manifold(system))


def _substituted(form: ClosedForm, sub: dict, guards=()) -> ClosedForm:
    """The closed form with the thesis' ratios written in a model's own parameters (`sub`), and more guards."""
    def relation(g):
        return type(g)(sp.sympify(g.lhs).xreplace(sub), sp.sympify(g.rhs).xreplace(sub), evaluate=False)

    cands = tuple(Candidate(tuple(guards) + tuple(relation(g) for g in c.guards),
                            {k: sp.sympify(v).xreplace(sub) for k, v in c.values.items()},
                            None if c.balls is None else sp.sympify(c.balls).xreplace(sub)) for c in form.candidates)
    return ClosedForm(form.name, form.arguments, cands)


def frictionless_balanced(system: FirstOrderSystem, d: Description) -> Description:
    """A friction scene's dimensional rotating-frame model with equal balls (one mu_r): the balanced state 1 (3.6)
    in its own parameters (mu = m/M, delta = eps/R, the rotor at rest), given where mu_r == 0.  There the balls'
    friction in slip, R mu_r N_i along the mode, vanishes and a stuck ball's row, phi_i'' = 0, holds at rest, so
    the state is an equilibrium of the frictionless model that friction scene is at mu_r = 0 (the check
    `friction, zero limit`): `adbgen design --objective residual` designs on it (docs/design.md)."""
    names = {p.name: p.symbol for p in system.parameters}
    n = len(_balls(system))
    if n < 2 or not {"m", "M", "eps", "R", "mu_r"} <= set(names) or system.solve.eom.driven:
        return d  # unequal balls (m_i, mu_r_i) or a driven spin: no closed form here
    from dataclasses import replace

    sub = {mu: names["m"] / names["M"], delta: names["eps"] / names["R"]}
    frictionless = (sp.Eq(names["mu_r"], 0, evaluate=False),)
    form = _substituted(balanced_form(n), sub, frictionless)
    exists = sp.And(sp.Ge(sub[mu], sub[delta] / n), *frictionless)
    note = ("balanced state (3.6) with mu = m/M, delta = eps/R, the rotor at rest: an equilibrium of the model's "
            "frictionless limit (given where mu_r == 0)")
    return replace(d, closed_forms=(form,), steady_states=(SteadyState("1", note, "balanced", (), exists),),
                   steady_state_names=THESIS_NAMES)


FIXED_SET = "thesis (5.1) in SI units (omega_n = 100 rad/s), k_Y = 1.2 k_X, c_Y = 1.2 c_X, gravity"


def fixed_frame(system: FirstOrderSystem, parameter_sets: Mapping | None = None) -> Description:
    """A fixed-frame model (X, Y, [psi], phi_i; dimensional).  With equal balls it gets the balanced state
    1 (3.6) in its own parameters (mu = m/M, delta = eps/R), given where there is no gravity (g = 0):
    the rotor at rest, no support force whatever the anisotropy, the balls still in the rotor's frame,
    an equilibrium of the forced system (`models.balanced_orbit_start`'s orbit)."""
    d = describe(system, rotating=False, dimensionless=False, parameter_sets=parameter_sets)
    names = {p.name: p.symbol for p in system.parameters}
    n = len(_balls(system))
    if n < 2 or "m" not in names or "omega" not in names or system.solve.eom.driven:
        return d  # unequal balls, a torque drive or a prescribed run-up (schedule): no closed form
    sub = {mu: names["m"] / names["M"], delta: names["eps"] / names["R"]}
    no_gravity = (sp.Eq(names["g"], 0, evaluate=False),) if "g" in names else ()
    form = _substituted(balanced_form(n), sub, no_gravity)
    exists = sp.And(sp.Ge(sub[mu], sub[delta] / n), *no_gravity)
    note = ("balanced state (3.6) with mu = m/M, delta = eps/R, the rotor at rest: an equilibrium of the forced "
            "model" + (" without gravity (given where g == 0)" if no_gravity else ""))
    from dataclasses import replace

    return replace(d, closed_forms=(form,), steady_states=(SteadyState("1", note, "balanced", (), exists),),
                   steady_state_names=THESIS_NAMES)
