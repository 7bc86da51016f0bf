"""The figures' shared style (adbgen.analysis.figure_style, issue 24 item 7)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, strategies as st

from adbgen.analysis import figure_style as fs


@given(st.floats(-1e4, 1e4))
def test_wrap_lands_in_minus_pi_to_pi_and_keeps_the_angle(a):
    w = float(fs.wrap(np.array([a]))[0])
    assert -math.pi < w <= math.pi
    assert abs(math.remainder(w - a, 2 * math.pi)) < 1e-9 * max(1.0, abs(a))


def test_wrapped_lines_break_at_the_jumps():
    t = np.linspace(0, 10, 101)
    tt, w = fs._broken(t, fs.wrap(2.0 * t))  # 20 rad: through pi, 3 pi and 5 pi, three jumps to -pi
    assert np.isnan(w).sum() == 3 and len(tt) == len(w) == 104
    assert np.nanmax(np.abs(np.diff(w))) < math.pi


def test_axes_show_pi_ticks_units_and_labelled_lines(tmp_path):
    plt = fs.pyplot()
    fig, (a1, a2) = plt.subplots(2)
    t = np.linspace(0, 10, 200)
    r = 1e-2 * np.exp(-t) + 1e-16
    fs.amplitude_panel(a1, t, r, 5e-5, 5.3, "m", "s", "a tenth of eps")
    fs.angle_panel(a2, t, np.vstack([2 * t, -t]), ["phi_1", "phi_2"])
    labels = [line.get_label() for line in a1.get_lines()]
    assert labels[1] == "threshold 50 \u00b5m (a tenth of eps)" and labels[2] == "$t_{dec}$ = 5.3 s"
    assert a1.get_ylabel() == "$r$ (m)" and a1.get_ylim()[0] >= 5e-8 * 0.99  # the round-off floor clipped
    assert [tk.get_text() for tk in a2.get_yticklabels()] == ["$-\\pi$", "$-\\pi/2$", "0", "$\\pi/2$", "$\\pi$"]
    assert "wrapped" in a2.get_ylabel()
    assert fs.title("rig.toml", {"omega": 300.0}, {"omega": "rad/s"}) == "rig.toml\nomega = 300 rad/s"
    plt.close(fig)


def test_a_long_title_breaks_before_its_remarks_and_the_caption_between_words():
    """The sweep figures' titles (issue 36): each remark whole on its line, the caption between words."""
    title = ("thesis_rotating_n3: unstable eigenvalues of the steady state (balanced 1, continued from START) "
             "(3 tolerance-sensitive, marked)")
    caption = ", ".join(f"$\\\\zeta_{k}$ = 0.01" for k in range(20))
    lines = fs.title_lines(title, caption).splitlines()
    assert lines[:3] == ["thesis_rotating_n3: unstable eigenvalues of the steady state",
                         "(balanced 1, continued from START)", "(3 tolerance-sensitive, marked)"]
    assert all(len(line) <= fs.CAPTION_WIDTH for line in lines[3:]) and len(lines) > 4
    assert fs.title_lines("short: basins", "a = 1").splitlines() == ["short: basins", "a = 1"]  # control: as it was
