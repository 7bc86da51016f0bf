"""Shared fixtures of the analysis tests: the thesis models at the parameters of thesis ch. 4, their
scans along Omega (computed once per session), and AUTO-07p's availability (a failure in CI)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from adbgen.analysis import auto, continuation
from adbgen.analysis.loading import load_model

# pytest runs with --import-mode=importlib: put this folder on sys.path so tests import its helpers
sys.path.insert(0, str(Path(__file__).parent))

from thesis_ch4 import CH4  # noqa: E402

_scans: dict = {}


def require_auto() -> None:
    """Fail (CI=true) or skip (elsewhere) when AUTO-07p or its toolchain is missing."""
    missing = auto.missing_tools()
    if not missing:
        return
    what = ", ".join(missing) + " (Debian packages auto-07p gfortran gcc make)"
    if os.environ.get("CI") == "true":
        pytest.fail(f"{what} required in CI but missing")
    pytest.skip(f"{what} not available")


@pytest.fixture(scope="session")
def thesis():
    """n -> the generated thesis model."""
    return lambda n: load_model(f"thesis_rotating_n{n}")


@pytest.fixture(scope="session")
def balanced_scan(thesis):
    """n -> the scan of the balanced state (START) from Omega = 4 down to 0.5 at CH4."""
    def get(n: int) -> continuation.Scan:
        if n not in _scans:
            m = thesis(n)
            p = m.params({"Omega": 4.0, **CH4})
            _scans[n] = continuation.scan(m, p, m.module.START, "Omega", 4.0, 0.5)
        return _scans[n]
    return get
