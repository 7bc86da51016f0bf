"""The Jacobi integral of the rotating frame: exact rate identity and conservation along a trajectory."""

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from adbgen.core import is_identity
from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane import verify
from adbgen.families.single_plane.jacobi import rotating_lagrangian, undamped
from adbgen.core.numeric import NumericFirstOrder
from adbgen.families.single_plane.reductions import thesis_chain


@pytest.mark.parametrize("n", (1, 2, 3, 4, 6))
def test_rate_of_h_is_minus_rayleigh_power_identically(n):
    result = verify.jacobi(n)
    assert result.passed, result.detail


def test_rate_identity_would_catch_a_wrong_integral():
    rl = rotating_lagrangian(Scene(n=2))
    _, rate = rl.jacobi_rate_identities()
    x_dot = sp.Symbol("x_dot", real=True)
    assert is_identity(undamped(rate))
    assert not is_identity(undamped(rate) + sp.Symbol("Omega", positive=True) * x_dot**3)


def _h_along(n, y0, p_over, t_end):
    system = thesis_chain(n)["first_order"]
    f = NumericFirstOrder(system)
    p = f.defaults.copy()
    for name, value in p_over.items():
        p[f.parameter_names.index(name)] = value
    h = sp.lambdify([[sp.Symbol(s, real=True) for s in f.state_names], [q.symbol for q in system.parameters]],
                    rotating_lagrangian(Scene(n=n)).jacobi_integral())
    sol = solve_ivp(f, (0, t_end), y0, args=(p,), method="DOP853", rtol=1e-12, atol=1e-14)
    assert sol.success
    return np.array([h(sol.y[:, i], p) for i in range(sol.y.shape[1])])


@pytest.mark.parametrize("n", (2, 3))
def test_h_conserved_without_damping(n):
    """zeta = beta = 0, DOP853 at rtol 1e-12: |h(t) - h(0)| <= 1e-9 |h(0)| over 100 time units."""
    rng = np.random.default_rng(n)
    y0 = np.concatenate([rng.normal(0, 0.05, 2), rng.uniform(-np.pi, np.pi, n), rng.normal(0, 0.1, 2 + n)])
    hs = _h_along(n, y0, {"zeta": 0.0, "beta": 0.0}, 100.0)
    assert abs(hs[0]) > 1e-3
    assert np.max(np.abs(hs - hs[0])) <= 1e-9 * abs(hs[0])


def test_h_changes_by_the_rayleigh_work_with_damping():
    """With damping, h(T) - h(0) = -int_0^T q'.dF/dq' dt (not monotone: the rotor's damping acts in the
    fixed frame, so in the rotating frame it also does work through the frame's rotation)."""
    n = 2
    system = thesis_chain(n)["first_order"]
    f = NumericFirstOrder(system)
    p = f.defaults.copy()
    p[f.parameter_names.index("zeta")] = 0.05
    p[f.parameter_names.index("beta")] = 0.05
    rl = rotating_lagrangian(Scene(n=n))
    args = [[sp.Symbol(s, real=True) for s in f.state_names], [q.symbol for q in system.parameters]]
    h = sp.lambdify(args, rl.jacobi_integral())
    power = sp.lambdify(args, sum(c.qd * sp.diff(rl.F, c.qd) for c in rl.eom.coordinates))

    def augmented(t, z):
        return np.append(f(t, z[:-1], p), -power(z[:-1], p))

    y0 = np.array([0.02, -0.01, 0.5, -2.0, 0.1, 0.0, 0.3, -0.1])
    sol = solve_ivp(augmented, (0, 50.0), np.append(y0, 0.0), method="DOP853", rtol=1e-12, atol=1e-14)
    work = sol.y[-1, -1]
    change = h(sol.y[:-1, -1], p) - h(y0, p)
    assert abs(work) > 1e-3
    assert abs(change - work) <= 1e-9 * abs(work)
