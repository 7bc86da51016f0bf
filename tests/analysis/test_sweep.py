"""adbgen sweep: equals the points run one by one, shortcuts give the full integration's labels,
resumes after SIGKILL, runs on an external Dask scheduler, refuses bad grids and foreign stores."""

from __future__ import annotations

import json
import math
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import figure_checks as fc
from adbgen.analysis import attractors
from adbgen.analysis.loading import load_model
from adbgen.analysis.simulate import simulate
from adbgen.analysis.sweep import SweepSpec, prepare, run_sweep

import xarray as xr  # noqa: E402 - declared dependencies: a missing one is an error, not a skip
import zarr  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
GRID8 = ["phi_1=0:2*pi*7/8:8", "phi_2=0:2*pi*7/8:8"]
DAMPED = ["zeta=0.1", "beta=0.1"]  # fast transients (thesis Fig. 5.15): short tests, early stops happen


def _open(out):
    return xr.open_zarr(Path(out) / "sweep.zarr", consolidated=False).load()


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _cli(*args, timeout=300):
    return subprocess.run([sys.executable, "-m", "adbgen.cli", *args], capture_output=True, text=True, env=_env(),
                          timeout=timeout, cwd=REPO)


def test_attractor_sweep_equals_points_one_by_one(tmp_path, saved_figures):
    spec = SweepSpec(model="thesis_rotating_n2", grid=GRID8, measure="attractor", set=DAMPED, t_end=300.0, chunk=16)
    summary = run_sweep(spec, tmp_path, progress=False)
    assert summary["points"] == 64 and summary["computed"] == 64 and summary["reused"] == 0
    assert {Path(f).name for f in summary["figures"]} == {"attractor.png", "attractor.pdf"}
    ds = _open(tmp_path)
    assert ds["attractor"].dims == ("phi_1", "phi_2")
    assert ds.attrs["model"] == "thesis_rotating_n2" and ds.attrs["SOURCE_HASH"]
    names = json.loads(ds.attrs["labels"])
    model, grid = prepare(spec)
    p = grid.base_params
    clf = attractors.classifier(model, p)
    for i, a in enumerate(ds.phi_1.values):
        for j, b in enumerate(ds.phi_2.values):
            sim = simulate(model, p, model.state({"phi_1": a, "phi_2": b}), t_end=300.0, keep_trajectory=False,
                           check=False)
            alone = clf.label(sim.status, sim.y_end, -1, t=300.0, threshold=spec.threshold)
            assert names[int(ds.attractor.values[i, j])] == alone, (a, b)
    got = {names[c] for c in np.unique(ds.attractor.values)}
    assert "balanced 1" in got and "coincident 2-" in got  # the diagonal: balls together stay together
    # the figure draws the store: one cell per grid point coloured by its attractor, each in the legend with
    # its count, the angles on the axes
    codes = ds.attractor.values
    present = sorted(int(c) for c in np.unique(codes))
    [ax] = fc.figure(saved_figures, "attractor.png").axes
    [mesh] = ax.collections
    index = np.asarray(mesh.get_array()).reshape(codes.T.shape)
    np.testing.assert_array_equal(np.array(present)[index - 1], codes.T)
    fc.assert_legend(ax, [f"{names[c]} ({int((codes == c).sum())})" for c in present])
    fc.assert_labels(ax, xlabel="$\\phi_{1}(0)$", ylabel="$\\phi_{2}(0)$")
    fc.assert_title(ax, "thesis_rotating_n2: basins of attraction")


