"""The Schur-complement solve equals a dense solve and refuses coupled leaves."""

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from adbgen.core import Coordinate, EquationsOfMotion, schur_solve

t = sp.Symbol("t", real=True)


def _system(rng, r, leaves, symmetric):
    n = r + leaves
    M = np.zeros((n, n))
    A = rng.normal(size=(r, r))
    M[:r, :r] = A @ A.T + r * np.eye(r)
    for i in range(r, n):
        M[i, i] = 1.0 + rng.random()
        M[:r, i] = rng.normal(size=r) * 0.3
        M[i, :r] = M[:r, i] if symmetric else rng.normal(size=r) * 0.3
    f = rng.normal(size=n)
    coords = [Coordinate.make(f"core_{i}") for i in range(r)] + [Coordinate.make(f"leaf_{i}") for i in range(leaves)]
    mass = {(i, j): sp.Float(M[i, j], 30) for i in range(n) for j in range(n) if M[i, j] != 0}
    eom = EquationsOfMotion(tuple(coords), mass, tuple(sp.Float(v, 30) for v in f), t)
    return eom, M, f, [c.name for c in coords[:r]]


@settings(max_examples=25, deadline=None)
@given(st.integers(1, 4), st.integers(0, 6), st.booleans(), st.integers(0, 2**32 - 1))
def test_schur_equals_dense_solve(r, leaves, symmetric, seed):
    eom, M, f, core = _system(np.random.default_rng(seed), r, leaves, symmetric)
    solve = schur_solve(eom, core)
    S = np.array(solve.schur.tolist(), dtype=float)
    a_core = np.linalg.solve(S, np.array(solve.rhs, dtype=float).ravel())
    subs = dict(zip(solve.core_accel_symbols, a_core))
    a_leaf = [float(e.xreplace(subs)) for e in solve.leaf_accel]
    expected = np.linalg.solve(M, f)
    assert np.allclose(np.concatenate([a_core, a_leaf]), expected, rtol=1e-10, atol=1e-12)


def test_coupled_leaves_are_refused():
    eom, *_ = _system(np.random.default_rng(1), 2, 2, True)
    mass = dict(eom.mass)
    mass[(2, 3)] = mass[(3, 2)] = sp.Float(0.1)
    with pytest.raises(ValueError, match="coupled"):
        schur_solve(EquationsOfMotion(eom.coordinates, mass, eom.forcing, t), ["core_0", "core_1"])
