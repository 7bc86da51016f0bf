"""The documentation site as `adbgen docs` builds it: no warning, every page, every CLI command, every
module, the notebooks with their outputs, every benchmark chart (issue 19 item 6)."""

from __future__ import annotations

import pkgutil
import re

from site_helpers import DOCS, ROOT, all_parsers, command_paths, ids, notebook_outputs_shown, text_of

import adbgen
import adbgen.models
from benchmarks import registry
from adbgen.cli import build_parser


def test_the_site_builds_without_a_warning(site):
    out, run = site
    log = run["stdout"] + run["stderr"]
    assert run["returncode"] == 0, log
    assert not re.search(r"WARNING|ERROR|CRITICAL", log), log
    assert (out / "index.html").is_file() and "no warnings" in run["stdout"]


def test_every_page_of_docs_is_in_the_site_and_its_navigation(site):
    out, _ = site
    nav = (out / "index.html").read_text()
    pages = [p.relative_to(DOCS) for p in DOCS.rglob("*") if p.suffix in (".md", ".rst")
             and not p.relative_to(DOCS).as_posix().startswith(("_build/", "reference/api/", "derive/"))
             and not p.name.startswith("reproduction-")]
    assert len(pages) >= 20
    for page in pages:
        name = page.with_suffix(".html").as_posix()
        assert (out / name).is_file(), name
        assert page.name == "index.md" or f'href="{name}"' in nav, f"{name} is not in the navigation"


def test_every_command_of_the_parser_is_in_the_cli_reference(site):
    """Both ways: each (nested) subcommand of build_parser and each registered benchmark has its
    section, and each command section of the page is a command of the parser."""
    out, _ = site
    parser = build_parser()
    paths = command_paths(parser) + [("bench", name) for name in registry.REGISTRY]
    expected = {"adbgen-" + "-".join(path) for path in paths}
    assert {"adbgen-two-plane-verify", "adbgen-bench-precision", "adbgen-docs", "adbgen-simulate"} <= expected
    found = ids(out / "reference" / "cli.html")
    assert not expected - found, f"commands missing from the CLI reference: {sorted(expected - found)}"
    groups = {"positional-arguments", "named-arguments"} | {
        g.title.lower().replace(" ", "-") for p in all_parsers(parser) for g in p._action_groups if g.title}
    sections = {i for i in found if i.startswith("adbgen-")}
    stray = {i for i in sections if i not in expected
             and not any(i == f"{cmd}-{g}" for cmd in expected | {"adbgen"} for g in groups)}
    assert not stray, f"sections of the CLI reference that are no command of the parser: {sorted(stray)}"


def test_every_module_has_an_api_page(site):
    out, _ = site
    for package in (adbgen,):
        # private modules (a leading _, __main__ included: importing it would run the program) have none
        names = [package.__name__] + [m.name for m in pkgutil.walk_packages(package.__path__, package.__name__ + ".")
                                      if not m.name.rpartition(".")[2].startswith("_")]
        missing = [n for n in names if not (out / "reference" / "api" / f"{n}.html").is_file()]
        assert not missing, missing
    models = [f"adbgen.models.{name}" for name in adbgen.models.names()]
    assert len(models) >= 11 and all((out / "reference" / "api" / f"{m}.html").is_file() for m in models)
    text = text_of(out / "reference" / "api" / "adbgen.analysis.sweep.html")
    assert "run_sweep" in text and "spec = SweepSpec(" in text  # docstrings and their indented blocks


def test_the_notebooks_appear_executed(site):
    out, _ = site
    notebooks = sorted((ROOT / "derive").glob("[0-9][0-9]_*.ipynb"))
    assert len(notebooks) >= 6
    for nb in notebooks:
        page = out / "derive" / f"{nb.stem}.html"
        assert page.is_file(), page
        assert notebook_outputs_shown(page, nb) == [], nb.name


def test_reproduction_readme_and_benchmark_charts_are_shown(site):
    out, _ = site
    reproduction = (out / "reproduction.html").read_text()
    for fig in re.findall(r"\]\(reproduction/([^)]+\.png)\)", (DOCS / "reproduction.md").read_text()):
        assert f"_images/{fig}" in reproduction, fig
    readme = " ".join(text_of(out / "getting-started.html").split())
    assert "Two commands on a fresh machine" in readme and "A five-minute tour" in readme
    assert "_images/fig5_4.png" in (out / "getting-started.html").read_text()
    shown = set()
    for page in out.rglob("*.html"):
        shown |= set(re.findall(r'<img[^>]+src="[^"]*?([^/"]+\.png)"', page.read_text()))
    charts = {p.name for p in (ROOT / "benchmarks").glob("*.png")}
    assert charts and not charts - shown, f"charts on no page: {sorted(charts - shown)}"


def test_the_build_time_is_reported(site):
    _, run = site
    assert re.search(r"built .*index\.html in \d+\.\d s", run["stdout"]), run["stdout"]
