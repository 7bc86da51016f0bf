"""Closed-form steady states of the rotating-frame system and their existence: thesis ch. 3.

States are returned as {symbol: expression} for the coordinates x, y, phi_i of `rotating_frame`
(all rates zero).  Each is shown, in the tests, to be an exact zero of the *derived* right-hand side.

- `balanced`   (3.6): x = y = 0, sum cos phi_i = -delta/mu, sum sin phi_i = 0; phi_3..phi_n free;
- `coincident` (3.9): all balls together, states 2+-;
- `inline`     (3.10): m balls together, n - m opposite, states 3(n-m)+-;
- existence (3.14)-(3.18), the critical speeds where (3.16)/(3.18) hold with equality, and the
  wedge tips (4.1)-(4.4) where those two speeds meet (K = 0).

The arccosine/arctangent forms of (3.9)-(3.10) need zeta > 0 (the thesis assumes all parameters
positive, ch. 2.2); with zeta = 0 the arctangent is undefined.
"""

from __future__ import annotations

import math
from typing import Sequence

import sympy as sp

from ...core import Coordinate
from .symbols import Omega, delta, mu, zeta


def K(n: int, mu_=mu, Omega_=Omega):
    """(2.27)."""
    return 1 - Omega_**2 * (1 + n * mu_)


def _coords(n: int):
    x, y = Coordinate.make("x"), Coordinate.make("y")
    return x, y, [Coordinate.make(f"phi_{i + 1}") for i in range(n)]


def balanced(n: int, free_angles: Sequence[sp.Expr] | None = None, branch: int = 1) -> dict[sp.Symbol, sp.Expr]:
    """Balanced family 1 (3.6) with phi_3..phi_n = free_angles (n - 2 of them).

    phi_1,2 = alpha +- branch*gamma with alpha = atan2(B, A), gamma = acos(sqrt(A^2 + B^2)/2),
    A = -delta/mu - sum_{i>2} cos phi_i, B = -sum_{i>2} sin phi_i.
    """
    if n < 2:
        raise ValueError("one ball balances only when mu = delta (phi_1 = pi): (3.6) has no family for n = 1")
    free = list(free_angles) if free_angles is not None else [sp.Symbol(f"phi_{i + 1}", real=True)
                                                               for i in range(2, n)]
    if len(free) != n - 2:
        raise ValueError(f"the balanced family of n = {n} balls has {n - 2} free angles, got {len(free)}")
    A = -delta / mu - sum((sp.cos(a) for a in free), sp.S.Zero)
    B = -sum((sp.sin(a) for a in free), sp.S.Zero)
    alpha = sp.atan2(B, A)
    gamma = sp.acos(sp.sqrt(A**2 + B**2) / 2)
    x, y, phis = _coords(n)
    out = {x.q: sp.S.Zero, y.q: sp.S.Zero, phis[0].q: alpha + branch * gamma, phis[1].q: alpha - branch * gamma}
    out.update({p.q: a for p, a in zip(phis[2:], free)})
    return out


