"""Render a model into a scratch folder and import its numba module (benchmarks and tests).

Not for generated/: `adbgen regenerate` writes that through its staging folder.  A module imported
here gets an alias (numba's on-disk cache records it), so never use this on generated/ itself:
import `generated.<model>` by its real name there.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

from .ir.model import ModelIR
from .render import render_model


def render_into(ir: ModelIR, root: Path, targets=None) -> Path:
    """Write the model's files under `root`; returns the model's folder, root/<name>."""
    for rel, text in render_model(ir, targets).items():
        path = root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root / ir.name


def import_numba(folder: Path, alias: str):
    """Import the numba module in `folder` (its __init__.py) under the module name `alias`."""
    spec = importlib.util.spec_from_file_location(alias, folder / "__init__.py",
                                                  submodule_search_locations=[str(folder)])
    module = importlib.util.module_from_spec(spec)
    sys.modules[alias] = module
    spec.loader.exec_module(module)
    return module
