"""`adbgen bench failures` / `smallest`: the exactness of what they measure with, on tiny inputs
(no timed assertions)."""

from __future__ import annotations

import json
import math
import shutil

import figure_checks as fc
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from toolchain import require_tool

from benchmarks import fixed_step as fs
from benchmarks import pairs as bp
from adbgen.analysis.loading import load_model
from adbgen.analysis.simulate import simulate
from benchmarks.problems import PROBLEM_A

HILL_PAIRS = (("theta_1", "theta_2"), ("theta_3", "theta_4"))


def _require_gcc():
    require_tool(bool(shutil.which("gcc") or shutil.which("cc")), "a C compiler (the compiled engines need gcc)")


@pytest.fixture(scope="module")
def hill():
    m = load_model("two_plane_hill")
    return m, bp.make_pair_rhs(m, HILL_PAIRS), bp.make_pair_rhs(m, HILL_PAIRS, compensate=False)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(st.floats(-10, 10), min_size=16, max_size=16), st.floats(0.0, 500.0),
       st.floats(0.0, 1e-3), st.floats(0.0, 1e-3))
def test_pair_coordinates_are_an_exact_change_of_variables(hill, state, t, c_bb, c_bt):
    """z' = T f(T^-1 z) at any state, time and race damping: the pair rhs against the transformed
    generated rhs, T^-1 T = 1, and the pair Jacobian T J T^-1 against central differences."""
    m, (rhs, _, jac), (rhs_nc, _, _) = hill
    ia, ib = bp.pair_indices(m, HILL_PAIRS)
    p = m.params({"c_bb": c_bb, "c_bt": c_bt})
    y = np.array(state)
    z = bp.to_pairs(y, ia, ib)
    assert np.allclose(bp.from_pairs(z, ia, ib), y, rtol=0, atol=1e-14)
    f = np.asarray(m.module.rhs(t, bp.from_pairs(z, ia, ib), p))
    expected = bp.to_pairs(f, ia, ib)
    # a pair's difference d'' = f_a - f_b rounds relative to its operands, not to its (possibly zero) value:
    # Hypothesis found 1.2e-14 on a d'' of 0 from accelerations of 9.03 (a state with entries 3 and 10)
    scale = 1 + np.maximum(np.abs(expected), np.max(np.abs(f)))
    assert np.max(np.abs(rhs(t, z, p) - expected) / scale) < 1e-14
    assert np.max(np.abs(rhs_nc(t, z, p) - expected) / scale) < 1e-14
    # the Jacobian in pair coordinates, T J T^-1, against central differences of the pair rhs
    J = jac(t, z, p)
    step = 1e-6
    fd = np.column_stack([(rhs(t, z + step * e, p) - rhs(t, z - step * e, p)) / (2 * step)
                          for e in np.eye(m.n_states)])
    assert np.max(np.abs(J - fd)) < 1e-6 * (1 + np.max(np.abs(J)))


def test_separation_survives_below_round_off_only_in_pair_coordinates():
    """thesis n = 2 from phi = pi +- 1e-20: the original form starts (and stays) merged; the pair form
    with the rounding correction separates the balls (the coincident state is unstable); without the
    correction its d stays frozen at 1e-20 (d'' computes to 0)."""
    _require_gcc()
    m = load_model("thesis_rotating_n2")
    pairs = (("phi_1", "phi_2"),)
    _, pin, _ = bp.make_pair_rhs(m, pairs)
    _, pnc, _ = bp.make_pair_rhs(m, pairs, compensate=False)
    p = m.params()
    d0, t_end = 1e-20, 600.0
    i1, i2 = m.index("phi_1"), m.index("phi_2")
    y0 = m.state({"phi_1": math.pi + d0, "phi_2": math.pi - d0})
    assert y0[i1] == y0[i2]  # not representable in the original variables
    orig = simulate(m, p, y0, t_end=t_end, rtol=1e-10, atol=1e-12, engine="cyrk-dop853", keep_trajectory=False)
    assert orig.y_end[i1] == orig.y_end[i2]
    z0 = m.state({"phi_1": math.pi, "phi_2": d0})
    pair = bp.cyrk_solve(pin, m.n_states, z0, p, t_end, 1e-10, 1e-12)
    frozen = bp.cyrk_solve(pnc, m.n_states, z0, p, t_end, 1e-10, 1e-12)
    assert bp.wrapped(2 * pair["y"][i2, -1]) > 0.1
    assert frozen["y"][i2, -1] == d0


