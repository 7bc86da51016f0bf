"""The scipy engines (adbgen/analysis/engines/scipy_ivp.py): the step limit, which solve_ivp lacks, is kept by
refusing the step after max_steps accepted ones, without changing a step the method takes; a derivative that is
non-finite from the start reports the start as what was reached, as the compiled engines do."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from adbgen.analysis.simulate import simulate

START = {"phi_1": 1.0, "phi_2": 2.0}


@pytest.mark.parametrize("key, method", [("dop853", "DOP853"), ("rk45", "RK45"), ("radau", "Radau"),
                                         ("lsoda", "LSODA"), ("bdf", "BDF")])
def test_the_step_limit_changes_no_step_and_stops_at_the_last_accepted_one(thesis, key, method):
    m = thesis[2]
    p, y0 = m.params(), m.state(START)
    jac = {"jac": lambda t, y: m.module.jac(t, y, p)} if method in ("Radau", "LSODA", "BDF") else {}
    plain = solve_ivp(lambda t, y: m.module.rhs(t, y, p), (0.0, 5.0), y0, method=method, rtol=1e-8, atol=1e-10,
                      **jac)
    n = len(plain.t) - 1
    whole = simulate(m, None, START, t_end=5.0, engine="scipy-" + key, max_steps=n)
    assert whole.status == "success" and whole.n_steps == n
    assert np.array_equal(whole.t, plain.t) and np.array_equal(whole.y, plain.y)  # bit for bit
    cut = simulate(m, None, START, t_end=5.0, engine="scipy-" + key, max_steps=n - 1, check=False)
    assert cut.status == "max_steps" and cut.n_steps == n - 1 and cut.t_dec is None
    assert cut.t_fail == plain.t[n - 1] and np.array_equal(cut.y_end, plain.y[:, n - 1])
    assert cut.r_max >= np.hypot(*plain.y[:2, :n]).max()


def test_a_derivative_non_finite_from_the_start_reports_the_start(thesis):
    m = thesis[2]
    y0 = {"x": 0.01, "phi_1": 1.0}
    ours = simulate(m, {"mu": 1e308}, y0, t_end=10.0, engine="scipy-dop853", check=False)
    compiled = simulate(m, {"mu": 1e308}, y0, t_end=10.0, engine="cvode-adams", check=False)
    assert ours.status == compiled.status == "nonfinite" and ours.t_fail == compiled.t_fail == 0.0
    assert ours.r_max == compiled.r_max == 0.01 and np.array_equal(ours.y_end, compiled.y_end)
