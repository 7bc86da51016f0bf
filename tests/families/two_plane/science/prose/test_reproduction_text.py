"""The two-plane reproduction's sections rendered from their templates (prose/*.md.j2) with the published run's
numbers give the committed docs/reproduction.md's lines exactly: section 3.2.3, Figure 5(a) and section 6's
set-up and table.  The numbers below are those of the committed page (the run of 2026-11-29); the words come from
the templates, so a changed word fails here (the negative control plants one)."""

from pathlib import Path
from types import SimpleNamespace

import pytest

from adbgen.families.two_plane.science import prose
from adbgen.families.two_plane.science import reproduce as rp
from template_checks import changed_template

ROOT = Path(__file__).resolve().parents[5]
DOC = (ROOT / "docs" / "reproduction.md").read_text().split("\n")


def _exchange():
    ex = SimpleNamespace(
        m_c=0.0025, omega_1=0.9950371898, omega_2=1.7960530216, frozen=(0.99503719031, 1.7960530203),
        small_eps=(1e-4, 0.999950, 1.808937), curve={0.6: 0.3184},
        study={0.01: (1.0247, 1.8662), 0.001: (1.0041, 1.8237), 0.0001: (0.9984, 1.8037), 1e-05: (0.9966, 1.7988)})
    return {"ex": ex, "odd": {0.6: 0.3267}, "even": {0.6: 1.0},
            "figure": ROOT / "docs" / "reproduction" / "two_plane_exchange.png"}


def _fig5a():
    pts = [(0.00335636, 0.34786, False), (0.00379393, 0.36525, True), (0.00544378, 0.61134, False),
           (0.0701526, 1.64208, True), (0.0938595, 2.01428, False)]
    return {"m_c": 0.0025, "stable_at_pitchfork": True, "m_max": 0.103,
            "points": [{"m": m, "frequency": f, "stable_after": s} for m, f, s in pts]}


def _study():
    by_rtol = {  # the table's columns rtol 1e-7, 1e-9, 1e-11 (the last is "converged")
        "stalls_15a": ([(0.9939, 1.11, 3.18)], [(0.9938, 1.11, 3.18)], [(0.9936, 1.11, 3.18)]),
        "sync_15a": (None, None, None), "end_min_15a": (3.6 * 0.9784,) * 3,
        "stalls_15b": ([(0.9973, 1.04, 1.22), (1.8208, 1.87, 2.48)], [(0.9976, 1.04, 1.22), (1.8208, 1.87, 2.48)],
                       [(0.9984, 1.04, 1.22), (1.8199, 1.87, 2.48)]),
        "sync_15b": (5643.0,) * 3, "end_A_15b": (0.000387,) * 3, "t_plain_peak": (218.2, 218.4, 218.4),
        "sync_16a": (1596.0,) * 3, "end_A_16a": (3.21e-07,) * 3, "burst_16a": (792.5, 792.5, 792.64),
        "sync_16b": (914.0,) * 3, "ratio_16b": (0.7196, 0.7189, 0.7192), "ratio_16a": (0.9946, 0.9948, 0.9948)}
    study = {r: {k: v[i] for k, v in by_rtol.items()} for i, r in enumerate(rp.RUN_RTOLS)}
    study[rp.RUN_RTOLS[-1]]["t_con"] = 200.7
    return study


def _rendered():
    return (rp.exchange_lines(_exchange(), ROOT / "docs") + rp.figure_5a_lines(_fig5a())
            + ["@"] + rp.runup_table_lines(_study(), 0.0))


def _published(lines):
    """The committed page's lines the three renderings stand for (`@` marks where section 6 starts)."""
    cut = lines.index("@")
    first = DOC.index(lines[0])
    six = DOC.index("### Section 6: run-ups (Figures 15, 16)")
    return DOC[first:first + cut] + ["@"] + DOC[six:six + len(lines) - cut - 1]


def test_sections_equal_the_committed_page():
    lines = _rendered()
    assert len(lines) > 60
    assert lines == _published(lines)


