"""The rk and ensemble benchmarks' machinery on tiny problems (no timed assertions beyond sanity)."""

from __future__ import annotations

from toolchain import require_module

from benchmarks.ensemble import bench_ensemble
from benchmarks.rk import measure


def test_bench_rk_row():
    """One row: both engines' runs counted alike (same method: rhs counts within 2 %), the floor ratios
    positive and the integration alone no dearer than with r_max/t_dec."""
    [row] = measure("thesis_rotating_n2", rtols=(1e-6,), repeats=1)
    assert row["ns_per_rhs"] > 0 and row["ns_per_rhs_fixed_states"] > 0 and row["states_visited"] > 100
    assert abs(row["rk"]["n_rhs"] - row["cyrk"]["n_rhs"]) <= 0.02 * row["cyrk"]["n_rhs"]
    for key in ("rk", "rk_simulate", "cyrk", "cyrk_simulate"):
        assert row[key]["floor_ratio"] > 0.3 and row[key]["n_steps"] > 100
        assert row[key]["floor_ratio_fixed_states"] > 0.3


def test_bench_ensemble_tiny_map():
    """A 2 x 4 map to t = 100: every engine's final states labelled alike, heyoka's included (8 points, not 16:
    the labelling of each run's end states is most of this test's time, and 8 still fill a batch of 8)."""
    require_module("heyoka", "the peers extra")
    r = bench_ensemble(workers=1, grid=["phi_1=0:pi:2", "phi_2=0:2*pi*3/4:4"], t_end=100.0, sweeps=False,
                       progress=None)
    runs = r["runs"]
    ladder = {f"ensemble {e} rtol {r:g}" for e in ("rk-dop853-batch", "taylor-batch-inf") for r in (1e-9, 1e-10)}
    from benchmarks.ensemble import heyoka_runs

    theirs = {f"ensemble {name}" for name, _, _ in heyoka_runs()} - {"ensemble heyoka"}
    assert len(theirs) == 5  # heyoka at two widths (4 and 8), three tolerances each, one of them "heyoka"
    ours = {f"ensemble {e}" for e in ("cyrk-dop853", "rk-dop853", "rk-dop853-batch", "taylor", "taylor-batch",
                                      "taylor-batch-inf", "auto", "heyoka")}
    assert set(runs) == ours | ladder | theirs
    assert [lv["heyoka_run"] for lv in r["at_equal_labels"]][:3] == ["heyoka", "heyoka tol 1e-09", "heyoka tol 1e-10"]
    assert {runs[f"ensemble {name}"]["batch"] for name, _, _ in heyoka_runs()} == {4, 8}
    # every run is off at 0 points here, so each level is reached by both sides (which run is fastest: timing)
    assert all(lv["heyoka_fastest"].startswith("heyoka") and lv["ours_fastest"] for lv in r["at_equal_labels"])
    for key in ladder:  # the tighter runs: their tolerance recorded, other steps than at the sweep's (fewer, for
        # taylor-batch-inf at 1e-9: heyoka's rule raises the order from 11 to 12)
        assert runs[key]["rtol"] == float(key.rsplit(" ", 1)[1])
        assert runs[key]["steps"] != runs[key.rsplit(" rtol", 1)[0]]["steps"]
    assert runs["ensemble auto"]["picked"]["engine"] == "rk-dop853-batch"  # the default's pick for ensembles
    for row in runs.values():
        assert row["trajectories"] == 8 and row["labels_differing_from_today"] == 0
        assert sum(row["labels"].values()) == 8
    scalar, batch = runs["ensemble rk-dop853"]["rhs_evaluations"], runs["ensemble rk-dop853-batch"]["rhs_evaluations"]
    assert abs(batch / scalar - 1) < 0.02  # the same steps but for libmvec's last bits
    assert [t["target"] for t in r["targets"]] == ["ahead of heyoka's ensemble", "1.5x heyoka's ensemble"]
    # labels judged against the converged maps, on the map and on the map shifted by half a cell
    assert r["reference"]["shifted_grid"] == ["phi_1=1.5707963267948966:4.71238898038469:2",
                                              "phi_2=0.7853981633974483:5.497787143782138:4"]
    assert r["reference"]["unresolved"]["map"] == 0
    for e in ("rk-dop853-batch", "taylor-batch-inf", "heyoka", *(k.removeprefix("ensemble ") for k in ladder | theirs)):
        assert runs[f"ensemble {e}"]["label_errors"] == {"map": 0, "shifted_map": 0, "total": 0}


