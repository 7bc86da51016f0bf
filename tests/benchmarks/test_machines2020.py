"""The Machines 2020 reproduction (benchmarks/machines2020.py, issue 37 item 5): the cases, the verdicts on planted
distributions, and the study scene's values.  The tiny version on the model (3 x 3 starts) runs with the study,
`python3 -m benchmarks.machines2020 --check`, not here: its model is the stick/slip model of
speed_reduction_scene.toml, whose first generation is minutes (test_speed_reduction.py)."""

from __future__ import annotations

import numpy as np
import pytest

from adbgen.analysis.residual import AT_REST, MOVING, distribution
from benchmarks import friction_studies as fs
from benchmarks import machines2020 as m20


def _case(name, group, r, depth=0.0, **more):
    r = np.asarray(r, float)
    return {"name": name, "group": group, "values": {"depth": depth}, "distribution":
            distribution(r, np.full(r.size, AT_REST)), **more}


def _result(none, best, worst, low_mu, high_mu):
    return {"values": {"mu_s": 0.005}, "cases": [
        _case("no reduction", "grid", none),
        _case("best", "grid", best, depth=0.5),
        _case("worst", "grid", worst, depth=0.8),
        _case("low", "stiction", low_mu, value=0.0025, reduced=False),
        _case("high", "stiction", high_mu, value=0.01, reduced=False),
        _case("low reduced", "stiction", best, value=0.0025, reduced=True, depth=0.5),
    ]}


def test_verdicts_on_planted_distributions():
    wide = np.r_[np.full(80, 1.0), np.full(20, 5.0)]  # median 1, 90 % 5
    v = m20.verdicts(_result(wide, wide * 0.5, wide * 2, wide * 0.5, wide * 2))
    assert v == {**v, "stiction_scatters": True, "scatter_grows_with_stiction": True, "reduction_helps": True,
                 "best_reduction": "best"}
    assert [m for m, _ in v["q90_by_mu_s"]] == [0.0025, 0.005, 0.01]
    # negative controls: a narrow distribution does not scatter; stiction that does not order the 90 %;
    # reductions no better than none
    narrow = np.full(100, 1.0)
    assert m20.verdicts(_result(narrow, narrow, narrow, narrow, narrow))["stiction_scatters"] is False
    assert m20.verdicts(_result(wide, wide * 0.5, wide, wide * 2, wide * 0.5))["scatter_grows_with_stiction"] is False
    assert m20.verdicts(_result(wide, wide * 1.5, wide * 2, wide * 0.5, wide * 2))["reduction_helps"] is False


def test_a_case_without_starts_at_rest_leaves_the_verdicts_open():
    result = _result(np.full(10, 1.0), np.full(10, 1.0), np.full(10, 1.0), np.full(10, 1.0), np.full(10, 1.0))
    moving = np.full(10, np.nan)
    result["cases"][0]["distribution"] = distribution(moving, np.full(10, MOVING))
    v = m20.verdicts(result)
    assert v["stiction_scatters"] is None and v["reduction_helps"] is None and v["scatter_grows_with_stiction"] is None


def test_cases():
    base = fs.scene_values(m20.SCENE)
    grid = m20.grid_cases(base, (0.3, 0.5), (0.5, 1.0, 2.0))
    assert len(grid) == 7 and grid[0]["values"]["depth"] == 0.0
    assert {(c["values"]["depth"], c["values"]["t_plateau"]) for c in grid[1:]} == \
        {(d, p) for d in (0.3, 0.5) for p in (0.5, 1.0, 2.0)}
    inf = m20.influence_cases(base, (0.01,), (12.0,), ())
    assert len(inf) == 4
    stiction = [c for c in inf if c["group"] == "stiction"]
    assert all(c["values"]["mu_s"] == 0.01 and c["values"]["mu_r"] == pytest.approx(0.004) for c in stiction)
    assert [c["values"]["depth"] for c in stiction] == [0.0, base["depth"]]
    # the scene's values: mu_r / mu_s = 0.4, as the influence cases keep it
    assert base["mu_r"] / base["mu_s"] == pytest.approx(0.4)
    assert fs.free_response(base) == pytest.approx(
        base["eps"] * base["omega"] ** 2 / abs(complex(base["k"] - 1.02 * base["omega"] ** 2, base["c"] * base["omega"])))


def test_a_case_with_some_starts_moving_or_failed_leaves_its_verdicts_open():
    """The quantiles of a case with a start still moving (or failed) are over part of its starts only: the verdicts
    that read them are None, not decided on that part."""
    wide = np.r_[np.full(80, 1.0), np.full(20, 5.0)]
    result = _result(wide, wide * 0.5, wide * 2, wide * 0.5, wide * 2)
    assert m20.verdicts(result)["stiction_scatters"] is True  # all at rest: decided
    at_rest = np.full(wide.size + 1, AT_REST)
    at_rest[-1] = MOVING
    result["cases"][0]["distribution"] = distribution(np.r_[wide, np.nan], at_rest)
    v = m20.verdicts(result)
    assert v["stiction_scatters"] is None and v["reduction_helps"] is None and v["scatter_grows_with_stiction"] is None
    # a reduction with a start moving is not picked as the best one
    result = _result(wide, wide * 0.5, wide * 2, wide * 0.5, wide * 2)
    result["cases"][1]["distribution"] = distribution(np.r_[wide * 0.5, np.nan], at_rest)
    assert m20.verdicts(result)["best_reduction"] == "worst"
