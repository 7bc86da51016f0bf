"""The paper's charts in the reproduction (issue 36): Fig. 10(b) is Fig. 14(a)'s chart, Fig. 10(c) the coupled
supports (42) whose boundary tends to (42)'s conical speed, Fig. 13(c)'s extra Hopf points counted along rows
(the chart draws the stability boundary only), the insets' tick labels apart."""

import numpy as np
import pytest

from adbgen.families.two_plane.charts import CHARTS
from adbgen.families.two_plane.science import periodic_orbits as po

BY = {c.figure: c for c in CHARTS}


def test_every_paper_chart_is_listed_and_each_alias_names_a_computed_chart():
    assert [c.figure for c in CHARTS] == ["10(a)", "10(b)", "10(c)", "11", "13(a)", "13(b)", "13(c)", "13(d)",
                                          "14(a)", "14(b)"]
    for c in CHARTS:
        if c.same_as:
            target = BY[c.same_as]
            assert not target.same_as and CHARTS.index(target) < CHARTS.index(c)
            assert (target.model, target.sets, target.ties) == (c.model, c.sets, c.ties)
    # negative control: 10(b) (dynamic) is not 10(a)'s set-up
    assert BY["10(b)"].ties != BY["10(a)"].ties


def test_figure_10c_boundary_tends_to_the_conical_speed_of_42():
    """(42): Omega_con = 4.071091; B's stability change at eps/R = 1e-8 is 4.0735 (10(a): 1.8093, the (10) speed)."""
    (_, pts), = po.limit(BY["10(c)"], epsilons=(1e-8,), progress=lambda *_: None)
    assert [k for k, _ in pts] == ["hopf"] and pts[0][1] == pytest.approx(4.0711, abs=5e-3)
    (_, control), = po.limit(BY["10(a)"], epsilons=(1e-8,), progress=lambda *_: None)
    assert all(abs(v - 4.0711) > 1 for _, v in control)


def test_figure_13c_has_extra_hopf_points_where_13a_has_none():
    """At eps/R = m/M = 0.01: 13(a) has 4 Hopf points of B, 13(c) (ball 1 20 % heavier) 6."""
    a = po.hopf_rows(BY["13(a)"], (1e-2,), progress=lambda *_: None)[1e-2]
    c = po.hopf_rows(BY["13(c)"], (1e-2,), progress=lambda *_: None)[1e-2]
    assert len(a) == 4 and len(c) == 6
    assert sum(ch for _, ch in a) == sum(ch for _, ch in c) == 1  # the extra ones are where B is unstable
    extra = po.extra_curves(BY["13(c)"], BY["13(a)"], progress=lambda *_: None)
    assert "0.01" in extra["extra"]


def test_inset_tick_labels_do_not_overlap():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def overlaps(style):
        fig, ax = plt.subplots(figsize=(3.3, 3.0))
        th = np.linspace(0, 2 * np.pi, 200)
        ax.plot(6e-5 * np.cos(th) + 3e-5 * np.sin(th), 5.8e-4 * np.sin(th), label="(i)")  # inset (i)'s scale
        style(ax)
        fig.canvas.draw()
        boxes = [t.get_window_extent() for t in ax.get_xticklabels() if t.get_text()]
        plt.close(fig)
        return any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:])

    assert not overlaps(po.inset_style)

    def plain(ax):  # negative control: the old style, matplotlib's default ticks
        ax.set_aspect("equal", "datalim")
        ax.legend(fontsize=6)

    assert overlaps(plain)


def _wedge(chart: dict) -> list:
    """The stable windows of the chart's eps/R = 1e-5 row inside [1.70, 1.75] (B's wedge near the critical speed)."""
    row = min(chart["windows"]["rows"], key=lambda r: abs(r["epsilon"] - 1e-5))
    assert abs(row["epsilon"] - 1e-5) < 1e-12
    return [w for w in row["stable"] if 1.70 <= w[0] and w[1] <= 1.75]


def test_figure_11_chart_shades_the_wedge_near_the_critical_speed():
    """Issue 34: docs/reproduction/orbits_chart_11.json (certified) has B stable on about [1.722, 1.734] at
    eps/R = 1e-5 and states the resolution it certifies."""
    import json
    from pathlib import Path

    chart = json.loads((Path(po.__file__).resolve().parents[4] / "docs" / "reproduction" / "orbits_chart_11.json")
                       .read_text())
    assert chart["resolution"]["certified"]["refined"] and chart["resolution"]["certified"]["Omega"] < 0.01
    (a, b), = _wedge(chart)
    assert a == pytest.approx(1.722, abs=2e-3) and b == pytest.approx(1.734, abs=2e-3)
    # negative control: the same chart with the wedge's window taken out is caught
    for row in chart["windows"]["rows"]:
        row["stable"] = [w for w in row["stable"] if not 1.70 <= w[0] <= 1.75]
    assert _wedge(chart) == []