def test_r_max_sweep_equals_points_one_by_one(tmp_path):
    spec = SweepSpec(model="thesis_rotating_n2", grid=["phi_1=0:3*pi/2:4", "Omega=2:4:3"], measure="r_max",
                     t_end=100.0, chunk=4)
    run_sweep(spec, tmp_path, progress=False, figures=False)
    ds = _open(tmp_path)
    model = load_model("thesis_rotating_n2")
    for i, a in enumerate(ds.phi_1.values):
        for j, om in enumerate(ds.Omega.values):
            sim = simulate(model, model.params({"Omega": om}), model.state({"phi_1": a}), t_end=100.0,
                           keep_trajectory=False)
            assert ds.r_max.values[i, j] == pytest.approx(sim.r_max, rel=1e-12)
            np.testing.assert_allclose(ds.y_end.values[i, j], sim.y_end, rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("early_stop, symmetry, region", [(True, False, "lyapunov"), (False, True, "lyapunov"),
                                                            (True, True, "lyapunov"), (True, False, "contraction")])
def test_shortcuts_give_the_full_integrations_labels(tmp_path, early_stop, symmetry, region):
    def labels(out, **kw):
        spec = SweepSpec(model="thesis_rotating_n2", grid=GRID8, measure="attractor", set=DAMPED, t_end=400.0,
                         chunk=16, stop_region=region, **kw)
        s = run_sweep(spec, out, progress=False, figures=False)
        return _open(out), s

    full, s_full = labels(tmp_path / "full", early_stop=False, symmetry=False)
    fast, s_fast = labels(tmp_path / "fast", early_stop=early_stop, symmetry=symmetry)
    np.testing.assert_array_equal(fast.attractor.values, full.attractor.values)
    if symmetry:
        assert s_fast["integrated"] == 36 < s_full["integrated"] == 64  # 8 on the diagonal + 28 pairs
    if early_stop:
        stopped = fast.t_last.values < 400.0
        assert stopped.sum() > 20  # the shortcut is taken ...
        same = ~stopped  # ... and where it is not, the final states are bit for bit the full run's
        np.testing.assert_array_equal(fast.y_end.values[same], full.y_end.values[same])
    else:
        # the mirrored final states are the integrated ones to the tolerance (not bit for bit: the step
        # size control sums its error norm over the components in state order)
        np.testing.assert_allclose(fast.y_end.values, full.y_end.values, rtol=1e-6, atol=1e-8)


def test_an_oversized_stop_region_is_caught_by_the_label_comparison(tmp_path, monkeypatch):
    """Negative control: the comparison above fails when a stop region is not a basin region (here the
    Lyapunov region blown up 100 times across, so it swallows the diagonal's coincident runs)."""
    real = attractors.stop_region

    def oversized(*args, **kw):
        r = real(*args, **kw)
        if r is not None:
            r.c *= 1e4
            r.rho2 *= 1e4
        return r

    spec = dict(model="thesis_rotating_n2", grid=GRID8, measure="attractor", set=DAMPED, t_end=400.0, chunk=16,
                symmetry=False)
    run_sweep(SweepSpec(**spec, early_stop=False), tmp_path / "full", progress=False, figures=False)
    attractors._classifier_cached.cache_clear()
    monkeypatch.setattr(attractors, "stop_region", oversized)
    try:
        run_sweep(SweepSpec(**spec), tmp_path / "fast", progress=False, figures=False)
    finally:
        attractors._classifier_cached.cache_clear()
    full, fast = _open(tmp_path / "full"), _open(tmp_path / "fast")
    assert np.sum(fast.attractor.values != full.attractor.values) > 0


def test_symmetry_integrates_the_mirror_where_the_label_is_not_certain(tmp_path):
    """At t_end = 5 few trajectories have reached a basin region: the other labels are not certain, so
    both points of those pairs are integrated (near a basin boundary the full integration's own map need not be
    symmetric: its equivariance holds to rounding only) and the labels are the full run's."""
    spec = dict(model="thesis_rotating_n2", grid=GRID8, measure="attractor", set=DAMPED, t_end=5.0, chunk=16)
    s_full = run_sweep(SweepSpec(**spec, early_stop=False, symmetry=False), tmp_path / "full", progress=False,
                       figures=False)
    s_sym = run_sweep(SweepSpec(**spec, early_stop=True, symmetry=True), tmp_path / "sym", progress=False,
                      figures=False)
    full = _open(tmp_path / "full")
    model, grid = prepare(SweepSpec(**spec))
    clf = attractors.classifier(model, grid.base_params)
    inside = clf.inside(full.y_end.values.reshape(-1, model.n_states)).reshape(8, 8) >= 0
    certain_pairs = int(np.sum(np.triu(inside, 1)))  # canonical = the smaller flat index: i < j
    assert certain_pairs < 10  # few have reached a region by t = 5 ...
    # ... so nearly every pair is integrated twice (the 8 diagonal points once)
    assert s_sym["integrated"] == s_full["integrated"] - certain_pairs == 64 - certain_pairs
    np.testing.assert_array_equal(_open(tmp_path / "sym").attractor.values, full.attractor.values)


def test_stop_region_is_forward_invariant_and_labels_balanced():
    model = load_model("thesis_rotating_n2")
    p = model.params()
    clf = attractors.classifier(model, p)
    region = next(r for r in clf.regions if r.label == "balanced 1")
    # a point on the region's boundary converges: V decreases along its trajectory
    rng = np.random.default_rng(5)
    e = rng.standard_normal(model.n_states)
    for _ in range(60):  # scale e onto the boundary V = c (bisection on the scale)
        scale = math.sqrt(region.c / (e @ region.P @ e))
        if region.value(model, region.centre + e * scale)[1][0] <= region.c:
            break
        e *= 0.9
    lo, hi = 0.0, scale * 1.5
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        q, v = region.value(model, region.centre + mid * e)
        lo, hi = (mid, hi) if (q[0] <= region.rho2 and v[0] <= region.c) else (lo, mid)
    sim = simulate(model, p, region.centre + 0.999 * lo * e, t_end=200.0)
    _, V = region.value(model, sim.y.T)
    assert V.max() <= region.c * 1.0000001 and V[-1] < 0.5 * V[0]
    # the unstable coincident state 2- (one unstable eigenvalue at (5.1)) gets no region
    assert {r.label for r in clf.regions} == {"balanced 1"}


def test_resume_after_sigkill_equals_uninterrupted_run(tmp_path):
    args = ["sweep", "thesis_rotating_n2", "--grid", "phi_1=0:2*pi*7/8:8", "--grid", "Omega=3:4:8", "--measure",
            "r_max", "--t-end", "1000", "--chunk", "2", "--workers", "1", "--no-figures"]
    ref = tmp_path / "ref"
    assert _cli(*args, "--out", str(ref), "--json").returncode == 0
    out = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, "-m", "adbgen.cli", *args, "--out", str(out), "--json"],
                            env=_env(), cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    store = out / "sweep.zarr"
    deadline = time.time() + 120
    n_done = 0
    while time.time() < deadline and proc.poll() is None:
        if (store / "done" / "zarr.json").exists():
            n_done = int(np.asarray(zarr.open_group(str(store), mode="r")["done"][...]).sum())
            if n_done >= 4:
                break
        time.sleep(0.05)
    assert proc.poll() is None, "the sweep finished before it could be killed; make it longer"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    partial = int(np.asarray(zarr.open_group(str(store), mode="r")["done"][...]).sum())
    assert 0 < partial < 64
    res = _cli(*args, "--out", str(out), "--json")
    assert res.returncode == 0, res.stderr
    summary = json.loads(res.stdout)
    assert summary["reused"] >= partial and summary["computed"] == 64 - summary["reused"]
    a, b = _open(ref), _open(out)
    for name in ("r_max", "y_end", "t_last", "done"):
        np.testing.assert_array_equal(a[name].values, b[name].values)
    assert a.attrs == b.attrs


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_external_scheduler_runs_the_sweep(tmp_path):
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    def start(*args):
        return subprocess.Popen([sys.executable, "-m", *args], env=_env(), stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)

    procs = [start("distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", str(port),
                   "--dashboard-address", ":0")]
    try:
        time.sleep(1.0)
        procs.append(start("distributed.cli.dask_worker", address, "--nthreads", "1", "--nworkers", "1",
                           "--no-dashboard"))
        from distributed import Client

        with Client(address, timeout=30) as client:
            client.wait_for_workers(1, timeout=60)
        common = ["sweep", "thesis_rotating_n2", "--grid", "phi_1=0:2*pi*3/4:4", "--grid", "phi_2=0:2*pi*3/4:4",
                  "--measure", "t_dec", "--t-end", "200", "--chunk", "4", "--no-figures", "--json"]
        res = _cli(*common, "--scheduler", address, "--out", str(tmp_path / "remote"))
        assert res.returncode == 0, res.stderr
        assert json.loads(res.stdout)["computed"] == 16
        run_sweep(SweepSpec(model="thesis_rotating_n2", grid=["phi_1=0:2*pi*3/4:4", "phi_2=0:2*pi*3/4:4"],
                            measure="t_dec", t_end=200.0, chunk=4), tmp_path / "local", progress=False, figures=False)
        a, b = _open(tmp_path / "remote"), _open(tmp_path / "local")
        np.testing.assert_array_equal(a.t_dec.values, b.t_dec.values)
        np.testing.assert_array_equal(a.y_end.values, b.y_end.values)
    finally:
        for p in reversed(procs):
            p.terminate()
            p.wait(timeout=30)


