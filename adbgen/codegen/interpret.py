"""Run an intermediate-form function in plain Python (no numba, no C): checks of the lowering.

The function is printed by the same emitter and printer the numba template uses (loops and all) and
executed as an ordinary Python function, so `regenerate` can check each model's structured solve
against the closed form without compiling anything.
"""

from __future__ import annotations

import math

import numpy as np

from .emit import Dialect, Emitter, tables
from .ir import ModelIR
from .printers import PythonPrinter, identifiers


def python_source(ir: ModelIR, which: str, fname: str = "_f") -> str:
    """def fname(t, y, p, out): the body of function `which` as the numba target prints it."""
    kernel = ir.kernels()[which]
    names = identifiers(ir)
    dialect = Dialect("py", "y", "p", "out", kernel.shape[1] if len(kernel.shape) == 2 else 0)
    split = ir.loops.split if ir.loops is not None else None
    body = Emitter(kernel, dialect, PythonPrinter(names), names, split, ir.n_coordinates,
                   [s.symbol for s in ir.states], [p.symbol for p in ir.parameters]).emit()
    return f"def {fname}(t, y, p, out):\n{body}    return out\n"


def compile_program(ir: ModelIR, which: str):
    """A Python function (t, y, p) -> flat output array of the function `which` ('rhs', 'jac', ...)."""
    kernel = ir.kernels()[which]
    scope = {"math": math, "np": np}
    if ir.loops is not None:
        scope.update({name: np.array(values, dtype=np.int64 if kind == "int" else float)
                      for name, kind, values in tables(ir.loops.split)})
    exec(compile(python_source(ir, which), f"<{ir.name}.{which}>", "exec"), scope)  # noqa: S102 - our own printed code
    inner = scope["_f"]
    shape = kernel.shape

    def run(t, y, p):
        return inner(t, np.asarray(y, dtype=float), np.asarray(p, dtype=float), np.empty(shape)).ravel()
    return run
