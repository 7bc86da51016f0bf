"""Thesis Figs. 4.2, 4.3, 4.6, 4.7, 4.11, 4.12 recomputed as intervals (science/one_parameter.py, issue 36)."""

import pytest

from adbgen.families.single_plane.science import one_parameter as op


def test_fig_4_2a_balanced_state_windows_end_at_auto_s_hopf_points():
    s = op.state_intervals(2, "1", "Omega", {"mu": 0.05})
    (a, b), (c, d) = s["stable"]
    assert (a, b, c) == pytest.approx((1.0296942, 1.0936343, 1.8822394), abs=1e-6)  # AUTO-07p's HB labels
    assert d == op.RANGES["Omega"][1] and s["exists"] == [op.RANGES["Omega"]]


def test_fig_4_2a_coincident_states_exist_outside_the_critical_speeds_and_only_2_minus_is_stable():
    plus, minus = (op.state_intervals(2, k, "Omega", {"mu": 0.05}) for k in ("2+", "2-"))
    assert plus["exists"] == minus["exists"] and len(minus["exists"]) == 2
    assert plus["stable"] == []  # control: the other coincident state is nowhere stable on this line
    assert minus["stable"] == [(0.05, pytest.approx(minus["exists"][0][1], abs=1e-7))]


def test_the_balanced_state_of_n2_does_not_exist_below_mu_c():
    s = op.state_intervals(2, "1", "mu", {"Omega": 1.5})
    assert s["exists"][0][0] == pytest.approx(0.005, abs=1e-7)  # mu_c = delta/2 (3.14)


def test_the_section_renders_every_panel():
    panels = [{"figure": "4.2(a)", "n": 2, "parameter": "Omega", "fixed": {"mu": 0.05},
               "states": {"1": {"exists": [(0.05, 6.0)], "stable": [(1.88, 6.0)]}, "2+": {"exists": [], "stable": []}}}]
    text = "\n".join(op.lines(panels))
    assert "**Fig. 4.2(a)**: n = 2, in Omega, mu = 0.05" in text
    assert "| 1 | [0.05, 6] | [1.88, 6] |" in text and "| 2+ | nowhere | nowhere |" in text
