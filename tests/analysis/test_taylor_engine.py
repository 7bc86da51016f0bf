"""The Taylor engine (adbgen/analysis/engines/taylor.py, taylor_driver.c) and the auto engine (auto.py).

Problem A (issue 12): thesis model n = 3, (5.1), phi(0) = (pi/3, -pi/3, pi), t in [0, 2000].
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from adbgen.analysis.engines import DEFAULT, ENGINES
from adbgen.analysis.engines.by_tolerance import AutoEngine
from adbgen.analysis.engines.taylor import TaylorBatchEngine, TaylorEngine, heyoka_order
from adbgen.analysis.loading import load_model
from adbgen.analysis.results import IntegrationError
from adbgen.analysis.simulate import simulate

PHI_A = {"phi_1": math.pi / 3, "phi_2": -math.pi / 3, "phi_3": math.pi}


@pytest.fixture(scope="module")
def reference_a(thesis):
    """Problem A by CyRK Vern8 at rtol 1e-13 (another method), with its trajectory."""
    return simulate(thesis[3], None, PHI_A, t_end=2000.0, rtol=1e-13, atol=1e-15, engine="cyrk-vern8")


def test_problem_a(thesis, reference_a):
    """Taylor at rtol 1e-10 (order 13): the final state to 1e-8, r_max to 1e-9, t_dec to 1e-6, located on
    the step's polynomial (strictly inside a step ~0.15 wide)."""
    s = simulate(thesis[3], None, PHI_A, t_end=2000.0, rtol=1e-10, atol=1e-12, engine="taylor")
    assert s.picked == {"engine": "taylor", "rtol": 1e-10, "atol": 1e-12, "order": heyoka_order(1e-10),
                        "step_factor": 1.0}
    assert np.max(np.abs(s.y_end - reference_a.y_end)) < 1e-8
    assert s.r_max == pytest.approx(reference_a.r_max, rel=1e-9)
    assert s.t_dec == pytest.approx(reference_a.t_dec, abs=1e-6)
    k = np.searchsorted(s.t, s.t_dec)
    assert s.t[k - 1] < s.t_dec < s.t[k] and s.t[k] - s.t[k - 1] > 0.05
    r = np.hypot(s.y[0], s.y[1])
    assert s.r_max >= r.max() and s.n_rhs == s.n_steps * heyoka_order(1e-10)


def test_dense_output_is_the_step_polynomial(thesis, reference_a):
    """dense() at the step ends gives the steps back; between them it is the solution to 1e-9."""
    m = thesis[3]
    eng = ENGINES["taylor"]
    p, y0 = m.params(), m.state(PHI_A)
    out = eng.run(m, p, y0, 200.0, 1e-10, 1e-12, 1e-3, 10**6)
    t, y = out["t"], out["y"]
    np.testing.assert_array_equal(eng.dense(m, p, t, y, t[:-1], 1e-10, 1e-12), y[:, :-1])
    mid = 0.5 * (t[100:110] + t[101:111])
    ref = ENGINES["cyrk-vern8"]
    rr = ref.run(m, p, y0, 200.0, 1e-13, 1e-15, 1e-3, 10**7)
    np.testing.assert_allclose(eng.dense(m, p, t, y, mid, 1e-10, 1e-12),
                               ref.dense(m, p, rr["t"], rr["y"], mid, 1e-13, 1e-15), atol=1e-9)


def test_t_dec_sees_an_excursion_inside_one_step(thesis):
    """Problem A at rtol 1e-3 (order 5): t_dec is the sup of r >= H on the steps' polynomials (dense
    output on a fine grid), wherever the last excursion lies; r_max at least every grid value."""
    m = thesis[3]
    s = simulate(m, None, PHI_A, t_end=2000.0, rtol=1e-3, atol=1e-8, engine="taylor")
    grid = np.arange(600.0, 1000.0, 0.002)
    dense = ENGINES["taylor"].dense(m, m.params(), s.t, s.y, grid, 1e-3, 1e-8)
    r = np.hypot(dense[0], dense[1])
    sup = float(grid[r >= 1e-3][-1])
    assert sup <= s.t_dec < sup + 0.002 and s.r_max >= r.max()


