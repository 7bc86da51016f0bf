"""The thesis' printed equations, transcribed only to be compared with the derivation.

Source: ../shared/references/thesis-multi-ball-adb-2005.txt.  Nothing in the model is built from
this module; the tests show that the derived equations equal these, term for term, as exact
identities.  Each function returns the residuals "left-hand side minus right-hand side" of the
printed equations, keyed by coordinate name.

Errata found by that comparison (each tested both ways: the corrected form is an identity, the
printed form is not):

- (2.21): the gravity term is printed -G(1 + n mu).  With G = g/(eps omega_n^2) of (2.16) and the
  scaling by M R omega_n^2 used for (2.20), it is -delta G (1 + n mu) (as (2.22) has delta G).
- (A.12)-(A.13) are not an erratum (docs/errata.md): the text *extraction* breaks the lines so that
  the last two terms that stand on the line of g, mu(-Omega^2 x - 2 Omega v) sum sin^2 - mu(-Omega^2 y
  + 2 Omega u) sum sin cos, belong to f, and g is what follows on the next line; Appendix A is correct.
  "k" in (A.3), (A.4), (A.12), (A.13) is K of (2.27).
- (5.2): printed phi_1 = arccos(delta/(2 mu)); the value given, 1.67096374795646, and (3.6) require
  phi_1 = arccos(-delta/(2 mu)).
"""

from __future__ import annotations

import sympy as sp

from ..core import Coordinate

sin, cos = sp.sin, sp.cos

# Figs. 5.20-5.22: the captions' panel list (identical in the three captions, transcribed) and the sentence of the
# text that reads the n = 4 panel: the captions call it "(d)", the figures and the text "(c)" (docs/errata.md)
PANELS_CAPTION_5_20_22 = (r"The initial positions of the balls were $\phi_1(0) = \pi/2$, and $\phi_2(0) = -\pi/2$ for "
                          r"the ADB system with two balls (a); $\phi_1(0) = \pi/3$, $\phi_2(0) = -\pi/3$, and "
                          r"$\phi_3(0) = \pi$ for the ADB system with three balls (b); $\phi_1(0) = \pi/2$, "
                          r"$\phi_2(0) = -\pi/2$, $\phi_3(0) = \pi$, and $\phi_4(0) = 0$ for the ADB system with "
                          r"four balls (d).")
N4_PANEL_SENTENCE_5_20 = "In panel (c) we can see that for four balls, the system does not achieve the balance"


def _c(name: str) -> Coordinate:
    return Coordinate.make(name)


def fixed_frame(s, n: int, spin: tuple[sp.Expr, sp.Expr, sp.Expr] | None = None,
                torque: sp.Expr | None = None) -> dict[str, sp.Expr]:
    """(2.10)-(2.13) with symbols `s` (a DimensionalSymbols); spin = (psi, psi', psi'')."""
    X, Y = _c("X"), _c("Y")
    if spin is None:
        psi = _c("psi")
        spin = (psi.q, psi.qd, psi.qdd)
    p, pd, pdd = spin
    M, eps, R, g = s.M, s.eps, s.R, s.g
    phis = [_c(f"phi_{i + 1}") for i in range(n)]
    Xdd, Ydd = X.qdd, Y.qdd
    out = {}
    out["X"] = (M * Xdd - M * eps * pd**2 * cos(p) - M * eps * pdd * sin(p)
                + sum(s.m[i] * (Xdd - R * (pdd + f.qdd) * sin(p + f.q) - R * (pd + f.qd) ** 2 * cos(p + f.q))
                      for i, f in enumerate(phis))
                + s.kX * X.q + s.cX * X.qd)  # (2.10)
    out["Y"] = (M * Ydd - M * eps * pd**2 * sin(p) + M * eps * pdd * cos(p)
                + sum(s.m[i] * (Ydd + R * (pdd + f.qdd) * cos(p + f.q) - R * (pd + f.qd) ** 2 * sin(p + f.q))
                      for i, f in enumerate(phis))
                + s.kY * Y.q + M * g + sum(s.m[i] * g for i in range(n)) + s.cY * Y.qd)  # (2.11)
    if torque is not None:
        out["psi"] = (s.I_z * pdd - M * eps * Xdd * sin(p) + M * eps * Ydd * cos(p) + M * eps**2 * pdd
                      - sum(s.m[i] * (R * (Xdd * sin(p + f.q) - Ydd * cos(p + f.q)) - R**2 * (pdd + f.qdd))
                            for i, f in enumerate(phis))
                      + M * g * eps * cos(p) + sum(s.m[i] * g * R * cos(p + f.q) for i, f in enumerate(phis))
                      - torque)  # (2.12)
    for i, f in enumerate(phis):
        out[f.name] = (-s.m[i] * R * (Xdd * sin(p + f.q) - Ydd * cos(p + f.q)) + s.m[i] * R**2 * (pdd + f.qdd)
                       + s.m[i] * g * R * cos(p + f.q) + s.D[i] * f.qd)  # (2.13)
    return out


