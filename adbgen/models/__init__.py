"""The generated models as `adbgen.models.<model>`, the one import path that works everywhere.

* In a source checkout (editable install or PYTHONPATH) this package's path is the checkout's
  `generated/` folder, the one `adbgen regenerate` writes: `adbgen.models.thesis_rotating_n2` is the
  file `generated/thesis_rotating_n2/__init__.py`, which is also importable as
  `generated.thesis_rotating_n2` from the checkout's root (as before).
* In a wheel (`pip install .`) the models are installed inside this package (`setup.py` maps each
  `generated/<model>` to `adbgen.models.<model>`), and there is no top-level `generated` package
  that could collide with another project's.

`names()` lists the models found.  Nothing else is imported here: the models need numpy and numba
only.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

_ROOT = Path(__file__).resolve().parents[2]
CHECKOUT = _ROOT / "generated"
if (_ROOT / "pyproject.toml").is_file() and (_ROOT / "adbgen").is_dir():  # a source checkout
    __path__.insert(0, str(CHECKOUT))  # noqa: F821 (a package's __path__)
    # numba's cache (generated/<model>/__pycache__) is keyed by the file, not the module's name, and an
    # entry rebuilds its environment by importing the name it was compiled under: an entry written by a
    # process that imported `generated.<model>` (the README's SciPy example) crashed a later `adbgen`
    # run ("No module named 'generated'").  So the checkout's `generated` stays importable by that name
    # (unless another package of that name is there).
    if "generated" not in sys.modules and importlib.util.find_spec("generated") is None:
        _spec = importlib.util.spec_from_file_location("generated", CHECKOUT / "__init__.py",
                                                       submodule_search_locations=[str(CHECKOUT)])
        sys.modules["generated"] = importlib.util.module_from_spec(_spec)
        _spec.loader.exec_module(sys.modules["generated"])


def names() -> list[str]:
    """The models this package holds, sorted."""
    found = set()
    for folder in __path__:  # noqa: F821
        found.update(p.parent.name for p in Path(folder).glob("*/__init__.py"))
    return sorted(found)
