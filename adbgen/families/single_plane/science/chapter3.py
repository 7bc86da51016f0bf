"""Thesis ch. 3 recomputed on the generated models (issue 36: until now only in tests and `adbgen verify`,
which re-evaluate the thesis' closed forms): where the coincident states 2+- (3.16, Fig. 3.1) and the in-line
states 3(3-2)+- (3.18, Fig. 3.2) cease to exist, from the generated module's own steady states (found or not at
each Omega, bisected), and the balanced positions (3.6) the thesis prints in ch. 5 (Newton-polished members of
the family).  Prose: templates/chapter3.md.j2.
"""

from __future__ import annotations

import math

import numpy as np

from ....analysis.loading import load_model
from .balanced import family_member

# (source, n, the model's state, printed Omega_c1, Omega_c2) at mu = 0.05, zeta = delta = 0.01
CRITICAL = (("(3.16), Fig. 3.1: 2+-", 3, "2+", 0.8114, 1.0717),
            ("(3.18), Fig. 3.2: 3(3-2)+-", 3, "3(2)+", 0.8909, 0.9761))
# (source, n, which member, printed phi_1)
POSITIONS = (("(5.2) (sign corrected, docs/errata.md)", 2, "phi_3.. none", 1.67096374795646),
             ("section 5.1.2, phi_3 = 0", 3, 0.0, 2.21429743558818),
             ("section 5.1.2, phi_3 = pi", 3, math.pi, 1.15927948072741),
             ("section 5.1.2, phi_3 = phi_4 = pi", 4, "closed form", 0.45102681179626))


def existence_bounds(n: int, state: str, lo: float = 0.5, hi: float = 1.5, count: int = 201,
                     tol: float = 1e-11) -> list[float]:
    """The Omega in [lo, hi] where the model's closed-form `state` appears or disappears (found / not found by
    the generated module's `steady_state`), each bisected to `tol`."""
    model = load_model(f"thesis_rotating_n{n}")

    def exists(w: float) -> bool:
        return model.steady_state(state, model.params({"Omega": float(w)})) is not None

    ws = np.linspace(lo, hi, count)
    ex = [exists(w) for w in ws]
    out = []
    for i in range(count - 1):
        if ex[i] == ex[i + 1]:
            continue
        a, b = float(ws[i]), float(ws[i + 1])
        while b - a > tol:
            m = 0.5 * (a + b)
            a, b = (m, b) if exists(m) == ex[i] else (a, m)
        out.append(0.5 * (a + b))
    return out


def balanced_position(n: int, member) -> float:
    """|phi_1| of the balanced state at (5.1): the model's closed form ("1": phi_3.. = pi), or the n = 3 family's
    member with phi_3 = `member`, Newton-polished."""
    from ....analysis.attractors import newton

    model = load_model(f"thesis_rotating_n{n}")
    p = model.params({})
    seed = family_member(model, {}, member) if isinstance(member, float) else model.steady_state("1", p)
    y = newton(model, np.asarray(seed, float), p)
    return abs(float((y[model.index("phi_1")] + math.pi) % (2 * math.pi) - math.pi))


def compute() -> dict:
    from .published import printed_half_unit

    critical = [(src, n, state, (c1, c2), existence_bounds(n, state)) for src, n, state, c1, c2 in CRITICAL]
    positions = [(src, n, pub, balanced_position(n, member)) for src, n, member, pub in POSITIONS]
    return {"critical": critical, "positions": positions,
            "speeds_agree": all(len(ours) == 2 and all(abs(b - a) <= printed_half_unit(a) for a, b in zip(pub, ours))
                                for *_, pub, ours in critical),
            "positions_agree": all(abs(ours - pub) <= 5e-15 * 10 for *_, pub, ours in positions),
            "coincident": coincident()}


def lines(res: dict) -> list[str]:
    from .templates import render

    values = {k: v for k, v in res.items() if k != "coincident"}
    out = render("chapter3", **values)
    return out + ([""] + coincident_lines(res["coincident"]) if "coincident" in res else [])


# ----------------------------------------------------- ch. 4: where the coincident state 2- is stable

COINCIDENT_MUS = (0.05, 0.0025)  # the two lines of (Omega, mu) the thesis' text reads 2- on (Figs. 5.12-5.14 (a), (d))


def coincident_windows(n: int, mu: float, lo: float = 0.05, hi: float = 6.0, count: int = 1191,
                       tol: float = 1e-9) -> list[tuple[float, float]]:
    """The Omega intervals of [lo, hi] on which the coincident state 2- (the generated module's closed form)
    exists and is linearly stable at mu (zeta = beta = delta = 0.01), each end bisected to `tol`; an interval
    reaching lo or hi is cut there."""
    from .one_parameter import state_intervals

    return state_intervals(n, "2-", "Omega", {"mu": mu}, count=count, tol=tol, span=(lo, hi))["stable"]


def coincident(ns=(2, 3, 4)) -> dict:
    return {(n, mu): coincident_windows(n, mu) for n in ns for mu in COINCIDENT_MUS}


# (the thesis' statement, n, mu, Omega): 2- stable there
COINCIDENT_STATEMENTS = (
    ("section 5.2.1, Figs. 5.12-5.14 (a): \"attracted to the stable coincident state 2-\"", (2, 3, 4), 0.05, 0.5),
    ("section 5.2.1, Figs. 5.12(d), 5.13(d): 2- \"is stable for Omega = 4 and mu = 0.0025, in both cases n = 2 and "
     "n = 3\"", (2, 3), 0.0025, 4.0))


def split_at_pitchfork_hopf(windows: dict) -> bool:
    """Whether 2- of n = 4 at mu = mu_c = 0.0025 is stable on exactly two Omega windows: there the coincident state
    is also the balanced one, and the gap between the windows runs from one pitchfork-Hopf point of (4.1)-(4.2) to
    the other (thesis: 1.0079598 where H2- ends, 1.338096); the text names those ends only when this holds."""
    return len(windows.get((4, COINCIDENT_MUS[1]), ())) == 2


def coincident_lines(windows: dict) -> list[str]:
    from .templates import render

    checks = [(text, mu, Om, [(n, any(a <= Om <= b for a, b in windows[(n, mu)])) for n in ns])
              for text, ns, mu, Om in COINCIDENT_STATEMENTS]
    return render("coincident", windows=windows, checks=checks, lo=0.05, hi=6.0,
                  split_at_pitchfork_hopf=split_at_pitchfork_hopf(windows))
