"""Run an intermediate-form function in plain Python (no numba, no C): checks of the lowering and of
the self-description.

The function is printed by the same emitter and printer the numba template uses (loops and all) and
executed as an ordinary Python function, so `regenerate` can check each model's structured solve
against the closed form without compiling anything.
"""

from __future__ import annotations

import math

import numpy as np

from .emit import Emitter, tables
from .ir.loops import Kernel
from .ir.model import ModelIR
from .printers import identifiers
from .targets.numba.dialect import PythonDialect
from .targets.numba.printer import PythonPrinter


def kernel_source(ir: ModelIR, kernel: Kernel, fname: str = "_f", states=None, array: str = "y",
                  time: bool = True, result: str = "out") -> str:
    """def fname([t, ]<array>, p, out): `kernel` printed as the numba target prints it, returning
    `result`.  `states`: the symbols `array` holds (default: the model's states)."""
    names = identifiers(ir)
    dialect = PythonDialect(array, "p", "out", kernel.shape[1] if len(kernel.shape) == 2 else 0)
    split = ir.loops.split if ir.loops is not None else None
    states = [s.symbol for s in ir.states] if states is None else list(states)
    body = Emitter(kernel, dialect, PythonPrinter(names), names, split, ir.n_coordinates, states,
                   [p.symbol for p in ir.parameters]).emit()
    return f"def {fname}({'t, ' if time else ''}{array}, p, out):\n{body}    return {result}\n"


def python_source(ir: ModelIR, which: str, fname: str = "_f") -> str:
    """def fname(t, y, p, out): the body of function `which` as the numba target prints it."""
    return kernel_source(ir, ir.kernels()[which], fname)


def compile_kernel(ir: ModelIR, kernel: Kernel, label: str, **source):
    """The Python function of `kernel_source(ir, kernel, **source)` (the model's ball tables in scope)."""
    scope = {"math": math, "np": np}
    if ir.loops is not None:
        scope.update({name: np.array(values, dtype=np.int64 if kind == "int" else float)
                      for name, kind, values in tables(ir.loops.split)})
    exec(compile(kernel_source(ir, kernel, **source), f"<{ir.name}.{label}>", "exec"), scope)  # noqa: S102 - our own printed code
    return scope["_f"]


def compile_program(ir: ModelIR, which: str):
    """A Python function (t, y, p) -> flat output array of the function `which` ('rhs', 'jac', ...)."""
    kernel = ir.kernels()[which]
    inner = compile_kernel(ir, kernel, which)
    shape = kernel.shape

    def run(t, y, p):
        return inner(t, np.asarray(y, dtype=float), np.asarray(p, dtype=float), np.empty(shape)).ravel()
    return run


def compile_measures(ir: ModelIR):
    """(t, y, p) -> every measure of the self-description (MEASURES order), as the numba target prints it."""
    kernel = ir.description.measures
    inner = compile_kernel(ir, kernel, "measures")

    def run(t, y, p):
        return inner(t, np.asarray(y, dtype=float), np.asarray(p, dtype=float), np.empty(kernel.shape))
    return run


def compile_steady_states(ir: ModelIR):
    """label -> (p -> state array, or None): the self-description's closed forms, tried candidate by
    candidate as the generated steady_state does."""
    d = ir.description
    forms = [[compile_kernel(ir, k, f"{f.name}.{j}", states=f.arguments, array="a", time=False, result="True")
              for j, k in enumerate(f.candidates)] for f in d.closed_forms]

    def solver(form: int, args: tuple):
        def run(p):
            a, p = np.array(args, dtype=float), np.asarray(p, dtype=float)
            for cand in forms[form]:
                out = np.empty(ir.n_states)
                if cand(a, p, out) is True:
                    return out
            return None
        return run
    return {label: solver(form, args) for label, _, form, args in d.steady_states}
