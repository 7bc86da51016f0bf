"""The sweep figures' titles (adbgen/analysis/sweep_figures.py)."""


def test_a_long_title_breaks_before_its_remarks_and_the_caption_between_words():
    from adbgen.analysis.sweep_figures import CAPTION_WIDTH, title_lines

    title = ("thesis_rotating_n3: unstable eigenvalues of the steady state (balanced 1, continued from START) "
             "(3 tolerance-sensitive, marked)")
    caption = ", ".join(f"$\\\\zeta_{k}$ = 0.01" for k in range(20))
    lines = title_lines(title, caption).splitlines()
    assert lines[:3] == ["thesis_rotating_n3: unstable eigenvalues of the steady state",
                         "(balanced 1, continued from START)", "(3 tolerance-sensitive, marked)"]
    assert all(len(line) <= CAPTION_WIDTH for line in lines[3:]) and len(lines) > 4
    assert title_lines("short: basins", "a = 1").splitlines() == ["short: basins", "a = 1"]  # control: as it was
