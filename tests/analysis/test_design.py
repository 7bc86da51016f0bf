"""analysis.design: a speed range that contains a Hopf point is infeasible and one beside it is not; an imbalance
above the balls' capacity is infeasible (the capacity limit located where the closed form says) and one below it
is not; the margin's sensitivity from the emitted jac_p agrees with finite differences, and a planted wrong
jac_p is caught; a design line's stability boundary is located where the one-parameter scan crosses."""

from __future__ import annotations

import numpy as np
import pytest

from adbgen.analysis.design import Axis, Problem, assess, balancing_label, capacity, sensitivity, solve
from adbgen.analysis.loading import AnalysisError, load_model
from adbgen.analysis.steady import refine

# thesis (5.1): n = 3, Omega = 4, beta = 0.01, delta = 0.01, mu = 0.05, zeta = 0.01
THESIS = "thesis_rotating_n3"


@pytest.fixture(scope="module")
def thesis3():
    return load_model(THESIS)


@pytest.fixture(scope="module")
def paper():
    return load_model("two_plane_rotating")


def leading(model, values):
    p = model.params(values)
    return refine(model, p, model.steady_state(balancing_label(model), p)).margin.value


def test_balancing_state_read_from_the_closed_forms(thesis3, paper):
    assert balancing_label(thesis3) == "1" and balancing_label(paper) == "B"


def test_a_speed_range_containing_a_hopf_point_is_infeasible(paper):
    # B (paper (9)) at the defaults (c_b = 3e-5) loses stability below Omega ~ 2.9 by a complex pair
    base = paper.params({"epsilon": 0.001})
    lo, hi = 2.6, 3.2
    assert leading(paper, {"epsilon": 0.001, "Omega": lo}) > 0 > leading(paper, {"epsilon": 0.001, "Omega": hi})
    inside = Problem(paper, base, [Axis("Omega", lo, 4.0)], [Axis("c_bb", 1e-5, 1e-3)])
    v = assess(inside, [3e-5])
    assert v.exists and not v.feasible and v.unstable_at and v.margin > 0 and v.crossing == "Hopf"
    # the control: the range above the Hopf point
    above = Problem(paper, base, [Axis("Omega", hi, 4.0)], [Axis("c_bb", 1e-5, 1e-3)])
    w = assess(above, [3e-5])
    assert w.feasible and w.margin < 0 and not w.unstable_at


def test_an_imbalance_above_the_capacity_is_infeasible(thesis3):
    # thesis (3.14): the balanced state exists for delta <= n mu = 0.15 at mu = 0.05
    base = thesis3.params()
    box = [Axis("Omega", 4.0, 4.0), Axis("zeta", 0.01, 0.01)]
    over = Problem(thesis3, base, box + [Axis("delta", 0.0, 0.2)], [Axis("mu", 0.01, 0.1)])
    assert capacity(over, [0.05]) == pytest.approx(0.15, rel=1e-10)
    v = assess(over, [0.05])
    assert not v.exists and not v.feasible
    under = Problem(thesis3, base, box + [Axis("delta", 0.0, 0.01)], [Axis("mu", 0.01, 0.1)])  # the control
    assert assess(under, [0.05]).exists
    # the design over mu finds the capacity limit where (3.14) puts it: mu = 0.2 / 3
    d = solve(over)
    caps = [b for b in d.boundaries if b.kind == "capacity limit"]
    assert len(caps) == 1 and caps[0].values["mu"] == pytest.approx(0.2 / 3, rel=1e-9)
    assert all(a >= 0.2 / 3 * (1 - 1e-9) for a, _ in d.feasible_intervals)


def test_the_stability_boundary_is_where_the_scan_crosses(thesis3):
    # at beta = 0.01 the balanced state is stable for zeta < 0.02059 (docs/reproduction.md, thesis 5.2.2): a
    # design over zeta with nothing else in the box has its upper end at the crossing of the leading real part
    base = thesis3.params()
    pr = Problem(thesis3, base, [Axis("Omega", 4.0, 4.0)], [Axis("zeta", 0.005, 0.05)])
    d = solve(pr)
    (a, b), = d.feasible_intervals
    assert a == 0.005 and b == pytest.approx(0.02059, abs=5e-6)
    assert abs(leading(thesis3, {"zeta": b})) < 1e-9
    assert [bd.kind for bd in d.boundaries] == ["Hopf"]


