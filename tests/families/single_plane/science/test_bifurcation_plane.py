"""Thesis Figs. 4.1, 4.5, 4.10: every steady state along rows of the (Omega, mu) plane
(science/bifurcation_plane.py, issue 36)."""

import pytest

from adbgen.families.single_plane.science import bifurcation_plane as bp
from adbgen.families.single_plane.science import one_parameter as op


def test_changes_are_found_and_located_to_the_tolerance():
    """A planted count with a narrow window (0.30-0.31, narrower than one grid step) between two grid points."""
    f = lambda x: 1 if 0.30 < x < 0.31 else (0 if x < 0.7 else -1)  # noqa: E731
    xs = [0.0, 0.5, 1.0]
    changes, unresolved = bp._changes(f, xs, [f(x) for x in xs])
    assert unresolved == []
    # the window inside one cell is found only where the cell's ends differ: the negative control is the first
    # cell, whose ends agree (0 and 0): its window is not claimed, the second cell's end of existence is
    assert [(c[1], c[2]) for c in changes] == [(0, -1)]
    assert changes[0][0] == pytest.approx(0.7, abs=bp.TOL)


def test_several_changes_inside_one_cell_are_all_located():
    f = lambda x: 0 if x < 0.2 else (2 if x < 0.4 else 1)  # noqa: E731
    changes, _ = bp._changes(f, [0.0, 1.0], [f(0.0), f(1.0)])
    assert [(round(x, 5), a, b) for x, a, b in changes] == [(0.2, 0, 2), (0.4, 2, 1)]


@pytest.fixture(scope="module")
def row_n2(request):
    """One row of the n = 2 plane at mu = 0.0025 (below mu_c) and one at mu = 0.05 (above), on a coarse grid."""
    mp = pytest.MonkeyPatch()
    mp.setattr(bp, "ROWS", (0.005, 0.1))
    mp.setattr(bp, "OMEGA", tuple(float(v) for v in __import__("numpy").linspace(0.05, 3.0, 60)))
    try:
        yield bp.plane(2)
    finally:
        mp.undo()


def test_rows_agree_with_the_one_parameter_diagrams(row_n2):
    """The coincident state 2- at mu = 0.0025 (Fig. 4.2(b)) and the balanced state at mu = 0.05 (Fig. 4.2(a)):
    the row's stable windows equal one_parameter's, an independent grid bisected to 1e-8."""
    low, high = row_n2["rows"]
    ref = op.state_intervals(2, "2-", "Omega", {"mu": 0.0025}, span=(0.05, 3.0))["stable"]
    assert low["states"]["2-"]["stable"] == [pytest.approx(iv, abs=2e-7) for iv in ref]
    ref = op.state_intervals(2, "1", "Omega", {"mu": 0.05}, span=(0.05, 3.0))["stable"]
    assert high["states"]["1"]["stable"] == [pytest.approx(iv, abs=2e-7) for iv in ref]
    kinds = [c["kind"] for c in low["states"]["2-"]["changes"]]
    assert kinds == ["Hopf", "Hopf"]  # H2-: unstable only between two Hopf points below mu_c
    ends = [c for c in high["states"]["2-"]["changes"] if c["kind"] in ("exists", "ends")]
    assert len(ends) == 2 and {c["meets"] for c in ends} == {"2+"}  # SN2+-: 2- meets 2+ at both


def test_the_thesis_statements_hold_and_a_wrong_plane_fails_them(row_n2):
    res = {"planes": [dict(row_n2, figure="4.1")]}
    checks = {c["text"]: c for c in bp.statements(res)}
    assert checks["the coincident state 2+ is always unstable"]["holds"]
    assert checks["for mu < mu_c the only stable steady state is the coincident state 2-"]["holds"]
    # negative control: plant a stable window of 2+ on the first row
    import copy

    bad = copy.deepcopy(row_n2)
    bad["rows"][0]["states"]["2+"]["stable"] = [(0.5, 0.6)]
    checks = {c["text"]: c for c in bp.statements({"planes": [dict(bad, figure="4.1")]})}
    assert not checks["the coincident state 2+ is always unstable"]["holds"]
    assert checks["the coincident state 2+ is always unstable"]["first_failure"] == 0.005
    assert not checks["for mu < mu_c the only stable steady state is the coincident state 2-"]["holds"]


def test_the_coincident_curves_are_compared_across_n_and_a_difference_is_reported(row_n2):
    import copy

    same = {"planes": [row_n2, copy.deepcopy(row_n2)]}
    assert bp.coincident_agreement(same)["differing"] == [] and bp.coincident_agreement(same)["worst"] == 0.0
    other = copy.deepcopy(row_n2)
    other["rows"][0]["states"]["2-"]["changes"].pop()  # negative control: one Hopf point fewer
    agreement = bp.coincident_agreement({"planes": [row_n2, other]})
    assert [(d["total"], d["state"]) for d in agreement["differing"]] == [(0.005, "2-")]


def test_the_section_and_figure_are_written(row_n2, tmp_path):
    res = {"planes": [dict(row_n2, figure="4.1")]}
    paths = bp.draw(res, tmp_path)
    assert [p.name for p in paths] == ["fig4_n2_bifurcation_omega_mu.png"]
    import json

    data = json.loads(paths[0].with_suffix(".json").read_text())
    assert {k[2] for k in data["changes"]["2-"]} == {"Hopf", "exists", "ends"}
    text = "\n".join(bp.lines(res, paths, tmp_path))
    assert "## Thesis, Figs. 4.1, 4.5, 4.10: every steady state over (Omega, mu)" in text
    assert "| 2+ | never stable | - |" in text and "(fig4_n2_bifurcation_omega_mu.png)" in text
