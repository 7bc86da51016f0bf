"""The numba target's printer: math-module Python that numba compiles in nopython mode."""

from __future__ import annotations

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from ...printers import PrintRules


class PythonPrinter(PrintRules, PythonCodePrinter):
    """Python 3 with math.* functions (`printers.PrintRules`: floats, small powers as products, the
    ball-invariant order)."""

    def __init__(self, names: dict[sp.Symbol, str]):
        super().__init__(names, {"fully_qualified_modules": True, "standard": "python3"})
