"""Helpers of the documentation tests: the built site (once per run, shared by pytest-xdist workers),
a small copy of docs/ for negative controls, and what a page's HTML holds."""

from __future__ import annotations

import argparse
import fcntl
import html
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import toolchain

from adbgen import docsite

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"


def require_docs_extra() -> None:
    """Fail under CI (skip elsewhere) unless the docs extra's packages are importable."""
    for module, dist in docsite.REQUIRED.items():
        toolchain.require_module(module, f"{dist}, of the docs extra")


def env() -> dict:
    paths = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    return {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT)] + paths)}


def build_site(shared_tmp: Path) -> tuple[Path, dict]:
    """`adbgen docs --out DIR` run once per test run: the first pytest-xdist worker to get here builds,
    the others wait on the lock and read its result (two builds at once would share docs/reference/api)."""
    shared_tmp.mkdir(parents=True, exist_ok=True)
    out, record = shared_tmp / "site", shared_tmp / "site.json"
    with open(shared_tmp / "site.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not record.exists():
            proc = subprocess.run([sys.executable, "-m", "adbgen.cli", "docs", "--out", str(out)],
                                  capture_output=True, text=True, cwd=ROOT, env=env())
            record.write_text(json.dumps({"returncode": proc.returncode, "stdout": proc.stdout,
                                          "stderr": proc.stderr}))
    return out, json.loads(record.read_text())


def run_sphinx(source: Path, out: Path) -> subprocess.CompletedProcess:
    """The Sphinx command `adbgen docs` runs, on another source folder."""
    doctrees = out.parent / (out.name + ".doctrees")
    return subprocess.run(docsite.sphinx_command(source, out, doctrees), capture_output=True, text=True,
                          env=env())


def _title(path: Path) -> str:
    for line in path.read_text().splitlines():
        if line.startswith("# "):
            return line[2:].strip()
    return path.stem


def _toctrees(text: str) -> list[str]:
    return re.findall(r"^```\{toctree\}\n.*?^```\n", text, flags=re.S | re.M)


def stub_site(target: Path) -> Path:
    """A copy of docs/ that builds in seconds: conf.py and index.md as they are, every other page
    reduced to its title and its toctrees (so the page structure is the real one), two notebooks in
    derive/: 01 as committed (executed) and 01 with its outputs cleared."""
    import nbformat

    site = target / "docs"
    site.mkdir(parents=True)
    shutil.copy(DOCS / "conf.py", site / "conf.py")
    shutil.copy(DOCS / "index.md", site / "index.md")
    skip = ("_build/", "reference/api/", "derive/")
    for path in sorted(DOCS.rglob("*")):
        rel = path.relative_to(DOCS)
        if (rel.as_posix().startswith(skip) or path.name == "index.md" and rel.parent == Path(".")
                or path.suffix not in (".md", ".rst")):
            continue
        dest = site / rel
        dest.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".rst":
            title = path.read_text().splitlines()[0]
            dest.write_text(f"{title}\n{'=' * len(title)}\n")
        else:
            dest.write_text(f"# {_title(path)}\n\n" + "\n".join(_toctrees(path.read_text())))
    derive = site / "derive"
    derive.mkdir()
    source = ROOT / "derive" / "01_single_plane_lagrange.ipynb"
    shutil.copy(source, derive / "01_executed.ipynb")
    nb = nbformat.read(source, as_version=4)
    for cell in nb.cells:
        if cell.cell_type == "code":
            cell.outputs = []
    nbformat.write(nb, derive / "02_not_executed.ipynb")
    return site


def text_of(page: Path) -> str:
    """The page's article text, tags dropped, entities decoded."""
    raw = page.read_text()
    start, end = raw.find("<article"), raw.find("</article>")
    body = raw[start:end] if start >= 0 and end > start else raw
    return html.unescape(re.sub(r"<[^>]+>", "", body))


def ids(page: Path) -> set[str]:
    return set(re.findall(r'\bid="([^"]+)"', page.read_text()))


def command_paths(parser: argparse.ArgumentParser, prefix: tuple = ()) -> list[tuple[str, ...]]:
    """Every (sub)command of an argparse parser, nested ones included, as paths of names."""
    paths = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                paths.append(prefix + (name,))
                paths += command_paths(sub, prefix + (name,))
    return paths


def all_parsers(parser: argparse.ArgumentParser) -> list[argparse.ArgumentParser]:
    """The parser and every subcommand's parser, nested ones included."""
    found = [parser]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                found += all_parsers(sub)
    return found


def notebook_outputs_shown(page: Path, notebook: Path) -> list[str]:
    """What of the notebook's stored outputs the page lacks (empty: every output is on the page):
    each code cell with outputs is a rendered output block, each PNG an image, each printed line
    present, and Markdown outputs with $$ rendered as mathematics."""
    import nbformat

    nb = nbformat.read(notebook, as_version=4)
    raw = page.read_text()
    text = text_of(page)
    lacking = []
    cells = [c for c in nb.cells if c.cell_type == "code" and c.outputs]
    if not cells:
        lacking.append("the notebook has no stored outputs")
    blocks = raw.count('class="cell_output')
    if blocks < len(cells):
        lacking.append(f"{blocks} output blocks for {len(cells)} cells with outputs")
    pngs = sum("image/png" in o.get("data", {}) for c in cells for o in c.outputs)
    images = len(re.findall(r'<img[^>]+src="[^"]*\.png"', raw[raw.find("<article"):]))
    if images < pngs:
        lacking.append(f"{images} images for {pngs} PNG outputs")
    for c in cells:
        for o in c.outputs:
            if o.output_type == "stream":
                first = next((ln.strip() for ln in o.text.splitlines() if ln.strip()), "")
                if first and " ".join(first.split()) not in " ".join(text.split()):
                    lacking.append(f"printed line missing: {first[:60]!r}")
    if any("$$" in o.get("data", {}).get("text/markdown", "") for c in cells for o in c.outputs) \
            and 'class="math' not in raw:
        lacking.append("no rendered mathematics")
    return lacking
