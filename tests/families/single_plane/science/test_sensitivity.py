"""The reproduction's tolerance check of its transients (science/sensitivity.py): a published transient that
converges is robust; the same ladder with its tightest run planted from another start is flagged, and only
that one is listed; the Fig. 5.10 table marks what the check flags."""

from __future__ import annotations

import math

from adbgen.analysis.loading import load_model
from adbgen.analysis.simulate import simulate
from adbgen.families.single_plane.science import sensitivity, sweeps

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


def _outcomes(rtol, second, *runs):
    """The check's three outcomes (as run, tighter by 100, the second engine at rtol): (label, r_max, t_dec) each."""
    from adbgen.analysis.tolerance import Outcome

    how = (("as run", ENGINE, rtol), ("tighter", ENGINE, rtol / 100), ("second engine", second, rtol))
    return [Outcome(role, engine, engine, r, r * 1e-2, "success", label, r_max, t_dec)
            for (role, engine, r), (label, r_max, t_dec) in zip(how, runs)]


def _judged(rtol, second, runs, ode45=None):
    from adbgen.analysis.tolerance import Outcome, judge

    shown = [] if ode45 is None else [
        Outcome("thesis' solver", "matlab-ode45", "matlab-ode45", 1e-3, 1e-6, "success", ode45, 0.1, None)]
    return judge(_outcomes(rtol, second, *runs), shown)


def test_the_tolerance_sections_render_the_published_lines(published_section):
    """templates/tolerance.md.j2, named_checked.md.j2 and transient_check.md.j2 on the committed run's outcomes
    (the real `judge` of analysis.tolerance) give docs/reproduction.md's lines exactly.  Controls: with no flagged
    transient the list ends with "."; a named start's flag changes its row."""
    from pathlib import Path

    lim, bal = "limit cycle", "balanced 1"
    checks = [_judged(1e-8, "taylor", [(bal, 0.1, 1074.59), (lim, 0.1, None), (bal, 0.1, 1074.59)], lim),
              _judged(1e-8, "taylor", [(lim, 0.1, None)] * 3, lim),
              _judged(1e-8, "taylor", [(lim, 0.690084, None), (lim, 0.733013, None), (lim, 0.745399, None)], lim),
              _judged(1e-8, "taylor", [(bal, 0.1, 841.038), (bal, 0.1, 912.813), (bal, 0.1, 1100.44)], lim)]
    labels = [((bal, 0), (bal, 0), (lim, 1), (bal, 0), 1), ((lim, 3),) * 4 + (3,),
              ((lim, 3),) + ((lim, 4),) * 3 + (3,), ((lim, 1),) + ((bal, 0),) * 3 + (1,)]
    rtols = (1e-6, 1e-8, 1e-10, 1e-12)
    runs = [{"run": run, "check": c, "ode45_laps": steps[-1],
             "ladder": {r: {"label": lab, "laps": laps} for r, (lab, laps) in zip(rtols, steps[:-1])}}
            for run, c, steps in zip(sensitivity.RUNS, checks, labels)]
    check = {"rtol": 1e-10, "second_engine": "taylor-batch"}
    ends = [(lim,) * 3, ("in-line 3(3-2)-", lim, "in-line 3(3-2)-"), *[("in-line 3(3-2)-",) * 3] * 2, (lim,) * 3,
            (bal,) * 3, (bal,) * 3, *[("in-line 3(4-3)-",) * 3] * 4]
    named = [{"figure": f, "phi_1": phi, "words": words, "check": check, "sensitive": len(set(got)) > 1,
              "labels": dict(zip(("as run", "tighter", "second engine"), got))}
             for (f, phi, words, _), got in zip(sweeps.NAMED, ends)]
    root = Path("docs")
    res = {"ladder": sensitivity.Ladder(ENGINE, rtols, 3000.0, ("matlab-ode45", 1e-3, 1e-6)), "runs": runs,
           "figure": root / "reproduction" / "fig5_10_tolerance.png", "named": named}
    published = published_section(
        "## Thesis, Fig. 5.10 (and Fig. 5.9(a1)'s named start): outcomes that hang on the tolerance")
    assert sensitivity.lines(res, root) == published
    robust = [(f"r{k}", "(0, 0)", _judged(1e-10, "taylor", [(bal, 0.1, 1.0)] * 3)) for k in range(32)]
    flagged = [("5.14(c)", "(pi/2, -pi/2, pi, 0)",
                _judged(1e-10, "taylor", [(bal, 0.1, 642.009), (bal, 0.1, 634.757), (bal, 0.1, 642.009)])),
               ("5.16(a)", "(pi/3, -pi/3, pi)",
                _judged(1e-10, "taylor", [(lim, 0.190574, None), (lim, 0.104225, None), (lim, 0.185988, None)])),
               ("5.17(a)", "(pi/2, -pi/2, pi, 0)",
                _judged(1e-10, "taylor", [(lim, 0.16794, None), (lim, 0.239923, None), (lim, 0.224477, None)]))]
    assert sensitivity.transient_lines(robust + flagged) == published_section("### Tolerance check of every transient")
    assert sensitivity.transient_lines(robust)[2].endswith("32 of 32 robust.")
    named[0]["sensitive"] = True
    assert sensitivity.lines(res, root) != published