def test_stability_map_n2_window_and_hopf_point(tmp_path, saved_figures):
    """mu = 0.05, zeta = beta = delta = 0.01: the balanced state of n = 2 is stable in (1.02969, 1.09363)
    and beyond H1 = 1.88224 (README, ch. 4), unstable elsewhere; n = 3 reports its neutral zero."""
    spec = SweepSpec(model="thesis_rotating_n2", grid=["Omega=1.0:2.2:13"], measure="stability", chunk=4)
    run_sweep(spec, tmp_path / "n2", progress=False)
    ds = _open(tmp_path / "n2")
    om = ds.Omega.values
    stable = ds.stability.values == 0
    # regression values: the Hopf points of verify's chapter-4 check (= AUTO-07p's HB labels to 1e-6)
    expect = ((om > 1.02969) & (om < 1.09363)) | (om > 1.88224)
    np.testing.assert_array_equal(stable, expect)
    assert (tmp_path / "n2" / "stability.png").is_file() and (tmp_path / "n2" / "stability.pdf").is_file()
    # the figure draws the count of unstable eigenvalues the store holds, at each Omega of the grid
    [ax] = fc.figure(saved_figures, "stability.png").axes
    [step] = ax.get_lines()
    assert step.get_drawstyle() == "steps-mid"
    np.testing.assert_array_equal(step.get_xdata(), om)
    np.testing.assert_array_equal(step.get_ydata(), ds.stability.values)
    fc.assert_labels(ax, ylabel="unstable eigenvalues")
    fc.assert_title(ax, "thesis_rotating_n2")
    spec3 = SweepSpec(model="thesis_rotating_n3", grid=["Omega=1.8:2.0:3"], measure="stability", chunk=4)
    run_sweep(spec3, tmp_path / "n3", progress=False, figures=False)
    ds3 = _open(tmp_path / "n3")
    np.testing.assert_array_equal(ds3.neutral.values, [1, 1, 1])
    np.testing.assert_array_equal(ds3.stability.values == 0, ds3.Omega.values > 1.87537)


