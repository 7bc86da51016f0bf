"""The benchmark's peers integrate the generated code's equations.

CI installs the optional extra ``peers`` (JiTCODE, heyoka; README's test command), so there a missing
peer is a failure; on a developer machine without it these skip with the reason (`require_module`).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from toolchain import require_module

from benchmarks import peers as bench_peers
from adbgen.analysis.loading import load_model

MODEL = "thesis_rotating_n2"


@pytest.fixture(scope="module")
def setting():
    model = load_model(MODEL)
    return model, model.module, model.params()


def test_generated_program_is_the_modules_statements():
    model = load_model(MODEL)
    statements, outputs = bench_peers.generated_program(model.module)
    assert sorted(outputs) == list(range(model.n_states))
    names = [name for name, _ in statements]
    assert len(names) == len(set(names)) and names[:2] == ["x", "y_"]  # state reads first, in order
    # evaluated on floats, the program is the generated rhs itself (same operations: bitwise)
    import math

    y = np.linspace(-0.3, 0.4, model.n_states)
    p = model.params()
    got = bench_peers._translate(model.module, {"sin": math.sin, "cos": math.cos}, y, p, 0.0)
    assert np.array_equal(np.array(got, float), model.module.rhs(0.0, y, p))


def test_heyoka_same_equations_and_run(setting):
    require_module("heyoka", "the 'peers' extra: pip install -e '.[peers]'")
    model, module, p = setting
    peer = bench_peers.Heyoka(module)
    assert bench_peers.check_equations(peer, model.module, p, samples=20) < 1e-13
    y0 = model.state({"phi_1": math.pi / 2, "phi_2": -math.pi / 2})
    out = peer.run(y0, p, 5.0, 1e-10)
    assert out["status"] == "success" and out["n_steps"] > 0 and peer.compile_s[1e-10] > 0
    from scipy.integrate import solve_ivp

    ref = solve_ivp(model.module.rhs, (0, 5.0), y0, args=(p,), method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
    assert np.max(np.abs(out["y_end"] - ref)) < 1e-8


def test_jitcode_same_equations_and_run(setting, tmp_path, monkeypatch):
    require_module("jitcode", "the 'peers' extra: pip install -e '.[peers]'")
    model, module, p = setting
    monkeypatch.chdir(tmp_path)
    peer = bench_peers.JiTCODE(module)
    assert list(tmp_path.iterdir()) == []  # built in a scratch folder, not the working directory
    assert bench_peers.check_equations(peer, model.module, p, samples=20) < 1e-13
    y0 = model.state({"phi_1": math.pi / 2, "phi_2": -math.pi / 2})
    out = peer.run(y0, p, 5.0, 1e-10, 1e-12)
    assert out["status"] == "success" and peer.count_rhs(y0, p, 5.0, 1e-10, 1e-12) > 0
    from scipy.integrate import solve_ivp

    ref = solve_ivp(model.module.rhs, (0, 5.0), y0, args=(p,), method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
    assert np.max(np.abs(out["y_end"] - ref)) < 1e-8


def test_peers_follow_a_piecewise_law_of_time():
    """The Hill run-up's angle (45) is piecewise in t (a series below the switch, the closed form above):
    each peer gets its own conditional and equals the generated rhs on both sides of the switch."""
    model = load_model("two_plane_hill")
    p = model.params()
    y = np.random.default_rng(3).uniform(-0.1, 0.1, model.n_states)
    for name in ("heyoka", "jitcode"):
        require_module(name, "pip install 'adbgen[peers]'")
        peer = bench_peers.PEERS[name](model.module)
        for t in (20.0, 60.0, 400.0):
            ref = np.asarray(model.module.rhs(t, y, p))
            assert np.max(np.abs(peer.rhs(y, p, t) - ref)) <= 1e-12 * np.max(np.abs(ref)), (name, t)


def test_the_translation_in_extended_precision_is_the_generated_rhs():
    """The reference of `bench tolerance` integrates the program in the widest type heyoka offers
    (`extended_type`): evaluated in that type (and in long double) at random states and times, the run-up's
    rhs (a law of time) equals the generated double rhs to round-off.  Negative control: a translation with
    one output 0.1 % off (a planted wrong program) is caught."""
    require_module("heyoka", "the 'peers' extra: pip install -e '.[peers]'")
    model = load_model("two_plane_ramp")
    p = model.params({"t_ramp": 300.0})
    peer = bench_peers.Heyoka(model.module)
    fp, name, eps = bench_peers.extended_type()
    assert eps < np.finfo(float).eps / 1000 and name in ("real128", "long double")
    for kind in (fp, np.longdouble):
        assert bench_peers.check_extended(peer, model.module, p, kind, samples=8, t_span=600.0) < 1e-12
    peer.outputs = list(peer.outputs[:-1]) + [peer.outputs[-1] * 1.001]
    peer._cfuncs = {}
    assert bench_peers.check_extended(peer, model.module, p, fp, samples=8, t_span=600.0) > 1e-6


def test_time_breakpoints_are_the_switches_of_a_law_of_time():
    """The run-up's ramp switches at t = t_ramp (found from program.json alone), the Hill profile at its
    series' switch; a model forced at a constant speed has none (negative control), nor a ramp whose switch
    lies beyond t_end."""
    ramp = load_model("two_plane_ramp")
    got = bench_peers.time_breakpoints(ramp.module, ramp.params({"t_ramp": 378.6}), 1000.0, grid=201)
    assert got == [pytest.approx(378.6, abs=1e-9)]
    assert bench_peers.time_breakpoints(ramp.module, ramp.params({"t_ramp": 378.6}), 300.0, grid=201) == []
    hill = load_model("two_plane_hill")
    assert len(bench_peers.time_breakpoints(hill.module, hill.params({"t_half": 105.4}), 1000.0, grid=201)) == 1
    rot = load_model(MODEL)
    assert bench_peers.time_breakpoints(rot.module, rot.params(), 100.0, grid=51) == []


def test_an_extended_run_locates_t_dec_and_stops_at_a_switch():
    """run_extended in long double: t_dec (sup{t : r >= threshold}) as CyRK Vern8 at rtol 1e-13 finds it,
    and on the ramp the run stopping at t_ramp agrees with Vern8 while one stepping across it is off
    (negative control: the wrong branch over part of a step)."""
    require_module("heyoka", "the 'peers' extra: pip install -e '.[peers]'")
    from adbgen.analysis.simulate import simulate

    model = load_model("two_plane_ramp")
    p = model.params({"t_ramp": 37.86})
    y0 = model.state({"theta_1": 1.0, "theta_2": 2.5, "theta_3": 4.0, "theta_4": 5.5})
    peer = bench_peers.Heyoka(model.module)
    stops = bench_peers.time_breakpoints(model.module, p, 60.0, grid=201)
    ref = simulate(model, p, y0, t_end=60.0, rtol=1e-13, atol=1e-15, engine="cyrk-vern8", keep_trajectory=False,
                   threshold=0.02)
    run = dict(threshold=0.02, amplitude=model.amplitude_indices)
    good = peer.run_extended(y0, p, 60.0, 1e-18, **run, breakpoints=stops)
    bad = peer.run_extended(y0, p, 60.0, 1e-18, **run)
    assert good["status"] == "success" and 0.0 < good["t_dec"] < 60.0
    assert abs(good["t_dec"] - ref.t_dec) < 1e-8 and np.max(np.abs(good["y_end"] - ref.y_end)) < 1e-9
    assert np.max(np.abs(bad["y_end"] - ref.y_end)) > 100 * np.max(np.abs(good["y_end"] - ref.y_end))
