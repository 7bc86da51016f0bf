"""A family registered from a test gets `simulate`, `stability` and `sweep` through its self-description
alone (issue 19 item 2): the toy pendulum on a sprung cart of test_toy_family_and_target.py, generated
into a temporary folder, runs through the ordinary commands; the analysis layer reads its roles, angles,
amplitude, symmetries and closed-form steady states ("hanging", "inverted") from the generated module,
and nothing in the package names it.  The negative control changes what the module says about itself
and the results follow."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
from toolchain import require_tool

from adbgen import families
from adbgen.analysis.loading import load_model
from adbgen.cli import main

sys.path.insert(0, str(Path(__file__).parent))

from test_toy_family_and_target import Pendulum  # noqa: E402


@pytest.fixture(scope="module")
def toy(tmp_path_factory):
    """The toy family's model, generated (numba and C: the compiled engines build the C) into a folder."""
    require_tool(shutil.which("gcc") is not None, "gcc")
    families.register(Pendulum())
    try:
        out = tmp_path_factory.mktemp("toy")
        assert main(["regenerate", "--family", "toy-pendulum", "--out", str(out), "--targets", "numba", "c",
                     "--quiet"]) == 0
    finally:
        families.unregister("toy-pendulum")
    return out / "toy_pendulum"


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_its_self_description_is_what_the_analysis_reads(toy):
    m = load_model(str(toy))
    assert m.family == "toy-pendulum" and m.kind == "pendulum"
    assert m.roles[:3] == ("translation", "translation", "ball_angle") and m.angles == ("phi",)
    assert m.amplitude == ("X", "Y") and m.steady_states == ("hanging", "inverted")


def test_simulate(toy, capsys, tmp_path):
    code, out, err = run(capsys, "simulate", toy, "--y0", "phi=1.0", "--t-end", "50", "--out", tmp_path, "--json")
    assert (code, err) == (0, "")
    sim = json.loads(out)
    assert sim["status"] == "success" and sim["model"] == "toy_pendulum"
    traj = np.load(tmp_path / "trajectory.npz")
    names = list(traj["state_names"])
    r = np.hypot(traj["y"][names.index("X")], traj["y"][names.index("Y")])
    # r is the amplitude the module names (the cart's X, Y), r_max located on the continuous solution
    assert 0.0 < r.max() <= sim["r_max"] <= 1.01 * r.max()
    assert sim["y_end"]["Y"] == 0.0  # the bob swings in the X-z plane: Y is never excited


def test_simulate_follows_the_declared_amplitude(toy, capsys, monkeypatch):
    """Negative control: declared otherwise (the cart's X and the pendulum's angle), r follows."""
    code, out, _ = run(capsys, "simulate", toy, "--y0", "phi=1.0", "--t-end", "50", "--json")
    base = json.loads(out)["r_max"]
    monkeypatch.setattr(load_model(str(toy)).module, "AMPLITUDE", ("X", "phi"))
    code, out, _ = run(capsys, "simulate", toy, "--y0", "phi=1.0", "--t-end", "50", "--json")
    assert code == 0 and json.loads(out)["r_max"] >= 1.0 > base  # phi starts at 1; the cart swings less


def test_stability_of_its_closed_form_states(toy, capsys):
    code, out, err = run(capsys, "stability", toy, "--json")
    hanging = json.loads(out)
    assert (code, err) == (0, "") and hanging["state_label"] == "start" and hanging["classification"] == "stable"
    code, out, err = run(capsys, "stability", toy, "--state", "inverted", "--json")
    inverted = json.loads(out)
    assert code == 0 and inverted["state"]["phi"] == pytest.approx(np.pi) and inverted["n_unstable"] == 1
    # a label it does not have: one line naming the ones it has
    code, out, err = run(capsys, "stability", toy, "--state", "2+")
    assert code == 2 and "labels: start, hanging, inverted" in err


def test_sweeps(toy, capsys, tmp_path):
    import xarray as xr

    code, out, err = run(capsys, "sweep", toy, "--grid", "phi=0.2:pi/2:3", "--measure", "r_max", "--t-end", "20",
                         "--out", tmp_path / "r", "--workers", "1", "--json")
    assert code == 0, err
    r_max = xr.open_zarr(tmp_path / "r" / "sweep.zarr", consolidated=False)["r_max"].values
    assert np.all(np.diff(r_max) > 0)  # a larger swing shakes the cart more
    code, out, err = run(capsys, "sweep", toy, "--grid", "phi=0.2:pi/2:3", "--measure", "attractor", "--t-end", "200",
                         "--out", tmp_path / "a", "--workers", "1", "--json")
    assert code == 0, err
    ds = xr.open_zarr(tmp_path / "a" / "sweep.zarr", consolidated=False)
    names = json.loads(ds.attrs["labels"])
    assert [names[c] for c in ds["attractor"].values] == ["hanging at rest"] * 3  # the toy's own name (its description)
    assert ds["phi"].attrs["angle"] and ds["phi"].attrs["kind"] == "state"
    code, out, err = run(capsys, "sweep", toy, "--grid", "k_spring=5:20:3", "--measure", "stability",
                         "--out", tmp_path / "s", "--workers", "1", "--json")
    assert code == 0, err
    unstable = xr.open_zarr(tmp_path / "s" / "sweep.zarr", consolidated=False)["stability"].values
    assert list(unstable) == [0, 0, 0]
