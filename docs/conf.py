"""Sphinx configuration of adbgen's documentation site; `adbgen docs` builds it (warnings are errors).

Sources: the Markdown pages of docs/ (MyST), the executed derivation notebooks of derive/ (through the
symlink docs/derive, rendered from their stored outputs by myst-nb, never executed here), the CLI
reference from adbgen.cli.build_parser (sphinx-argparse) and the benchmark registry, and the API
reference from the package itself (autosummary, recursive).
"""

from __future__ import annotations

import shutil
import sys
import types
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
# Document this checkout's adbgen and generated/, whatever is installed.
sys.path.insert(0, str(ROOT))

project = "adbgen"
author = "the adbgen authors"
html_title = "adbgen"

extensions = [
    "myst_nb",  # Markdown pages and the executed notebooks (includes myst_parser)
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinxarg.ext",  # the CLI reference from the argparse parser
    "adbgen.docsite.plain_docstrings",  # the docstrings are plain text, not reST
    "adbgen.docsite.cli_reference",  # `adbgen bench WHAT`: one section per registered benchmark
]

root_doc = "index"
suppress_warnings = [
    # Automatic links from the API's type annotations: a short name two modules define (e.g. Curve)
    # is ambiguous to the Python domain.  Links written in the pages are checked all the same.
    "ref.python",
]
exclude_patterns = [
    "_build",
    # `adbgen reproduce --only PART` writes partial documents docs/reproduction-<parts>.md locally (the parts
    # are the families' keys); reproduction-method.md is a page
    "reproduction-thesis*.md",
    "reproduction-two-plane*.md",
    "derive/*.py",
]

# The notebooks are committed executed (`adbgen notebooks --check` says whether they are current);
# the site shows their stored outputs.
nb_execution_mode = "off"
nb_merge_streams = True
nb_render_markdown_format = "myst"  # the notebooks' Markdown outputs carry $$ mathematics
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3  # [text](page.md#a-heading) links are checked like page links

# "--out" must stay two hyphens and 'x' straight quotes in command lines and prose.
smartquotes = False

# The API reference: autosummary writes a page per module into reference/api/ (git-ignored) on every
# build; stale pages of modules that moved or went away are removed first, so they cannot fail the
# build or linger.
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
shutil.rmtree(DOCS / "reference" / "api", ignore_errors=True)
# autosummary imports every module it finds, and a package's __main__.py runs its program when imported
# (here with Sphinx's own command line): such modules stand in sys.modules as mocks, which it skips.
for _main in sorted(ROOT.glob("adbgen/**/__main__.py")):
    _name = ".".join(_main.relative_to(ROOT).with_suffix("").parts)
    sys.modules.setdefault(_name, types.SimpleNamespace(__sphinx_mock__=True, __name__=_name))

html_theme = "sphinx_book_theme"
html_theme_options = {"show_toc_level": 2, "navigation_with_keys": False}
html_last_updated_fmt = None  # no dates: the same sources give the same pages
html_static_path = ["_static"]
html_css_files = ["tables.css"]  # wide tables wrap or scroll instead of being cut (issue 33)


def _drop_empty_glob(app, docname, source):
    """The index's Guide toctree ends in the glob `*`: every docs/*.md page that no entry names (pages
    other branches add) joins the site without an edit.  Sphinx warns on a glob that matches nothing,
    and that warning cannot be suppressed, so the glob is dropped when no such page exists."""
    if docname != root_doc:
        return
    lines = source[0].splitlines()
    named = {line.strip() for line in lines}
    others = [d for d in app.env.found_docs if "/" not in d and d != root_doc and d not in named]
    if not others:
        source[0] = "\n".join(line for line in lines if line.strip() != "*") + "\n"


def setup(app):
    app.connect("source-read", _drop_empty_glob)
