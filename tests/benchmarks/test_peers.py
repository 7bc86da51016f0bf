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
