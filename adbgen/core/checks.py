"""The result of one check (a symbolic identity or a number against a reference), and how to time it."""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class CheckResult:
    name: str
    reference: str
    passed: bool
    detail: str
    seconds: float


def timed(name: str, reference: str, fn: Callable[[], tuple[bool, str]]) -> CheckResult:
    start = time.perf_counter()
    passed, detail = fn()
    return CheckResult(name, reference, bool(passed), detail, time.perf_counter() - start)