def test_a_changed_template_word_is_caught(tmp_path, monkeypatch):
    """Negative control: the same numbers through a template with one word changed do not give the page."""
    with changed_template(prose, "runups.md.j2", "undeflected", "deflected", tmp_path, monkeypatch):
        lines = _rendered()
        assert lines != _published(lines)


@pytest.mark.parametrize("later", [True, False])
def test_figure_5a_without_later_points_ends_the_sentence(later):
    r = _fig5a()
    if not later:
        r["points"] = r["points"][:3]
    text = rp.figure_5a_lines(r)[-2]
    assert text.endswith("compare them with)." if later else "Hopf bifurcations.")


def _fig12():
    """Figure 12(a)'s published brute force: the points carried on, the peaks, the limit and the intervals (the
    rest of Figure 12 given but not compared here)."""
    pts = [{"Omega": w, "first": w < 1.2 or w > 2.6, "balanced": True, "t": 16000.0 if 1.5 < w < 2.6 else 8000.0,
            "settled": True, "A_bar": 1e-9} for w in (1.1, 1.6, 1.65, 1.7, 2.5, 3.0)]
    return {"peaks": [(1.0, 1.00009), (2.242, 2.23735)], "limit": {10.0: 0.0001053, 20.0: 0.0001013, 40.0: 0.000100349},
            "points": pts, "intervals": [(1.1, 1.7), (2.5, 5.0)], "first_intervals": [(1.1, 1.55), (2.55, 5.0)],
            "floquet": {"stable": [(1.1, 1.7)], "parity": {}}, "dyn_floquet": {"stable": [], "growth": {}},
            "dyn_points": [], "omegas": [0.2, 5.0], "plain": [1e-4, 1.003e-4], "worst_ratio": (1.5, 30.0),
            "figure": ROOT / "docs" / "reproduction" / "a.png", "figure_b": ROOT / "docs" / "reproduction" / "b.png",
            "dyn_intervals": [], "dyn_first_intervals": []}


def _fig12_published(lines):
    """The rendered Figure 12(a) paragraph on the carried points and the table's rows that are lines of the page."""
    para = next(x for x in lines if "Carried on:" in x or "No point changes" in x)
    rows = [x for x in lines if x.startswith(("| plain rotor", "| conical", "| ABB balances"))]
    return [para] + rows


def test_figure_12a_carried_points_and_table_equal_the_committed_page():
    got = _fig12_published(rp.fig12_lines(_fig12(), ROOT / "docs"))
    assert len(got) == 6 and all(x in DOC for x in got)
    first = DOC.index(got[1])
    assert DOC[first:first + 5] == got[1:]


def test_figure_12a_changed_word_is_caught(tmp_path, monkeypatch):
    with changed_template(prose, "fig12.md.j2", "Converged: balanced on", "Converged: balanced at", tmp_path,
                          monkeypatch):
        got = _fig12_published(rp.fig12_lines(_fig12(), ROOT / "docs"))
        assert got[0] not in DOC and all(x in DOC for x in got[1:])


def _notes(**figures):
    """runup_notes.md.j2 with every value but the figures a placeholder (its words are checked by hand; its
    figure lines here)."""
    from jinja2 import meta

    env = prose._environment()
    source = (prose.FOLDER / "runup_notes.md.j2").read_text()
    names = meta.find_undeclared_variables(env.parse(source)) - set(figures) - set(env.globals)
    return prose.render("runup_notes", **{n: f"<{n}>" for n in names}, **figures)


def test_section_6_ends_with_its_two_figures_as_the_committed_page():
    """The notes end section 6 with Figures 15 and 16 (moved from Python into runup_notes.md.j2): the
    committed page's last lines of the section, blank line kept.  Negative control: the figures swapped."""
    figures = {"figure_15": "reproduction/two_plane_15.png", "figure_16": "reproduction/two_plane_16.png"}
    tail = _notes(**figures)[-5:]
    at = DOC.index(tail[1])
    assert tail[0] == "" and DOC[at - 1:at + 4] == tail
    swapped = _notes(figure_15=figures["figure_16"], figure_16=figures["figure_15"])[-5:]
    assert DOC[at - 1:at + 4] != swapped
