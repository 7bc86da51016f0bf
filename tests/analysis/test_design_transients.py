"""analysis.design_transients: the verification runs of a feasible design settle from both starts at every corner
of the box, and those of an infeasible one (unstable at zeta = 0.5: the control) do not settle there; the t_dec
objective chooses among feasible designs inside the varied box only."""

from __future__ import annotations

import numpy as np
import pytest

from adbgen.analysis.design import Axis, Design, Problem, Verdict, assess
from adbgen.analysis.design_transients import STARTS, best_by_t_dec, by_runs, operating_point, verify
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


# --- the residual objective on a friction scene (issue 39 item 3) --------------------------------------------------
# a constant-speed stiction scene ((5.1) in SI: omega_n = 100 rad/s, R = 50 mm, m = 50 g, M = 1 kg) and its
# frictionless twin (what `adbgen design` makes of it: rolling_resistance = 0.0, no static_friction), which shares
# the scene's parameters and units and has the closed-form balancing state of its frictionless limit
STICK_SCENE = "n = 2\nrolling_resistance = 0.01\nstatic_friction = 0.02\n[speed]\nomega = 400.0\n"
TWIN_SCENE = "n = 2\nrolling_resistance = 0.0\n[speed]\nomega = 400.0\n"
RUN_TIME = 20.0  # s: long enough for every start to come to rest (8000 rad at 400 rad/s)


@pytest.fixture(scope="module")
def friction_pair(tmp_path_factory):
    """(the twin's design problem, a feasible design's verdict, the stiction model): generated once through the
    scene cache (ADBGEN_CACHE; the stiction model takes tens of seconds cold)."""
    folder = tmp_path_factory.mktemp("friction")
    (folder / "stick.toml").write_text(STICK_SCENE)
    (folder / "twin.toml").write_text(TWIN_SCENE)
    twin, runs = load_model(scene=folder / "twin.toml"), load_model(scene=folder / "stick.toml")
    pr = Problem(twin, twin.params(), [Axis("omega", 400.0, 400.0), Axis("eps", 5e-4, 5e-4)], [Axis("D", 1e-3, 5e-3)])
    v = assess(pr, [3e-3])
    return pr, v, runs


def test_the_frictionless_limit_has_the_balancing_state_in_closed_form(friction_pair):
    pr, v, runs = friction_pair
    assert v.feasible and v.margin < 0
    p = pr.params([3e-3])
    y = pr.model.steady_state("1", p)
    assert y is not None and np.max(np.abs(pr.model.module.rhs(0.0, y, p))) < 1e-12
    # the same closed form on the stiction model (its frictionless limit), absent where friction acts in slip
    q = runs.params({"mu_r": 0.0})
    assert runs.steady_state("1", q) is not None and runs.steady_state("1", runs.params({"mu_r": 0.01})) is None
    assert pr.model.steady_state("1", pr.model.params({"mu_r": 1e-3})) is None


def _residual(friction_pair, run_set, **kw):
    pr, v, runs = friction_pair
    d = by_runs(Design(pr, "interval", None, verdicts=[v]), "residual", runs, run_time=RUN_TIME, run_set=run_set,
                workers=1, starts=4, **kw)
    return d, d.objective_runs[0]


def test_residual_grows_with_stiction_and_a_target_below_it_is_infeasible(friction_pair):
    pr, v, runs = friction_pair
    near, row0 = _residual(friction_pair, {"mu_r": 0.0, "mu_s": 1e-4})
    assert row0["at_rest"] == 4 and row0["undecided"] == row0["failed"] == 0 and near.best is v
    eps = 5e-4
    assert row0["residual_quantile"] < 1e-2 * eps  # near the frictionless balanced value, r = 0
    rough, row1 = _residual(friction_pair, {"mu_r": 0.01, "mu_s": 0.02})
    assert row1["at_rest"] == 4 and rough.best is v
    assert row1["residual_quantile"] > 100 * row0["residual_quantile"]  # the negative control: more stiction
    assert rough.residual["chosen_quantile"] == row1["residual_quantile"] and rough.residual["unit"] == "m"
    assert row1["mapped"] and "mu_r" not in row1["mapped"]  # the run model keeps its own friction
    # a planted target below the achievable residual: no best design, said so
    low, row2 = _residual(friction_pair, {"mu_r": 0.01, "mu_s": 0.02}, target=0.5 * row1["residual_quantile"])
    assert low.best is None and row2["meets_target"] is False and "no design reaches the target" in low.residual["note"]
    ok, row3 = _residual(friction_pair, {"mu_r": 0.01, "mu_s": 0.02}, target=2 * row1["residual_quantile"])
    assert ok.best is v and row3["meets_target"] is True
    # another quantile of the same runs
    _, row4 = _residual(friction_pair, {"mu_r": 0.01, "mu_s": 0.02}, quantile=0.25)
    assert row4["residual_quantile"] == pytest.approx(np.quantile(row1["residuals"], 0.25), rel=1e-12)


def test_runs_not_at_rest_are_undecided_never_balanced(friction_pair):
    """Without stiction (mu_s = 0) no ball sticks: r at t_end is tiny but no run is at rest, so no quantile."""
    d, row = _residual(friction_pair, {"mu_r": 0.0, "mu_s": 0.0})
    assert max(row["residuals"]) < 1e-9 * 5e-4 * 1e3  # the balls have all but balanced the rotor
    assert row["undecided"] == 4 and row["at_rest"] == 0 and row["residual_quantile"] is None and d.best is None
    assert "undecided" in d.residual["note"]


def test_run_params_keep_the_run_models_own_friction(friction_pair):
    from adbgen.analysis.design_runs import run_params

    pr, v, runs = friction_pair
    q, taken = run_params(pr, runs, [3e-3], {"eps": 5e-4}, {"mu_r": 0.01})
    assert q[runs.param_names.index("mu_r")] == 0.01 and q[runs.param_names.index("D")] == 3e-3
    # negative control: without it the twin's mu_r = 0 reaches the run model
    q0, _ = run_params(pr, runs, [3e-3], {"eps": 5e-4})
    assert q0[runs.param_names.index("mu_r")] == 0.0