def nondimensional(n: int, mu, Omega, zeta, beta, delta, G, t, printed: bool = False) -> dict[str, sp.Expr]:
    """(2.20)-(2.22); printed=True keeps the misprinted gravity term -G(1 + n mu) of (2.21)."""
    X, Y = _c("X"), _c("Y")
    phis = [_c(f"phi_{i + 1}") for i in range(n)]
    th = [Omega * t + f.q for f in phis]
    gravity_21 = G if printed else delta * G
    out = {
        "X": (1 + n * mu) * X.qdd + 2 * zeta * X.qd + X.q - delta * Omega**2 * cos(Omega * t)
        - mu * sum(f.qdd * sin(a) + (Omega + f.qd) ** 2 * cos(a) for f, a in zip(phis, th)),  # (2.20)
        "Y": (1 + n * mu) * Y.qdd + 2 * zeta * Y.qd + Y.q - delta * Omega**2 * sin(Omega * t)
        + mu * sum(f.qdd * cos(a) - (Omega + f.qd) ** 2 * sin(a) for f, a in zip(phis, th))
        + gravity_21 * (1 + n * mu),  # (2.21)
    }
    for f, a in zip(phis, th):
        out[f.name] = f.qdd - X.qdd * sin(a) + Y.qdd * cos(a) + delta * G * cos(a) + beta * f.qd  # (2.22)
    return out


def K_2_27(n: int, mu, Omega) -> sp.Expr:
    """(2.27)."""
    return 1 - Omega**2 * (1 + n * mu)


def rotating_frame(n: int, mu, Omega, zeta, beta, delta) -> dict[str, sp.Expr]:
    """(2.25)-(2.26) with K of (2.27)."""
    x, y = _c("x"), _c("y")
    phis = [_c(f"phi_{i + 1}") for i in range(n)]
    K = K_2_27(n, mu, Omega)
    a = 1 + n * mu
    out = {
        "x": a * x.qdd + 2 * zeta * x.qd - 2 * Omega * a * y.qd + K * x.q - 2 * Omega * zeta * y.q
        - delta * Omega**2 - mu * sum((Omega + f.qd) ** 2 * cos(f.q) + f.qdd * sin(f.q) for f in phis),
        "y": a * y.qdd + 2 * Omega * a * x.qd + 2 * zeta * y.qd + 2 * Omega * zeta * x.q + K * y.q
        - mu * sum(-f.qdd * cos(f.q) + (Omega + f.qd) ** 2 * sin(f.q) for f in phis),
    }
    for f in phis:
        out[f.name] = (f.qdd + beta * f.qd - (x.qdd - Omega**2 * x.q - 2 * Omega * y.qd) * sin(f.q)
                       + (y.qdd - Omega**2 * y.q + 2 * Omega * x.qd) * cos(f.q))  # (2.26)
    return out


def appendix_a(n: int, mu, Omega, zeta, beta, delta, printed: bool = False) -> dict[str, sp.Expr]:
    """(A.6)-(A.13) in the states (x, u, y, v, phi_i, theta_i) of (A.1)-(A.2).

    Returns a, b, c, f, g, G_1, G_2 and G_{2+i} (the latter in terms of u' and v', as (A.6) is).
    printed=True takes (A.12)-(A.13) line by line as the text extraction has them (f ends after "- mu beta
    sum theta sin", g takes the next terms), which the tests show to be wrong: a line-break artefact of the
    extraction, not of the thesis.
    """
    x, y = sp.Symbol("x", real=True), sp.Symbol("y", real=True)
    u, v = sp.Symbol("x_dot", real=True), sp.Symbol("y_dot", real=True)
    ud, vd = sp.Symbol("x_ddot", real=True), sp.Symbol("y_ddot", real=True)
    phi = [sp.Symbol(f"phi_{i + 1}", real=True) for i in range(n)]
    theta = [sp.Symbol(f"phi_{i + 1}_dot", real=True) for i in range(n)]
    K = K_2_27(n, mu, Omega)
    S = lambda seq: sum(seq, sp.S.Zero)  # noqa: E731
    a = (1 + n * mu) - mu * S(sin(p) ** 2 for p in phi)  # (A.9)
    b = mu * S(sin(p) * cos(p) for p in phi)  # (A.10)
    c = (1 + n * mu) - mu * S(cos(p) ** 2 for p in phi)  # (A.11)
    moved = (mu * (-Omega**2 * x - 2 * Omega * v) * S(sin(p) ** 2 for p in phi)
             - mu * (-Omega**2 * y + 2 * Omega * u) * S(sin(p) * cos(p) for p in phi))
    f = (-2 * zeta * u + 2 * Omega * (1 + n * mu) * v - K * x + 2 * Omega * zeta * y + delta * Omega**2
         + mu * S((Omega + th) ** 2 * cos(p) for p, th in zip(phi, theta))
         - mu * beta * S(th * sin(p) for p, th in zip(phi, theta)))  # (A.12)
    g = (-2 * Omega * (1 + n * mu) * u - 2 * zeta * v - 2 * Omega * zeta * x - K * y
         + mu * beta * S(th * cos(p) for p, th in zip(phi, theta))
         - mu * (-Omega**2 * x - 2 * Omega * v) * S(sin(p) * cos(p) for p in phi)
         + mu * (-Omega**2 * y + 2 * Omega * u) * S(cos(p) ** 2 for p in phi)
         + mu * S((Omega + th) ** 2 * sin(p) for p, th in zip(phi, theta)))  # (A.13)
    if printed:
        g = g + moved
    else:
        f = f + moved
    det = b**2 - a * c
    out = {"a": a, "b": b, "c": c, "f": f, "g": g,
           "G_1": (b * g - c * f) / det, "G_2": (b * f - a * g) / det}  # (A.7), (A.8)
    for i, (p, th) in enumerate(zip(phi, theta)):
        out[f"G_{3 + i}"] = (-beta * th + (ud - Omega**2 * x - 2 * Omega * v) * sin(p)
                             - (vd - Omega**2 * y + 2 * Omega * u) * cos(p))  # (A.6)
    return out
