"""The module map of a checkout: files and lines per folder of adbgen/, and its upward imports.

    python3 .ci/module_map.py [ROOT]        (ROOT: a checkout, default this one; needs grimp, which
                                              import-linter installs)

Layers, bottom to top (issue 19 item 5): 0 core, errors, cli_types, references, the package's
__init__; 1 the families' derivations; 2 codegen; 3 analysis; 4 the families' science packages,
bench (adbgen/bench/ of checkouts before issue 33 moved it to the top-level benchmarks/), notebooks;
5 cli and docsite (the documentation build reads the command line and the benchmarks' registry).  A module counts in the layer of the folder it sits in (a command module inside codegen/ is
codegen's).  An upward import is an import, at module level or inside a function
(not under `if TYPE_CHECKING:`), from a module to one in a higher layer; "family names in generic
layers" are imports of adbgen.families by core, codegen or analysis.
"""

from __future__ import annotations

import collections
import subprocess
import sys
from pathlib import Path


def layer(module: str) -> int:
    parts = module.split(".")
    if parts[0] != "adbgen" or len(parts) == 1:
        return 0
    top = parts[1]
    if top in ("core", "errors", "cli_types", "references"):
        return 0
    if top == "families":
        return 4 if "science" in parts else 1
    return {"codegen": 2, "analysis": 3, "bench": 4, "notebooks": 4, "cli": 5, "docsite": 5}.get(top, 0)


def main(root: Path) -> None:
    files = subprocess.run(["git", "ls-files", "adbgen"], cwd=root, capture_output=True, text=True,
                           check=True).stdout.split()
    per = collections.defaultdict(lambda: [0, 0])
    for f in files:
        if f.endswith((".py", ".c", ".h", ".j2")):
            folder = str(Path(f).parent)
            per[folder][0] += 1
            per[folder][1] += len((root / f).read_text().splitlines())
    print(f"{'folder':44s} {'files':>5s} {'lines':>6s}")
    for folder in sorted(per):
        print(f"{folder:44s} {per[folder][0]:5d} {per[folder][1]:6d}")
    print(f"{'total':44s} {sum(v[0] for v in per.values()):5d} {sum(v[1] for v in per.values()):6d}")

    sys.path.insert(0, str(root))
    import grimp

    graph = grimp.build_graph("adbgen", exclude_type_checking_imports=True, cache_dir=None)
    up, named = [], []
    for importer in sorted(graph.modules):
        for imported in sorted(graph.find_modules_directly_imported_by(importer)):
            lines = sorted({d["line_number"] for d in graph.get_import_details(importer=importer, imported=imported)})
            where = f"{importer} -> {imported} (l. {', '.join(map(str, lines))})"
            if layer(importer) < layer(imported):
                up.append(where)
            if imported.startswith("adbgen.families") and importer.split(".")[1:2] in (["core"], ["codegen"],
                                                                                        ["analysis"]):
                named.append(where)
    print(f"\nupward imports: {len(up)}")
    for line in up:
        print("  " + line)
    print(f"family imports in core, codegen, analysis: {len(named)}")
    for line in named:
        print("  " + line)


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parents[1]))
