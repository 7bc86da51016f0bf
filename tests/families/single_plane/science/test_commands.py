"""`adbgen demo`: the single-plane family's command that runs a generated model (thesis Fig. 5.4)."""

import re

from adbgen.cli import main


def test_demo_recomputes_fig_5_4_and_plots_it(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    rows = re.findall(r"Fig\. 5\.4\((\w)1\): r_max = ([\d.]+) \(thesis ([\d.]+)\), t_dec = ([\d.]+) \(thesis ([\d.]+)\)",
                      out)
    assert [r[0] for r in rows] == ["a", "c", "d"]
    for _, r, r_pub, t, t_pub in rows:
        assert abs(float(r) / float(r_pub) - 1) < 5e-3 and abs(float(t) / float(t_pub) - 1) < 5e-3
    assert (tmp_path / "fig5_4.png").stat().st_size > 1000