@pytest.mark.parametrize("grid, message", [
    ([], "no grid"),
    (["phi_1=1:1:5"], "empty range"),
    (["phi_1=2:1:5"], "reversed range"),
    (["phi_1=0:1:0"], "at least 1"),
    (["phi_9=0:1:4"], "unknown name"),
    (["Omega=0:1"], "NAME=FROM:TO:COUNT"),
    (["Omega=a:1:3"], "cannot read"),
])
def test_bad_grids_are_refused_with_one_line(tmp_path, grid, message):
    args = ["sweep", "thesis_rotating_n2", "--measure", "r_max", "--out", str(tmp_path / "o")]
    for g in grid:
        args += ["--grid", g]
    from adbgen.cli import main

    import contextlib
    import io

    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(args)
    assert code == 2
    lines = err.getvalue().strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("adbgen: error:") and message in lines[0], lines
    assert not (tmp_path / "o").exists()


def test_foreign_store_and_other_settings_are_refused(tmp_path):
    from adbgen.cli import main

    foreign = tmp_path / "foreign" / "sweep.zarr"
    foreign.mkdir(parents=True)
    (foreign / "notes.txt").write_text("mine")
    base = ["sweep", "thesis_rotating_n2", "--grid", "phi_1=0:1:2", "--measure", "r_max", "--t-end", "10",
            "--no-figures", "--json"]
    assert main([*base, "--out", str(foreign.parent)]) == 2
    assert sorted(p.name for p in foreign.iterdir()) == ["notes.txt"]
    out = tmp_path / "ours"
    assert main([*base, "--out", str(out)]) == 0
    before = {p: p.read_bytes() for p in (out / "sweep.zarr").rglob("*") if p.is_file()}
    import contextlib
    import io

    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        assert main([*base, "--rtol", "1e-6", "--out", str(out)]) == 2
    assert "other settings (rtol" in err.getvalue()
    after = {p: p.read_bytes() for p in (out / "sweep.zarr").rglob("*") if p.is_file()}
    assert before == after