def test_heyoka_runs_at_both_widths_and_the_median_of_repeats():
    from benchmarks.ensemble import heyoka_runs, median_run

    names = [n for n, _, _ in heyoka_runs(recommended=8)]
    assert names[:3] == ["heyoka", "heyoka tol 1e-09", "heyoka tol 1e-10"] and "heyoka batch 4" in names
    assert {w for _, _, w in heyoka_runs(recommended=4)} == {4, 8}
    rows = [{"cpu_s": c, "wall_s": c} for c in (5.0, 1.0, 9.0, 3.0, 4.0)]
    kept = median_run(rows)
    assert kept["cpu_s"] == 4.0 and kept["repeats_cpu_s"] == [5.0, 1.0, 9.0, 3.0, 4.0]
    assert median_run(rows[:1])["cpu_s"] == 5.0  # one run: itself (negative control: not the fastest of five)


def test_at_equal_labels_is_the_fastest_run_reaching_heyokas_label_error():
    """The ensemble target's rule: a faster run off the converged maps at more points than heyoka does not
    count; among those at or under, the fastest; none under, None."""
    from benchmarks.ensemble import at_equal_labels

    runs = {"a": (17, 1365.0), "a rtol 1e-09": (12, 1200.0), "a rtol 1e-10": (9, 1050.0), "b": (21, 885.0)}
    assert at_equal_labels(runs, 15) == "a rtol 1e-09"
    assert at_equal_labels(runs, 17) == "a"
    assert at_equal_labels(runs, 9) == "a rtol 1e-10"
    assert at_equal_labels(runs, 8) is None


def test_the_inf_norm_rule_takes_heyokas_steps():
    """taylor-batch-inf (heyoka's step rule, order and factor 1), with heyoka's one tolerance (rtol = atol =
    1e-8), takes heyoka's steps on the hand-written equations, trajectory by trajectory (measured: 1027 to
    1253 steps to t = 200, all equal); the per-component rule with atol 1e-10 takes more (negative control)."""
    import numpy as np

    from adbgen.analysis.engines.taylor import TaylorBatchEngine, heyoka_order
    from adbgen.analysis.simulate import simulate_many
    from benchmarks import ensemble as E

    require_module("heyoka", "the peers extra")
    model, P, Y0 = E.points()
    Y0 = Y0[::1250][:8]
    P = np.repeat(P[:1], len(Y0), axis=0)
    row = [(0.0, heyoka_order(1e-8), 1.0)]
    ta, _ = E.heyoka_integrator(model, 1e-8, len(Y0))
    ta.set_time(0.0)
    ta.state[:] = Y0.T
    ta.pars[:] = P.T
    ta.propagate_until(200.0)
    theirs = [int(o[3]) for o in ta.propagate_res]
    ours = simulate_many(model, P, Y0, t_end=200.0, rtol=1e-8, atol=1e-8, threads=1, measures=False,
                         engine="taylor-batch-inf")
    assert list(ours.n_steps) == theirs
    component = simulate_many(model, P, Y0, t_end=200.0, rtol=1e-8, atol=1e-10, threads=1, measures=False,
                              engine=TaylorBatchEngine("component", table=row))
    assert np.all(np.asarray(component.n_steps) > 1.3 * np.asarray(theirs))