def test_sensitivity_from_jac_p_agrees_with_finite_differences(thesis3, monkeypatch):
    base = thesis3.params()
    # mu moves the balanced state (its angles follow delta / mu, thesis (3.6)): jac_p's state term is exercised
    pr = Problem(thesis3, base, [Axis("Omega", 4.0, 4.0), Axis("zeta", 0.3, 0.5)], [Axis("beta", 0.2, 1.0),
                                                                                   Axis("mu", 0.03, 0.1)])
    v = assess(pr, [0.3, 0.05])
    assert v.feasible
    s = sensitivity(pr, v)
    assert [x["agree"] for x in s] == [True, True] and not any(x["kink"] for x in s)
    # negative control: a planted wrong parameter Jacobian (its mu column doubled) is caught
    true = thesis3.module.jac_p
    k = thesis3.param_names.index("mu")

    def wrong(t, y, p):
        out = np.array(true(t, y, p))
        out[:, k] *= 2.0
        return out
    monkeypatch.setattr(thesis3.module, "jac_p", wrong)
    bad = {x["parameter"]: x["agree"] for x in sensitivity(pr, v)}
    assert bad == {"beta": True, "mu": False}


def test_bad_problems_refused(thesis3):
    base = thesis3.params()
    with pytest.raises(AnalysisError, match="not a parameter"):
        Problem(thesis3, base, [], [Axis("nope", 0, 1)])
    with pytest.raises(AnalysisError, match="given twice"):
        Problem(thesis3, base, [Axis("beta", 0, 1)], [Axis("beta", 0, 1)])
    with pytest.raises(AnalysisError, match="nothing to vary"):
        Problem(thesis3, base, [], [Axis("beta", 0.1, 0.1)])
    # a time-dependent model that is not periodically forced (a run-up) has no balancing state or orbit; a
    # periodically forced one is designed on its balancing orbit (tests/analysis/test_design_orbit.py)
    ramp = load_model("two_plane_ramp")
    with pytest.raises(AnalysisError, match="not periodically forced"):
        Problem(ramp, ramp.params(), [], [Axis("c_bb", 1e-5, 1e-3)])


# a planted feasible strip in the design plane, narrower than the chart's grid spacing (1/6) and wider than its
# certified resolution (1/24): the margin of two crossing branches, as in tests/analysis/test_windows.py
C1, C2 = 0.40, 0.46


def planted(problem, design):
    import math

    from adbgen.analysis.design import Verdict

    x = float(design[0])
    m = max(3.0 * (C1 - x), 5.0 * (x - C2))
    return Verdict(tuple(map(float, design)), True, math.inf, feasible=m < 0, margin=m, worst={},
                   leading=complex(m, 1.0))


def test_chart_finds_a_planted_window_at_its_resolution(thesis3, monkeypatch):
    import adbgen.analysis.design as design

    monkeypatch.setattr(design, "assess", planted)
    monkeypatch.setattr(design, "capacity_slack", lambda problem, d: 1.0)
    monkeypatch.setattr(design, "sensitivity", lambda problem, best: [])
    pr = Problem(thesis3, thesis3.params(), [Axis("Omega", 4.0, 4.0)], [Axis("beta", 0.0, 1.0), Axis("mu", 0.03, 0.1)])
    d = solve(pr)
    assert d.resolution["beta"] == pytest.approx(1 / 24) and C2 - C1 > d.resolution["beta"]
    # the grid alone misses the strip (the negative control): no grid cell is feasible
    assert not any(any(row) for row in d.chart["feasible"])
    # every certified row finds it, its ends located where the margin crosses
    for row in d.chart["rows"]:
        (a, b), = row["feasible"]
        assert a == pytest.approx(C1, abs=1e-9) and b == pytest.approx(C2, abs=1e-9)
    kinds = {bd.kind for bd in d.boundaries}
    assert kinds == {"Hopf"} and len(d.boundaries) == 2 * 7
    assert d.best is not None and C1 < d.best.design[0] < C2


