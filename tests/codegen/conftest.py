"""Models for the code-generation tests: the committed default set, or rendered into a temporary folder.

`generated_model(family, n)` returns (numba module, FirstOrderSystem, folder with the C files).  The
default set (n = 2, 3, 4) is imported from the committed `generated/` (so the tests check what users
get); other n are rendered from the same templates into a session temporary folder.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from pathlib import Path

import pytest

from adbgen.codegen import models
from adbgen.codegen.regenerate import DEFAULT_OUT
from adbgen.codegen.render import render_model

FAMILIES = {"thesis_rotating": models.thesis_rotating, "single_plane_fixed": models.single_plane_fixed}
_cache: dict = {}


def _import_from(folder: Path, name: str):
    spec = importlib.util.spec_from_file_location(f"_adbgen_test_{name}", folder / "__init__.py",
                                                  submodule_search_locations=[str(folder)])
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def generated_model(tmp_path_factory):
    def get(family: str, n: int):
        key = (family, n)
        if key not in _cache:
            spec = FAMILIES[family](n)
            system = spec.system()
            folder = DEFAULT_OUT / spec.name
            if folder.is_dir():
                # by its real name: numba's on-disk cache records the module name, so an alias here
                # would leave a cache that `import generated.<model>` cannot load afterwards
                module = importlib.import_module(f"generated.{spec.name}")
            else:
                root = tmp_path_factory.mktemp("rendered")
                for rel, text in render_model(spec.build(), ("numba", "c")).items():
                    path = root / rel
                    path.parent.mkdir(parents=True, exist_ok=True)
                    path.write_text(text)
                folder = root / spec.name
                module = _import_from(folder, spec.name)
            _cache[key] = (module, system, folder)
        return _cache[key]
    return get
