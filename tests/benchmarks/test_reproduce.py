"""`adbgen bench reproduce`: the comparison of a fresh document with the committed one (the full run is the
benchmark itself; here the machinery, on small stand-ins)."""

from __future__ import annotations

from benchmarks import reproduce


def _doc(folder, text: str, png: bytes):
    (folder / "reproduction").mkdir(parents=True)
    (folder / "reproduction.md").write_text(text)
    (folder / "reproduction" / "a.png").write_bytes(png)
    return folder / "reproduction.md"


def test_an_identical_document_and_figures_compare_identical(tmp_path):
    old = _doc(tmp_path / "old", "# T\n\nrow 1\nrow 2\n", b"png")
    new = _doc(tmp_path / "new", "# T\n\nrow 1\nrow 2\n", b"png")
    res = reproduce.compare(new, new.parent / "reproduction", committed=old)
    assert res["document_identical"] and res["lines_differing"] == 0 and res["figures_differing"] == []


def test_a_changed_line_or_figure_is_reported(tmp_path):
    """Negative control: one digit and one figure's bytes differ."""
    old = _doc(tmp_path / "old", "# T\n\nrow 1\nrow 2\n", b"png")
    new = _doc(tmp_path / "new", "# T\n\nrow 1\nrow 3\n", b"pnG")
    res = reproduce.compare(new, new.parent / "reproduction", committed=old)
    assert not res["document_identical"]
    assert res["lines_differing"] == 1 and res["first_differences"] == [(4, "row 2", "row 3")]
    assert res["figures_differing"] == ["a.png"]
    short = _doc(tmp_path / "short", "# T\n\nrow 1\n", b"png")
    assert reproduce.compare(short, short.parent / "reproduction", committed=old)["lines_differing"] == 1


def test_a_run_kept_into_the_committed_folder_is_compared_with_what_was_there_before(tmp_path):
    """`--keep docs/` writes over the committed document: the comparison uses the snapshot taken before the
    run, not the file it has just written (which would always compare identical)."""
    doc = _doc(tmp_path / "docs", "# T\n\nrow 1\nrow 2\n", b"png")
    before = reproduce.snapshot(doc)
    doc.write_text("# T\n\nrow 1\nrow 3\n")  # the run, kept in place
    (doc.parent / "reproduction" / "a.png").write_bytes(b"pnG")
    res = reproduce.compare(doc, doc.parent / "reproduction", before)
    assert not res["document_identical"] and res["figures_differing"] == ["a.png"]
    assert reproduce.compare(doc, doc.parent / "reproduction", doc)["document_identical"]  # the trap it avoids


def test_the_figures_data_is_compared_too(tmp_path):
    """The charts' curves are written as .json beside their figures: a difference there (a timing once crept
    in) is reported like a figure's."""
    old = _doc(tmp_path / "old", "# T\n", b"png")
    new = _doc(tmp_path / "new", "# T\n", b"png")
    (old.parent / "reproduction" / "a.json").write_text('{"curves": []}')
    (new.parent / "reproduction" / "a.json").write_text('{"curves": [], "wall_s": 3.1}')
    res = reproduce.compare(new, new.parent / "reproduction", committed=old)
    assert res["figures"] == 2 and res["figures_differing"] == ["a.json"]


def test_an_inserted_line_is_one_difference_not_every_line_after_it(tmp_path):
    """A paragraph added in the middle: one changed stretch, reported where it starts; the lines after it
    are matched as a diff matches them (a line-by-line zip had counted all of them)."""
    old = _doc(tmp_path / "old", "# T\n\nrow 1\nrow 2\nrow 3\nrow 4\n", b"png")
    new = _doc(tmp_path / "new", "# T\n\nrow 1\nnew row\nrow 2\nrow 3\nrow 4\n", b"png")
    res = reproduce.compare(new, new.parent / "reproduction", committed=old)
    assert res["lines_differing"] == 1 and res["first_differences"] == [(4, "", "new row")]


def test_a_document_written_elsewhere_is_compared_as_written_into_docs(tmp_path):
    """The benchmark writes into a temporary folder, from which the links to the documentation pages read
    `../../<checkout>/docs/orbits.md` where the committed document has `./orbits.md` (the only differing
    line of the run of 2026-11-27 18:19): compared as if written into docs/, identical.  Negative control:
    the same document with one number changed still differs."""
    docs = tmp_path / "repo" / "docs"
    committed = _doc(docs, "# T\n\nsee [Periodic orbits](./orbits.md).\nr = 0.05\n", b"png")
    away = tmp_path / "tmp" / "run"
    rel = reproduce.os.path.relpath(docs, away)
    assert rel.startswith("../")
    written = _doc(away, f"# T\n\nsee [Periodic orbits]({rel}/orbits.md).\nr = 0.05\n", b"png")
    res = reproduce.compare(written, away / "reproduction", committed, docs)
    assert res["document_identical"] and res["lines_differing"] == 0
    written.write_text(f"# T\n\nsee [Periodic orbits]({rel}/orbits.md).\nr = 0.06\n")
    res = reproduce.compare(written, away / "reproduction", committed, docs)
    assert not res["document_identical"] and res["first_differences"] == [(4, "r = 0.05", "r = 0.06")]
