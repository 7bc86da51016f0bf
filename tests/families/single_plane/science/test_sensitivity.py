"""The reproduction's tolerance check of its transients (science/sensitivity.py): a published transient that
converges is robust; the same ladder with its tightest run planted from another start is flagged, and only
that one is listed; the Fig. 5.10 table marks what the check flags."""

from __future__ import annotations

import math

from adbgen.analysis.loading import load_model
from adbgen.analysis.simulate import simulate
from adbgen.families.single_plane.science import sensitivity

PI = math.pi
ENGINE = "cyrk-dop853"


def _ladder(phi0, planted=None):
    """Fig. 5.4(a) on rtol 1e-8, 1e-10 (t to 1000); `planted`: the 1e-10 run from that start instead."""
    model = load_model("thesis_rotating_n2")
    out = {}
    for rtol in (1e-8, 1e-10):
        start = planted if (planted is not None and rtol == 1e-10) else phi0
        y0 = model.state({"phi_1": start[0], "phi_2": start[1]})
        out[rtol] = simulate(model, model.params({}), y0, t_end=1000.0, rtol=rtol, atol=rtol * 1e-2, engine=ENGINE,
                             keep_trajectory=False)
    return out


def test_check_transient_robust_and_planted():
    start = (PI / 2, -PI / 2)
    robust = sensitivity.check_transient(2, start, {}, _ladder(start), ENGINE)
    assert not robust.sensitive, robust.reasons
    assert [o.rtol for o in robust.runs] == [1e-8, 1e-10, 1e-8] and robust.runs[2].picked == "taylor"
    planted = sensitivity.check_transient(2, start, {}, _ladder(start, planted=(PI / 4, -PI / 4)), ENGINE)
    assert planted.sensitive and any(r.startswith("tighter: label balanced 1 vs") for r in planted.reasons)
    lines = sensitivity.transient_lines([("5.4(a)", "(pi/2, -pi/2)", robust), ("planted", "(pi/4, -pi/4)", planted)])
    text = "\n".join(lines)
    assert "1 of 2 robust" in text and "Fig. planted" in text and "Fig. 5.4(a)" not in text


def test_fig_5_10_table_marks_the_flagged_run(tmp_path):
    """lines() on two studies, one flagged by its check and one not (the runs are the planted ladder's)."""
    from adbgen.analysis.tolerance import MARK

    start = (PI / 2, -PI / 2)
    robust = sensitivity.check_transient(2, start, {}, _ladder(start), ENGINE)
    planted = sensitivity.check_transient(2, start, {}, _ladder(start, planted=(PI / 4, -PI / 4)), ENGINE)
    ladder = sensitivity.Ladder(ENGINE, (1e-8, 1e-10), 1000.0, ("matlab-ode45", 1e-3, 1e-6))
    steps = {r: {"label": "balanced 1", "laps": 0} for r in ladder.rtols}
    studies = [{"run": run, "check": c, "ladder": steps, "ode45_laps": 0}
               for run, c in zip(sensitivity.RUNS[:2], (robust, planted))]
    for c in (robust, planted):
        c.shown = [(c.runs[0], [])]
    res = {"runs": studies, "ladder": ladder, "figure": tmp_path / "f.png"}
    rows = [ln for ln in sensitivity.lines(res, tmp_path) if ln.startswith("| 5.10")]
    assert len(rows) == 2 and rows[0].endswith("| robust |") and f"tolerance-sensitive {MARK}" in rows[1]


def test_named_starts_table_marks_only_the_flagged():
    check = {"rtol": 1e-10, "atol": 1e-12, "second_engine": "taylor-batch", "rel_tol": 0.01, "checked": 100}
    rows = [{"figure": "5.9(a1)", "phi_1": 23 * PI / 99, "words": "a limit cycle", "expect": "limit cycle",
             "labels": {"as run": "balanced 1", "tighter": "limit cycle", "second engine": "balanced 1"},
             "sensitive": True, "check": check},
            {"figure": "5.9(a2)", "phi_1": PI, "words": "coincident", "expect": "coincident 2-",
             "labels": dict.fromkeys(("as run", "tighter", "second engine"), "coincident 2-"), "sensitive": False,
             "check": check}]
    table = [ln for ln in sensitivity.named_lines(rows) if ln.startswith("| 5.9")]
    assert "tolerance-sensitive" in table[0] and "| balanced 1 | limit cycle | balanced 1 |" in table[0]
    assert "| robust |" in table[1] and "tolerance-sensitive" not in table[1]
    assert "rtol 1e-08 against 1e-10" in sensitivity.named_lines(rows)[0]


def test_the_document_places_the_check_before_the_figures_and_fig_5_10_before_the_launches(monkeypatch, tmp_path):
    """reproduce.lines splices the check of every transient before "## Figures" and the Fig. 5.10 section before
    the launches' section; without the check's results (an older result dict) the document is as before."""
    from adbgen.families.single_plane.science import reproduce, sweeps

    monkeypatch.setattr(reproduce, "_document", lambda *a, **k: [
        "## Thesis, chapter 5: transients", "", "## Figures", "",
        "## Thesis, chapter 4: stability of the balanced state"])
    monkeypatch.setattr(sweeps, "lines", lambda *a, **k: ["## Thesis, Figs. 5.5, 5.7, 5.9: r_max", "",
                                                          "## Thesis, Figs. 5.10-5.11: launches", ""])
    monkeypatch.setattr(sensitivity, "lines", lambda res, root: ["## FIG 5.10 CHECK", ""])
    start = (PI / 2, -PI / 2)
    check = sensitivity.check_transient(2, start, {}, _ladder(start, planted=(PI / 4, -PI / 4)), ENGINE)

    class Row:
        figure, phi0_text = "5.4(a)", "(pi/2, -pi/2)"

    res = {k: None for k in ("figures", "statements", "maps", "basins", "basins_n4", "sweeps", "sweep_figures",
                             "lyapunov")}
    res.update(transients=[{"row": Row(), "check": check}], results=[])
    before = reproduce.lines(res, tmp_path)
    assert not any("Tolerance check" in ln or "FIG 5.10" in ln for ln in before)  # the control
    res["sensitivity"] = {}
    doc = reproduce.lines(res, tmp_path)
    heads = [ln for ln in doc if ln.startswith("#")]
    assert heads.index("### Tolerance check of every transient") + 1 == heads.index("## Figures")
    assert heads.index("## FIG 5.10 CHECK") + 1 == heads.index("## Thesis, Figs. 5.10-5.11: launches")
    assert any(ln.startswith("* (!) Fig. 5.4(a)") for ln in doc)