def test_tied_states_and_their_exchange_symmetry(tmp_path):
    """--tie phi_3=phi_1+pi --tie phi_4=phi_2+pi (thesis Fig. 5.19): the tied states follow their axes,
    and the exchange (1 2)(3 4) maps the grid onto itself, giving the full computation's results."""
    grid = ["phi_1=0:3*pi/2:4", "phi_2=0:3*pi/2:4"]
    ties = ["phi_3=phi_1+pi", "phi_4=phi_2+pi"]

    def run(out, symmetry):
        spec = SweepSpec(model="thesis_rotating_n4", grid=grid, tie=ties, measure="r_max", t_end=100.0, chunk=4,
                         symmetry=symmetry)
        return run_sweep(spec, tmp_path / out, progress=False, figures=False), _open(tmp_path / out)

    s_sym, sym = run("sym", True)
    s_full, full = run("full", False)
    assert s_sym["integrated"] == 10 and s_full["integrated"] == 16  # 4 on the diagonal + 6 pairs
    np.testing.assert_allclose(sym.r_max.values, full.r_max.values, rtol=1e-6)
    model = load_model("thesis_rotating_n4")
    a, b = full.phi_1.values[1], full.phi_2.values[2]
    sim = simulate(model, model.params(), model.state({"phi_1": a, "phi_2": b, "phi_3": a + math.pi,
                                                       "phi_4": b + math.pi}), t_end=100.0, keep_trajectory=False)
    assert full.r_max.values[1, 2] == pytest.approx(sim.r_max, rel=1e-12)
    assert json.loads(full.attrs["ties"]) == [["phi_3", "phi_1", math.pi], ["phi_4", "phi_2", math.pi]]


@pytest.mark.parametrize("tie, message", [
    ("phi_3", "expected NAME=AXIS+OFFSET"),
    ("phi_3=phi_9+pi", "does not start with a state axis"),
    ("phi_1=phi_2+pi", "already a grid axis"),
    ("phi_3=phi_1+x", "cannot read"),
])
def test_bad_ties_are_refused(tmp_path, tie, message):
    from adbgen.analysis.loading import AnalysisError

    spec = SweepSpec(model="thesis_rotating_n4", grid=["phi_1=0:1:2", "phi_2=0:1:2"], tie=[tie], measure="r_max")
    with pytest.raises(AnalysisError, match=message.replace("+", r"\+")):
        prepare(spec)


