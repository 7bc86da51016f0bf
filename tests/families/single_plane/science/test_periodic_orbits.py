"""The thesis' periodic orbits section (issue 36): Fig. 5.10(b)'s desynchronised orbit, the special points drawn
on their own sheet of a folded branch."""

import math

import numpy as np
import pytest

from adbgen.families.single_plane.science import periodic_orbits


def test_fig_5_10b_is_a_desynchronised_orbit_with_the_balls_together():
    res = periodic_orbits.fig510b(progress=lambda *_: None)
    o = res["orbit"]
    assert o.period == pytest.approx(1.98590, abs=5e-6)  # the audit's independent value
    assert o.windings == {"phi_1": -1, "phi_2": -1, "phi_3": -1} and o.stable
    assert res["spread"] < 1e-9


def test_a_special_point_is_marked_on_the_sheet_of_its_period():
    # a branch folding back in Omega: two sheets over the same Omega, told apart by the period
    lam = np.array([1.50, 1.55, 1.60, 1.62, 1.60, 1.55])
    per = np.array([4.0, 4.1, 4.2, 4.4, 4.6, 4.8])
    special = {"Omega": 1.601, "period": 4.6}
    k = periodic_orbits.special_index(lam, per, special)
    assert k == 4
    assert int(np.argmin(np.abs(lam - special["Omega"]))) == 2  # negative control: by Omega alone, the other sheet


def _every_hopf(n):
    from adbgen.analysis import continuation
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.orbits.parameters import ParameterMap

    m = load_model(f"thesis_rotating_n{n}")
    p = m.params({"Omega": 4.0, **periodic_orbits.CH4})
    sc = continuation.scan(m, p, m.module.START, "Omega", 4.0, 0.5)
    return periodic_orbits.every_hopf(m, ParameterMap(m, p, ["Omega"]), sc)


def test_every_hopf_point_of_n2_has_its_l1():
    pts = _every_hopf(2)
    assert [round(h.lam, 7) for h in pts] == [1.8822393, 1.0936343, 1.0296942]  # AUTO-07p's HB labels
    assert all(h.criticality == "supercritical" for h in pts)
    assert pts[0].l1 == pytest.approx(-0.0525811, rel=1e-4)


def test_n3_has_a_subcritical_hopf_point_below_h1():
    """Negative control for the criticality column: not every point is supercritical."""
    crit = {round(h.lam, 4): h.criticality for h in _every_hopf(3)}
    assert crit[1.8754] == "supercritical" and crit[1.6128] == "subcritical"


def test_n4_past_h1_balls_at_one_angle_drift_and_moved_apart_they_lap():
    """Issue 36: docs/orbits.md (0.39 rad) and the reproduction (r = 0.436, balls lapping) disagreed; the run on
    `simulate` at two rtols gives docs/orbits.md's drift."""
    from adbgen.analysis import continuation
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.orbits.parameters import ParameterMap

    m = load_model("thesis_rotating_n4")
    p = m.params({"Omega": 4.0, **periodic_orbits.CH4})
    h1 = continuation.scan(m, p, m.module.START, "Omega", 4.0, 0.5).points[0]
    d = periodic_orbits.drift_past_h1(m, ParameterMap(m, p, ["Omega"]), h1.y, h1.value)
    assert d["angle_change"] == pytest.approx(0.3918, abs=1e-3) and d["r_end"] == pytest.approx(0.0401, abs=1e-3)
    (r1, a1), (r2, a2) = d["runs"].values()
    assert abs(a1 - a2) < 1e-5 and abs(r1 - r2) < 1e-6  # the same at both tolerances
    # the start has balls 3, 4 at one angle, an unstable invariant set: split by 1e-9 they lap (the flow at
    # rtol 1e-11 left the set by round-off and reported this; sampling density was not the cause)
    sp = d["split"]
    assert sp["r_end"] > 0.3 and sp["angle_change"] > 1e3


def test_split_run_only_when_free_balls_coincide():
    """Negative control for `split`: free balls at distinct angles are left alone (no run, None); coincident ones
    are moved apart (a 1-unit run, so it is cheap)."""
    from adbgen.analysis.loading import load_model

    m = load_model("thesis_rotating_n4")
    p = m.params({"Omega": 2.1666, **periodic_orbits.CH4})
    free = list(m.angle_indices)[2:]
    apart = m.state({"phi_3": 3.0, "phi_4": 3.3})
    assert periodic_orbits._split_run(m, p, apart, free, 1.0) is None
    together = m.state({"phi_3": math.pi, "phi_4": math.pi})
    sp = periodic_orbits._split_run(m, p, together, free, 1.0)
    assert sp is not None and sp["size"] == periodic_orbits.SPLIT
