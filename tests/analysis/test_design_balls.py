"""analysis.design_balls: the ball count chosen over every count designed, with why.  The count with the smallest
objective value among the feasible ones is chosen and ranked first; a count beyond the balls' capacity is named
with its capacity; two counts whose worst margins are not apart beyond their uncertainties leave the choice
undecided (negative control: the same margins with small uncertainties decide it); no feasible count, no choice."""

from __future__ import annotations

import pytest

from adbgen.analysis import design_balls as db
from adbgen.analysis.design import Axis, Design, Problem, assess
from adbgen.analysis.loading import load_model


@pytest.fixture(scope="module")
def thesis3():
    return load_model("thesis_rotating_n3")


def _row(n, value, uncertainty=1e-12, feasible=True, limit="Hopf"):
    return {"n": n, "feasible": feasible, "best": {"beta": 0.1 * n} if feasible else None, "margin": value,
            "t_dec": None, "objective_value": value if feasible else None, "margin_uncertainty": uncertainty,
            "capacity": 0.01 * n, "limit": limit}


def test_rows_say_the_capacity_limit_and_the_margin(thesis3):
    # n mu = 0.03 below the interval's maximum 0.05: beyond the capacity at every design assessed
    pr = Problem(thesis3, thesis3.params({"zeta": 0.3}), [Axis("Omega", 4, 4), Axis("delta", 0, 0.05)],
                 [Axis("mu", 0.005, 0.01)])
    v = assess(pr, [0.01])
    row = db.row(1, Design(pr, "interval", None, verdicts=[v]), "margin")
    assert not row["feasible"] and row["objective_value"] is None and "beyond the balls' capacity" in row["limit"]
    assert "0.03" in row["limit"]
    pr = Problem(thesis3, thesis3.params({"zeta": 0.3}), [Axis("Omega", 4, 4), Axis("delta", 0, 0.01)],
                 [Axis("beta", 0.3, 0.6)])
    v = assess(pr, [0.45])
    row = db.row(3, Design(pr, "interval", v, verdicts=[v]), "margin")
    assert row["feasible"] and row["objective_value"] == row["margin"] == v.margin < 0
    assert row["best"] == {"beta": 0.45} and row["margin_uncertainty"] == v.margin_uncertainty
    # the objective's value is the chosen design's run, not its margin
    design = Design(pr, "interval", v, verdicts=[v], objective_runs=[{"design": {"beta": 0.45}, "r_max": 0.004,
                                                                       "t_dec": None}])
    assert db.row(3, design, "r_max-run-up")["objective_value"] == 0.004
    design.objective_runs[0]["design"] = {"beta": 0.3}  # negative control: another design's run is not its value
    assert db.row(3, design, "r_max-run-up")["objective_value"] is None


def test_choose_ranks_the_counts_and_says_why():
    rows = [_row(1, None, feasible=False, limit="beyond the balls' capacity everywhere"), _row(2, -1e-6),
            _row(3, -0.0097), _row(4, -0.005)]
    chosen, choice = db.choose(rows, "margin")
    assert chosen == 3 == choice["chosen"] and choice["runner_up"] == 4 and choice["decided"]
    assert [r["n"] for r in choice["ranking"]] == [3, 4, 2]
    assert choice["why"].startswith("n = 3 (beta = 0.3): worst margin -0.0097, limited by: Hopf")
    assert "n = 1: beyond the balls' capacity" in choice["why"] and "\n" not in choice["why"]
    # not apart beyond the uncertainties: chosen by the value, said undecided
    close = [_row(2, -0.0097, uncertainty=1e-3), _row(3, -0.0098, uncertainty=1e-3)]
    chosen, choice = db.choose(close, "margin")
    assert chosen == 3 and not choice["decided"] and "not decided" in choice["why"]
    # negative control: the same values with small uncertainties decide it
    close = [_row(2, -0.0097, uncertainty=1e-6), _row(3, -0.0098, uncertainty=1e-6)]
    assert db.choose(close, "margin")[1]["decided"]
    # the runs' objectives: smaller is better, apart beyond RUN_RTOL
    runs = [dict(_row(2, 0.004), objective_value=0.004), dict(_row(3, 0.006), objective_value=0.006)]
    chosen, choice = db.choose(runs, "r_max-run-up")
    assert chosen == 2 and choice["decided"] and "r_max through the run-up 0.004" in choice["why"]
    chosen, choice = db.choose([_row(2, None, feasible=False, limit="no design of the varied box is stable")], "margin")
    assert chosen is None and choice["chosen"] is None and choice["why"].startswith("no count has a feasible design")
