"""The one common-subexpression pass (`codegen.passes.cse`, issue 33): what it returns means the same
as what it was given, its names are the caller's prefix numbered in order, it is deterministic, and no
other module of code generation eliminates common subexpressions on its own."""

from __future__ import annotations

import ast
from pathlib import Path

import sympy as sp

import adbgen.codegen
from adbgen.codegen.ir.loops import Let
from adbgen.codegen.passes.cse import cse, cse_lets

x, y, z = sp.symbols("x y z", real=True)
EXPRS = [sp.sin(x + y) * sp.cos(x + y) + z, sp.sin(x + y) ** 2 / (1 + z), (x + y) * sp.cos(x + y)]


def _back(replacements, reduced):
    """The reduced expressions with every temporary substituted back, innermost last."""
    full: dict = {}
    for sym, expr in replacements:
        full[sym] = expr.xreplace(full)
    return [e.xreplace(full) for e in reduced]


def test_the_reduced_expressions_with_their_temporaries_are_the_given_ones():
    replacements, reduced = cse(EXPRS, "w_")
    assert replacements, "the shared x + y, sin and cos are not factored out"
    assert [sp.simplify(a - b) for a, b in zip(_back(replacements, reduced), EXPRS)] == [0, 0, 0]


def test_names_are_the_prefix_numbered_in_order_and_the_result_is_the_same_every_time():
    replacements, reduced = cse(EXPRS, "wb_")
    assert [s.name for s, _ in replacements] == [f"wb_{k}" for k in range(len(replacements))]
    assert all(s.is_real for s, _ in replacements)
    assert cse(list(EXPRS), "wb_") == (replacements, reduced)


def test_cse_lets_is_cse_with_let_statements():
    replacements, reduced = cse(EXPRS, "v_")
    lets, reduced_lets = cse_lets(EXPRS, "v_")
    assert lets == [Let(s, e) for s, e in replacements] and reduced_lets == reduced


def _callers_of_sympy_cse(root: Path) -> list[str]:
    """Modules under `root` that call sympy's cse (as sp.cse, sympy.cse or an imported cse)."""
    out = []
    for path in sorted(root.rglob("*.py")):
        tree = ast.parse(path.read_text())
        imported = any(isinstance(n, ast.ImportFrom) and (n.module or "").startswith("sympy")
                       and any(a.name == "cse" for a in n.names) for n in ast.walk(tree))
        called = any(isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "cse"
                     and isinstance(n.func.value, ast.Name) and n.func.value.id in ("sp", "sympy")
                     for n in ast.walk(tree))
        if imported or called:
            out.append(path.relative_to(root).as_posix())
    return out


def test_only_the_cse_pass_calls_sympys_cse(tmp_path):
    root = Path(adbgen.codegen.__file__).parent
    assert _callers_of_sympy_cse(root) == ["passes/cse.py"]
    # negative control: a second elimination planted in a copy is found
    (tmp_path / "passes").mkdir()
    (tmp_path / "passes" / "cse.py").write_text((root / "passes" / "cse.py").read_text())
    (tmp_path / "loops.py").write_text("import sympy as sp\n\ndef f(e):\n    return sp.cse(e)\n")
    assert _callers_of_sympy_cse(tmp_path) == ["loops.py", "passes/cse.py"]
