"""Run an intermediate-form program in plain Python (no numba, no C): checks of the lowering.

The program is printed with the same printer the numba template uses and executed as an ordinary
Python function, so `regenerate` can check each model's structured solve against the closed form
without compiling anything.
"""

from __future__ import annotations

import math

import numpy as np

from .ir import ModelIR
from .printers import PythonPrinter, identifiers


def compile_program(ir: ModelIR, which: str):
    """A Python function (t, y, p) -> flat output array of the program `which` ('rhs', 'jac', ...)."""
    program = getattr(ir, which)
    names = identifiers(ir)
    printer = PythonPrinter(names)
    printer.set_program(program.assignments)
    lines = ["def _f(t, y, p):"]
    lines += [f"    {names[s.symbol]} = y[{k}]" for k, s in enumerate(ir.states)]
    lines += [f"    {names[q.symbol]} = p[{k}]" for k, q in enumerate(ir.parameters)]
    lines += [f"    {printer.doprint(lhs)} = {printer.doprint(rhs)}" for lhs, rhs in program.assignments]
    lines.append(f"    out = np.zeros({math.prod(program.shape)})")
    lines += [f"    out[{i}] = {printer.doprint(e)}" for i, e in program.outputs]
    lines.append("    return out")
    scope = {"math": math, "np": np}
    exec(compile("\n".join(lines), f"<{ir.name}.{which}>", "exec"), scope)  # noqa: S102 - our own printed code
    return scope["_f"]
