"""The package's imports, and the benchmarks' (the checkout's benchmarks/), form no cycle (issue 8: `cli`
and `two_plane.commands` imported each other).

Every import statement of every module is read from its syntax tree, at module level and inside
functions alike (a lazy import still ties two modules together), but not the ones under
`if TYPE_CHECKING:`.  `from .x import y` counts as an import of x, and of x.y when that is a module.
"""

from __future__ import annotations

import ast
from pathlib import Path

import adbgen

ROOT = Path(adbgen.__file__).parent


def module_name(path: Path) -> str:
    rel = path.relative_to(ROOT.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


BENCHMARKS = ROOT.parent / "benchmarks"  # the benchmarks, beside the package in the checkout (issue 33)
MODULES = {module_name(p): p for p in [*ROOT.rglob("*.py"), *BENCHMARKS.rglob("*.py")]}


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for child in node.body:
                skip.update(id(n) for n in ast.walk(child))
    return skip


def imports_of(name: str) -> set[str]:
    path = MODULES[name]
    tree = ast.parse(path.read_text())
    skip = _type_checking_nodes(tree)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module
            # `from package import submodule` needs the submodule, not the package's own names (Python imports
            # it even while the package's __init__ is still running); any other name is the package's
            targets = [f"{stem}.{a.name}" if f"{stem}.{a.name}" in MODULES else stem for a in node.names]
        else:
            continue
        out.update(t for t in targets if t in MODULES and t != name)
    return out


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt)
                if found:
                    return found
        stack.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state:
            found = visit(node)
            if found:
                return found
    return None


def test_no_import_cycles():
    graph = {name: imports_of(name) for name in MODULES}
    assert sum(len(v) for v in graph.values()) > 100, "the walk finds the imports"
    cycle = find_cycle(graph)
    assert cycle is None, " -> ".join(cycle)


def test_the_walk_finds_a_cycle_when_there_is_one():
    """Negative control: two modules importing each other, as cli and two_plane.commands did."""
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}
    assert find_cycle(graph) == ["a", "b", "c", "a"]


def test_layers():
    """core imports no family and no code generation; codegen imports no family (the command line reads
    the family registry); families import no command line.  (import-linter's contracts in pyproject.toml,
    tests/test_layers.py, check the whole layering; this walk also sees the lazy imports' targets.)"""
    graph = {name: imports_of(name) for name in MODULES}
    for name, deps in graph.items():
        if name.startswith("adbgen.core"):
            assert not {d for d in deps if d.startswith(("adbgen.families", "adbgen.codegen", "adbgen.cli"))}, name
        if name.startswith("adbgen.codegen"):
            assert not {d for d in deps if d.startswith(("adbgen.families", "adbgen.cli"))}, name
        if name.startswith("adbgen.families"):
            assert "adbgen.cli" not in deps, name
        if name.startswith("adbgen"):
            assert not {d for d in deps if d.startswith("benchmarks")}, name