def test_separation_is_exact_for_tiny_differences():
    a = np.array([1000.0, 3.0])
    b = np.nextafter(a, 0)
    assert np.all(bp.wrapped(a - b) > 0)
    assert bp.wrapped(np.array([2 * math.pi + 0.5]))[0] == pytest.approx(0.5)


def test_stability_boundaries_of_rk4():
    """|R(z)| = 1 at z = -2.7853 and z = 2.8284 i for the classical RK4 (Hairer-Wanner IV.2)."""
    assert fs.stability_boundary(fs.RK4, math.pi) == pytest.approx(2.78529, abs=1e-5)
    assert fs.stability_boundary(fs.RK4, math.pi / 2) == pytest.approx(2 * math.sqrt(2), abs=1e-6)
    tabs = fs.tableaus()
    assert np.allclose(fs.stability_polynomial(tabs["rk4"])[::-1][:5], [1, 1, 1 / 2, 1 / 6, 1 / 24])
    assert np.allclose(fs.stability_polynomial(tabs["dop853"])[::-1][:9], [1 / math.factorial(k) for k in range(9)])


def test_fixed_rk4_converges_at_fourth_order_and_blows_up_past_the_limit():
    m = load_model(PROBLEM_A.model)
    p, y0 = PROBLEM_A.vectors(m)
    ref = simulate(m, p, y0, t_end=20.0, rtol=1e-13, atol=1e-15, engine="scipy-dop853").y_end
    e1 = np.max(np.abs(fs.run_fixed(m, p, y0, 20.0, 200, fs.RK4)["y_end"] - ref))
    e2 = np.max(np.abs(fs.run_fixed(m, p, y0, 20.0, 400, fs.RK4)["y_end"] - ref))
    assert 12 < e1 / e2 < 20  # 2^4
    assert not fs.run_fixed(m, p, y0, 200.0, 200, fs.RK4)["ok"]  # h = 1 > 2.83 / |lambda|max (about 0.57)


def test_jacobi_integral_is_conserved_undamped_and_not_damped():
    _require_gcc()
    from benchmarks import jacobi as bj

    m = load_model(PROBLEM_A.model)
    H = bj.jacobi_function(3)
    y0 = m.state({"phi_1": 1.0, "phi_2": -0.5, "phi_3": 2.0, "x_dot": 0.1})
    for params, conserved in (({"zeta": 0.0, "beta": 0.0}, True), ({}, False)):
        p = m.params(params)
        s = simulate(m, p, y0, t_end=100.0, rtol=1e-12, atol=1e-14, engine="cyrk-dop853")
        J = H(m, s.y, p)
        drift = np.max(np.abs(J - J[0]))
        if conserved:
            assert drift < 1e-9
        else:
            assert drift > 1e-4
    p = m.params({"zeta": 0.0, "beta": 0.0})
    times = np.arange(1, 101) * 1.0
    mid = bj.midpoint(m, p, y0, 0.01, times)
    assert mid["status"] == "success" and mid["n_steps"] >= 10000
    J = H(m, mid["y"], p)
    assert np.max(np.abs(J - H(m, y0[:, None], p)[0])) < 1e-4


