"""The result of one check (a symbolic identity or a number against a reference), how to time it, and
the registry entry every family declares its checks with: what the check compares (its kind) and a
deliberately wrong variant that it must reject (its negative control)."""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

import sympy as sp

# What a check compares.
DERIVED = "derived-model check"  # the model adbgen derives against a reference (equations or numbers)
CONSISTENCY = "reference-consistency check"  # the reference against itself (one printed form vs another)
FORMULA = "formula re-evaluation"  # a printed closed form re-evaluated at the printed parameters
KINDS = (DERIVED, CONSISTENCY, FORMULA)

# How a number compares with a printed one.
NOT_REPRODUCED = "not reproduced"


@dataclass(frozen=True)
class CheckResult:
    name: str
    reference: str
    passed: bool
    detail: str
    seconds: float
    kind: str = DERIVED
    # "" for an ordinary pass/fail; NOT_REPRODUCED for a printed value the model does not give at its
    # printed precision (passed then means: the model's own value is the one documented in the errata)
    status: str = ""

    @property
    def label(self) -> str:
        if not self.passed:
            return "FAIL"
        return "NOT REPRODUCED" if self.status == NOT_REPRODUCED else "ok"


def timed(name: str, reference: str, fn: Callable[[], tuple[bool, str]], kind: str = DERIVED,
          status: str = "") -> CheckResult:
    start = time.perf_counter()
    passed, detail = fn()
    return CheckResult(name, reference, bool(passed), detail, time.perf_counter() - start, kind, status)


@dataclass(frozen=True)
class Registered:
    """A check as a family declares it: ``run(wrong)`` gives its result(s); with ``wrong=True`` it runs
    the deliberately wrong variant described by ``wrong`` (a flipped term, a dropped factor, the
    misprinted form, a printed value moved by a few units of its last digit), which must fail."""

    name: str
    kind: str
    run: Callable[[bool], "CheckResult | list[CheckResult]"]
    wrong: str

    def results(self, wrong: bool = False) -> list[CheckResult]:
        out = self.run(wrong)
        return list(out) if isinstance(out, (list, tuple)) else [out]


def run_registered(checks, progress: Callable[[CheckResult], None] | None = None) -> list[CheckResult]:
    """Every result of a family's registered checks, in order, each given to `progress` as it comes (what
    `PackageFamily.verify` runs)."""
    results = []
    for check in checks:
        for r in check.results():
            results.append(r)
            if progress:
                progress(r)
    return results


def flip_term(expr: sp.Expr) -> sp.Expr:
    """The negative control's mutation of an equation: the first term (in SymPy's sorted order) of the
    expanded expression with its sign flipped (an expression that is not a sum is doubled)."""
    e = sp.expand(expr)
    if isinstance(e, sp.Add):
        first = sp.Add.make_args(e)[0]
        return e - 2 * first
    return 2 * e


def printed_tolerance(printed: str) -> float:
    """Half a unit in the last printed digit: '1.65' -> 0.005, '0.9950372' -> 5e-8, '1' -> 0.5."""
    decimals = len(printed.split(".")[1]) if "." in printed else 0
    return 0.5 * 10.0 ** -decimals


def moved(printed: str, units: int = 3) -> str:
    """A printed value moved by `units` in its last digit (a number check's wrong variant)."""
    decimals = len(printed.split(".")[1]) if "." in printed else 0
    return f"{float(printed) + units * 10.0 ** -decimals:.{decimals}f}"
