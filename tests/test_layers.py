"""The layers hold (issue 19 item 5): import-linter's contracts in pyproject.toml are kept by the tree,
and are broken by an upward import planted in a copy of it (the negative control).

The contracts: core <- the families' derivations <- codegen <- analysis <- the families' science <-
cli; core, codegen and analysis import no family; the generated modules import neither adbgen nor
SymPy; the package does not import the benchmarks (the checkout's top-level `benchmarks`, issue 33),
which do not import the command line; code generation's intermediate form (codegen/ir) imports none of
its passes, targets or printers (see pyproject.toml, [tool.importlinter])."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from toolchain import require_module

import adbgen

ROOT = Path(adbgen.__file__).resolve().parents[1]
LINT = ("import sys; from importlinter.cli import lint_imports; "
        "sys.exit(lint_imports(config_filename='pyproject.toml', no_cache=True, no_logo=True))")


def _lint(root: Path) -> subprocess.CompletedProcess:
    """lint-imports on the tree at `root` (its own adbgen and generated imported, not this checkout's)."""
    env = {**os.environ, "PYTHONPATH": str(root), "COLUMNS": "1000"}  # wide: no wrapped names or chains
    return subprocess.run([sys.executable, "-c", LINT], cwd=root, env=env, capture_output=True, text=True,
                          timeout=600)


def _copy_tree(dest: Path) -> Path:
    for top in ("adbgen", "generated", "benchmarks"):  # benchmarks/: its code, not its results
        shutil.copytree(ROOT / top, dest / top, ignore=shutil.ignore_patterns("__pycache__", "*.so", "*.o", "*.json",
                                                                             "*.png"))
    shutil.copy(ROOT / "pyproject.toml", dest / "pyproject.toml")
    return dest


def test_the_layers_hold():
    require_module("importlinter", "import-linter, the test extra")
    r = _lint(ROOT)
    assert r.returncode == 0, r.stdout[-4000:] + r.stderr[-2000:]
    assert "Contracts: 7 kept, 0 broken." in r.stdout


@pytest.mark.parametrize("module, line, chain, contract", [
    # the analysis layer reaching up to the command line
    ("adbgen/analysis/loading.py", "from ..cli import arguments", "adbgen.analysis.loading -> adbgen.cli.arguments",
     "layers:"),
    # the analysis layer naming a family
    ("adbgen/analysis/steady.py", "from ..families import verification",
     "adbgen.analysis.steady -> adbgen.families.verification", "core, codegen and analysis know no family"),
    # a family's derivation importing its own science
    ("adbgen/families/single_plane/model.py", "from .science import published",
     "adbgen.families.single_plane.model -> adbgen.families.single_plane.science.published",
     "the families' derivations import neither"),
    # the package importing the benchmarks, and the benchmarks the command line
    ("adbgen/analysis/engines/by_tolerance.py", "import benchmarks.engine_table",
     "adbgen.analysis.engines.by_tolerance -> benchmarks.engine_table", "the package does not import the benchmarks"),
    ("benchmarks/report.py", "from adbgen.cli import arguments", "benchmarks.report -> adbgen.cli.arguments",
     "the benchmarks do not import the command line"),
    # code generation's intermediate form importing a pass
    ("adbgen/codegen/ir/loops.py", "from ..passes import cse", "adbgen.codegen.ir.loops -> adbgen.codegen.passes.cse",
     "code generation's intermediate form is data"),
    # a generated module importing SymPy
    ("generated/thesis_rotating_n2/__init__.py", "import sympy", "generated.thesis_rotating_n2 -> sympy",
     "the generated modules import neither"),
])
def test_a_planted_upward_import_breaks_its_contract(tmp_path, module, line, chain, contract):
    require_module("importlinter", "import-linter, the test extra")
    root = _copy_tree(tmp_path)
    path = root / module
    path.write_text(path.read_text() + "\n" + line + "  # planted\n")
    r = _lint(root)
    assert r.returncode == 1, r.stdout[-3000:]
    sections = _broken_contracts(r.stdout)
    name = next(n for n in sections if n.startswith(contract))
    assert chain in sections[name], sections


def _broken_contracts(report: str) -> dict[str, str]:
    """{contract name: its part of lint-imports' report} for each broken contract (a name is the line
    above a line of dashes as long as it)."""
    lines = report[report.index("Broken contracts"):].splitlines()[3:]
    heads = [k for k in range(1, len(lines)) if lines[k] and set(lines[k]) == {"-"} and len(lines[k]) == len(lines[k - 1])]
    return {lines[k - 1]: "\n".join(lines[k + 1:(heads[i + 1] - 1 if i + 1 < len(heads) else len(lines))])
            for i, k in enumerate(heads)}
