"""The thesis' rows of the covered / not covered table (science/coverage.py, issue 36)."""

from pathlib import Path

import pytest

from adbgen.families.single_plane.science import coverage, periodic_orbits, reproduce

SCIENCE = Path(coverage.__file__).parent



def test_every_thesis_figure_of_chapters_3_to_5_has_a_row():
    assert coverage.missing() == []


def test_a_figure_without_a_row_is_found():
    """Negative control: the table without its Fig. 5.18 row misses 5.18."""
    rows = tuple(c for c in coverage.THESIS if "5.18" not in c.item)
    assert coverage.missing(rows) == ["5.18"]


@pytest.mark.parametrize("row", [c for c in coverage.THESIS if c.covered], ids=lambda c: c.item)
def test_a_covered_row_names_a_heading_the_sections_write(row):
    text = "\n".join(p.read_text() for p in [*SCIENCE.glob("*.py"), *SCIENCE.glob("templates/*.j2")])
    assert f"## {row.where}" in text


def test_the_rows_are_split_between_the_two_sections():
    assert set(reproduce.REPRODUCTION.coverage) | set(periodic_orbits.REPRODUCTION.coverage) == set(coverage.THESIS)
    assert all(c.where == coverage.ORBITS for c in periodic_orbits.REPRODUCTION.coverage)


def test_maps_are_captioned_by_their_own_figure_and_n2_has_no_zeta_beta_map():
    captions = [reproduce.map_caption(n, plane, fig) for n, plane, _, fig in reproduce.MAPS]
    assert len(set(captions)) == len(captions)
    assert [(n, fig) for n, plane, _, fig in reproduce.MAPS if "Omega" in plane] == [(2, "4.1"), (3, "4.5"), (4, "4.10")]
    assert not any(n == 2 and "zeta" in plane for n, plane, _, _ in reproduce.MAPS)


def test_the_new_sections_are_spliced_where_the_table_says(monkeypatch, tmp_path):
    """Figs. 5.1-5.3 and the named starts after the scans, ch. 3 before ch. 4, the plain rotor before the n = 3
    basins: every covered heading of the section is written once by reproduce.lines."""
    from adbgen.families.single_plane.science import bifurcation_plane, chapter3, one_parameter, plain, starts, sweeps

    monkeypatch.setattr(reproduce, "_document", lambda *a, **k: [
        f"## {coverage.TRANSIENTS}", "", "## Figures", "", f"## {coverage.CH4}"])
    monkeypatch.setattr(sweeps, "lines", lambda *a, **k: [f"## {coverage.SCANS}", "", f"## {coverage.LAUNCHES}", "",
                                                          f"## {coverage.BASIN_N3}", ""])
    monkeypatch.setattr(starts, "lines", lambda res: [f"## {coverage.RANDOM}", "", f"## {coverage.NAMED}"])
    monkeypatch.setattr(chapter3, "lines", lambda res: [f"## {coverage.CH3}"])
    monkeypatch.setattr(plain, "lines", lambda results, lyap: [f"## {coverage.PLAIN}"])
    monkeypatch.setattr(one_parameter, "lines", lambda res: [f"## {coverage.ONE_PARAMETER_DIAGRAMS}"])
    monkeypatch.setattr(bifurcation_plane, "lines", lambda res, paths, root: [f"## {coverage.PLANE}"])
    res = {k: None for k in ("figures", "statements", "maps", "basins", "basins_n4", "sweeps", "sweep_figures",
                             "lyapunov", "starts", "chapter3", "one_parameter")}
    res["bifurcation_plane"] = {"figures": []}
    res.update(transients=[], results=[])
    heads = [ln[3:] for ln in reproduce.lines(res, tmp_path) if ln.startswith("## ")]
    assert heads == [coverage.TRANSIENTS, "Figures", coverage.SCANS, coverage.RANDOM, coverage.NAMED,
                     coverage.LAUNCHES, coverage.PLAIN, coverage.BASIN_N3, coverage.CH3,
                     coverage.ONE_PARAMETER_DIAGRAMS, coverage.PLANE, coverage.CH4]
