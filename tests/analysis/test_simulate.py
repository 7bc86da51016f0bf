"""Transients on the compiled engines (adbgen/analysis/simulate.py, engines/).

Problem A (issue 12): thesis model n = 3, (5.1), phi(0) = (pi/3, -pi/3, pi), t in [0, 2000].
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbgen.analysis.engines import DEFAULT, ENGINES
from adbgen.analysis.loading import AnalysisError
from adbgen.analysis.results import IntegrationError
from adbgen.analysis.simulate import simulate, simulate_many

PHI_A = {"phi_1": math.pi / 3, "phi_2": -math.pi / 3, "phi_3": math.pi}
PI3 = {"phi_1": math.pi, "phi_2": math.pi, "phi_3": math.pi}


@pytest.fixture(scope="module")
def reference_a(thesis):
    """Problem A by solve_ivp DOP853 at rtol 1e-12 (a different code path: numba rhs, SciPy's DOP853)."""
    return simulate(thesis[3], None, PHI_A, t_end=2000.0, rtol=1e-12, atol=1e-14, engine="scipy-dop853",
                    keep_trajectory=False)


def _rel(a, b):
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def test_default_is_compiled_and_matches_solve_ivp(thesis, reference_a):
    """The default engine and solve_ivp DOP853 at the same tolerance agree on problem A to the tolerance,
    and both agree with the tight reference; t_dec and r_max as well."""
    m = thesis[3]
    fast = simulate(m, None, PHI_A, t_end=2000.0, rtol=1e-8, atol=1e-10)
    slow = simulate(m, None, PHI_A, t_end=2000.0, rtol=1e-8, atol=1e-10, engine="scipy-dop853")
    assert fast.engine == DEFAULT == "auto" and fast.picked["engine"] in ENGINES
    assert _rel(fast.y_end, slow.y_end) < 1e-7
    assert _rel(fast.y_end, reference_a.y_end) < 1e-7
    assert fast.r_max == pytest.approx(reference_a.r_max, rel=1e-7)
    assert fast.t_dec == pytest.approx(reference_a.t_dec, abs=1e-3)
    assert fast.n_rhs > 10_000 and fast.n_steps > 500 and fast.wall_s > 0


# every compiled engine of the registry (a C library of its own: `library`); the short run of every
# registered engine, whatever it is: tests/analysis/test_engine_registry.py
COMPILED = sorted(n for n, e in ENGINES.items() if callable(getattr(e, "library", None)))


@pytest.mark.parametrize("name", COMPILED)
def test_every_compiled_engine(thesis, reference_a, name):
    """Each compiled engine reaches problem A's final state at t = 2000; r_max, t_dec by its own event
    location."""
    s = simulate(thesis[3], None, PHI_A, t_end=2000.0, rtol=1e-9, atol=1e-11, engine=name, keep_trajectory=False)
    assert _rel(s.y_end, reference_a.y_end) < 2e-6
    assert s.r_max == pytest.approx(reference_a.r_max, rel=1e-6)
    assert s.t_dec == pytest.approx(reference_a.t_dec, abs=0.01)


@pytest.mark.parametrize("engine", [DEFAULT, "cyrk-dop853"])
def test_decay_time_is_located_on_the_continuous_solution(thesis, reference_a, engine):
    """t_dec is where r crosses the threshold on the solution, not the nearest accepted step."""
    s = simulate(thesis[3], None, PHI_A, t_end=2000.0, engine=engine)
    r = np.hypot(s.y[0], s.y[1])
    k = int(np.searchsorted(s.t, s.t_dec))
    assert s.t[k - 1] < s.t_dec < s.t[k] and np.all(r[k:] < 1e-3)
    assert abs(s.t_dec - reference_a.t_dec) < 1e-3 * (s.t[k] - s.t[k - 1])
    # r_max: at least the largest step value, and the peak between steps
    assert s.r_max >= r.max()


def test_not_settled_and_never_reached(thesis):
    m = thesis[2]
    short = simulate(m, None, {"phi_1": math.pi / 2, "phi_2": -math.pi / 2}, t_end=50.0)
    assert short.t_dec is None and short.r_max > 1e-3
    quiet = simulate(m, None, m.module.START, t_end=50.0)  # the balanced state: r stays 0
    assert quiet.t_dec == 0.0 and quiet.r_max < 1e-6


@pytest.mark.parametrize("panel, phi0, r_ref, t_ref", [
    ("a", (math.pi / 2, -math.pi / 2), 0.0483, 462.42),
    ("c", (3 * math.pi / 4, -3 * math.pi / 4), 0.2878, 745.02),
])
def test_figure_5_4(thesis, panel, phi0, r_ref, t_ref):
    """Thesis Fig. 5.4 (n = 2, (5.1)): r_max and t_dec as printed, within 0.5 % (Matlab ode45, loose)."""
    s = simulate(thesis[2], None, {"phi_1": phi0[0], "phi_2": phi0[1]}, t_end=1000.0, rtol=1e-10, atol=1e-12)
    assert s.r_max == pytest.approx(r_ref, rel=5e-3)
    assert s.t_dec == pytest.approx(t_ref, rel=5e-3)


# the exact symmetry of every engine declaring it: tests/analysis/test_engine_registry.py (check_exact_symmetry)


def test_figure_5_4a_ends_balanced(thesis):
    """Fig. 5.4(a) settles at the balanced state (5.2), phi = +-1.67096374795646 (still ringing at t = 700)."""
    s = simulate(thesis[2], None, {"phi_1": math.pi / 2, "phi_2": -math.pi / 2}, t_end=700.0, rtol=1e-10, atol=1e-12,
                 keep_trajectory=False)
    assert abs(s.y_end[2] - 1.67096374795646) < 5e-3 and abs(s.y_end[3] + 1.67096374795646) < 5e-3


def test_a_generic_path_loses_the_symmetry(thesis):
    """Negative control: solve_ivp (stage sums through BLAS) separates the balls by round-off, and the
    run no longer ends at the coincident state."""
    s = simulate(thesis[3], None, PI3, t_end=2000.0, engine="scipy-dop853", keep_trajectory=False)
    assert not (s.y_end[2] == s.y_end[3] == s.y_end[4])
    assert not ENGINES["scipy-dop853"].symmetric


def test_many_equals_one_by_one(thesis):
    """The batch path (OpenMP threads inside the library) gives each trajectory bit for bit."""
    m = thesis[2]
    Y0 = np.zeros((6, m.n_states))
    Y0[:, 2] = np.linspace(0.3, 2.8, 6)
    Y0[:, 3] = -1.0
    P = m.params({"Omega": 3.0})
    batch = simulate_many(m, P, Y0, t_end=300.0, threads=2)
    for k in range(6):
        one = simulate(m, P, Y0[k], t_end=300.0, keep_trajectory=False)
        assert np.array_equal(one.y_end, batch.y_end[k])
        assert one.r_max == batch.r_max[k]
        assert one.n_rhs == batch.n_rhs[k]
        assert (one.t_dec is None and np.isnan(batch.t_dec[k])) or one.t_dec == batch.t_dec[k]
    assert list(batch.status) == ["success"] * 6


def test_early_stop_in_a_target_region(thesis):
    """A trajectory entering a target region stops there (sweeps' shortcut); the others run to t_end."""
    m = thesis[2]
    start = np.array(m.module.START)
    Y0 = np.array([start + 1e-4, m.state({"phi_1": 3.0, "phi_2": 3.0})])
    region = (start, np.full(m.n_states, 1e2))  # |y - start| <= 1e-2 in every component
    out = simulate_many(m, m.params(), Y0, t_end=500.0, check_dt=10.0, targets=[region])
    assert out.status[0] == "stopped" and out.target[0] == 0 and out.t_last[0] == pytest.approx(10.0)
    assert out.target[1] == -1 and out.t_last[1] == 500.0


def test_segments_and_ellipsoid_targets(thesis):
    """CyRK: check_dt segments the run with or without targets (bit-identical trajectories until a stop);
    an ellipsoid target e'We <= 1 stops; measures=False gives the same states with r_max and t_dec NaN.
    (The Taylor engine tests the state on its steps' polynomials instead: tests/analysis/test_taylor_engine.py.)"""
    m = thesis[2]
    start = np.array(m.module.START)
    Y0 = np.array([start + 1e-4, m.state({"phi_1": 3.0, "phi_2": 3.0})])
    cyrk = {"engine": "cyrk-dop853"}
    plain = simulate_many(m, m.params(), Y0, t_end=300.0, check_dt=10.0, **cyrk)
    lean = simulate_many(m, m.params(), Y0, t_end=300.0, check_dt=10.0, measures=False, **cyrk)
    assert np.array_equal(plain.y_end, lean.y_end) and np.array_equal(plain.n_rhs, lean.n_rhs)
    assert np.all(np.isnan(lean.r_max)) and np.all(np.isnan(lean.t_dec)) and not np.any(np.isnan(plain.r_max))
    whole = simulate_many(m, m.params(), Y0, t_end=300.0, **cyrk)
    assert not np.array_equal(whole.y_end, plain.y_end)  # the segments are real restarts
    W = np.eye(m.n_states) * 1e4  # |y - start| <= 1e-2 (Euclidean)
    stop = simulate_many(m, m.params(), Y0, t_end=300.0, check_dt=10.0, targets=[(start, W)], measures=False, **cyrk)
    assert list(stop.status) == ["stopped", "success"] and stop.t_last[0] == pytest.approx(10.0)
    assert np.array_equal(stop.y_end[1], lean.y_end[1])
    with pytest.raises(AnalysisError, match="target region"):
        simulate_many(m, m.params(), Y0, t_end=10.0, check_dt=5.0, targets=[(start, np.eye(3))])


def test_failures_name_the_time(thesis):
    m = thesis[2]
    y0 = {"phi_1": 1.0}
    with pytest.raises(IntegrationError, match=r"failed at t = [0-9.e+-]+ \(step limit reached"):
        simulate(m, None, y0, t_end=100.0, max_steps=50)
    with pytest.raises(IntegrationError, match="non-finite"):
        simulate(m, {"mu": 1e308}, y0, t_end=10.0)
    with pytest.raises(IntegrationError, match="step size underflow"):
        simulate(m, None, y0, t_end=10.0, rtol=1e-15, atol=1e-300, engine="cyrk-dop853")
    for engine in ("cvode-adams", "scipy-dop853"):
        with pytest.raises(IntegrationError, match="non-finite"):
            simulate(m, {"mu": 1e308}, y0, t_end=10.0, engine=engine)
    s = simulate(m, None, y0, t_end=100.0, max_steps=50, check=False)
    assert s.status == "max_steps" and 0 < s.t_fail < 100.0


@pytest.mark.parametrize("engine", ["cvode-adams", "arkode-dp5", "cyrk-dop853", "taylor", "matlab-ode45",
                                    "scipy-dop853", "scipy-radau", "scipy-lsoda"])
def test_a_failed_run_reports_r_max_of_what_it_reached(thesis, engine):
    """A run stopped by its step limit: r_max is at least r where it stopped (SUNDIALS' returns are its roots;
    before its failure state counted, cvode-adams reported r_max = 0 from rest with r = 0.16 reached; the
    scipy engines reported NaN, and ran on to t_end with success as they ignored the limit)."""
    m = thesis[2]
    s = simulate(m, None, None, t_end=200.0, max_steps=50, threshold=0.3, engine=engine, check=False,
                 keep_trajectory=False)
    assert s.status == "max_steps" and s.t_dec is None
    assert s.r_max >= np.hypot(s.y_end[0], s.y_end[1]) > 0.01


@pytest.mark.parametrize("engine", ["cvode-adams", "arkode-erk8", "cyrk-dop853", "scipy-rk45", "scipy-bdf"])
@pytest.mark.parametrize("keep", [False, True])
def test_the_step_limit_bounds_the_whole_run(thesis, engine, keep):
    """max_steps bounds a run's steps on every engine, with or without samples; SUNDIALS' own limit is per
    call (steps between returns at its roots and samples), so before the driver kept count, cvode-adams took
    9842 steps under max_steps = 50 and reported success."""
    s = simulate(thesis[2], None, None, t_end=200.0, max_steps=50, engine=engine, check=False, keep_trajectory=keep)
    assert s.status == "max_steps" and s.n_steps <= 50 and 0 < s.t_fail < 200.0


@pytest.mark.parametrize("kwargs", [{"t_end": -1.0}, {"rtol": 0.0}, {"atol": float("nan")}, {"engine": "euler"},
                                    {"rtol": 1e-17}, {"threshold": 0.0}, {"max_steps": 0}])
def test_bad_settings(thesis, kwargs):
    with pytest.raises(AnalysisError):
        simulate(thesis[2], None, {"phi_1": 1.0}, **kwargs)


def test_bad_batches(thesis):
    m = thesis[2]
    with pytest.raises(AnalysisError):
        simulate_many(m, m.params(), np.zeros((0, m.n_states)))
    with pytest.raises(AnalysisError):
        simulate_many(m, np.zeros((2, m.n_params)), np.zeros((3, m.n_states)))
    with pytest.raises(AnalysisError):
        simulate_many(m, m.params(), np.full((2, m.n_states), np.nan))
