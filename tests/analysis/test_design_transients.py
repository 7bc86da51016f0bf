"""analysis.design_transients: the verification runs of a feasible design settle from both starts at every corner
of the box, and those of an infeasible one (unstable at zeta = 0.5: the control) do not settle there; the t_dec
objective chooses among feasible designs inside the varied box only."""

from __future__ import annotations

import pytest

from adbgen.analysis.design import Axis, Problem, Verdict, assess
from adbgen.analysis.design_transients import STARTS, best_by_t_dec, operating_point, verify
from adbgen.analysis.loading import load_model


@pytest.fixture(scope="module")
def problem():
    m = load_model("thesis_rotating_n3")
    return Problem(m, m.params(), [Axis("Omega", 4.0, 4.0), Axis("zeta", 0.3, 0.5)], [Axis("beta", 0.25, 1.0)])


def test_verification_runs_every_corner_from_both_starts(problem):
    assert assess(problem, [0.3]).feasible
    runs = verify(problem, [0.3])
    assert [(r["point"]["zeta"], r["start"]) for r in runs] == [(0.3, STARTS[0]), (0.3, STARTS[1]), (0.5, STARTS[0]),
                                                               (0.5, STARTS[1])]
    assert all(r["settled"] and r["t_dec"] > 0 and r["r_end"] < r["threshold"] for r in runs)
    # the control: beta = 0.2 is unstable at zeta = 0.5 (a Hopf point at beta = 0.2346), and no run settles there
    bad = verify(problem, [0.2])
    assert not assess(problem, [0.2]).feasible
    assert [r["settled"] for r in bad if r["point"]["zeta"] == 0.5] == [False, False]


def test_t_dec_objective_keeps_to_the_varied_box(problem):
    inside = assess(problem, [0.5])
    outside = Verdict((1.5,), True, inside.capacity, feasible=True, margin=inside.margin)  # planted beyond the range
    best, runs = best_by_t_dec(problem, [inside, outside])
    assert [r["design"]["beta"] for r in runs] == [0.5] and best is inside
    assert operating_point(problem) == {"Omega": 4.0, "zeta": 0.4, "delta": 0.01}
    assert runs[0]["settled"]
