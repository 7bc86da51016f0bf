"""The D4-equivariant pitchfork of the symmetric set-up: paper section 3.2, (17)-(39).

a_1 and a_2 are found by the paper's method, but from the *derived* steady-state equations: the
best quadratic approximations m - m_c = (a_1 + a_2) alpha_hat^2 of the balanced branch B and
m - m_c = a_1 alpha_hat^2 of the branch C3 (one race coincident, the other split), compared with the
normal form's (21)-(22).  Each branch is an implicit equation E(m, alpha_hat) = 0, even in alpha_hat,
so m = m_c + m_2 alpha_hat^2 + O(4) with m_2 = -(1/2) E_aa / E_m at (m_c, 0): exact, no series
truncation of a closed form is needed.

- B (23): r = 0, alpha_{1,2} = alpha_{3,4} = pi +- alpha_hat (the balance (9) of a static imbalance);
- C3 (24)-(33): undamped, y = phi_x = 0, phi_y = x/z (the bottom race centre at rest, (26)),
  alpha_1 = alpha_2 = pi, alpha_{3,4} = pi +- alpha_hat (30); x eliminated between the x and phi_y rows.

Stability (35)-(38) is the normal form's Jacobian (36) at the branches.  The unfolding (39) by a
misalignment chi: the pitchforks of the coincident state C1 where one race starts to split are at
m_t, m_b, found the same way (`unfolding_masses`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from ...references import two_plane_2011 as paper
from .reductions import at_rest, rotating_frame
from .scene import TwoPlaneScene
from .symbols import R, TwoPlaneSymbols, c, k, l, m, symmetric_substitution, z

a_hat = sp.Symbol("alpha_hat", real=True)
mu, a1, a2, v1, v2 = sp.symbols("mu a_1 a_2 v_1 v_2", real=True)


@dataclass(frozen=True)
class SymmetricModel:
    """The derived rotating-frame equations (7)-(8) with the section-3 symbols."""

    eom: object
    s: TwoPlaneSymbols

    def rows_at_rest(self, state: dict, extra: dict | None = None) -> dict[str, sp.Expr]:
        names = [c_.name for c_ in self.eom.coordinates]
        rows = at_rest(self.eom, {**{sp.Symbol(k_, real=True): v for k_, v in state.items()}, **(extra or {})})
        return dict(zip(names, rows))


@lru_cache(maxsize=1)
def symmetric_model() -> SymmetricModel:
    scene = TwoPlaneScene()  # paper (10): the structure of section 3 (values are not used here)
    s = TwoPlaneSymbols.for_scene(scene)
    sub = symmetric_substitution(s)
    sub.update({s.beta: 0})  # the static imbalance along xi (the phase is immaterial: Figure 5)
    eom = rotating_frame(scene).map(lambda e: sp.expand(e.xreplace(sub)))
    return SymmetricModel(eom, s)


def quadratic_coefficient(E: sp.Expr, m_c: sp.Expr) -> sp.Expr:
    """m_2 of m = m_c + m_2 alpha_hat^2 + O(4) on the branch E(m, alpha_hat) = 0 (E even in alpha_hat)."""
    at = {m: m_c, a_hat: 0}
    if not sp.simplify(E.xreplace(at)) == 0:
        raise AssertionError("the branch does not pass through (m_c, 0)")
    return sp.simplify(-sp.diff(E, a_hat, 2).xreplace(at) / (2 * sp.diff(E, m).xreplace(at)))


def critical_mass(s: TwoPlaneSymbols | None = None):
    s = s or symmetric_model().s
    return s.M * s.eps / (4 * R)  # below (19)


def balanced_branch() -> tuple[dict[str, sp.Expr], sp.Expr]:
    """Rows of (7)-(8) at rest on B; returns (rows, E) with E the one row that does not vanish."""
    sm = symmetric_model()
    state = {"x": 0, "y": 0, "phi_x": 0, "phi_y": 0, "alpha_1": sp.pi + a_hat, "alpha_2": sp.pi - a_hat,
             "alpha_3": sp.pi + a_hat, "alpha_4": sp.pi - a_hat}
    rows = sm.rows_at_rest(state, {sm.s.chi: 0})
    return rows, rows["x"]


def c3_branch(chi_value=0, top_coincident: bool = True) -> tuple[dict[str, sp.Expr], sp.Expr]:
    """Rows at rest on C3 (30), undamped; returns (rows, E(m, alpha_hat)) with x eliminated.

    top_coincident: balls 1, 2 together at pi and the bottom race (z_b = -z) split, its centre at rest
    (phi_y = x/z); otherwise the mirror image (phi_y = -x/z).
    """
    sm = symmetric_model()
    x = sp.Symbol("x", real=True)
    sign = 1 if top_coincident else -1
    split = ("alpha_3", "alpha_4") if top_coincident else ("alpha_1", "alpha_2")
    state = {"y": 0, "phi_x": 0, "phi_y": sign * x / z}
    state.update({name: sp.pi for name in ("alpha_1", "alpha_2", "alpha_3", "alpha_4")})
    state.update({split[0]: sp.pi + a_hat, split[1]: sp.pi - a_hat})
    rows = sm.rows_at_rest(state, {c: 0, sm.s.chi: chi_value})
    x_sol = sp.solve(rows["x"], x)
    if len(x_sol) != 1:
        raise AssertionError("the x row of C3 is not linear in x")
    E = sp.together(sp.expand(rows["phi_y"].xreplace({x: x_sol[0]})))
    return rows, sp.numer(E)


def kappa_at_critical_mass():
    """(32) at m = m_c."""
    s = symmetric_model().s
    return paper.kappa_32(s.M, s.Jt, s.Jp, k, l, critical_mass(), z, s.Omega).xreplace({})


@lru_cache(maxsize=1)
def coefficients() -> dict[str, sp.Expr]:
    """a_1 + a_2 from B (23), a_1 from C3 (33), a_2 = the difference (34): all from the derived model."""
    m_c = critical_mass()
    a_sum = quadratic_coefficient(balanced_branch()[1], m_c)
    a_1 = quadratic_coefficient(c3_branch()[1], m_c)
    return {"a1+a2": a_sum, "a1": a_1, "a2": sp.simplify(a_sum - a_1), "m_c": m_c}


def unfolding_masses(values: dict) -> dict[str, float]:
    """(39): m_b (bottom race splits: C1 -> Ct3) and m_t (top race splits: C1 -> Cb3) on the undamped
    C1 branch with a misalignment, at numbers ``values`` {symbol: value} (chi among them).

    Each is the root near m_c of E(m, 0) = 0 of the C3-type branch (kappa depends on m, so E is a
    quadratic in m); with chi = 0 both are m_c.
    """
    s = symmetric_model().s
    m_c = float(critical_mass().xreplace(values))
    out = {}
    for name, top in (("m_b", True), ("m_t", False)):
        E = c3_branch(s.chi, top_coincident=top)[1].xreplace({a_hat: 0}).xreplace(values)
        roots = [complex(r) for r in sp.Poly(sp.expand(E), m).nroots(n=30)]
        out[name] = min((r.real for r in roots if abs(r.imag) < 1e-12), key=lambda r: abs(r - m_c))
    return out


def unfolded_slopes(values: dict) -> dict[str, float]:
    """Quadratic coefficients of the undamped branches Ct3 (born at m_b) and Cb3 (born at m_t) with the
    misalignment in ``values``; (39) approximates both by a_1."""
    masses = unfolding_masses(values)
    out = {}
    for name, top, m0 in (("Ct3", True, masses["m_b"]), ("Cb3", False, masses["m_t"])):
        E = c3_branch(symmetric_model().s.chi, top_coincident=top)[1].xreplace(values)
        at = {m: m0, a_hat: 0}
        out[name] = float(-sp.diff(E, a_hat, 2).xreplace(at) / (2 * sp.diff(E, m).xreplace(at)))
    return out


# --- the normal form itself: (20), (36)-(38) --------------------------------------------------------------
def normal_form() -> sp.Matrix:
    return paper.normal_form_20(mu, a1, a2, v1, v2)


def jacobian() -> sp.Matrix:
    """(36), computed from (20)."""
    return normal_form().jacobian([v1, v2])


def jacobian_at(branch: str) -> sp.Matrix:
    """(37) at C3 = (0, sqrt(mu/a1)) or (38) at B = (a, a), a^2 = mu/(a1 + a2)."""
    J = jacobian()
    if branch == "C3":
        at = {v1: 0, v2: sp.sqrt(mu / a1)}
    elif branch == "B":
        at = {v1: sp.sqrt(mu / (a1 + a2)), v2: sp.sqrt(mu / (a1 + a2))}
    else:
        raise ValueError(branch)
    return J.xreplace(at).applyfunc(sp.simplify)


def stable(branch: str, mu_: float, a1_: float, a2_: float) -> bool:
    """Stability on the centre manifold from the eigenvalues of (37)/(38)."""
    J = jacobian_at(branch).xreplace({mu: mu_, a1: a1_, a2: a2_})
    return all(sp.re(ev) < 0 for ev in J.eigenvals())