def inline_parts(n: int, m, sign=1) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(x, y, phi_1) of the in-line states (3.10) for m balls at phi_1 (numbers or symbols m, sign)."""
    p = 2 * m - n  # net number of balls on the side of phi_1
    Kn = K(n)
    den = Kn**2 + (2 * Omega * zeta) ** 2
    phi1 = sign * sp.acos(arccos_argument(n, m)) - sp.atan(-Kn / (2 * Omega * zeta))
    x = (Kn * Omega**2 * (p * mu * sp.cos(phi1) + delta) + 2 * p * mu * Omega**3 * zeta * sp.sin(phi1)) / den
    y = (p * Kn * mu * Omega**2 * sp.sin(phi1) - 2 * Omega * zeta * (delta * Omega**2 + p * mu * Omega**2 * sp.cos(phi1))) / den
    return x, y, phi1


def inline(n: int, m: int, sign: int = 1) -> dict[sp.Symbol, sp.Expr]:
    """In-line states 3(n-m)+- (3.10): phi_1..phi_m together, phi_{m+1}..phi_n opposite.

    m = n gives the coincident states 2+- (3.9).
    """
    if not 1 <= m <= n:
        raise ValueError(f"need 1 <= m <= n, got m = {m}, n = {n}")
    x, y, phi1 = inline_parts(n, m, sign)
    xs, ys, phis = _coords(n)
    out = {xs.q: x, ys.q: y}
    for i, ph in enumerate(phis):
        out[ph.q] = phi1 if i < m else phi1 + sp.pi
    return out


def coincident(n: int, sign: int = 1) -> dict[sp.Symbol, sp.Expr]:
    """Coincident states 2+- (3.9)."""
    return inline(n, n, sign)


def arccos_argument(n: int, m: int):
    """The argument of the arccosine in (3.9)/(3.10); the state exists where |it| <= 1."""
    p = 2 * m - n
    return -2 * p * mu * zeta * Omega / sp.sqrt((2 * Omega * zeta * delta) ** 2 + (K(n) * delta) ** 2)


def balanced_exists(n: int, mu_: float, delta_: float) -> bool:
    """(3.14): mu >= mu_c = delta/n (necessary; sufficient for n = 2 or phi_3.. = pi)."""
    return mu_ >= delta_ / n


def inline_condition(n: int, m: int):
    """(3.18) (m < n) and (3.16) (m = n) as a SymPy relation in the parameters."""
    p = 2 * m - n
    return sp.Ge(K(n) ** 2, (2 * Omega * zeta) ** 2 * ((p * mu / delta) ** 2 - 1))


def inline_exists(n: int, m: int, mu_: float, Omega_: float, zeta_: float, delta_: float) -> bool:
    """(3.18) (m < n) and (3.16) (m = n): K^2 >= (2 Omega zeta)^2 (((2m-n) mu/delta)^2 - 1)."""
    p = 2 * m - n
    Kn = 1 - Omega_**2 * (1 + n * mu_)
    return Kn**2 >= (2 * Omega_ * zeta_) ** 2 * ((p * mu_ / delta_) ** 2 - 1)


def critical_speed_polynomial(n: int, m: int):
    """K^2 - (2 Omega zeta)^2 (((2m-n) mu/delta)^2 - 1) as a polynomial in s = Omega^2."""
    s = sp.Symbol("s", positive=True)
    p = 2 * m - n
    expr = (1 - s * (1 + n * mu)) ** 2 - 4 * s * zeta**2 * ((p * mu / delta) ** 2 - 1)
    return sp.Poly(sp.expand(expr), s), s


def critical_speeds(n: int, m: int, mu_: float, zeta_: float, delta_: float) -> tuple[float, float] | None:
    """Omega_c1 < Omega_c2 bounding the speeds where 3(n-m)+- (or 2+- for m = n) do not exist.

    The roots of the quadratic in Omega^2 of `critical_speed_polynomial`; None when the states
    exist at every speed (right-hand side of (3.16)/(3.18) negative, or no real roots).
    """
    poly, s = critical_speed_polynomial(n, m)
    coeffs = [float(c.subs({mu: mu_, zeta: zeta_, delta: delta_})) for c in poly.all_coeffs()]
    a2, a1, a0 = coeffs
    disc = a1 * a1 - 4 * a2 * a0
    if ((2 * m - n) * mu_ / delta_) ** 2 - 1 <= 0 or disc < 0:
        return None
    roots = sorted(((-a1 - math.sqrt(disc)) / (2 * a2), (-a1 + math.sqrt(disc)) / (2 * a2)))
    return math.sqrt(roots[0]), math.sqrt(roots[1])


def wedge_tip(n: int, m: int, delta_: float) -> tuple[float, float]:
    """(4.1)-(4.4): where Omega_c1 = Omega_c2: mu = delta/(2m - n) and K = 0, Omega = 1/sqrt(1 + n mu)."""
    p = 2 * m - n
    if p <= 0:
        raise ValueError("the in-line states with 2m <= n exist at every speed: no wedge")
    mu_tip = delta_ / p
    return mu_tip, 1.0 / math.sqrt(1.0 + n * mu_tip)


def wrap_angle(a: float) -> float:
    """An angle in (-pi, pi]."""
    a = math.remainder(a, 2 * math.pi)
    return math.pi if a == -math.pi else a


def evaluate(state: dict[sp.Symbol, sp.Expr], values: dict[str, float]) -> dict[str, float]:
    """Numbers for a closed-form state at parameter values {name: value}; angles wrapped."""
    subs = {s: values[s.name] for s in (mu, Omega, zeta, delta) if s.name in values}
    out = {}
    for sym, expr in state.items():
        value = complex(sp.sympify(expr).xreplace(subs).evalf(30))
        if abs(value.imag) > 1e-12 * max(1.0, abs(value.real)):
            raise ValueError(f"{sym} is not real here: the state does not exist at these parameters")
        out[sym.name] = wrap_angle(value.real) if sym.name.startswith("phi_") else value.real
    return out


def residual_at(eom, state: dict[sp.Symbol, sp.Expr]) -> list[sp.Expr]:
    """The forcing f of M q'' = f at a state at rest (all rates zero): zero at a steady state.

    zeta is taken positive here, as (3.9)-(3.10) require.
    """
    rest = {c.qd: sp.S.Zero for c in eom.coordinates}
    zeta_positive = {zeta: sp.Symbol("zeta", positive=True)}
    return [f.xreplace(rest).xreplace(state).xreplace(zeta_positive) for f in eom.forcing]


def is_steady_state(eom, state: dict[sp.Symbol, sp.Expr]) -> bool:
    """Exact: every row of the derived right-hand side vanishes identically at the state."""
    from ...core import is_identity

    return all(is_identity(r) for r in residual_at(eom, state))