def test_optimiser_over_three_parameters(thesis3):
    """More than two varied parameters: COBYLA, each evaluation a certified box scan.  It improves on the centre
    of the design box and stays inside it; where no design is feasible (beta too small for zeta up to 0.5: the
    control) it returns none."""
    box = [Axis("zeta", 0.3, 0.5)]
    pr = Problem(thesis3, thesis3.params(), box, [Axis("Omega", 3.0, 5.0), Axis("beta", 0.2, 1.0), Axis("mu", 0.03, 0.1)])
    d = solve(pr)
    assert d.method == "optimiser" and d.best is not None and d.best.feasible
    assert all(a.low <= x <= a.high for a, x in zip(pr.varied, d.best.design))
    assert d.best.margin < assess(pr, [4.0, 0.6, 0.065]).margin < 0
    assert d.active is not None and d.active.kind == "range end (mu at its low end)"
    none = Problem(thesis3, thesis3.params(), box, [Axis("Omega", 3.0, 5.0), Axis("beta", 0.01, 0.1),
                                                    Axis("mu", 0.03, 0.1)])
    assert solve(none).best is None


def test_a_tied_parameter_follows_the_varied_one(paper):
    pr = Problem(paper, paper.params(), [Axis("Omega", 3.0, 3.0)], [Axis("c_bb", 1e-5, 1e-3)], ties={"c_bt": "c_bb"})
    p = pr.params([2e-4])
    assert p[paper.param_names.index("c_bt")] == p[paper.param_names.index("c_bb")] == 2e-4
    untied = Problem(paper, paper.params(), [Axis("Omega", 3.0, 3.0)], [Axis("c_bb", 1e-5, 1e-3)])
    assert untied.params([2e-4])[paper.param_names.index("c_bt")] == 3e-5  # the control: left at its value
    with pytest.raises(AnalysisError, match="not a varied parameter"):
        Problem(paper, paper.params(), [], [Axis("c_bb", 1e-5, 1e-3)], ties={"c_bt": "Omega"})
    with pytest.raises(AnalysisError, match="given twice"):
        Problem(paper, paper.params(), [Axis("c_bt", 0, 1)], [Axis("c_bb", 1e-5, 1e-3)], ties={"c_bt": "c_bb"})


def test_sensitivity_moves_the_tied_parameters_too(paper):
    """With --tie c_bt=c_bb the worst margin's slope in c_bb is both races' damping moving together: jac_p's
    slope agrees with the finite differences (it takes both columns); negative control: the same problem
    untied in jac_p's direction (the tie dropped from the sensitivity's Problem) gives about half the slope, which
    the tied finite differences do not match."""
    base = paper.params({"epsilon": 0.001})
    tied = Problem(paper, base, [Axis("Omega", 3.6, 3.6)], [Axis("c_bb", 1e-4, 1e-3)], ties={"c_bt": "c_bb"})
    v = assess(tied, [2.5e-4])
    assert v.feasible
    (s,) = sensitivity(tied, v)
    assert s["agree"] and not s["kink"]
    # the same point (c_bt = c_bb = 2.5e-4), the tied verdicts for the finite differences, jac_p's direction without c_bt
    untied = Problem(paper, paper.params({"epsilon": 0.001, "c_bt": 2.5e-4}), [Axis("Omega", 3.6, 3.6)],
                     [Axis("c_bb", 1e-4, 1e-3)])
    untied.cache = tied.cache
    (bad,) = sensitivity(untied, v)
    assert not bad["agree"] and bad["dmargin"] == pytest.approx(s["dmargin"] / 2, rel=0.05)


def _journalled(model, folder, omega=4.0, parallel=True):
    from adbgen.analysis.design_runs import Journal

    # the interval of test_the_stability_boundary_is_where_the_scan_crosses: zeta at beta = 0.01, Omega fixed
    pr = Problem(model, model.params(), [Axis("Omega", omega, omega)], [Axis("zeta", 0.005, 0.05)])
    pr.journal, pr.parallel, pr.workers = Journal(folder), parallel, 2
    return pr


