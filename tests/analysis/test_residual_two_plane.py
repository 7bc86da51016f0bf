"""`adbgen sweep --measure residual` on a two-plane stick model (issue 37, item 3; analysis/residual.py's
`residual_at_end`, the sweep's `residual_measure`): the residual imbalance of two planes is the model's own
measure A at t_end (two_plane.description.vibration: the mean of the rotor's amplitudes |q_1 + q_2|,
|q_1 - q_2| at the two points one unit from the midspan, paper (2)), zero exactly where the paper's balanced
condition holds (the rotor at rest, X = Y = phi_X = phi_Y = 0: state B of (9), section 3.2.2).  r = hypot(X, Y)
of the centre alone misses a couple (the negative control below).  The model is the scene of
test_stick_phase.py (2 + 2 balls, one cached model), its parameters set here: a free rotor (tau_0 = 0) at
Omega = 3 (above both critical speeds), J_p = 1.
"""

from __future__ import annotations

import numpy as np
import pytest

from adbgen.analysis.loading import AnalysisError
from adbgen.analysis.residual import AT_REST, MOVING, distribution
from adbgen.analysis.simulate import simulate
from adbgen.analysis.sweep import SweepSpec, run_sweep
from adbgen.families.two_plane.science.stick_slip_energy import stick_model

OMEGA = 3.0
ROTOR = {"J_p": 1.0, "tau_0": 0.0, "c_bt": 1e-3, "c_bb": 1e-3}
SPIN = [f"theta_{k}_dot={OMEGA}" for k in range(5)]
STUCK = {"mu_r": 0.2, "mu_s": 0.5}  # far above any force the vibration makes: the balls stay where they start


@pytest.fixture(scope="module")
def model():
    return stick_model()


def _sweep(model, tmp_path, grid, set_, y0=(), tie=(), t_end=1000.0, measure="A", out=None):
    spec = SweepSpec(model=str(model.folder), grid=list(grid), measure="residual", y0=[*SPIN, *y0], tie=list(tie),
                     set=[f"{k}={v}" for k, v in set_.items()], t_end=t_end, residual_measure=measure)
    summary = run_sweep(spec, tmp_path / (out or f"sw_{measure}"), workers=1, progress=False, figures=False)
    import xarray as xr

    ds = xr.open_zarr(summary["store"], consolidated=False)
    return summary, ds


def test_stuck_balls_leave_their_imbalance_and_balanced_ones_none(model, tmp_path):
    # no rotor imbalance; top race's balls opposite (balanced), bottom's third ball at pi, the fourth at 0 (all
    # balanced: residual ~ 0) or at pi (both bottom balls together: 2 m R of imbalance left, stuck)
    set_ = {**ROTOR, **STUCK, "epsilon": 0.0, "chi": 0.0}
    summary, ds = _sweep(model, tmp_path, ["theta_4=0:pi:2"], set_, y0=["theta_1=0", "theta_2=pi", "theta_3=pi"])
    assert (ds["at_rest"].values == AT_REST).all() and summary["residual"]["at_rest"] == 2
    balanced, off = ds["residual"].values
    assert balanced < 1e-9
    assert off > 1e-4  # planted off-balance start: above a threshold the balanced one is far below
    assert ds["residual"].attrs["measure"] == "A"


def test_a_couple_is_seen_by_a_and_missed_by_r(model, tmp_path):
    # the balls make a pure couple (top pair together at theta, bottom pair together at theta + pi, z = +-1)
    set_ = {**ROTOR, **STUCK, "epsilon": 0.0, "chi": 0.0}
    tie = ["theta_2=theta_1+0", "theta_3=theta_1+pi", "theta_4=theta_1+pi"]
    a, ds_a = _sweep(model, tmp_path, ["theta_1=0:1:2"], set_, tie=tie)
    r, ds_r = _sweep(model, tmp_path, ["theta_1=0:1:2"], set_, tie=tie, measure="r")
    assert a["residual"]["at_rest"] == r["residual"]["at_rest"] == 2
    assert a["residual"]["quantiles"]["max"] > 1e-4
    assert r["residual"]["quantiles"]["max"] < 1e-6  # the centre does not move: r alone would call it balanced


def test_a_sweep_of_starts_stores_the_distribution_of_a_at_rest(model, tmp_path):
    set_ = {**ROTOR, "epsilon": 5e-4, "chi": 1e-4, "mu_r": 2e-3, "mu_s": 4e-3}
    tie = ["theta_2=theta_1+2", "theta_4=theta_3+2"]
    summary, ds = _sweep(model, tmp_path, ["theta_1=0:3:2", "theta_3=0:5:2"], set_, tie=tie, t_end=3000.0)
    got = summary["residual"]
    assert got["at_rest"] + got["not_at_rest"] + got["failed"] == 4 and got["at_rest"] >= 1
    runs = []
    for t1 in ds["theta_1"].values:
        for t3 in ds["theta_3"].values:
            y0 = {"theta_1": t1, "theta_2": t1 + 2, "theta_3": t3, "theta_4": t3 + 2,
                  **{f"theta_{k}_dot": OMEGA for k in range(5)}}
            s = simulate(model, set_, y0, t_end=3000.0, keep_trajectory=False)
            a = model.measure("A", 3000.0, s.y_end, model.params(set_))
            runs.append((a, AT_REST if all(s.stuck) else MOVING))
            assert float(ds["residual"].sel(theta_1=t1, theta_3=t3)) == pytest.approx(a, rel=1e-12)
    assert got == distribution(*map(np.array, zip(*runs)))


