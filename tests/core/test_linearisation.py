"""Stability from the exact linearisation: chapter 4's results, and the linearisation itself checked
against finite differences and against simulation."""

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane import steady_states as ss
from adbgen.families.single_plane import verify
from adbgen.core.numeric import NumericFirstOrder
from adbgen.families.single_plane.reductions import first_order, rotating_frame
from adbgen.core.linearisation import Linearisation, hopf_crossing


@pytest.mark.parametrize("result", verify.chapter4_numbers(), ids=lambda r: r.name)
def test_chapter4_results(result):
    assert result.passed, result.detail


@pytest.fixture(scope="module")
def n2():
    rot = rotating_frame(Scene(n=2))
    return Linearisation(rot), NumericFirstOrder(first_order(rot))


def test_jacobian_equals_finite_differences(n2):
    lin, f = n2
    p = lin.parameters(Omega=1.5)
    q = lin.point(ss.evaluate(ss.coincident(2, -1), dict(mu=0.05, Omega=1.5, zeta=0.01, delta=0.01)))
    assert np.max(np.abs(lin.residual(q, p))) < 1e-13
    y = np.concatenate([q, np.zeros(4)])
    fd = np.column_stack([(f(0, y + h, p) - f(0, y - h, p)) / 2e-7 for h in np.eye(8) * 1e-7])
    assert np.allclose(lin.jacobian(q, p), fd, rtol=1e-6, atol=1e-7)


def test_a_non_equilibrium_has_a_residual(n2):
    lin, _ = n2
    assert np.max(np.abs(lin.residual(np.array([0.01, 0.0, 0.3, -0.3]), lin.parameters()))) > 1e-4


def test_low_speed_coincident_states(n2):
    """Thesis ch. 4.1: for small Omega the coincident state 2- is stable, 2+ and 3 unstable."""
    lin, _ = n2
    values = dict(mu=0.05, Omega=0.5, zeta=0.01, delta=0.01)
    p = lin.parameters(Omega=0.5)
    assert lin.spectrum(lin.point(ss.evaluate(ss.coincident(2, -1), values)), p).stable
    assert not lin.spectrum(lin.point(ss.evaluate(ss.coincident(2, 1), values)), p).stable
    for Om in (0.5, 1.5, 4.0):
        state = ss.evaluate(ss.inline(2, 1, 1), {**values, "Omega": Om})
        assert not lin.spectrum(lin.point(state), lin.parameters(Omega=Om)).stable


def test_hopf_point_agrees_with_simulation(n2):
    """Just above H1 a perturbed balanced state returns, just below it leaves (n = 2, mu = 0.05)."""
    lin, f = n2
    q = lin.point(ss.evaluate(ss.balanced(2, branch=-1), dict(mu=0.05, delta=0.01)))
    h1 = hopf_crossing(lin, lambda v: q, "Omega", (1.8, 2.0))
    for Om, should_decay in ((h1 + 0.1, True), (h1 - 0.1, False)):
        y0 = np.concatenate([q, np.zeros(4)])
        y0[0] += 1e-4
        sol = solve_ivp(f, (0, 400.0), y0, args=(lin.parameters(Omega=Om),), method="DOP853", rtol=1e-10, atol=1e-13)
        final = np.hypot(*sol.y[:2, -1])
        assert (final < 1e-4) == should_decay, (Om, final)


def test_balanced_family_has_n_minus_2_zero_eigenvalues():
    for n in (3, 4):
        lin = Linearisation(rotating_frame(Scene(n=n)))
        q = lin.point(ss.evaluate(ss.balanced(n, [sp.pi] * (n - 2), branch=-1), dict(mu=0.05, delta=0.01)))
        assert lin.spectrum(q, lin.parameters(Omega=3.0)).n_zero == n - 2
