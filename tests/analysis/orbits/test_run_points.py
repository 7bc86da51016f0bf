"""`run_points.add_margins` (adbgen/analysis/orbits/run_points.py): at a bifurcation point of AUTO's run the margin's
uncertainty counts where AUTO placed the point.  thesis_rotating_n2's balanced state 1 has a Hopf point near
Omega = 1.0297 (thesis Fig. 4.2); the exact one is found here by a root of the leading real part, and the row is
put 4.5e-9 beyond it, as far as AUTO-07p placed HB 4 from the equilibrium scan's (1.0296941594 against
1.0296941549), inside AUTO's location tolerance EPSS (1 + sqrt|DS DSMAX|) ~ 1e-8."""

from __future__ import annotations

import pytest

from adbgen.analysis.auto07p import location_tolerance
from adbgen.analysis.orbits import run_points

from analysis_helpers import thesis_n2_hopf, thesis_n2_state


def _setup():
    model, p, _ = thesis_n2_state(4.0)
    hopf, follow = thesis_n2_hopf()
    return model, p, lambda omega: thesis_n2_state(omega)[1:], hopf, follow


def _row(model, state, omega, location):
    _, y = state(omega)
    row = {"type": "HB", "Omega": omega, "state": dict(zip(model.state_names, map(float, y)))}
    return row if location is None else {**row, "location_uncertainty": location}


def test_the_hopf_point_auto_placed_is_marginal_and_a_regular_point_keeps_its_verdict():
    model, p, state, hopf, follow = _setup()
    tol = location_tolerance(1e-8, 0.0025, 0.005)  # the c. file's EPSS, `continue`'s DS, DSMAX for 4 -> 0.5
    hb, bare, regular = _row(model, state, hopf + 4.5e-9, tol), _row(model, state, hopf + 4.5e-9, None), \
        _row(model, state, 4.0, None)
    run_points.add_margins(model, [hb, bare, regular], "Omega", p, follow)
    assert hb["margin"] < 0 and hb["marginal"] and hb["margin_uncertainty"] > abs(hb["margin"])
    assert "where AUTO-07p placed the point" in hb["margin_estimate"]
    # negative controls: the same point counted without its location error was certified "stable" (the audit's
    # HB 4, margin -1.2e-8 certain to 4.3e-9); a point far from any bifurcation keeps its plain verdict
    assert not bare["marginal"] and bare["margin_uncertainty"] < abs(bare["margin"])
    assert not regular["marginal"] and regular["margin"] < -1e-3


def test_a_bifurcation_point_with_a_clear_margin_is_not_made_marginal():
    """The location term is |d margin / d Omega| x the location error, not a blanket verdict: a row marked as a
    bifurcation point where the leading real part is far from zero keeps its certified margin."""
    model, p, state, _, follow = _setup()
    row = _row(model, state, 4.0, location_tolerance(1e-8, 0.0025, 0.005))
    run_points.add_margins(model, [row], "Omega", p, follow)
    assert not row["marginal"] and row["margin_uncertainty"] < 1e-8 and row["margin"] < -1e-3


def test_a_bifurcation_point_with_no_state_beside_it_is_not_certified():
    """Where the followed state cannot be found on either side the location's effect is unknown: the margin is
    certified to nothing (uncertainty inf, null in JSON) and the row is marginal, even with a clear margin."""
    from adbgen.analysis.loading import AnalysisError

    model, p, state, _, _ = _setup()

    def lost(q, guess):
        raise AnalysisError("Newton did not converge")

    row = _row(model, state, 4.0, 1e-8)
    run_points.add_margins(model, [row], "Omega", p, lost)
    assert row["marginal"] and row["margin_uncertainty"] == float("inf") and row["margin"] < -1e-3
    assert "nothing certified" in row["margin_estimate"]
