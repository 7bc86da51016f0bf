"""Fixtures of the analysis tests and the commands' tests (tests/cli): the committed generated models, gcc
for the compiled engines, and the scans of the balanced state along Omega at the parameters of thesis
ch. 4 (computed once per session).  Each folder's conftest.py imports them."""

from __future__ import annotations

import shutil

import pytest
from toolchain import require_tool

from analysis_helpers import CH4

_scans: dict = {}


@pytest.fixture(autouse=True)
def _needs_gcc():
    """The compiled engines build the generated C library with gcc."""
    require_tool(shutil.which("gcc") is not None, "gcc")


@pytest.fixture(scope="session")
def thesis():
    from adbgen.analysis.loading import load_model

    return {n: load_model(f"thesis_rotating_n{n}") for n in (2, 3, 4)}


@pytest.fixture(scope="session")
def balanced_scan(thesis):
    """n -> the scan of the balanced state (START) from Omega = 4 down to 0.5 at CH4."""
    from adbgen.analysis import equilibrium_scan

    def get(n: int) -> equilibrium_scan.Scan:
        if n not in _scans:
            m = thesis[n]
            p = m.params({"Omega": 4.0, **CH4})
            _scans[n] = equilibrium_scan.scan(m, p, m.module.START, "Omega", 4.0, 0.5)
        return _scans[n]
    return get
