"""Paper Figure 12 (issue 36): the brute force quoted at its converged transient, Figure 12(b) compared with
the dynamic imbalance's own B (Floquet), the points near B's weak ends carried on until they settle."""

import numpy as np
import pytest

from adbgen.analysis.loading import load_model
from adbgen.families.two_plane.science import reproduce as rtp
from adbgen.families.two_plane.science import runs as tr

DYNAMIC = {"epsilon": 5e-5, "chi": 5e-5, "beta": 1.0, **tr._ball_values(1e-4, 0.01)}


def _abb(omegas, t, dynamic=False):
    return [o.A_bar for o in tr.figure_12a(omegas, t_transient=t, with_plain=False, dynamic=dynamic)["abb"]]


def test_settle_carries_a_changing_point_until_two_transients_agree():
    calls = []

    def rerun(ws, t):
        calls.append((tuple(ws), t))
        return [1e-12 for _ in ws]

    out = rtp.settle([1.0, 2.0], first=[1e-12, 1e-5], second=[1e-12, 1e-9], rerun=rerun)
    assert [q["balanced"] for q in out] == [True, True] and [q["t"] for q in out] == [8000.0, 16000.0]
    assert calls == [((2.0,), 16000.0)] and out[1]["first"] is False and all(q["settled"] for q in out)
    # negative control: a point that flips at every doubling is reported unsettled at the cap
    flip = iter([1e-12, 1e-5] * 10)
    out = rtp.settle([2.0], first=[1e-12], second=[1e-5], rerun=lambda ws, t: [next(flip)], cap=32000.0)
    assert out[0]["settled"] is False and out[0]["t"] == 32000.0


def test_settle_carries_a_point_against_B_until_it_agrees():
    seq = {16000.0: 1e-6, 32000.0: 1e-8, 64000.0: 1e-10}
    out = rtp.settle([4.6], first=[1e-5], second=[1e-5], rerun=lambda ws, t: [seq[t]], stable=lambda w: True)
    assert out[0]["balanced"] and out[0]["t"] == 64000.0 and out[0]["settled"]
    # without B's stability the two agreeing transients are taken as they are
    out = rtp.settle([4.6], first=[1e-5], second=[1e-5], rerun=lambda ws, t: [seq[t]])
    assert not out[0]["balanced"] and out[0]["t"] == 8000.0


def test_dynamic_B_cancels_the_imbalance_at_every_speed_and_time():
    m = load_model("two_plane_fixed")
    y = tr.balanced_state(m, DYNAMIC)
    for W in (1.0, 3.3):
        for t in (0.0, 0.7, 3.1):
            assert np.abs(np.asarray(m.module.rhs(t, y, m.params(dict(DYNAMIC, Omega=W))))).max() < 1e-15
    # negative control: the static closed form is not B of the dynamic imbalance
    y0 = tr.balanced_orbit(m, dict(DYNAMIC, epsilon=1e-4, chi=0.0))
    assert np.abs(np.asarray(m.module.rhs(0.0, y0, m.params(dict(DYNAMIC, Omega=3.0))))).max() > 1e-6


def test_figure_12b_is_compared_with_the_dynamic_B():
    """The dynamic imbalance's B is stable on (2.4796, 2.6780) and (4.5857, 5]: not the static B's windows."""
    dyn = rtp.floquet_section([], [], dynamic=True)["stable"]
    assert np.ravel(dyn) == pytest.approx([2.4796, 2.6779, 4.5858, 5.0], abs=2e-4)
    static = rtp.floquet_section([], [])["stable"]
    assert np.ravel(static) == pytest.approx([2.4818, 2.6697, 4.5060, 5.0], abs=2e-4)


def test_figure_12a_converged_intervals_end_at_1_70_and_begin_at_2_50():
    """t = 4000 balances on [1.10, 1.55] and [2.55, 5]; t = 8000 and 16000 agree on [1.10, 1.70], [2.50, 5]."""
    w = [1.7, 1.75, 2.45, 2.5]
    first, second, third = (rtp.balanced_by(_abb(w, t)) for t in (4000.0, 8000.0, 16000.0))
    assert list(first) == [False, False, False, False]
    assert list(second) == list(third) == [True, False, False, True]


def test_figure_12b_settles_at_2_5_and_4_6_only_with_long_transients():
    assert not rtp.balanced_by(_abb([2.5, 4.6], 4000.0, dynamic=True)).any()
    assert rtp.balanced_by(_abb([2.5], 16000.0, dynamic=True)).all()
    assert not rtp.balanced_by(_abb([4.6], 32000.0, dynamic=True)).any()
    assert rtp.balanced_by(_abb([4.6], 64000.0, dynamic=True)).all()


def _title_fits(t):
    import matplotlib.pyplot as plt

    w = np.linspace(0.2, 5.0, 49)
    fig = rtp.brute_force_figure(w, 1e-4 + 0 * w, 1e-9 + 0 * w, [(2.48, 2.68)], "B stable", t, 0.1)
    fig.canvas.draw()
    box, whole = fig.axes[0].title.get_window_extent(), fig.bbox
    plt.close(fig)
    return box.x0 >= whole.x0 and box.x1 <= whole.x1


def test_figure_12_titles_fit_the_figure():
    assert _title_fits(rtp.FIG12A_TITLE) and _title_fits(rtp.FIG12B_TITLE)
    # negative control: 12(b)'s title on one line, as it was, runs past the figure's edge
    assert not _title_fits(rtp.FIG12B_TITLE.replace("\n", " "))


def test_better_agreement_compares_the_shares_of_agreeing_points():
    """The verdict the template prints (decided here, not in prose/fig12.md.j2): Figure 12(b)'s share of grid
    points agreeing with its B's Floquet stability against Figure 12(a)'s.  Controls: equal shares and a larger
    count over a larger grid (a smaller share) are not a better agreement."""
    assert rtp.better_agreement(90, 100, 170, 200)
    assert not rtp.better_agreement(85, 100, 170, 200)  # equal shares
    assert not rtp.better_agreement(150, 200, 80, 100)  # more points agree, a smaller share