def test_a_step_never_crosses_a_piecewise_switch():
    """The ramp's speed law has a kink at t_ramp: a step ends there (the Piecewise condition's series
    bounds the step), and the run equals CyRK Vern8 at rtol 1e-13 to 1e-9 across it."""
    m = load_model("two_plane_ramp")
    p = m.params({"t_ramp": 5.0})
    y0 = m.state({"theta_1": 0.3})
    s = simulate(m, p, y0, t_end=12.0, rtol=1e-10, atol=1e-13, engine="taylor")
    assert np.min(np.abs(s.t - 5.0)) <= 4 * np.spacing(5.0)
    ref = simulate(m, p, y0, t_end=12.0, rtol=1e-13, atol=1e-16, engine="cyrk-vern8", keep_trajectory=False)
    assert np.max(np.abs(s.y_end - ref.y_end)) < 1e-9


def test_the_hill_run_up_from_rest():
    """The Hill profile's series branch (powers of t, from t = 0 where their base is 0) and its closed
    form after the switch: Taylor equals CyRK Vern8 at rtol 1e-13 to 1e-9 over t in [0, 300]."""
    m = load_model("two_plane_hill")
    y0 = m.state({"theta_2": math.pi, "theta_4": math.pi})
    s = simulate(m, None, y0, t_end=300.0, rtol=1e-11, atol=1e-16, engine="taylor", keep_trajectory=False)
    ref = simulate(m, None, y0, t_end=300.0, rtol=1e-13, atol=1e-18, engine="cyrk-vern8", keep_trajectory=False)
    assert np.max(np.abs(s.y_end - ref.y_end)) < 1e-9 * max(1.0, np.max(np.abs(ref.y_end)))


def test_many_equals_one_and_targets_keep_the_steps(thesis):
    """The OpenMP batch gives each trajectory bit for bit; with check_dt the state is tested on the
    step's polynomial, so the steps are the same with or without targets, and a stop is at a multiple
    of check_dt."""
    m = thesis[2]
    eng = ENGINES["taylor"]
    Y0 = np.zeros((4, m.n_states))
    Y0[:, 2] = np.linspace(0.3, 2.8, 4)
    Y0[:, 3] = -1.0
    P = np.repeat(m.params({"Omega": 3.0})[None], 4, axis=0)
    batch = eng.run_many(m, P, Y0, 300.0, 1e-9, 1e-11, 1e-3, 10**7, threads=2)
    for k in range(4):
        one = eng.run(m, P[k], Y0[k], 300.0, 1e-9, 1e-11, 1e-3, 10**7, keep_trajectory=False)
        assert np.array_equal(one["y_end"], batch["y_end"][k]) and one["r_max"] == batch["r_max"][k]
    start = np.array(m.module.START)
    Y1 = np.array([start + 1e-4, m.state({"phi_1": 3.0, "phi_2": 3.0})])
    plain = eng.run_many(m, P[:2], Y1, 300.0, 1e-9, 1e-11, 1e-3, 10**7)
    checked = eng.run_many(m, P[:2], Y1, 300.0, 1e-9, 1e-11, 1e-3, 10**7, check_dt=10.0)
    assert np.array_equal(plain["y_end"], checked["y_end"]) and np.array_equal(plain["n_steps"], checked["n_steps"])
    stop = eng.run_many(m, P[:2], Y1, 300.0, 1e-9, 1e-11, 1e-3, 10**7, check_dt=10.0,
                        targets=[(start, np.full(m.n_states, 1e2))])
    assert list(stop["status"]) == ["stopped", "success"] and stop["t_last"][0] == 10.0
    assert np.array_equal(stop["y_end"][1], plain["y_end"][1])


def test_failures_name_the_time(thesis):
    m = thesis[2]
    y0 = {"phi_1": 1.0}
    with pytest.raises(IntegrationError, match=r"failed at t = [0-9.e+-]+ \(step limit reached; engine taylor"):
        simulate(m, None, y0, t_end=100.0, max_steps=50, engine="taylor")
    with pytest.raises(IntegrationError, match="non-finite"):
        simulate(m, {"mu": 1e308}, y0, t_end=10.0, engine="taylor")
    s = simulate(m, None, y0, t_end=100.0, max_steps=50, check=False, engine="taylor")
    assert s.status == "max_steps" and 0 < s.t_fail < 100.0


# --------------------------------------------------------------------------------------------- auto

def test_auto_is_the_default_and_says_what_it_picked(thesis):
    s = simulate(thesis[3], None, PHI_A, t_end=100.0, rtol=1e-9, atol=1e-11, keep_trajectory=False)
    assert DEFAULT == "auto" and s.engine == "auto"
    row = ENGINES["auto"].choice(1e-9)
    assert s.picked["engine"] == row["engine"] and s.picked["rtol"] == pytest.approx(row.get("rtol_run", 1e-9))
    assert s.to_json()["picked"] == s.picked