def test_without_friction_no_run_is_at_rest_and_nothing_is_drawn(model, tmp_path):
    # negative control: mu = 0, the balls never stick, so every run is counted apart (not at rest), no quantile
    set_ = {**ROTOR, "epsilon": 5e-4, "chi": 1e-4, "mu_r": 0.0, "mu_s": 0.0}
    summary, _ = _sweep(model, tmp_path, ["theta_1=0:3:2"], set_, y0=["theta_2=2", "theta_3=1", "theta_4=3"],
                        t_end=500.0)
    assert summary["residual"]["not_at_rest"] == 2 and summary["residual"]["at_rest"] == 0
    assert summary["residual"]["quantiles"]["max"] is None


def test_mirrored_starts_read_the_measure_at_their_own_end_state(model, tmp_path):
    # theta_1, theta_2 over the same values: the sweep integrates one start of each ball-swapped pair and swaps
    # its end state for the other.  slip_rate_1 is not invariant under the swap (it is ball 1's), so a copied
    # value would be ball 2's rate: with the shortcut the store must equal the sweep without it (balls still
    # slipping at t_end = 50, values stored though not at rest)
    set_ = {**ROTOR, "epsilon": 5e-4, "chi": 1e-4, "mu_r": 2e-3, "mu_s": 4e-3}
    grid = ["theta_1=0:2:3", "theta_2=0:2:3"]
    y0 = ["theta_3=0.5", "theta_4=2.5"]
    spec = dict(model=str(model.folder), grid=grid, measure="residual", y0=[*SPIN, *y0],
                set=[f"{k}={v}" for k, v in set_.items()], t_end=50.0, residual_measure="slip_rate_1")
    on = run_sweep(SweepSpec(**spec), tmp_path / "on", workers=1, progress=False, figures=False)
    off = run_sweep(SweepSpec(**spec, symmetry=False), tmp_path / "off", workers=1, progress=False, figures=False)
    import xarray as xr

    a = xr.open_zarr(on["store"], consolidated=False)["residual"].values
    b = xr.open_zarr(off["store"], consolidated=False)["residual"].values
    assert on["integrated"] < off["integrated"] == 9  # the shortcut was taken
    scale = np.abs(b).max()
    np.testing.assert_allclose(a, b, rtol=1e-4, atol=1e-6 * scale)  # equivariant up to rounding (events)
    assert np.abs(b - b.T).max() > 1e-3 * scale  # the planted copy (the partner's value) would be wrong


def test_without_residual_measure_the_sweep_reads_the_models_own(model, tmp_path):
    # the model names A its residual imbalance (RESIDUAL_MEASURE, declared by its family): no --residual-measure
    # gives the store of an explicit A, bit for bit; an explicit r still wins (the couple of the test above: A sees
    # it, r does not, so the default cannot be r)
    set_ = {**ROTOR, **STUCK, "epsilon": 0.0, "chi": 0.0}
    tie = ["theta_2=theta_1+0", "theta_3=theta_1+pi", "theta_4=theta_1+pi"]
    assert model.residual_measure == "A"
    own, ds_own = _sweep(model, tmp_path / "own", ["theta_1=0:1:2"], set_, tie=tie, measure=None)
    a, ds_a = _sweep(model, tmp_path / "a", ["theta_1=0:1:2"], set_, tie=tie, measure="A")
    r, ds_r = _sweep(model, tmp_path / "r", ["theta_1=0:1:2"], set_, tie=tie, measure="r")
    assert ds_own["residual"].attrs["measure"] == "A" and ds_r["residual"].attrs["measure"] == "r"
    np.testing.assert_array_equal(ds_own["residual"].values, ds_a["residual"].values)
    assert own["residual"]["quantiles"]["max"] > 1e-4 > 1e-6 > r["residual"]["quantiles"]["max"]


def test_a_store_resumes_with_the_measure_it_was_written_with(model, tmp_path):
    # a store written by the default (the model's A) resumes with the same settings, explicit or not; asked for r
    # it is refused in one line (it holds A)
    set_ = {**ROTOR, **STUCK, "epsilon": 0.0, "chi": 0.0}
    _sweep(model, tmp_path, ["theta_1=0:1:2"], set_, y0=["theta_2=1", "theta_3=2", "theta_4=3"], measure=None)
    again, _ = _sweep(model, tmp_path, ["theta_1=0:1:2"], set_, y0=["theta_2=1", "theta_3=2", "theta_4=3"],
                      measure=None, out="sw_None")
    assert again["reused"] == 2 and again["computed"] == 0
    with pytest.raises(AnalysisError, match="other settings \\(residual_measure") as info:
        _sweep(model, tmp_path, ["theta_1=0:1:2"], set_, y0=["theta_2=1", "theta_3=2", "theta_4=3"], measure="r",
               out="sw_None")
    assert "\n" not in str(info.value)


def test_an_unknown_residual_measure_is_refused(model, tmp_path):
    with pytest.raises(AnalysisError, match="^--residual-measure: 'B' is not a measure of ") as info:
        _sweep(model, tmp_path, ["theta_1=0:1:2"], {**ROTOR, **STUCK}, measure="B")
    assert "\n" not in str(info.value)
