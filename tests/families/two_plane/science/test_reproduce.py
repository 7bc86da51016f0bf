"""`adbgen reproduce`'s two-plane part: its measures on synthetic runs."""

import numpy as np
import pytest

from adbgen.families.two_plane.science import reproduce as rtp
from adbgen.families.two_plane.science import runs as tr


def _run(spin, speeds):
    t = np.arange(len(spin), dtype=float)
    speeds = np.asarray(speeds, float)
    return tr.RunUp("x", 0.1, t, np.asarray(spin, float), speeds, speeds, t, speeds[:, -1], float(spin[-1]))


def test_stall_speed_is_the_plateau_while_the_balls_lag():
    spin = np.linspace(0, 3, 301)
    ball = np.minimum(spin, 0.99)  # stall just below 1
    ball[250:] = spin[250:]  # caught up
    assert rtp.stall_speed(_run(spin, np.tile(ball, (4, 1)))) == pytest.approx(0.99)
    assert rtp.stall_speed(_run(spin, np.tile(spin, (4, 1)))) is None


def test_synchronised_from_is_the_last_time_a_ball_lags():
    spin = np.full(10, 2.0)
    balls = np.tile(spin, (4, 1))
    balls[2, :6] = 1.0
    assert tr.synchronised_from(_run(spin, balls)) == 6.0
    balls[2, -1] = 1.9
    assert tr.synchronised_from(_run(spin, balls)) is None


def test_every_stall_is_reported_not_one_median():
    """Figure 15(b) has two stalls: each stretch of lagging balls is its own entry (speed, Omega from, to)."""
    spin = np.linspace(0, 3, 3001)
    ball = spin.copy()
    ball[500:900] = 0.5  # lags from Omega = 0.5 to 0.9
    ball[1800:2400] = 1.8  # again from 1.8 to 2.4
    found = rtp.stalls(_run(spin, np.tile(ball, (4, 1))))
    # the balls lag beyond the drive's own lag (Omega' m R^2 / c_b = 0.001 / 0.1 = 0.01) by 5 % of Omega from
    # 0.537 and 1.905
    assert [(round(s, 3), round(a, 2), round(b, 2)) for s, a, b in found] == [(0.5, 0.54, 0.9), (1.8, 1.91, 2.4)]
    ball[1800:2400] = spin[1800:2400]  # negative control: one stall left
    assert len(rtp.stalls(_run(spin, np.tile(ball, (4, 1))))) == 1


def test_B_at_the_critical_mass_is_not_hyperbolic():
    """The slow eigenvalues of B vanish as m -> m_c (proportional to m - m_c, (38)): at m = m_c B is
    non-hyperbolic, neither stable nor unstable (the document no longer calls it stable there)."""
    from adbgen.analysis.loading import load_model
    from adbgen.families.two_plane.science import exchange as tx

    damped = tx.Pitchfork(load_model(tx.MODEL), {})
    near, nearer = damped.slow_spectrum(2.2, rel=1e-6), damped.slow_spectrum(2.2, rel=1e-7)
    for part in ("even", "odd"):
        assert near[part].real < 0 and abs(near[part]) > 1e-6  # just above m_c: stable (Omega > Omega_con)
        assert abs(nearer[part]) == pytest.approx(abs(near[part]) / 10, rel=0.05)  # -> 0 linearly in m - m_c


