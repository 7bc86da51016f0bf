"""`adbgen demo`: the single-plane family's command that runs a generated model (thesis Fig. 5.4)."""

import re

import numpy as np

import figure_checks as fc
from adbgen.analysis.figure_style import wrap
from adbgen.cli import main
from adbgen.families.single_plane.science.published import FIGURE_5_4


def test_demo_recomputes_fig_5_4_and_plots_it(tmp_path, capsys, saved_figures):
    assert main(["demo", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    rows = re.findall(r"Fig\. 5\.4\((\w)1\): r_max = ([\d.]+) \(thesis ([\d.]+)\), t_dec = ([\d.]+) \(thesis ([\d.]+)\)",
                      out)
    assert [r[0] for r in rows] == ["a", "c", "d"]
    for _, r, r_pub, t, t_pub in rows:
        assert abs(float(r) / float(r_pub) - 1) < 5e-3 and abs(float(t) / float(t_pub) - 1) < 5e-3
    # fig5_4.png draws the runs it printed: one column per panel, r peaking at the printed r_max (less the
    # sampling: about 5 samples a forcing period), t_dec's line where it was printed, the published values
    # beside them, the angles starting at the panel's phi(0) and running to t = 1000
    fig = fc.figure(saved_figures, "fig5_4.png")
    tops, bottoms = fig.axes[:3], fig.axes[3:]
    assert len(fig.axes) == 6 and fig.get_suptitle().startswith("thesis Fig. 5.4: transients of thesis_rotating_n2")
    for (panel, r, r_pub, t, t_pub), top, bottom in zip(rows, tops, bottoms, strict=True):
        fc.assert_title(top, f"Fig. 5.4({panel})")
        fc.assert_peak(top, "$r$", float(r), rel=0.015)
        assert np.max(fc.line(top, "$r$").get_ydata()) < float(r) + 5e-5  # not above the printed digits
        fc.assert_vline(top, f"$t_{{dec}}$ = {t}", float(t), rel=1e-5)
        fc.assert_hline(top, "threshold 0.001 (the thesis')", 1e-3)
        fc.assert_labels(top, ylabel="$r$ (in units of the race radius R)")
        assert [f"(thesis {r_pub})" in x.get_text() and f"(thesis {t_pub})" in x.get_text()
                for x in top.texts] == [True]
        fc.assert_legend(bottom, ["$\\phi_{1}$", "$\\phi_{2}$"])
        phi0 = FIGURE_5_4[panel][0]
        for k, name in enumerate(["$\\phi_{1}$", "$\\phi_{2}$"]):
            ln = fc.line(bottom, name)
            assert ln.get_ydata()[0] == wrap(np.array([phi0[k]]))[0] and ln.get_xdata()[-1] == 1000.0