def test_decided_outcomes_are_counted_and_undecided_is_never_not_balanced(tmp_path):
    """Fig. 5.11's n = 3 launches 0-2 (rtol 1e-10, t_end 3000): 0 and 1 end in the balanced state's region,
    2 is not named at t_end and is carried on to the cap 6000 and decided by its exponential approach.  The
    --json summary counts the decided labels; an undecided point (planted into the store) is counted as
    undecided, never as not balanced, and the figure draws it as its own legend entry."""
    spec = SweepSpec(model="thesis_rotating_n3", grid=["phi_1=0:2*pi*2/100:3"], measure="attractor",
                     y0=["phi_1_dot=-4", "phi_2_dot=-4", "phi_3_dot=-4"],
                     tie=["phi_2=phi_1+2*pi/3", "phi_3=phi_1-2*pi/3"], t_end=3000.0, rtol=1e-10, atol=1e-12,
                     engine="cyrk-dop853")
    summary = run_sweep(spec, tmp_path, progress=False, workers=1)
    out = summary["outcomes"]
    assert out["counts"] == {"balanced 1": 3} and (out["balanced"], out["not_balanced"], out["undecided"]) == (3, 0, 0)
    assert out["approaches"] == {"exponential": 1} and "2 t_end" in out["carry_on"]
    ds = _open(tmp_path)
    assert ds["t_decided"].values.tolist() == [3000.0, 3000.0, 6000.0]
    # negative control: plant an undecided point; it must not move into "not balanced"
    from adbgen.analysis.sweep import outcome_counts
    from adbgen.analysis.sweep_figures import write_figures

    names = json.loads(ds.attrs["labels"])
    group = zarr.open_group(str(tmp_path / "sweep.zarr"), mode="r+")
    group["attractor"][2] = names.index("undecided")
    group["undecided"][2] = 2
    out = outcome_counts(tmp_path / "sweep.zarr")
    assert (out["balanced"], out["not_balanced"], out["undecided"]) == (2, 0, 1)
    assert list(out["undecided_reasons"]) == [attractors.UNDECIDED_REASONS[2]]
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    seen = []
    real_savefig = plt.Figure.savefig

    def spy(fig, *a, **kw):
        seen.extend(t.get_text() for ax in fig.axes for t in ax.get_yticklabels())
        return real_savefig(fig, *a, **kw)

    plt.Figure.savefig = spy
    try:
        write_figures(tmp_path / "sweep.zarr")
    finally:
        plt.Figure.savefig = real_savefig
    assert "undecided" in seen and "balanced 1" in seen


def test_a_failed_run_is_counted_and_marked_never_drawn_as_not_settled(tmp_path):
    """t_dec over mu x zeta with mu = 1e300 (the run overflows: non-finite): those points are failed, their NaN is
    not a t_dec "not settled by t_end" (the map's grey): the summary counts them ("failed"), the title says so
    and the map marks them; the settled points keep their values (control)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    spec = SweepSpec(model="thesis_rotating_n2", grid=["mu=0.05:1e300:2", "zeta=0.01:0.02:2"], measure="t_dec",
                     t_end=50.0, threshold=0.3)
    titles, marks = [], []
    real_savefig = plt.Figure.savefig

    def spy(fig, *a, **kw):
        titles.extend(ax.get_title() for ax in fig.axes)
        marks.extend(line.get_label() for ax in fig.axes for line in ax.get_lines())
        return real_savefig(fig, *a, **kw)

    plt.Figure.savefig = spy
    try:
        summary = run_sweep(spec, tmp_path, progress=False, workers=1)
    finally:
        plt.Figure.savefig = real_savefig
    ds = _open(tmp_path)
    assert ds["failed"].values.tolist() == [[0, 0], [1, 1]] and np.all(np.isfinite(ds["t_dec"].values[0]))
    assert summary["failed"] == 2
    assert any("2 failed" in t for t in titles) and "failed run" in marks
