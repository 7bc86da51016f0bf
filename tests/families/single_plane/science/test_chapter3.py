"""Thesis ch. 3 recomputed from the generated models (science/chapter3.py, issue 36)."""

import pytest

from adbgen.families.single_plane.science import chapter3


def test_coincident_states_cease_to_exist_at_the_printed_critical_speeds():
    c1, c2 = chapter3.existence_bounds(3, "2+")
    assert c1 == pytest.approx(0.8114, abs=5e-5) and c2 == pytest.approx(1.0717, abs=5e-5)


def test_in_line_states_bounds_are_3_18_s_not_3_16_s():
    d1, d2 = chapter3.existence_bounds(3, "3(2)+")
    assert d1 == pytest.approx(0.8909, abs=5e-5) and d2 == pytest.approx(0.9761, abs=5e-5)
    assert abs(d1 - 0.8114) > 1e-2  # negative control: the other state's printed speed is not matched


@pytest.mark.parametrize("n, member, printed", [(3, 0.0, 2.21429743558818), (3, 3.141592653589793, 1.15927948072741),
                                                (4, "closed form", 0.45102681179626)])
def test_balanced_positions(n, member, printed):
    assert chapter3.balanced_position(n, member) == pytest.approx(printed, abs=5e-14)


def test_the_text_says_disagree_when_a_speed_is_off():
    res = {"critical": [("(3.16)", 3, "2+", (0.8114, 1.0717), [0.8114, 1.0717])],
           "positions": [("(5.2)", 2, 1.67096374795646, 1.67096374795646)], "speeds_agree": False,
           "positions_agree": True}
    text = "\n".join(chapter3.lines(res))
    assert "do **not** all agree to the four printed digits" in text and "| (3.16) | 3 | 2+ | 0.8114, 1.0717 |" in text


def test_2_minus_windows_end_at_the_pitchfork_hopf_points_for_n4_at_mu_c():
    w = chapter3.coincident_windows(4, 0.0025, lo=0.9, hi=1.5, count=61)
    assert w[0][1] == pytest.approx(1.0079598, abs=1e-6) and w[1][0] == pytest.approx(1.338096, abs=1e-6)


def test_the_statements_on_2_minus_are_judged_from_the_windows():
    windows = {(n, mu): [(0.05, 0.8)] for n in (2, 3, 4) for mu in chapter3.COINCIDENT_MUS}
    text = "\n".join(chapter3.coincident_lines(windows))
    assert "(Omega = 0.5, mu = 0.05): n = 2 stable, n = 3 stable, n = 4 stable." in text
    # planted: no window reaches Omega = 4 at mu = 0.0025, so the second statement fails
    assert "(Omega = 4, mu = 0.0025): n = 2 **not stable**, n = 3 **not stable**." in text
