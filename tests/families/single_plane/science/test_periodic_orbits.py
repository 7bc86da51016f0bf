"""The thesis' periodic orbits section (issue 36): Fig. 5.10(b)'s desynchronised orbit, the special points drawn
on their own sheet of a folded branch."""

import math
from types import SimpleNamespace as NS

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
    from adbgen.analysis import equilibrium_scan
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.orbits.parameters import ParameterMap

    m = load_model(f"thesis_rotating_n{n}")
    p = m.params({"Omega": 4.0, **periodic_orbits.CH4})
    sc = equilibrium_scan.scan(m, p, m.module.START, "Omega", 4.0, 0.5)
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
    from adbgen.analysis import equilibrium_scan
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.orbits.parameters import ParameterMap

    m = load_model("thesis_rotating_n4")
    p = m.params({"Omega": 4.0, **periodic_orbits.CH4})
    h1 = equilibrium_scan.scan(m, p, m.module.START, "Omega", 4.0, 0.5).points[0]
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


HEADING = "## Periodic orbits of the single-plane balancer (thesis ch. 4-6)"


class _Branch:
    def __init__(self, orbits, specials, parameter, stable, period=()):
        self.orbits, self.specials = [None] * orbits, specials
        self._json = {"parameter": parameter, "stable": stable, "period": list(period)}

    def to_json(self):
        return self._json


def _hopf(lam, omega, l1, criticality="supercritical", drift=None):
    return NS(lam=lam, omega=omega, l1=l1, criticality=criticality, info={"drift": drift})


def _inputs():
    """The committed section's values, to the digits it prints."""
    o = NS(period=6.2105202807, r_min=0.017886, r_max=0.161001, trivial_multiplier_error=8.3e-11,
           nontrivial=[0.970007, 0.970007j, 0.963207, 0.963207, 0.945204, 0.945204, 0.888342])
    a = {"orbit": o, "returns": 321, "T_sim": 6.2105202807 * (1 + 1.0e-12),
         "auto": {"Omega": 3.9999963182, "period": 6.2105278661 * (1 + 2.5e-12),
                  "multipliers": [(x, 0.0) for x in (0.888342, 0.945204, 0.945204, 0.963207, 0.963207, 0.970007,
                                                     0.970007, 1.0)]},
         "auto_ours": NS(period=6.2105278661)}
    specials = [{"kind": k, "Omega": w, "period": t} for k, w, t in (
        ("torus", 1.867450, 8.63054), ("period-doubling", 1.679319, 11.76308), ("torus", 1.627565, 13.12118),
        ("fold", 1.536488, 17.64295), ("fold", 1.537931, 17.79840), ("fold", 1.537821, 17.97786),
        ("period-doubling", 1.568184, 18.50246))]
    every = {2: [(1.88223935, 0.7431173, -0.052581), (1.09363427, 0.2516524, -0.10528),
                 (1.02969415, 0.1243969, -2.5779)],
             3: [(1.87536745, 0.4721717, -0.034452), (1.71244687, 0.6821876, -0.68264),
                 (1.61276725, 0.6050406, 1.3409, "subcritical")],
             4: [(2.17660048, 1.1103468, -0.1538), (1.30263949, 0.4614496, 0.4082, "subcritical"),
                 (1.23945331, 0.3007487, -53.798)]}
    runs = {3: {1e-10: (1.236209e-03, 0.222491), 1e-12: (1.236209e-03, 0.222491)},
            4: {1e-10: (4.007421e-02, 0.391759), 1e-12: (4.007421e-02, 0.391759)}}
    h1 = [{"n": 2, "hopf": _hopf(*every[2][0]), "every_hopf": [_hopf(*h) for h in every[2]],
           "branch": _Branch(300, specials, [1.882226, 1.867488, 1.5871], [True, True, False])}]
    for n, drift, omega, r_end, change in ((3, 0.00479, 1.8654, 1.236209e-03, 0.222491),
                                           (4, 0.00911, 2.1666, 4.007421e-02, 0.391759)):
        h1.append({"n": n, "hopf": _hopf(*every[n][0], drift=drift), "every_hopf": [_hopf(*h) for h in every[n]],
                   "branch": _Branch(1, [], [], []),
                   "drift": {"Omega": omega, "r_end": r_end, "angle_change": change, "runs": runs[n]}})
    h1[2]["drift"]["split"] = {"size": 1e-9, "r_end": 0.441, "angle_change": 26986, "rtol": 1e-12}
    ds = [{"n": n, "orbit": NS(period=period, windings={f"phi_{i + 1}": -1 for i in range(n)}, r_min=lo, r_max=hi,
                                stable=True),
           "branch": _Branch(2, [], [0.0, to], [], [0.0, there])}
          for n, period, lo, hi, to, there in ((3, 1.89357422, 0.1112, 0.1306, 0.9877, 13.2162),
                                               (4, 1.87595473, 0.1342, 0.1529, 0.9735, 12.9491))]
    b = {"orbit": NS(period=1.98589725, windings={"phi_1": -1, "phi_2": -1, "phi_3": -1}, r_min=0.5237, r_max=0.5418,
                     stable=True), "spread": 1.2e-14}
    return a, h1, ds, b


def _document_lines(text: str) -> list[str]:
    """The section as the document has it: its links' placeholders resolved as `adbgen reproduce` does for
    docs/reproduction.md."""
    return text.replace("@DOCS@", ".").replace("@FIGURES@", "reproduction").splitlines()


def test_the_periodic_orbits_section_renders_the_published_lines(published_section):
    """Controls: without AUTO-07p's run its paragraph goes; without the split start its clause goes; a branch
    with no stable orbit says no stable interval."""
    published = published_section(HEADING)
    a, h1, ds, b = _inputs()
    # the section ends without the blank line the document puts before the next family's
    assert _document_lines(periodic_orbits.lines(a, h1, ds, b)) == published[:-1]
    no_auto = {k: v for k, v in a.items() if k not in ("auto", "auto_ours")}
    lines = _document_lines(periodic_orbits.lines(no_auto, h1, ds, b))
    assert not any(line.startswith("AUTO-07p (collocation") for line in lines) and len(lines) == len(published) - 3
    del h1[2]["drift"]["split"]
    assert "unstable invariant set" not in periodic_orbits.lines(a, h1, ds, b)
    h1[0]["branch"]._json["stable"] = [False] * 3
    assert "stable for Omega in" not in periodic_orbits.lines(a, h1, ds, b)
