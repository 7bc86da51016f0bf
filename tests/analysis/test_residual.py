"""The residual imbalance at rest as a sweep quantity (adbgen/analysis/residual.py, `adbgen sweep --measure
residual`): quantiles and histogram of r at t_end over the starts whose balls all ended stuck; runs still
moving and failed runs counted apart, never in the distribution (negative controls: a planted moving or
failed run with a large r would change the maximum if it were counted)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from adbgen.analysis.loading import AnalysisError, load_model
from adbgen.analysis.residual import AT_REST, MOVING, NOT_RUN, at_rest_codes, distribution, residual_measure
from adbgen.analysis.simulate import simulate
from adbgen.analysis.sweep import SweepSpec, run_sweep
from stick_slip_scene import TORQUE_SCENE

FRICTION = {"eps": 1e-3, "tau0": 0.0, "kappa": 0.0, "mu_r": 0.002, "mu_s": 0.005}


def test_quantiles_and_histogram_of_the_runs_at_rest_only():
    r = np.arange(1.0, 101.0)
    codes = np.full(100, AT_REST)
    d = distribution(r, codes)
    assert d["quantiles"]["50"] == pytest.approx(50.5) and d["quantiles"]["max"] == 100.0
    assert sum(d["histogram"]["counts"]) == 100 and d["histogram"]["edges"][-1] == 100.0
    # planted: two runs with a huge r, one still moving and one failed: counted apart, not in the quantiles
    d2 = distribution(np.append(r, [1e6, 1e7]), np.append(codes, [MOVING, NOT_RUN]))
    assert d2["quantiles"] == d["quantiles"] and d2["histogram"] == d["histogram"]
    assert (d2["at_rest"], d2["not_at_rest"], d2["failed"]) == (100, 1, 1)
    # the negative control: counted as at rest, the same two runs do change the distribution
    assert distribution(np.append(r, [1e6, 1e7]), np.append(codes, [AT_REST, AT_REST]))["quantiles"]["max"] == 1e7


def test_at_rest_codes():
    stuck = np.array([[True, True], [True, False], [True, True]])
    assert at_rest_codes(stuck, [False, False, True]).tolist() == [AT_REST, MOVING, NOT_RUN]


def test_no_run_at_rest_gives_no_quantiles():
    d = distribution([1.0, 2.0], [MOVING, NOT_RUN])
    assert d["quantiles"]["max"] is None and d["histogram"]["counts"] == [] and d["at_rest"] == 0


class _Measured:
    """A stand-in with what residual_measure reads of a Model: its name, measures and own residual measure."""
    name, measures, residual_measure = "planted", ("r", "A"), "A"


def test_the_residual_measure_is_the_one_given_else_the_models_own():
    assert residual_measure(_Measured()) == "A"  # the model's own
    assert residual_measure(_Measured(), "r") == "r"  # an explicit name wins, r included
    with pytest.raises(AnalysisError) as info:
        residual_measure(_Measured(), "B")
    # the one wording both `sweep` and `design` refuse an unknown name with
    assert str(info.value) == "--residual-measure: 'B' is not a measure of planted; its measures: r, A"


def test_a_sweep_refuses_an_unknown_residual_measure_in_one_line(stick_model, tmp_path, capsys):
    from adbgen.cli import main

    code = main(["sweep", str(stick_model.folder), "--grid", "phi_1=0:1:2", "--measure", "residual",
                 "--residual-measure", "B", "--t-end", "1", "--out", str(tmp_path / "out")])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code != 0 and out == "" and len(lines) == 1, err
    assert f"--residual-measure: 'B' is not a measure of {stick_model.name}; its measures: " in lines[0]
    assert not (tmp_path / "out").exists()  # refused before any computing


@pytest.fixture(scope="module")
def stick_model(tmp_path_factory):
    path = tmp_path_factory.mktemp("residual") / "braked.toml"
    path.write_text(TORQUE_SCENE)  # test_hybrid_engine.py's scene: one cached model
    return load_model(scene=path)


def test_a_residual_sweep_stores_the_distribution_of_its_runs(stick_model, tmp_path):
    m = stick_model
    spec = SweepSpec(model=str(m.folder), grid=["phi_1=0:2*pi:3", "phi_2=0.5:3:2"], measure="residual",
                     set=[f"{k}={v}" for k, v in FRICTION.items()], y0=["psi_dot=100"], t_end=10.0)
    summary = run_sweep(spec, tmp_path / "sw", workers=1, progress=False)
    import xarray as xr

    ds = xr.open_zarr(summary["store"], consolidated=False)
    assert json.loads(ds.attrs["residual_distribution"]) == summary["residual"]
    # each point is the run simulate gives on its own (the engine chosen by the model: hybrid-dop853)
    runs = []
    for phi1 in ds["phi_1"].values:
        for phi2 in ds["phi_2"].values:
            s = simulate(m, FRICTION, {"phi_1": phi1, "phi_2": phi2, "psi_dot": 100.0}, t_end=10.0,
                         keep_trajectory=False)
            runs.append((s.r_end, AT_REST if all(s.stuck) else MOVING))
            assert float(ds["residual"].sel(phi_1=phi1, phi_2=phi2)) == s.r_end
    r, codes = map(np.array, zip(*runs))
    assert summary["residual"] == distribution(r, codes)
    assert summary["residual"]["at_rest"] + summary["residual"]["not_at_rest"] == 6
    assert any(p.endswith("residual.png") for p in summary["figures"])


def test_residual_needs_a_stick_slip_model(tmp_path):
    spec = SweepSpec(model="thesis_rotating_n2", grid=["phi_1=0:1:2"], measure="residual", t_end=1.0)
    with pytest.raises(AnalysisError, match="no stick/slip modes"):
        run_sweep(spec, tmp_path / "sw", workers=1, progress=False)


def test_residual_refuses_the_tolerance_check(stick_model, tmp_path):
    spec = SweepSpec(model=str(stick_model.folder), grid=["phi_1=0:1:2"], measure="residual", t_end=1.0,
                     check_tolerance=True)
    with pytest.raises(AnalysisError, match="no second engine"):
        run_sweep(spec, tmp_path / "sw", workers=1, progress=False)
