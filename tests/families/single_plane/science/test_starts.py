"""The named starts of Figs. 5.7(a2), 5.9(a2), 5.9(b2) and the random rotor starts of Figs. 5.1-5.3 (issue 36)."""

import math

import pytest

from adbgen.families.single_plane.science import starts


def test_all_at_pi_reaches_2_minus_and_the_tie_s_minus_pi_does_not():
    """-pi differs from pi in the last bit of sin: the scan's start leaves the unstable coincident state."""
    res = starts.tie_bit_runs(ns=(3,))[3]
    assert res["phi_2(0) = pi"] == "coincident 2-"
    assert res["phi_2(0) = -pi"] == "in-line 3(3-2)-"
    unstable, lead = res["2-"]
    assert unstable == 2 and lead > 1.0
    assert math.sin(-math.pi) == -math.sin(math.pi) != 0.0  # the bit


def test_the_thesis_3_4_1_plus_is_the_label_3_4_3_minus():
    xy = starts.inline_names_agree()
    assert xy["3(1)+"] == pytest.approx(xy["3(3)-"], abs=1e-12)
    assert xy["3(1)-"] == pytest.approx(xy["3(3)+"], abs=1e-12)
    assert xy["3(1)+"][0] != pytest.approx(xy["3(3)+"][0], abs=1e-3)  # negative control: the other sign differs


def test_fig_5_1_a_balances_near_t_600():
    rows = starts.random_rotor_starts(ns=(2,), panels="a")[2]
    assert rows["a"]["label"] == "balanced 1"
    assert 550 < rows["a"]["t_dec"] < 700  # the thesis: "more or less when t = 600"


def test_final_positions_differ_only_when_they_do():
    same = {"a": {"angles": [1.0, -1.0, 3.0]}, "b": {"angles": [-1.0, 1.0, 3.0]}}
    assert not starts.final_positions_differ(same)
    assert starts.final_positions_differ({**same, "c": {"angles": [0.5, -1.5, 2.0]}})


def test_the_section_renders_from_its_template():
    res = {"random": {2: {"a": {"r_max": 0.25, "t_dec": 610.0, "label": "balanced 1", "angles": [1.67, -1.67]}}},
           "tie": {3: {"phi_2(0) = pi": "coincident 2-", "phi_2(0) = -pi": "in-line 3(3-2)-", "2-": (2, 1.43)}},
           "inline": {k: (0.1, 0.0) for k in ("3(1)+", "3(3)-", "3(1)-", "3(3)+")}}
    text = "\n".join(starts.lines(res))
    assert "| 2 | (a) | (-0.0433, 0.0125, -0.1666, 0.0288) | balanced 1 | 0.2500 | 610.00 |" in text
    assert "| 3 | coincident 2- | in-line 3(3-2)- | 2, +1.4300 |" in text
    assert "unsettled" not in text
