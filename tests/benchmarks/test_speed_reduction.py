"""The speed-reduction study (benchmarks/speed_reduction.py, issue 37): the feasibility verdict on planted
distributions, the cases and end times.  The check on the scene's model (a reduction of zero depth gives the
distribution of no reduction, a deep one does not) runs with the study (`python3 -m benchmarks.speed_reduction
--check`), not here: its model's first generation is the suite's longest setup (187 s on a cold cache)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbgen.analysis.residual import AT_REST, MOVING, NOT_RUN, distribution
from benchmarks import speed_reduction as sr


def _dist(values, codes=None):
    values = np.asarray(values, float)
    return distribution(values, np.full(values.size, AT_REST) if codes is None else np.asarray(codes))


def test_a_case_is_feasible_only_when_every_start_is_at_rest_below_the_target():
    d = _dist([1e-5, 2e-5, 3e-5])
    assert sr.feasible(d, 5e-5) is True
    # negative control: a planted target below the largest residual is infeasible
    assert sr.feasible(d, 2.5e-5) is False
    assert sr.feasible(d, 3e-5) is False  # "below": equal is not below
    # a start still moving or failed is not counted as physics: below the target it leaves the verdict open
    assert sr.feasible(_dist([1e-5, 2e-5, math.nan], [AT_REST, AT_REST, MOVING]), 5e-5) is None
    assert sr.feasible(_dist([1e-5, math.nan], [AT_REST, NOT_RUN]), 5e-5) is None
    # ... but a start at rest above the target already decides it
    assert sr.feasible(_dist([1e-4, math.nan], [AT_REST, MOVING]), 5e-5) is False


def test_the_cases_and_end_times():
    cs = sr.cases((0.3,), (0.5, 1.0))
    assert cs[0] == {"depth": 0.0, "plateau": 0.0} and len(cs) == 3
    s = sr.SCHEDULE
    assert sr.t_end_for(0.0, 0.0) == pytest.approx(s["t_ramp"] + s["t_hold"] + sr.SETTLE)
    assert sr.t_end_for(0.5, 1.0) == pytest.approx(sr.t_end_for(0.0, 0.0) + 1.0 + 0.5 * s["omega"] *
                                                   (1 / s["drop_rate"] + 1 / s["recovery_rate"]))
    # r without balls: eps M w^2 / |k - (M + 2m) w^2 + i c w| at the study's rotor (M 1 kg, k 1000 N/m, m 10 g)
    w = s["omega"]
    assert sr.free_response() == pytest.approx(5e-4 * w**2 / abs(complex(1000 - 1.02 * w**2, 6 * w)), rel=1e-12)


def test_every_start_below_is_the_largest_residual_only_when_all_starts_are_at_rest():
    assert sr.every_start_below(_dist([1e-5, 3e-5]), 2) == pytest.approx(3e-5)
    # negative control: a start not at rest leaves it undecided, not the largest of the others
    assert sr.every_start_below(_dist([1e-5, math.nan], [AT_REST, MOVING]), 2) is None
