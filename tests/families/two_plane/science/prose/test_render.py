"""The two-plane reproduction's prose templates, read by analysis.prose in the package's one template convention:
a line ending in `{##}` goes on in the next, every other line is a line of the document (tables, headings, a
line break kept); a value the template names but the caller does not give is an error (never an empty word)."""

import jinja2
import pytest

from adbgen.families.two_plane.science import prose


def test_a_line_ending_in_the_empty_comment_goes_on_and_the_others_are_kept(tmp_path, monkeypatch):
    (tmp_path / "t.md.j2").write_text("### Head\n\nfirst {{ a }} {##}\nsecond\nthird\n\n| x | y |\n|---|---|\n"
                                      "| {{ a }} | {##}\n2 |\n{% if a %}\nyes\n{% endif %}\n")
    monkeypatch.setattr(prose, "FOLDER", tmp_path)
    prose._environment.cache_clear()
    try:
        assert prose.render("t", a=1) == ["### Head", "", "first 1 second", "third", "", "| x | y |", "|---|---|",
                                          "| 1 | 2 |", "yes"]
        with pytest.raises(jinja2.UndefinedError):  # negative control: a missing value
            prose.render("t")
    finally:
        prose._environment.cache_clear()


def test_the_shipped_templates_name_only_given_values():
    names = sorted(p.name for p in prose.FOLDER.glob("*.md.j2"))
    assert names == ["chart.md.j2", "exchange.md.j2", "fig12.md.j2", "figure_5a.md.j2", "orbits.md.j2",
                     "runup_notes.md.j2", "runups.md.j2"]
    with pytest.raises(jinja2.UndefinedError):
        prose.render("runup_notes", burst="1")
