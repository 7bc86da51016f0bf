"""The numba target against the symbolic model (issue: code generation, "What must be shown").

Reference: the closed-form first-order system (Cramer's rule on the full mass matrix, `FirstOrderSystem.rhs`)
and its SymPy Jacobian, lambdified: independent of the structured lowering the generated code uses.
Tolerance: norm-wise relative, max_k |a_k - b_k| <= 1e-12 max_k |b_k| at every sample.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from sampling import random_inputs

RTOL = 1e-12
SAMPLES = 1000
NS = (1, 2, 3, 4, 5, 6)
FAMILIES = ("thesis_rotating", "single_plane_fixed")


def _reference(system):
    """rhs by the closed form; Jacobian by implicit differentiation of M(q) q'' = f(q, q'):
    d(q'')/dy = M^-1 (df/dy - (dM/dy) q''), with M, f and their derivatives lambdified and M solved
    densely by numpy (no Schur structure), so neither shares code with the generated solve."""
    eom = system.solve.eom
    law = dict(eom.driven_law)
    prep = lambda e: sp.sympify(e).xreplace(law)  # noqa: E731
    states = list(system.states)
    args = (eom.time, states, [p.symbol for p in system.parameters])
    f = sp.lambdify(args, [prep(e) for e in system.rhs()], modules="numpy", cse=True)
    M = eom.mass_matrix().applyfunc(prep)
    F = sp.Matrix([prep(e) for e in eom.forcing])
    acc = sp.Matrix([c.qdd for c in eom.coordinates])
    R = F - M * acc  # zero along solutions; its y-derivative at fixed q'' gives M d(q'')/dy
    mass = sp.lambdify(args, M, modules="numpy", cse=True)
    dR = sp.lambdify(args + (list(acc),), R.jacobian(states), modules="numpy", cse=True)
    N = eom.size

    def J(t, y, p):
        a = np.asarray(f(t, y, p), float)[N:]
        out = np.zeros((2 * N, 2 * N))
        out[:N, N:] = np.eye(N)
        out[N:, :] = np.linalg.solve(np.asarray(mass(t, y, p), float), np.asarray(dR(t, y, p, a), float))
        return out

    return f, J


def _relative(a, b) -> float:
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


@pytest.mark.parametrize("family", FAMILIES)
@pytest.mark.parametrize("n", NS)
def test_rhs_and_jac_equal_the_symbolic_model(generated_model, family, n):
    module, system, _ = generated_model(family, n)
    assert module.STATE_NAMES == system.state_names
    assert module.PARAM_NAMES == tuple(p.name for p in system.parameters)
    f, J = _reference(system)
    t, y, p = random_inputs(module, SAMPLES, seed=n)
    worst_f = worst_J = 0.0
    for k in range(SAMPLES):
        worst_f = max(worst_f, _relative(module.rhs(t[k], y[k], p[k]), np.array(f(t[k], y[k], p[k]), float).ravel()))
        worst_J = max(worst_J, _relative(module.jac(t[k], y[k], p[k]), np.array(J(t[k], y[k], p[k]), float)))
    assert worst_f <= RTOL, worst_f
    assert worst_J <= RTOL, worst_J


@pytest.mark.parametrize("family", FAMILIES)
@pytest.mark.parametrize("n", (1, 3, 6))
def test_jac_equals_finite_differences_of_rhs(generated_model, family, n):
    """Central differences, h = 1e-6 (truncation O(h^2) plus roundoff ~ 1e-16 |rhs| / h): tolerance 1e-6."""
    module, _, _ = generated_model(family, n)
    t, y, p = random_inputs(module, 50, seed=100 + n)
    h = 1e-6
    for k in range(50):
        J = module.jac(t[k], y[k], p[k])
        fd = np.column_stack([(module.rhs(t[k], y[k] + h * e, p[k]) - module.rhs(t[k], y[k] - h * e, p[k])) / (2 * h)
                              for e in np.eye(module.N_STATES)])
        assert _relative(J, fd) <= 1e-6


@pytest.mark.parametrize("family", FAMILIES)
def test_jac_p_equals_finite_differences(generated_model, family):
    module, _, _ = generated_model(family, 2)
    t, y, p = random_inputs(module, 50, seed=7)
    for k in range(50):
        Jp = module.jac_p(t[k], y[k], p[k])
        fd = np.column_stack([(module.rhs(t[k], y[k], p[k] + h * e) - module.rhs(t[k], y[k], p[k] - h * e)) / (2 * h)
                              for e in np.eye(p.shape[1]) for h in [1e-7 * max(1.0, abs(p[k] @ e))]])
        assert _relative(Jp, fd) <= 1e-6


@pytest.mark.parametrize("family", FAMILIES)
def test_mass_matrix_and_forcing_give_the_accelerations(generated_model, family):
    """M q'' = f with q'' from rhs, and M has exactly the declared sparsity."""
    module, _, _ = generated_model(family, 3)
    t, y, p = random_inputs(module, 100, seed=3)
    nq = module.N_STATES // 2
    pattern = np.zeros((nq, nq), bool)
    for i, j in module.MASS_PATTERN:
        pattern[i, j] = True
    for k in range(100):
        M, f = module.mass_matrix(t[k], y[k], p[k]), module.forcing(t[k], y[k], p[k])
        acc = module.rhs(t[k], y[k], p[k])[nq:]
        assert np.max(np.abs(M @ acc - f)) <= 1e-12 * max(1.0, np.max(np.abs(f)))
        assert not np.any(M[~pattern])
        balls = [module.STATE_NAMES.index(name) for name in module.LEAVES]
        block = M[np.ix_(balls, balls)]
        assert np.count_nonzero(block - np.diag(np.diag(block))) == 0  # ball-ball block diagonal


def test_solve_ivp_callbacks_and_metadata(generated_model):
    from scipy.integrate import solve_ivp

    module, _, _ = generated_model("thesis_rotating", 2)
    assert module.PARAM_NAMES == ("Omega", "beta", "delta", "mu", "zeta")
    assert module.STATE_NAMES == ("x", "y", "phi_1", "phi_2", "x_dot", "y_dot", "phi_1_dot", "phi_2_dot")
    np.testing.assert_array_equal(module.DEFAULTS, [4.0, 0.01, 0.01, 0.05, 0.01])  # thesis (5.1)
    assert module.AUTONOMOUS and module.N_BALLS == 2 and len(module.SOURCE_HASH) == 16
    assert np.max(np.abs(module.rhs(0.0, module.START, module.START_PARAMETERS))) < 1e-14
    y0 = np.zeros(8)
    y0[module.state_index("phi_1")], y0[module.state_index("phi_2")] = np.pi / 2, -np.pi / 2
    sol = solve_ivp(module.rhs, (0, 5), y0, args=(module.params(),), jac=module.jac, method="Radau", rtol=1e-8)
    assert sol.success and sol.njev >= 1
    with pytest.raises(KeyError, match="not a parameter"):
        module.params(omega=3)
    with pytest.raises(KeyError, match="not a state"):
        module.state_index("z")
