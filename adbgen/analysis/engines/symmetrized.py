"""A compiled engine whose right-hand side is exactly equivariant under one symmetry the model declares.

    eng = symmetrized("cyrk-dop853", model, "race-swap")
    sim = simulate(model, p, y0, engine=eng)        # any engine name or engine object

The generated rhs is equivariant under its declared symmetries only up to rounding where the symmetry
maps one expression onto a differently ordered one (a race swap such as the paper's gamma_r exchanges the races
and reverses the tilt: sums of the four balls' terms in another order), so a run started on the symmetric
subspace leaves it by rounding (a tilt of 1e-17 that an unstable odd mode grows to 1e-4, issue 23).  This
engine compiles the model with f_S(y) = (f(y) + S f(S y))/2 in place of f (symmetrize.h): bit-exactly
equivariant, equal to f in exact arithmetic wherever the parameters are S-symmetric (checked before each
run), at twice the evaluations.  With the Runge-Kutta engines' element-wise stage updates a symmetric
start then stays symmetric to the last bit.
"""

from __future__ import annotations

import numpy as np

from ..loading import AnalysisError
from .compiled import CyRKEngine
from .matlab_ode45 import MatlabOde45Engine


def _symmetry(model, kind_or_name: str) -> dict:
    for sym in model.symmetries:
        if kind_or_name in (sym["kind"], sym["name"]):
            return sym
    raise AnalysisError(f"{model.name} declares no symmetry {kind_or_name!r}; it declares: "
                        + ", ".join(s["name"] for s in model.symmetries))


def _check_involution(model, sym: dict) -> None:
    perm, signs = np.asarray(sym["states"]), np.asarray(sym["signs"], float)
    if not (np.array_equal(perm[perm], np.arange(model.n_states)) and np.all(signs * signs[perm] == 1.0)):
        raise AnalysisError(f"symmetry {sym['name']!r} of {model.name} is not an involution with consistent signs")


def symmetric_parameters(model, sym: dict, p) -> bool:
    """p == param_signs * p[params]: the parameters the symmetry needs (e.g. chi = 0 and z_b = -z_t)."""
    p = np.asarray(p, float)
    return bool(np.array_equal(p, np.asarray(sym["param_signs"], float) * p[list(sym["params"])]))


class _Symmetrized:
    """Mixed into a compiled engine: its library built with symmetrize.h."""

    def __init__(self, base_name: str, sym: dict, *args):
        super().__init__(*args)
        self.sym = sym
        self.name = f"{base_name}+{sym['kind']}"
        self.description = f"{base_name} with the rhs symmetrized under {sym['name']} (exactly equivariant)"
        self.tag = "-sym" + "".join(f"{k:x}" for k in sym["states"])

    def extra(self, model) -> tuple[str, ...]:
        states = ",".join(str(int(k)) for k in self.sym["states"])
        signs = ",".join(f"{float(s):.1f}" for s in self.sym["signs"])
        return ("-include", "symmetrize.h", f"-DADB_MODEL_RHS={model.name}_rhs", "-DADB_RHS=adb_symmetrized_rhs",
                f"-DADB_SYM_STATES={states}", f"-DADB_SYM_SIGNS={signs}")

    def _refuse(self, model, P) -> None:
        for p in np.atleast_2d(P):
            if not symmetric_parameters(model, self.sym, p):
                raise AnalysisError(f"the parameters are not symmetric under {self.sym['name']!r}: symmetrizing "
                                    f"would change the equations")

    def run(self, model, p, *args, **kw):
        self._refuse(model, p)
        return super().run(model, p, *args, **kw)

    def run_many(self, model, P, *args, **kw):
        self._refuse(model, P)
        return super().run_many(model, P, *args, **kw)


class SymmetrizedCyRK(_Symmetrized, CyRKEngine):
    pass


class SymmetrizedOde45(_Symmetrized, MatlabOde45Engine):
    def __init__(self, base_name, sym):
        _Symmetrized.__init__(self, base_name, sym)


def symmetrized(engine: str, model, symmetry: str):
    """The engine `engine` (a CyRK one or matlab-ode45) with the rhs symmetrized under the model's declared
    symmetry `symmetry` (its kind, e.g. "race-swap", or its name)."""
    sym = _symmetry(model, symmetry)
    _check_involution(model, sym)
    if engine.startswith("cyrk-"):
        from .compiled import _cyrk_methods

        method = next((m for m in _cyrk_methods() if "cyrk-" + m.lower() == engine), None)
        if method is None:
            raise AnalysisError(f"unknown CyRK engine {engine!r}")
        return SymmetrizedCyRK(engine, sym, method)
    if engine == "matlab-ode45":
        return SymmetrizedOde45(engine, sym)
    raise AnalysisError(f"engine {engine!r} cannot be symmetrized (CyRK engines and matlab-ode45 can)")
