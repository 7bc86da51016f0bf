"""Rotating frames: the substitution of fixed coordinates X, Y by axes x, y turning at a rate.

thesis (2.23)-(2.24), paper (5)-(6) for the rotor's centre; both families use it.
"""

from __future__ import annotations

import sympy as sp

from .lagrange import Coordinate, time_derivative
from .symbols import t


def rotating_substitution(rate: sp.Expr) -> tuple[tuple[Coordinate, Coordinate], dict]:
    """(2.23)-(2.24) with its first and second time derivatives, axes turning at `rate`."""
    x, y = Coordinate.make("x"), Coordinate.make("y")
    X = x.q * sp.cos(rate * t) - y.q * sp.sin(rate * t)
    Y = x.q * sp.sin(rate * t) + y.q * sp.cos(rate * t)
    Xd, Yd = (time_derivative(e, (x, y), t) for e in (X, Y))
    Xdd, Ydd = (time_derivative(e, (x, y), t) for e in (Xd, Yd))
    Xc, Yc = Coordinate.make("X"), Coordinate.make("Y")
    sub = {Xc.q: X, Yc.q: Y, Xc.qd: Xd, Yc.qd: Yd, Xc.qdd: Xdd, Yc.qdd: Ydd}
    return (x, y), sub
