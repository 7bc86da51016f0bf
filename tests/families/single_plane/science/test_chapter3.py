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


def test_the_pitchfork_hopf_sentence_prints_by_the_verdict_not_by_the_template():
    """split_at_pitchfork_hopf decides (two windows of n = 4 at mu_c); the template only prints by it."""
    from adbgen.families.single_plane.science.templates import render

    base = {(n, mu): [(0.05, 0.8)] for n in (2, 3, 4) for mu in chapter3.COINCIDENT_MUS}
    two = {**base, (4, 0.0025): [(0.05, 1.0079598), (1.338096, 6.0)]}
    three = {**base, (4, 0.0025): [(0.05, 1.0), (1.2, 1.3), (1.4, 6.0)]}
    assert chapter3.split_at_pitchfork_hopf(two)
    assert not chapter3.split_at_pitchfork_hopf(base) and not chapter3.split_at_pitchfork_hopf(three)
    assert "1.0079598 and 1.3380960, are the pitchfork-Hopf points" in "\n".join(chapter3.coincident_lines(two))
    assert "pitchfork-Hopf points of" not in "\n".join(chapter3.coincident_lines(three))

    def sentence(windows, verdict):
        text = "\n".join(render("coincident", windows=windows, checks=[], lo=0.05, hi=6.0,
                                split_at_pitchfork_hopf=verdict))
        return "pitchfork-Hopf points of" in text
    # planted verdicts against the windows: the template follows the boolean, whatever the windows say
    assert sentence(two, True) and not sentence(two, False)
    assert sentence({**base, (4, 0.0025): [(0.05, 1.0), (1.3, 6.0), (7.0, 8.0)]}, True)


def test_the_committed_section_renders_again_from_its_own_table():
    """docs/reproduction.md's 2- section comes out byte-identical from the windows its table prints (to 7
    decimals, as printed), the pitchfork-Hopf sentence included; planted: a False verdict drops that sentence."""
    import re
    from pathlib import Path

    from adbgen.families.single_plane.science.templates import render

    full = (Path(__file__).parents[4] / "docs" / "reproduction.md").read_text()
    head = "## Thesis, chapter 4: where the coincident state 2- is stable"
    section = full[full.index(head):].split("\n## ", 1)[0]
    windows = {(int(n), float(mu)): [(float(a), float(b)) for a, b in re.findall(r"\[([\d.]+), ([\d.]+)\]", cells)]
               for n, mu, cells in re.findall(r"^\| (\d) \| ([\d.]+) \| (.*) \|$", section, re.M)}
    assert len(windows) == 6 and chapter3.split_at_pitchfork_hopf(windows)
    text = "\n".join(chapter3.coincident_lines(windows))
    assert text.strip() == section.strip()
    checks = [(t, mu, Om, [(n, any(a <= Om <= b for a, b in windows[(n, mu)])) for n in ns])
              for t, ns, mu, Om in chapter3.COINCIDENT_STATEMENTS]
    planted = "\n".join(render("coincident", windows=windows, checks=checks, lo=0.05, hi=6.0,
                               split_at_pitchfork_hopf=False))
    assert planted.strip() != section.strip() and "pitchfork-Hopf" not in planted
