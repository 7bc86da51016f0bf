"""The thesis' (Omega, mu) map certified (issue 34 item 3): the n = 2 window at mu = 0.05 (Omega 1.0297-1.0936
by an independent scan) lies between two grid columns (step 0.1); the certified map finds it on the rows
mu = 0.049 and 0.052, the grid alone (refine off, the negative control) does not."""

from __future__ import annotations

import json

import pytest

from adbgen.analysis.sweep import SweepSpec, run_sweep


@pytest.mark.parametrize("refine", [True, False])
def test_n2_window_at_mu_005(tmp_path, refine):
    import xarray as xr

    spec = SweepSpec(model="thesis_rotating_n2", grid=["Omega=0.2:4:39", "mu=0.049:0.052:2"], measure="stability",
                     refine=refine)
    summary = run_sweep(spec, tmp_path / "map", progress=False, figures=refine, workers=1)
    ds = xr.open_zarr(tmp_path / "map" / "sweep.zarr", consolidated=False)
    stable_cols = ds["Omega"].values[(ds["stability"].values == 0).any(axis=1)]
    assert not ((stable_cols > 1.0) & (stable_cols < 1.1)).any()  # no grid point inside the window
    if not refine:
        assert "windows" not in ds.attrs and "resolution" not in summary
        return
    assert summary["resolution"]["Omega"] == pytest.approx(0.1 / 8)
    rows = json.loads(ds.attrs["windows"])["rows"]
    near = [[w for w in r["stable"] if w[1] < 1.5] for r in rows]
    assert near[0] == [pytest.approx([1.0314444, 1.0919187], abs=1e-6)]
    assert near[1] == [pytest.approx([1.0262732, 1.0971374], abs=1e-6)]
    assert (ds["failure"].values == 0).all()
