"""analysis.design_report's report.md from its template (analysis/prose/design_report.md.j2) is byte-identical to
the report main wrote before the words moved out of Python (tests/analysis/data/design_report_*.md, captured
once from main at 0fae997 with these designs): two fixed designs (no computation) that between them take every
section of the report.  Negative controls: one word of the template changed, and one number of the design
changed, each gives another report."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from adbgen.analysis import design_report as dr
from adbgen.analysis import prose
from adbgen.analysis.design import Axis, Boundary, Design, Problem, Verdict
from adbgen.analysis.loading import load_model
from template_checks import changed_template

DATA = Path(__file__).parent / "data"


def designs():
    """(name, design, command, objective, balls, choice): fixed verdicts, boundaries and runs."""
    m = load_model("thesis_rotating_n3")
    pr = Problem(m, m.params({"zeta": 0.3}), [Axis("Omega", 3.5, 4.5)], [Axis("beta", 0.3, 0.6)])
    worst = {"Omega": 3.5, pr.eccentricity: 0.1}
    vs = [Verdict((b,), True, 0.4, feasible=b > 0.35, margin=-0.01 * b, margin_uncertainty=2e-6, worst=worst)
          for b in (0.3, 0.45, 0.6)]
    bounds = [Boundary({"beta": 0.3}, "range end"), Boundary({"beta": 0.3512}, "Hopf", worst)]
    run = {"run_model": "thesis_ramp_n3", "point": {"Omega": 4.5}, "start": "balls spread at 2 pi k / n",
           "mapped": ["beta", "zeta"], "schedule_end": 400.0, "t_end": 1200.0, "status": "ok", "r_max": 0.0213,
           "t_dec": None, "r_end": 3.1e-3, "threshold": 1e-3, "settled": False, "trace": {"t": [0.0, 1.0], "r": [1, 2]},
           "design": {"beta": 0.45}}
    full = Design(pr, "interval", vs[1], feasible_intervals=[(0.3512, 0.6)], boundaries=bounds, active=bounds[1],
                  sensitivity=[{"parameter": "beta", "dmargin": -0.01, "dmargin_finite_difference": [-0.0101, math.nan],
                                "agree": True, "kink": False, "room_linear": 0.9}],
                  resolution={"statement": "every feasible interval wider than 0.003 in beta holds a grid point"},
                  verdicts=vs, verification_run_up=run,
                  objective_runs=[{"point": {"Omega": 4.5}, "settled": True, "t_dec": 310.5},
                                  {"point": {"Omega": 4.5}, "settled": False, "t_dec": None}],
                  verification=[{"point": {"Omega": 3.5}, "start": "spread", "status": "ok", "t_dec": 290.0,
                                 "r_max": 0.02, "r_end": 1e-5, "settled": True},
                                {"point": {"Omega": 4.5}, "start": "bunched", "status": "ok", "t_dec": None,
                                 "r_max": 0.05, "r_end": 0.01, "settled": False}])
    balls = [{"n": 3, "feasible": True, "best": {"beta": 0.45}, "margin": -0.0045, "t_dec": 310.5},
             {"n": 4, "feasible": False, "best": None, "margin": None, "t_dec": None}]
    choice = {"why": "the largest decay rate", "method": "each count's design compared by its objective"}
    none = Design(pr, "interval", None, boundaries=[Boundary({"beta": 0.3 + 0.001 * k}, "Hopf", worst)
                                                   for k in range(43)], verdicts=[vs[0]],
                  objective_runs=[{"point": {"Omega": 4.5}, "run_model": "thesis_ramp_n3", "residual_quantile": None}],
                  verification_run_up_note="the scene has no run-up model")
    return [("full", full, "adbgen design thesis_rotating_n3 --vary beta=0.3:0.6", "t_dec", balls, choice),
            ("none", none, "adbgen design thesis_rotating_n3 --objective residual", "residual", None, None)]


@pytest.fixture(scope="module")
def cases():
    return designs()


def test_report_equals_mains(cases):
    for name, *args in cases:
        assert dr.report(*args) == (DATA / f"design_report_{name}.md").read_text()


def test_a_changed_word_or_number_is_caught(cases, tmp_path, monkeypatch):
    name, design, *rest = cases[0]
    expected = (DATA / f"design_report_{name}.md").read_text()
    design.sensitivity[0]["room_linear"] = 0.8  # a planted wrong number
    try:
        assert dr.report(design, *rest) != expected
    finally:
        design.sensitivity[0]["room_linear"] = 0.9
    with changed_template(prose, "design_report.md.j2", "must exist", "must be", tmp_path, monkeypatch):
        assert dr.report(design, *rest) != expected
    assert dr.report(design, *rest) == expected
