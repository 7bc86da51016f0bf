"""Code-generation targets: one folder each, registered in one place, `REGISTRY` below.

A target is a `Target`: its name, its files (template -> output path), its printer and dialect (how
its language writes an expression and a statement), and hooks that hold its decisions in Python
rather than in templates (whether a model gets it, which form of the model it renders, extra template
data).  Its Python side lives in `adbgen/codegen/targets/<name>/` (`__init__.py`: the `Target`;
`printer.py`, `dialect.py`: its language), its jinja2 templates in the top-level `templates/<name>/`
(shipped in the wheel as `adbgen/templates/<name>/`).  targets/README.md lists the steps to add one
(SymForce's `codegen/backends/<language>/` in small).

`register` adds a target at run time (tests, plug-ins outside the package).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from ...registry import Registry
from ..ir.model import KERNELS

if TYPE_CHECKING:
    from ..emit import Dialect
    from ..ir.loops import Kernel
    from ..ir.model import ModelIR
    from ..passes.proof import Proof

# name -> "module:attribute", in rendering order; one line per target
REGISTRY: dict[str, str] = {
    "numba": "adbgen.codegen.targets.numba:TARGET",
    "c": "adbgen.codegen.targets.c:TARGET",
    "cvode": "adbgen.codegen.targets.cvode:TARGET",
    "auto": "adbgen.codegen.targets.auto:TARGET",
    "taylor": "adbgen.codegen.targets.taylor:TARGET",
    "lanes": "adbgen.codegen.targets.lanes:TARGET",
}
_registry = Registry("target", "targets", REGISTRY)

_PACKAGE = Path(__file__).resolve().parents[2]  # adbgen/


def template_root() -> Path:
    """Where the targets' template folders are: the wheel's copy inside the package (adbgen/templates,
    mapped from the top-level templates/ by pyproject's package-dir), else the source checkout's
    top-level templates/ beside the package."""
    installed = _PACKAGE / "templates"
    return installed if installed.is_dir() else _PACKAGE.parent / "templates"


@dataclass(frozen=True)
class Target:
    """A code-generation target.

    ``files``: (template name, output path) pairs; the path may use {name} (the model's name).  A
    template that renders to blank text writes no file (an optional file).  ``printer``: the printer
    class its functions are printed with (None: the target prints no functions, e.g. an adaptor over
    another target's library); ``dialect(which, kernel)`` then says how its language addresses arrays
    and writes statements.  ``functions``: which of the model's kernels it prints (``programs.<fn>``),
    at indentation ``depth``.  ``templates``: its template folder (default: templates/<name>/).
    """

    name: str
    files: tuple[tuple[str, str], ...]
    printer: type | None = None
    templates: Path | None = None
    description: str = ""
    filters: dict = field(default_factory=dict)
    # prints the functions' `code` (the loop form or the unrolled one, through codegen/emit.py); a
    # target that prints the programs' statements one by one (programs.<fn>.assignments, ir.rhs)
    # leaves it False and gets the unrolled form
    loops: bool = False
    functions: tuple[str, ...] = KERNELS
    depth: int = 1
    # prints the self-description's functions (measures, steady states: `describe`)
    describe: bool = False

    @property
    def template_folder(self) -> Path:
        return self.templates if self.templates is not None else template_root() / self.name

    def dialect(self, which: str, kernel: "Kernel") -> "Dialect":
        """The dialect of function `which` ('rhs', 'jac', ..., 'measures', ...) printing `kernel`."""
        raise NotImplementedError(f"target {self.name!r} has a printer but no dialect")

    def skip_reason(self, ir: "ModelIR") -> str | None:
        """Why this target does not render the model (None: it does)."""
        return None

    def model_for(self, ir: "ModelIR") -> "ModelIR":
        """The form of the model this target renders (the AUTO target: a forced model's extension)."""
        return ir

    def context(self, ir: "ModelIR") -> dict:
        """Template data beyond the common context (decisions made here, in Python)."""
        return {}

    def prove(self, proof: "Proof") -> None:
        """Prove this target's files before `regenerate` writes them (issue 20): they are written in
        ``proof.folder``; compare what they compute with ``proof.expected`` at ``proof.samples`` and
        refuse with ``proof.fail(...)``.  By default ``prove(target, proof)`` of the ``prove`` module in the
        target class's package (``targets/<name>/prove.py``); a target with neither that nor an override is
        refused: nothing unproven is written (`codegen.passes.proof`)."""
        module = proof_module(self)
        if module is None:
            raise NotImplementedError(f"target {self.name!r} has no proof")
        module.prove(self, proof)


def proof_module(target: Target):
    """The ``prove`` module beside the target's class (its package's), None if there is none."""
    name = f"{type(target).__module__}.prove"
    try:
        return importlib.import_module(name)
    except ModuleNotFoundError as exc:
        if exc.name != name and not name.startswith(f"{exc.name}."):
            raise  # a module the proof itself imports is missing: not the same as having no proof
        return None


def columns(kernel: "Kernel") -> int:
    """A kernel's output columns (0: a vector)."""
    return kernel.shape[1] if len(kernel.shape) == 2 else 0


register = _registry.register  # add a target object at run time: register(target, replace=False)
unregister = _registry.unregister
names = _registry.names
get = _registry.get
all_targets = _registry.all


def generation() -> int:
    """Changes whenever the registry does (so that caches of rendering know to rebuild)."""
    return _registry.generation