def test_auto_follows_its_table(thesis, tmp_path):
    """A requested rtol takes the row of the largest tabulated rtol at or below it (the tightest row
    below the table): here Taylor (order 10, factor 2) down to 1e-7, then CyRK Vern8 at rtol / 10."""
    table = tmp_path / "table.json"
    table.write_text(json.dumps({"rows": [
        {"rtol": 1e-4, "engine": "taylor", "order": 10, "step_factor": 2.0},
        {"rtol": 1e-7, "engine": "taylor", "order": 10, "step_factor": 2.0},
        {"rtol": 1e-9, "engine": "cyrk-vern8", "rtol_run": 1e-10}]}))
    auto = AutoEngine(ENGINES, table=str(table))
    assert auto.choice(1e-5)["rtol"] == 1e-7 and auto.choice(1e-7)["rtol"] == 1e-7
    assert auto.choice(5e-8)["engine"] == "cyrk-vern8" and auto.choice(1e-12)["engine"] == "cyrk-vern8"
    assert auto.choice(1.0)["rtol"] == 1e-4
    m = thesis[3]
    out = auto.run(m, m.params(), m.state(PHI_A), 50.0, 1e-8, 1e-10, 1e-3, 10**7, keep_trajectory=False)
    assert out["picked"] == {"engine": "cyrk-vern8", "rtol": pytest.approx(1e-10), "atol": pytest.approx(1e-12)}
    out = auto.run(m, m.params(), m.state(PHI_A), 50.0, 1e-6, 1e-8, 1e-3, 10**7, keep_trajectory=False)
    assert out["picked"]["order"] == 10 and out["picked"]["step_factor"] == 2.0


def test_auto_runs_a_model_without_a_series_on_the_fallback(thesis, tmp_path):
    """A model whose folder has no `<model>_taylor.c` (a model the taylor target skips) is run on CyRK's
    DOP853 at the requested tolerance, and `picked` says why; the same model with its series runs on
    Taylor (negative control).  (The model's folder is swapped for an empty one: loading a copy of a
    generated module would compile its numba functions again.)"""
    from types import SimpleNamespace

    from adbgen.analysis.engines.by_tolerance import FALLBACK

    m = thesis[2]
    bare = SimpleNamespace(name=m.name, folder=tmp_path, module=m.module)
    eng, rtol, atol, record = ENGINES["auto"].picked(1e-8, 1e-10, bare)
    assert eng is ENGINES[FALLBACK] and FALLBACK == "cyrk-dop853" and (rtol, atol) == (1e-8, 1e-10)
    assert record["engine"] == FALLBACK and record["reason"] == f"{m.name} has no Taylor series"
    eng, rtol, atol, record = ENGINES["auto"].picked(1e-8, 1e-10, m)
    assert record["engine"] == "taylor" and "reason" not in record and eng is not ENGINES[FALLBACK]


def test_auto_runs_ensembles_without_measures_on_the_batch_engine(thesis, tmp_path):
    """Sweeps' ensembles (measures=False) go to the SIMD batch engine at the requested tolerance, and the
    ensemble says so; with measures, or for a model without a lanes header, the table's pick as for one run
    (negative controls)."""
    from types import SimpleNamespace

    from adbgen.analysis.engines.by_tolerance import ENSEMBLE
    from adbgen.analysis.simulate import simulate_many

    m = thesis[2]
    auto = ENGINES["auto"]
    eng, rtol, atol, record = auto.picked_many(1e-8, 1e-10, m, measures=False)
    assert eng is ENGINES[ENSEMBLE] and ENSEMBLE == "rk-dop853-batch" and (rtol, atol) == (1e-8, 1e-10)
    assert record["engine"] == ENSEMBLE and "reason" in record
    assert auto.picked_many(1e-8, 1e-10, m, measures=True)[3] == auto.picked(1e-8, 1e-10, m)[3]
    bare = SimpleNamespace(name=m.name, folder=tmp_path, module=m.module)
    assert auto.picked_many(1e-8, 1e-10, bare, measures=False)[3]["engine"] != ENSEMBLE
    Y0 = np.array([m.state({"phi_1": a, "phi_2": -a}) for a in (0.3, 1.0, 2.0, 2.5, 3.0)])
    ens = simulate_many(m, m.params()[None], Y0, t_end=30.0, rtol=1e-8, atol=1e-10, engine="auto", measures=False)
    batch = simulate_many(m, m.params()[None], Y0, t_end=30.0, rtol=1e-8, atol=1e-10, engine=ENSEMBLE, measures=False)
    assert ens.picked["engine"] == ENSEMBLE and np.array_equal(ens.y_end, batch.y_end)
    assert simulate_many(m, m.params()[None], Y0[:2], t_end=30.0, rtol=1e-8, atol=1e-10, engine="auto").picked["engine"] != ENSEMBLE


