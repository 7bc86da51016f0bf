"""A toy target, kept in one folder as a target is (adbgen/codegen/targets/README.md): a pure-Python
module (no numpy, no numba) with rhs and jac as flat lists, printed in the loop form.

Its own printer (math functions unqualified: the module does ``from math import *``) and its own dialect
(flat row-major lists: out[r * ncol + c], work arrays as lists); its templates beside it in templates/.
tests/plugins/test_toy_family_and_target.py registers it with one call and regenerates with it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from adbgen.codegen import targets
from adbgen.codegen.emit import Dialect, paren
from adbgen.codegen.printers import PrintRules


class PurePythonPrinter(PrintRules, PythonCodePrinter):
    """sin(x), not math.sin(x)."""

    def __init__(self, names: dict[sp.Symbol, str]):
        super().__init__(names, {"fully_qualified_modules": False, "standard": "python3"})


@dataclass(frozen=True)
class ListDialect(Dialect):
    """y[k], p[k]; out[r] / out[r * ncol + c] in a flat list; ``for i in range(n):``."""

    def entry(self, row: str, col: str | None) -> str:
        if col is None:
            return f"{self.out}[{row}]"
        return f"{self.out}[{paren(row)} * {self.ncol} + {col}]"

    def let(self, name: str, value: str, mutable: bool = False) -> str:
        return f"{name} = {value}"

    def loop(self, var: str, count: int) -> str:
        return f"for {var} in range({count}):"

    def array(self, name: str, size: int) -> str:
        return f"{name} = [0.0] * {size}"

    def zero(self, shape) -> list[tuple[int, str]]:
        return [(0, f"{self.out}[:] = [0.0] * {math.prod(shape)}")]

    def guard(self, condition: str) -> list[tuple[int, str]]:
        return [(0, f"if not ({condition}):"), (1, "return False")]


class PyListTarget(targets.Target):
    def dialect(self, which, kernel):
        return ListDialect("y", "p", "out", targets.columns(kernel))

    def prove(self, proof):
        """Its module executed, rhs and jac against the model at the proof's sample points (issue 20)."""
        rel = proof.file(self, "pylist/module.py.j2")
        scope: dict = {}
        exec(compile(proof.files[rel], rel, "exec"), scope)  # noqa: S102 - the file just rendered
        for t, y, p in proof.samples():
            for which in ("rhs", "jac"):
                proof.compare(f"pylist {which}", scope[which](t, list(y), list(p)), proof.expected(which, t, y, p))


TARGET = PyListTarget(
    name="pylist",
    files=(("pylist/module.py.j2", "{name}/{name}_pylist.py"),),
    printer=PurePythonPrinter,
    templates=Path(__file__).parent / "templates",
    loops=True,
    functions=("rhs", "jac"),
    description="toy: rhs and jac as pure Python over flat lists",
)
