"""The thesis' periodic orbits section (issue 36): Fig. 5.10(b)'s desynchronised orbit, the special points drawn
on their own sheet of a folded branch."""

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