def test_the_committed_table_is_measured():
    """The auto engine's table comes from `adbgen bench auto` (its rows name the measured candidate and
    its time relative to the fastest that reached the tolerance)."""
    data = ENGINES["auto"].table()
    assert data["source"].startswith("adbgen bench auto") and data["rows"]
    for row in data["rows"]:
        assert row["engine"] in ENGINES and row["time_ratio_to_fastest"] >= 1.0


# ---------------------------------------------------------------------------------------- batch

@pytest.mark.parametrize("norm", ["component", "max"])
def test_the_batch_variant_is_bitwise_the_single_engine(thesis, norm):
    """taylor-batch with libm lane by lane (exact_math; the CPU's lanes per group, two threads) gives every
    trajectory of a mixed batch (other speeds, other starts, fewer than a full group at the end) bit for
    bit what the single engine gives: with measures, with early stop, and with neither (every step over
    the lanes at once)."""
    m = thesis[2]
    rng = np.random.default_rng(4)
    n = 10
    Y0 = np.zeros((n, m.n_states))
    Y0[:, 2:4] = rng.uniform(0.0, 2 * math.pi, (n, 2))
    P = np.repeat(m.params()[None], n, axis=0)
    P[:, 0] = rng.uniform(2.0, 4.0, n)
    one, batch = TaylorEngine(norm=norm), TaylorBatchEngine(exact_math=True, norm=norm)
    start = np.array(m.module.START)
    for kw in ({}, {"measures": False, "check_dt": 10.0, "targets": [(start, np.full(m.n_states, 1e2))]},
               {"measures": False, "check_dt": 10.0}):
        a = one.run_many(m, P, Y0, 200.0, 1e-9, 1e-11, 1e-3, 10**7, threads=1, **kw)
        b = batch.run_many(m, P, Y0, 200.0, 1e-9, 1e-11, 1e-3, 10**7, threads=2, **kw)
        for key in ("y_end", "r_max", "t_dec", "t_last", "n_steps", "target"):
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)
        assert list(a["status"]) == list(b["status"])


def test_a_bad_state_in_a_batch_is_its_own(thesis):
    """A non-finite initial state is refused for its trajectory only; the others run."""
    m = thesis[2]
    Y0 = np.zeros((5, m.n_states))
    Y0[:, 2] = 1.0
    Y0[2, 0] = np.nan
    out = ENGINES["taylor-batch"].run_many(m, np.repeat(m.params()[None], 5, axis=0), Y0, 20.0, 1e-8, 1e-10, 1e-3,
                                           10**7, threads=1)
    assert list(out["status"]) == ["success", "success", "bad_input", "success", "success"]
    assert np.array_equal(out["y_end"][0], out["y_end"][1])


def test_the_inf_norm_step_is_longer_where_the_rotor_is_small(thesis):
    """The inf-norm rule (taylor-batch-inf) weighs every component by the state's largest: on a balancing
    run the rotor's x, y are small and its steps longer than the per-component rule's (fewer steps), the
    final state still within 1e-6 of the per-component run at 1e-10 (measured on thesis_rotating_n2: 973
    steps against 1533 to t = 200, final states 1.0e-8 apart)."""
    m = thesis[2]
    y0 = np.zeros(m.n_states)
    y0[2:4] = (0.3, 2.0)
    comp = ENGINES["taylor"].run_many(m, m.params()[None], y0[None], 200.0, 1e-10, 1e-12, 1e-3, 10**7, threads=1)
    inf = TaylorEngine(norm="max")
    out = inf.run_many(m, m.params()[None], y0[None], 200.0, 1e-10, 1e-12, 1e-3, 10**7, threads=1)
    assert out["n_steps"][0] < 0.9 * comp["n_steps"][0]
    assert np.max(np.abs(out["y_end"][0] - comp["y_end"][0])) < 1e-6
    with pytest.raises(Exception, match="unknown step norm"):
        TaylorBatchEngine(norm="euclid")
    with pytest.raises(Exception, match="unknown step norm"):
        TaylorEngine(norm="euclid")