def test_rotating_and_fixed_frame_agree():
    """The (5.1) scene in both frames: the committed fixed-frame model with k_Y = k_X, c_Y = c_X, g = 0
    is the isotropic constant-speed scene of thesis_rotating_n3 (mu = m/M, delta = eps/R,
    zeta = c / (2 sqrt(k M)), beta = D / (m R^2 omega_n), Omega = omega / omega_n)."""
    from benchmarks.smallest import OMEGA_N, to_rotating

    rot = load_model("thesis_rotating_n3")
    fix = load_model("single_plane_fixed_n3")
    pf = fix.params({"c_Y": 2.0, "k_Y": 1e4, "g": 0.0})
    pr = rot.params()
    t_nd = np.linspace(0, 50.0, 51)[1:]
    a = bp.cyrk_solve(rot.module.rhs_inplace, rot.n_states, rot.state(PROBLEM_A.y0), pr, 50.0, 1e-11, 1e-13,
                      t_eval=t_nd)
    b = bp.cyrk_solve(fix.module.rhs_inplace, fix.n_states, fix.state(PROBLEM_A.y0), pf, 0.5, 1e-11, 1e-13,
                      t_eval=t_nd / OMEGA_N)
    mapped = to_rotating(b["t"], b["y"], fix)
    assert np.max(np.abs(mapped["x"] - a["y"][rot.index("x")])) < 1e-7
    assert np.max(np.abs(mapped["y"] - a["y"][rot.index("y")])) < 1e-7
    assert np.max(np.abs(mapped["phi"][0] - a["y"][rot.index("phi_1")])) < 1e-7
    pf_bad = fix.params({"c_Y": 2.0, "g": 0.0})  # anisotropic: a different scene (negative control)
    c = bp.cyrk_solve(fix.module.rhs_inplace, fix.n_states, fix.state(PROBLEM_A.y0), pf_bad, 0.5, 1e-11, 1e-13,
                      t_eval=t_nd / OMEGA_N)
    assert np.max(np.abs(to_rotating(c["t"], c["y"], fix)["x"] - a["y"][rot.index("x")])) > 1e-4


def test_bench_failures_machinery_quick(tmp_path, monkeypatch):
    from benchmarks import failures as bf
    from benchmarks.report import write

    _require_gcc()

    r = bf.bench_failures(quick=True, parts=["fixed_step"])
    assert r["quick"] and r["machine"]["load_average_at_start"] is not None and r["date"]
    rk4 = r["fixed_step"]["tableaus"]["rk4"]
    assert rk4["h_blow"] is not None and rk4["predicted_h_limit"] > 0
    # the measured blow-up step agrees with the linear stability prediction (Jacobian spectrum)
    assert 0.8 < rk4["h_blow_over_predicted"] < 1.25
    json.dumps(r)
    write(r, tmp_path / "failures.json")
    seen = fc.saved_figures(monkeypatch)
    paths = bf.charts(r, tmp_path / "failures.json")
    assert [p.name for p in paths] == ["failures_fixed_step.png"] and paths[0].is_file()
    ax = fc.figure(seen, "failures_fixed_step.tmp.png").axes[0]
    assert_fixed_step_chart(ax, r["fixed_step"])
    planted = json.loads(json.dumps(r["fixed_step"]))  # negative control: a stability limit moved
    planted["tableaus"]["rk4"]["predicted_h_limit"] *= 1.1
    with pytest.raises(AssertionError):
        assert_fixed_step_chart(ax, planted)


def assert_fixed_step_chart(ax, fx):
    """Each tableau's error against h as measured (its runs that finished), a dashed line at its measured
    blow-up step and a dotted one at its predicted stability limit; log-log, the axes' labels."""
    for name, rec in fx["tableaus"].items():
        pts = [(q["h"], q["error"]) for q in rec["runs"] if q["ok"] and q["error"]]
        if pts:
            fc.assert_line(ax, f"{name} (stages {rec['stages']})", [x for x, _ in pts], [y for _, y in pts])
        marks = fc.vertical_lines(ax)
        assert any(x == rec["predicted_h_limit"] for x in marks), (name, rec["predicted_h_limit"], marks)
        assert not rec["h_blow"] or any(x == rec["h_blow"] for x in marks), (name, rec["h_blow"], marks)
    assert ax.get_xscale() == ax.get_yscale() == "log"
    fc.assert_labels(ax, "fixed step h", "error of the final state (max abs)")


def test_bench_rejects_unknown_benchmark(capsys):
    from adbgen.cli import main

    assert main(["bench", "fail"]) == 2
    assert "failures" in capsys.readouterr().err
