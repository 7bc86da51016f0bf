"""The ROSS bridge's fixtures: ROSS's example rotor as it is and with its shaft made stiff (E x 1e3)."""

from __future__ import annotations

import pytest
from toolchain import require_module


@pytest.fixture(scope="session")
def ross():
    require_module("ross", "the ROSS bridge's extra: pip install 'adbgen[ross]'")
    from adbgen.ross.rotor import import_ross

    return import_ross()


@pytest.fixture(scope="session")
def example(ross):
    return ross.rotor_example()


@pytest.fixture(scope="session")
def stiff(example):
    from adbgen.ross.rigidity import stiff_shaft

    return stiff_shaft(example)
