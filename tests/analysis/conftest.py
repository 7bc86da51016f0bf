"""Shared fixtures of the analysis tests: the thesis models and their scans along Omega at the
parameters of thesis ch. 4 (computed once per session)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from adbgen.analysis import continuation
from adbgen.analysis.loading import load_model

# pytest runs with --import-mode=importlib: put this folder on sys.path so tests import its helpers
sys.path.insert(0, str(Path(__file__).parent))

from analysis_helpers import CH4  # noqa: E402

_scans: dict = {}


@pytest.fixture(scope="session")
def thesis():
    return {n: load_model(f"thesis_rotating_n{n}") for n in (2, 3, 4)}


@pytest.fixture(scope="session")
def balanced_scan(thesis):
    """n -> the scan of the balanced state (START) from Omega = 4 down to 0.5 at CH4."""
    def get(n: int) -> continuation.Scan:
        if n not in _scans:
            m = thesis[n]
            p = m.params({"Omega": 4.0, **CH4})
            _scans[n] = continuation.scan(m, p, m.module.START, "Omega", 4.0, 0.5)
        return _scans[n]
    return get
