"""Models for the code-generation tests: the committed default set, or rendered into a temporary folder.

`generated_model(family, n)` returns (numba module, FirstOrderSystem, folder with the C files).  The
default set (n = 2, 3, 4) is imported from the committed `generated/` (so the tests check what users
get); other n are rendered from the same templates into a session temporary folder.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import pytest

from adbgen import families
from adbgen.codegen.regenerate import DEFAULT_OUT
from adbgen.codegen.render_and_import import import_numba, render_into
from adbgen.codegen.spec import build as build_ir

# pytest runs with --import-mode=importlib, which puts no test folder on sys.path: put this one there
# so that the tests import their helpers (toolchain, sampling) by name
sys.path.insert(0, str(Path(__file__).parent))

_cache: dict = {}


@pytest.fixture(scope="session")
def generated_model(tmp_path_factory):
    def get(family: str, n: int):
        key = (family, n)
        if key not in _cache:
            spec = families.kinds()[family](n)
            system = spec.system()
            folder = DEFAULT_OUT / spec.name
            if folder.is_dir():
                # by its real name: numba's on-disk cache records the module name, so an alias here
                # would leave a cache that `import generated.<model>` cannot load afterwards
                module = importlib.import_module(f"generated.{spec.name}")
            else:
                folder = render_into(build_ir(spec), tmp_path_factory.mktemp("rendered"), ("numba", "c"))
                module = import_numba(folder, f"_adbgen_test_{spec.name}")
            _cache[key] = (module, system, folder)
        return _cache[key]
    return get
