"""Helpers of the analysis tests (a module name of its own: tests/codegen puts its folder on sys.path too)."""

from __future__ import annotations

from adbgen.analysis import auto07p

# tests/codegen/toolchain.py (conftest.py puts its folder on sys.path): a missing tool fails under CI
from toolchain import require_tool

# thesis ch. 4: mu = 0.05, zeta = beta = delta = 0.01 (Fig. 4.1, 4.5, 4.10)
CH4 = {"mu": 0.05, "zeta": 0.01, "beta": 0.01, "delta": 0.01}


def require_auto() -> None:
    """Fail (CI=true) or skip (elsewhere) when AUTO-07p or its toolchain is missing."""
    missing = auto07p.missing_tools()
    require_tool(not missing, ", ".join(missing) + " (Debian packages auto-07p gfortran gcc make)")
