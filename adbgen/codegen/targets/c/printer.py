"""The C target's printer (C99 with <math.h>); the CVODE and AUTO-07p targets print with it too."""

from __future__ import annotations

import math

from sympy.printing.c import C99CodePrinter

from ...printers import PrintRules


class CPrinter(PrintRules, C99CodePrinter):
    """C99 with <math.h>; constants as literals (M_PI, M_E are POSIX, not C99)."""

    def _print_other_Pow(self, expr, rational=False):
        return C99CodePrinter._print_Pow(self, expr)

    def _print_Pi(self, expr):
        return repr(math.pi)

    def _print_Exp1(self, expr):
        return repr(math.e)
