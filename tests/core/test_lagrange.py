"""Lagrange's equations on systems whose equations are known by hand."""

import pytest
import sympy as sp

from adbgen.core import Coordinate, EnergyTerm, EquationsOfMotion, lagrange_equations, time_derivative

t = sp.Symbol("t", real=True)
m, k, c, L, g, w = sp.symbols("m k c L g w", positive=True)


def test_damped_oscillator():
    x = Coordinate.make("x")
    eom = lagrange_equations([x], [EnergyTerm("mass", T=m * x.qd**2 / 2, V=k * x.q**2 / 2, F=c * x.qd**2 / 2)], t)
    assert sp.expand(eom.residual(0) - (m * x.qdd + c * x.qd + k * x.q)) == 0


def test_pendulum_on_a_cart_is_symmetric_and_correct():
    X, th = Coordinate.make("X"), Coordinate.make("theta")
    px, py = X.q + L * sp.sin(th.q), -L * sp.cos(th.q)
    vx, vy = (time_derivative(e, [X, th], t) for e in (px, py))
    terms = [EnergyTerm("cart", T=m * X.qd**2 / 2), EnergyTerm("bob", T=m * (vx**2 + vy**2) / 2, V=m * g * py)]
    eom = lagrange_equations([X, th], terms, t)
    M = eom.mass_matrix()
    assert M == M.T
    assert sp.simplify(M[1, 1] - m * L**2) == 0  # sin^2 + cos^2 folded by the engine
    expected_theta = m * L**2 * th.qdd + m * L * sp.cos(th.q) * X.qdd + m * g * L * sp.sin(th.q)
    assert sp.expand(eom.residual(1) - expected_theta) == 0


def test_driven_coordinate_and_generalised_force():
    """A bead on a hoop spun at a prescribed angle psi(t): no equation for psi, its rates are inputs."""
    th, psi = Coordinate.make("theta"), Coordinate.make("psi")
    pos = (L * sp.cos(psi.q + th.q), L * sp.sin(psi.q + th.q))
    v = [time_derivative(e, [th, psi], t) for e in pos]
    eom = lagrange_equations([th], [EnergyTerm("bead", T=m * (v[0] ** 2 + v[1] ** 2) / 2)], t,
                             forces={"theta": -c * th.qd}, driven=[psi])
    assert sp.expand(eom.residual(0) - (m * L**2 * (th.qdd + psi.qdd) + c * th.qd)) == 0
    assert eom.size == 1


def test_from_residuals_round_trip_and_nonlinear_rejection():
    x = Coordinate.make("x")
    eom = EquationsOfMotion.from_residuals([m * x.qdd + k * x.q], [x], t)
    assert eom.mass[(0, 0)] == m and sp.expand(eom.forcing[0] + k * x.q) == 0
    with pytest.raises(ValueError):
        EquationsOfMotion.from_residuals([m * x.qdd**2 + k * x.q], [x], t)