def test_the_start_up_lag_is_not_a_stall_and_a_real_stall_is_found_after_it():
    """Issue 34 item 5: balls following a ramp lag it by Omega' m R^2 / c_b from the start (Figure 15's ramp:
    0.06 at c_b/m = 0.01); measured against the speed alone that lag is > 5 % of Omega wherever Omega < 1.2, and
    was reported as a stall from Omega = 0.  Planted: a ramp Omega = 6e-4 t with the balls lagging by exactly
    that, then held at 0.99 from Omega = 1.1 (a real stall)."""
    t = np.linspace(0.0, 6000.0, 6001)
    spin = 6e-4 * t
    follow = spin - 6e-4 / 0.01 * (1 - np.exp(-0.01 * t))  # from rest, relaxing onto the steady start-up lag
    run = lambda balls, ratio=0.01: tr.RunUp("x", ratio, t, spin, np.tile(balls, (4, 1)),  # noqa: E731
                                             np.tile(balls, (4, 1)), t, np.full(4, balls[-1]), float(spin[-1]))
    assert rtp.stalls(run(follow)) == []  # the start-up lag alone: no stall
    stalled = np.where(spin < 1.1, follow, 0.99)
    (speed, start, end), = rtp.stalls(run(stalled))
    assert speed == pytest.approx(0.99) and 1.1 <= start < 1.2 and end == pytest.approx(3.6, abs=1e-3)
    # negative control: the same balls said to be 100 times more damped (the drive's lag 6e-4, not 0.06): their
    # lag is then beyond the drive's, and it is a stall from the start, as the relative 5 % measure had it
    (_, start, _), *_ = rtp.stalls(run(follow, ratio=1.0))
    assert start < 0.01


def test_kappa_is_drawn_whole_not_clipped_at_4():
    """Section 3.2.3's kappa has a pole at Omega_2: the panel draws every value at its size (issue 36)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    w = np.linspace(0.5, 3.0, 101)
    k = 0.3 / (w - 1.8101)  # a pole between grid points, values far beyond +-4

    def drawn_whole(ax):
        y = ax.lines[0].get_ydata()
        lo, hi = ax.get_ylim()
        return np.array_equal(y, k) and lo <= k.min() and hi >= k.max()

    fig, ax = plt.subplots()
    rtp.kappa_panel(ax, w, k)
    assert drawn_whole(ax) and ax.get_yscale() == "symlog"
    plt.close(fig)
    fig, ax = plt.subplots()  # negative control: the old panel, clipped at +-4
    ax.plot(w, np.clip(k, -4, 4), "k.")
    ax.set_ylim(-4, 4)
    assert not drawn_whole(ax)
    plt.close(fig)


def test_worse_phases_locates_where_the_ratio_exceeds_one():
    import math

    f = lambda ph: 1.0 + 0.5 * math.sin(2 * ph - 0.5)  # noqa: E731  (period pi, above 1 on (0.25, 0.25 + pi/2))
    iv = rtp.worse_phases(f)
    assert len(iv) == 1 and iv[0] == pytest.approx((0.25, 0.25 + math.pi / 2), abs=2e-3)
    # wrapping through phase 0 = pi gives two pieces; a ratio below 1 everywhere gives none (negative control)
    g = lambda ph: 1.0 + 0.5 * math.cos(2 * ph)  # noqa: E731
    got = rtp.worse_phases(g)
    want = ((0.0, math.pi / 4), (3 * math.pi / 4, math.pi))
    assert [tuple(iv) for iv in got] == [pytest.approx(w, abs=2e-3) for w in want]
    assert rtp.worse_phases(lambda ph: 0.9) == []


def test_figure_16d_worse_than_plain_depends_on_the_starting_phase():
    """c_b/m = 0.1: ABB / plain rotor at the critical speeds 0.72 at phase 0, 1.89 at pi/2; c_b/m = 0.01 below 1."""
    import math

    plain = tr.run_up("two_plane_hill", 0.1, 300.0, m=tr.PLAIN_MASS, samples=3001, rtol=1e-11).A.max()
    ratio = lambda r, ph: tr.run_up("two_plane_hill", r, 300.0, samples=3001, rtol=1e-11,  # noqa: E731
                                    phase=ph).A.max() / plain
    assert ratio(0.1, 0.0) == pytest.approx(0.7192, abs=1e-3)
    assert ratio(0.1, math.pi / 2) == pytest.approx(1.8883, abs=1e-3)
    assert ratio(0.01, 0.0) < 1 and ratio(0.01, math.pi / 2) < 1
