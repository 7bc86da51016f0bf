"""`adbgen docs` and what fails its build, on a small copy of docs/ (every page reduced to its title and
its toctrees, conf.py and index.md as they are), which builds in seconds: negative controls for the
warnings the real build must not have, and for the checks of test_site.py."""

from __future__ import annotations

from pathlib import Path

import pytest
from site_helpers import ROOT, notebook_outputs_shown, require_docs_extra, run_sphinx, stub_site

from adbgen import docsite
from adbgen.cli import main


@pytest.fixture
def stub(tmp_path):
    require_docs_extra()
    return stub_site(tmp_path / "src")


def test_a_new_page_joins_the_site_without_an_edit_of_the_index(stub, tmp_path):
    (stub / "zz-new-topic.md").write_text("# A topic another branch adds\n\nSee [Sweeps](sweeps.md#sweeps).\n")
    run = run_sphinx(stub, tmp_path / "out")
    assert run.returncode == 0, run.stderr
    assert "WARNING" not in run.stderr
    assert 'href="zz-new-topic.html"' in (tmp_path / "out" / "index.html").read_text()


def test_broken_links_and_unlisted_pages_fail_the_build(stub, tmp_path):
    (stub / "zz-links.md").write_text("# Links\n\n[gone](no-such-page.md), [no heading](sweeps.md#no-such-heading), "
                                      "[fine](sweeps.md)\n")
    (stub / "benchmarks" / "sub").mkdir()
    (stub / "benchmarks" / "sub" / "orphan.md").write_text("# In no toctree\n")
    run = run_sphinx(stub, tmp_path / "out")
    assert run.returncode != 0
    warnings = [line for line in run.stderr.splitlines() if "WARNING" in line]
    assert any("zz-links.md" in w and "no-such-page.md" in w for w in warnings), run.stderr
    assert any("zz-links.md" in w and "no-such-heading" in w for w in warnings), run.stderr
    assert any("orphan" in w and "toctree" in w for w in warnings), run.stderr
    assert not any("sweeps.md'" in w for w in warnings), run.stderr  # the good link is no warning


def test_the_executed_notebook_check_tells_an_executed_page_from_a_bare_one(stub, tmp_path):
    """Negative control of test_site's notebook check: a notebook without stored outputs fails it."""
    (stub / "zz-notebooks.md").write_text("# Notebooks\n\n```{toctree}\n:glob:\n\nderive/*\n```\n")
    run = run_sphinx(stub, tmp_path / "out")
    assert run.returncode == 0, run.stderr
    pages = tmp_path / "out" / "derive"
    assert notebook_outputs_shown(pages / "01_executed.html", stub / "derive" / "01_executed.ipynb") == []
    assert notebook_outputs_shown(pages / "02_not_executed.html", stub / "derive" / "02_not_executed.ipynb") != []
    # the check reads the page, not only the notebook: the executed notebook against the bare page fails
    assert notebook_outputs_shown(pages / "02_not_executed.html", stub / "derive" / "01_executed.ipynb") != []


def _prior_build(folder: Path) -> Path:
    folder.mkdir(parents=True)
    (folder / ".buildinfo").write_text("# an earlier build\n")
    (folder / "marker.html").write_text("the previous site\n")
    return folder


def test_a_failed_build_leaves_the_previous_site_and_a_passing_one_replaces_it(stub, tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(docsite, "source_dir", lambda: stub)
    out = _prior_build(tmp_path / "site" / "html")
    (stub / "zz-broken.md").write_text("# Broken\n\n[gone](no-such-page.md)\n")
    assert main(["docs", "--out", str(out)]) == 1
    assert "left as it was" in capsys.readouterr().err
    assert (out / "marker.html").is_file() and not (out / "index.html").exists()
    assert sorted(p.name for p in out.parent.iterdir()) == ["html"]  # no staging folder left behind
    (stub / "zz-broken.md").unlink()
    assert main(["docs", "--out", str(out)]) == 0
    assert (out / "index.html").is_file() and not (out / "marker.html").exists()
    assert sorted(p.name for p in out.parent.iterdir()) == ["html"]
    assert "no warnings" in capsys.readouterr().out


def _one_line_error(capsys, argv) -> str:
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1 and captured.err.startswith("adbgen: error: ")
    return captured.err


def test_refuses_to_replace_a_folder_that_is_not_a_build(tmp_path, capsys):
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "notes.txt").write_text("keep me\n")
    assert "not an earlier documentation build" in _one_line_error(capsys, ["docs", "--out", str(folder)])
    assert (folder / "notes.txt").read_text() == "keep me\n" and len(list(folder.iterdir())) == 1


def test_refuses_an_output_folder_inside_the_sources(capsys):
    assert "inside the documentation's sources" in _one_line_error(capsys, ["docs", "--out", str(ROOT / "docs" / "site")])
    assert not (ROOT / "docs" / "site").exists()


def test_without_the_docs_extra_one_line_names_it(monkeypatch, capsys, tmp_path):
    monkeypatch.setattr(docsite, "missing_packages", lambda: ["sphinx-argparse"])
    err = _one_line_error(capsys, ["docs", "--out", str(tmp_path / "html")])
    assert "sphinx-argparse" in err and ".[docs]" in err