def _answer(design) -> str:
    import json

    from adbgen.analysis.design_report import to_json

    out = to_json(design)
    out.pop("evaluations_resumed")
    return json.dumps(out, sort_keys=True)


def _killed_and_resumed(make, folder, k: int, monkeypatch):
    """solve(make(folder)) killed (KeyboardInterrupt) after its k-th verdict is journalled, then run again into the
    same folder: (the resumed design, the journal's lines)."""
    from adbgen.analysis.design_runs import JOURNAL, Journal

    put, count = Journal.put, {"puts": 0}

    def dies_after_k(self, key, result):
        if self.path is not None:  # a journal in a folder (not the lines' in-memory one)
            if count["puts"] == k:
                raise KeyboardInterrupt  # the kill
            count["puts"] += 1
        put(self, key, result)
    monkeypatch.setattr(Journal, "put", dies_after_k)
    with pytest.raises(KeyboardInterrupt):
        solve(make(folder))
    monkeypatch.setattr(Journal, "put", put)
    assert len((folder / JOURNAL).read_text().splitlines()) == k
    resumed = solve(make(folder))
    return resumed, (folder / JOURNAL).read_text().splitlines()


def test_a_killed_design_resumes_to_the_same_answer(thesis3, tmp_path, monkeypatch):
    """Issue 39 item 5: a design killed after k verdicts (in the Dask batch of the line's first samples, and later
    in the line's refinement, assessed in this process) and run again into the same journal gives the uninterrupted
    answer, reading the k verdicts back and computing only the rest; the Dask batches give the answer of the
    sequential scan.  Negative controls: a changed argument (another speed) reads nothing from that journal and
    gives another answer; a planted wrong verdict in the journal is read back and changes the answer."""
    import json

    from adbgen.analysis.design_runs import JOURNAL

    whole = solve(_journalled(thesis3, tmp_path / "whole"))
    total = whole.evaluations
    assert whole.resumed == 0 and total > 12
    assert len((tmp_path / "whole" / JOURNAL).read_text().splitlines()) == total
    assert _answer(solve(_journalled(thesis3, tmp_path / "seq", parallel=False))) == _answer(whole)
    for k in (4, 12):  # 4: inside the first Dask batch (VARY_POINTS designs); 12: in the refinement
        resumed, lines = _killed_and_resumed(lambda f: _journalled(thesis3, f), tmp_path / f"cut{k}", k, monkeypatch)
        assert resumed.resumed == k and resumed.evaluations == total and _answer(resumed) == _answer(whole)
        assert len(lines) == total and len({json.loads(x)["key"] for x in lines}) == total  # nothing computed twice
    # negative control: another speed, the same journal: nothing read back, another answer
    other = solve(_journalled(thesis3, tmp_path / "whole", omega=4.5))
    assert other.resumed == 0 and _answer(other) != _answer(whole)
    # negative control: the answer is read from the journal: a planted wrong margin there changes it
    rows = [json.loads(x) for x in (tmp_path / "cut4" / JOURNAL).read_text().splitlines()]
    for row in rows:
        row["result"]["margin"] -= 1.0
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / JOURNAL).write_text("".join(json.dumps(r) + "\n" for r in rows))
    bad = solve(_journalled(thesis3, tmp_path / "bad"))
    # (every sample now reads as more stable: the refinement goes elsewhere, so only some are read back)
    assert bad.resumed > 0 and _answer(bad) != _answer(whole)


def _chart_problem(model, folder, zeta=0.5, parallel=True):
    from adbgen.analysis.design_runs import Journal

    # thesis (5.1) at Omega = 4 and zeta = 0.5 (the ch. 4 question), a chart over (beta, mu): its Hopf boundary
    # near beta = 0.235
    pr = Problem(model, model.params({"zeta": zeta}), [Axis("Omega", 4.0, 4.0)],
                 [Axis("beta", 0.1, 0.6), Axis("mu", 0.03, 0.1)])
    pr.journal, pr.parallel, pr.workers = Journal(folder), parallel, 2
    return pr


