"""The SymPy side the benchmarks share: the families' model kinds, the closed form of a system
lambdified (what a user of SymPy alone would integrate), and a sample point.

Only benchmarks import this (the analysis layer never imports SymPy); the codegen, precision and
per-call benchmarks compare the generated code with ``sympy.lambdify(cse=True)`` of the same system.
"""

from __future__ import annotations

import time
from functools import lru_cache
from typing import Callable

import numpy as np


@lru_cache(maxsize=None)
def kinds() -> dict:
    """Every family's model kinds indexed by n, {kind: n -> ModelSpec} (`families.kinds`)."""
    from adbgen import families

    return families.kinds()


def closed_form(system) -> list:
    """The first-order system's right-hand side as closed expressions (Cramer's rule on the rotor
    core), the driven law substituted."""
    import sympy as sp

    law = dict(system.solve.eom.driven_law)
    return [sp.sympify(e).xreplace(law) for e in system.rhs()]


def lambdify(system, exprs, modules: str):
    """``sympy.lambdify(cse=True)`` of expressions of the system as f(t, y, p)."""
    import sympy as sp

    eom = system.solve.eom
    args = (eom.time, list(system.states), [q.symbol for q in system.parameters])
    return sp.lambdify(args, exprs, modules=modules, cse=True)


def lambdify_rhs(model_name: str) -> tuple[Callable, dict]:
    """sympy.lambdify(modules="math", cse=True) of a generated model's equations as rhs(t, y, p) -> ndarray.

    The closed form (Cramer's rule on the rotor core) where adbgen has one (core <= 3 coordinates);
    otherwise the mass matrix and forcing lambdified and solved by numpy.linalg.solve per call."""
    import sympy as sp

    from adbgen import families

    start = time.perf_counter()
    spec = next((s for f in families.all_families() for s in f.models() if s.name == model_name), None)
    if spec is None:
        raise KeyError(f"no model spec named {model_name!r}")
    system = spec.system()
    eom = system.solve.eom
    law = dict(eom.driven_law)
    if len(system.solve.core) <= 3:
        fn = lambdify(system, closed_form(system), "math")
        form = "closed form (Cramer's rule), sympy.lambdify(modules='math', cse=True)"

        def rhs(t, y, p):
            return np.asarray(fn(t, y, p), float)
    else:
        size = eom.size
        M = sp.zeros(size, size)
        for (i, j), e in eom.mass.items():
            M[i, j] = sp.sympify(e).xreplace(law)
        fm = lambdify(system, M.tolist(), "math")
        ff = lambdify(system, [sp.sympify(e).xreplace(law) for e in eom.forcing], "math")
        form = ("mass matrix and forcing, sympy.lambdify(modules='math', cse=True), numpy.linalg.solve per call "
                "(adbgen has no closed form for a core of more than 3 coordinates)")

        def rhs(t, y, p):
            acc = np.linalg.solve(np.asarray(fm(t, y, p), float), np.asarray(ff(t, y, p), float))
            return np.concatenate([np.asarray(y[size:], float), acc])
    return rhs, {"form": form, "lambdify_s": round(time.perf_counter() - start, 3)}


def sample_point(system, n_states: int, seed: int = 0):
    """A random state (positions scaled by 0.1) and the default parameters."""
    rng = np.random.default_rng(seed)
    y = rng.uniform(-1, 1, n_states)
    y[: n_states // 2] *= 0.1
    p = np.array([p.default for p in system.parameters], float)
    return y, p


__all__ = ["closed_form", "kinds", "lambdify", "lambdify_rhs", "sample_point"]
