"""The benchmark's peers integrate the generated code's equations.

CI installs the optional extra ``peers`` (JiTCODE, heyoka; README's test command), so there a missing
peer is a failure; on a developer machine without it these skip with the reason (`require_module`).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from toolchain import require_module

from adbgen import bench_peers
from adbgen.analysis.loading import load_model

MODEL = "thesis_rotating_n2"


@pytest.fixture(scope="module")
def setting():
    model = load_model(MODEL)
    return model, bench_peers.model_ir(MODEL), model.params()


def test_model_ir_by_name():
    with pytest.raises(ValueError, match="default families"):
        bench_peers.model_ir("no_such_model_n2")
    ir = bench_peers.model_ir(MODEL)
    assert ir.name == MODEL and ir.n_states == 8


def test_heyoka_same_equations_and_run(setting):
    require_module("heyoka", "the 'peers' extra: pip install -e '.[peers]'")
    model, ir, p = setting
    peer = bench_peers.Heyoka(ir)
    assert bench_peers.check_equations(peer, model.module, p, samples=20) < 1e-13
    y0 = model.state({"phi_1": math.pi / 2, "phi_2": -math.pi / 2})
    out = peer.run(y0, p, 5.0, 1e-10)
    assert out["status"] == "success" and out["n_steps"] > 0 and peer.compile_s[1e-10] > 0
    from scipy.integrate import solve_ivp

    ref = solve_ivp(model.module.rhs, (0, 5.0), y0, args=(p,), method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
    assert np.max(np.abs(out["y_end"] - ref)) < 1e-8


def test_jitcode_same_equations_and_run(setting, tmp_path, monkeypatch):
    require_module("jitcode", "the 'peers' extra: pip install -e '.[peers]'")
    model, ir, p = setting
    monkeypatch.chdir(tmp_path)
    peer = bench_peers.JiTCODE(ir)
    assert list(tmp_path.iterdir()) == []  # built in a scratch folder, not the working directory
    assert bench_peers.check_equations(peer, model.module, p, samples=20) < 1e-13
    y0 = model.state({"phi_1": math.pi / 2, "phi_2": -math.pi / 2})
    out = peer.run(y0, p, 5.0, 1e-10, 1e-12)
    assert out["status"] == "success" and peer.count_rhs(y0, p, 5.0, 1e-10, 1e-12) > 0
    from scipy.integrate import solve_ivp

    ref = solve_ivp(model.module.rhs, (0, 5.0), y0, args=(p,), method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
    assert np.max(np.abs(out["y_end"] - ref)) < 1e-8
