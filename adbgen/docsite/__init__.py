"""The documentation site of docs/, built with Sphinx, warnings as errors (`adbgen docs`: adbgen/cli/docs.py).

    adbgen docs                 build into docs/_build/html (git-ignored)
    adbgen docs --out DIR       build into DIR
    adbgen docs --jobs N        N Sphinx processes (default 1)

The site (docs/conf.py) is Sphinx with myst-nb (the Markdown pages and the executed notebooks of
derive/, never re-executed), sphinx-book-theme, sphinx-argparse (the CLI reference, from
`adbgen.cli.build_parser`) and autodoc/autosummary (the API, recursive).  Every build is a fresh one
(`-E`, new doctrees): an incremental build would not repeat the warnings of unchanged pages, and with
`-W --keep-going` every warning is printed and any one fails the build (exit 1).  A broken internal
link, a page in no toctree, a docstring or notebook that does not render: each is a warning.

Nothing is lost on failure: Sphinx writes into a new folder beside DIR, which replaces DIR only when
the build passed; a DIR that is not an earlier build (no `.buildinfo`) is refused, never replaced.
Needs the `docs` extra (`python3 -m pip install -e '.[docs]'`).
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from ..errors import AdbgenError

# The Python modules the build imports, and the distribution that provides each (the `docs` extra).
REQUIRED = {"sphinx": "sphinx", "myst_nb": "myst-nb", "sphinx_book_theme": "sphinx-book-theme",
            "sphinxarg": "sphinx-argparse"}
DEFAULT_OUT = Path("docs") / "_build" / "html"


class DocsError(AdbgenError):
    """The site cannot be built here (no docs/, packages missing, a DIR that is not a build)."""


def root() -> Path:
    return Path(__file__).resolve().parents[2]


def source_dir() -> Path:
    docs = root() / "docs"
    if not (docs / "conf.py").is_file():
        raise DocsError(f"no docs/conf.py at {root()} (the documentation lives in a source checkout)")
    return docs


def missing_packages() -> list[str]:
    return [dist for module, dist in REQUIRED.items() if importlib.util.find_spec(module) is None]


def _check_out(out: Path, docs: Path) -> None:
    if out.exists() and not out.is_dir():
        raise DocsError(f"--out {out}: not a folder")
    if out.is_dir() and any(out.iterdir()) and not (out / ".buildinfo").is_file():
        raise DocsError(f"--out {out}: a folder that is not an earlier documentation build (no .buildinfo); "
                        "name a new or empty folder")
    # Sphinx must not read its own output: inside docs/, only below docs/_build (excluded in conf.py).
    if (out == docs or docs in out.parents) and (docs / "_build") not in out.parents:
        raise DocsError(f"--out {out}: inside the documentation's sources; use docs/_build/... or a folder outside docs/")


def sphinx_command(docs: Path, out: Path, doctrees: Path, jobs: int = 1) -> list[str]:
    return [sys.executable, "-m", "sphinx", "-b", "html", "-E", "-W", "--keep-going", "-q",
            "-j", str(jobs), "-d", str(doctrees), str(docs), str(out)]


def build(out: Path, jobs: int = 1) -> int:
    """Build the site into `out` (replaced only on success); Sphinx's exit status."""
    docs = source_dir()
    missing = missing_packages()
    if missing:
        raise DocsError(f"the documentation needs the docs extra (missing: {', '.join(missing)}): "
                        "python3 -m pip install -e '.[docs]'")
    out = out.resolve()
    _check_out(out, docs)
    out.parent.mkdir(parents=True, exist_ok=True)
    # Sphinx writes into staging/html; its doctrees and myst-nb's extracted outputs (which it puts
    # beside the output folder, in jupyter_execute/) stay in staging/ and go with it.
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.new.", dir=out.parent))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(root())] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])}
    try:
        code = subprocess.call(sphinx_command(docs, staging / "html", staging / "doctrees", jobs), env=env)
        if code != 0:
            return code
        _replace(out, staging / "html")
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return 0


def _replace(out: Path, staging: Path) -> None:
    """Put the new build where `out` was, in two renames; the old one is removed last."""
    old = None
    if out.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old.", dir=out.parent))
        os.replace(out, old / out.name)
    os.replace(staging, out)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