def test_a_killed_chart_resumes_to_the_same_chart(thesis3, tmp_path, monkeypatch):
    """Issue 39 item 5 for two varied parameters: the chart's grid and its certified rows and columns run on the
    local Dask cluster (the lines together, each on a copy of the problem) and give the sequential chart; killed
    after k verdicts (in the grid's batch, and while the lines' verdicts are journalled) and run again into the
    same journal, the same chart, nothing computed twice.  Negative control: another zeta reads nothing back and
    gives another chart."""
    import json

    from adbgen.analysis.design_runs import JOURNAL

    whole = solve(_chart_problem(thesis3, tmp_path / "whole"))
    total = whole.evaluations
    assert whole.method == "chart" and {b.kind for b in whole.boundaries} == {"Hopf"} and total > 60
    assert len((tmp_path / "whole" / JOURNAL).read_text().splitlines()) == total
    assert _answer(solve(_chart_problem(thesis3, tmp_path / "seq", parallel=False))) == _answer(whole)
    for k in (20, 60):  # 20: in the grid's batch (49 designs); 60: in the lines' (after the grid)
        resumed, lines = _killed_and_resumed(lambda f: _chart_problem(thesis3, f), tmp_path / f"cut{k}", k, monkeypatch)
        assert resumed.resumed == k and resumed.evaluations == total and _answer(resumed) == _answer(whole)
        assert len(lines) == total and len({json.loads(x)["key"] for x in lines}) == total
    other = solve(_chart_problem(thesis3, tmp_path / "whole", zeta=0.4))  # the negative control
    assert other.resumed == 0 and _answer(other) != _answer(whole)


def test_the_optimiser_on_dask_gives_the_sequential_answer(thesis3, tmp_path, monkeypatch):
    """The optimiser (three varied parameters) with its evaluations on the local Dask cluster (its first designs
    together, then each design's box lines together) and journalled: the JSON equal to the sequential run's, every
    design assessed in the journal; a rerun reads every verdict back.  Negative control: the best design's verdict
    planted wrong in the journal gives another answer, so the equality is not vacuous.  The box lines are sampled more coarsely than the
    command's (LINE_POINTS 7) to keep the test short: both runs alike."""
    import json

    from adbgen.analysis import design, design_report
    from adbgen.analysis.design_runs import JOURNAL, Journal

    monkeypatch.setattr(design, "LINE_POINTS", 7)

    def run(parallel, journal=None, zeta=0.5):
        pr = Problem(thesis3, thesis3.params(), [Axis("zeta", 0.3, zeta), Axis("delta", 0.005, 0.01)],
                     [Axis("Omega", 3.0, 5.0), Axis("beta", 0.2, 1.0), Axis("mu", 0.03, 0.1)])
        pr.parallel, pr.workers, pr.journal = parallel, 2, journal
        d = solve(pr)
        out = design_report.to_json(d)
        return d, json.dumps({k: v for k, v in out.items() if k != "evaluations_resumed"}, sort_keys=True)
    seq, seq_json = run(False)
    par, par_json = run(True, Journal(tmp_path))
    assert par_json == seq_json and par.method == "optimiser" and par.best is not None and par.best.feasible
    assert len((tmp_path / JOURNAL).read_text().splitlines()) == par.evaluations and par.resumed == 0
    again, again_json = run(True, Journal(tmp_path))
    assert again_json == seq_json and again.resumed == again.evaluations
    # negative control: a verdict planted in the journal (the best design's margin doubled) changes the answer
    lines = (tmp_path / JOURNAL).read_text().splitlines()
    rows = [json.loads(line) for line in lines]
    for row in rows:
        if tuple(row["result"]["design"]) == tuple(par.best.design):
            row["result"]["margin"] *= 2
    (tmp_path / "planted").mkdir()
    (tmp_path / "planted" / JOURNAL).write_text("".join(json.dumps(row) + "\n" for row in rows))
    assert run(True, Journal(tmp_path / "planted"))[1] != seq_json
