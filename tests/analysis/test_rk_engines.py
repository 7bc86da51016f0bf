"""The DOP853 engines compiled with the model (engines/rk.py, rk_driver.c, rk_batch_driver.c; issue 22
items 3 and 4): the same method as cyrk-dop853 (same tableau, controller, errors of the same size), its
reports (statuses, r_max and t_dec on its interpolant, early stop), and the ensemble engine on SIMD lanes
(bitwise the scalar engine with glibc's sin/cos, within the tolerance's noise with libmvec's)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from adbgen.analysis.engines import ENGINES
from adbgen.analysis.engines.compiled import HERE
from adbgen.analysis.engines.rk import RKBatchEngine, RKEngine, lanes, lanes_source
from adbgen.analysis.loading import load_model
from adbgen.analysis.results import IntegrationError
from adbgen.analysis.simulate import simulate

PHI_A = {"phi_1": math.pi / 3, "phi_2": -math.pi / 3, "phi_3": math.pi}


def _rel(a, b):
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def test_tableau_is_hairers_as_scipy_prints_it():
    """dop853_tableau.h holds scipy's transcription of dop853.f's coefficients, digit for digit."""
    from scipy.integrate._ivp import dop853_coefficients as d

    text = (HERE / "dop853_tableau.h").read_text()

    def table(name):
        body = re.search(rf"{name}\[[^=]*= \{{(.*?)\}};", text, re.S).group(1)
        return np.array([float(v) for v in re.findall(r"[-+0-9.e]+(?=[,}\s])", body + " ")])

    assert np.array_equal(table("dop_c"), d.C)
    assert np.array_equal(table("dop_a"), d.A.ravel())
    assert np.array_equal(table("dop_b"), d.B)
    assert np.array_equal(table("dop_e3"), d.E3) and np.array_equal(table("dop_e5"), d.E5)
    assert np.array_equal(table("dop_d"), d.D.ravel())


@pytest.fixture(scope="module")
def problem_a(thesis):
    """Problem A at rtol 1e-9 by cyrk-dop853 and rk-dop853, and a reference by another method and code
    (CyRK's Vern8 at rtol 1e-13)."""
    m = thesis[3]
    kw = dict(t_end=2000.0, rtol=1e-9, atol=1e-11, keep_trajectory=False)
    return {"cyrk": simulate(m, None, PHI_A, engine="cyrk-dop853", **kw),
            "rk": simulate(m, None, PHI_A, engine="rk-dop853", **kw),
            "ref": simulate(m, None, PHI_A, t_end=2000.0, rtol=1e-13, atol=1e-15, engine="cyrk-vern8",
                            keep_trajectory=False)}


def test_same_method_as_cyrk(problem_a):
    """Same method and tolerance as CyRK's DOP853: as many steps (within 2 %), errors against the
    reference of the same size (within a factor 3), r_max and t_dec agreeing."""
    cy, rk, ref = problem_a["cyrk"], problem_a["rk"], problem_a["ref"]
    assert rk.status == cy.status == "success"
    assert abs(rk.n_steps - cy.n_steps) <= 0.02 * cy.n_steps
    e_rk, e_cy = _rel(rk.y_end, ref.y_end), _rel(cy.y_end, ref.y_end)
    assert 1e-12 < e_rk < 1e-5 and 1e-12 < e_cy < 1e-5
    assert 1 / 3 < e_rk / e_cy < 3
    assert rk.r_max == pytest.approx(ref.r_max, rel=1e-7)
    assert rk.t_dec == pytest.approx(ref.t_dec, abs=1e-3)
    assert (rk.n_rhs - 2) % 12 == 0 and rk.n_rhs >= 2 + 12 * rk.n_steps  # start (2), 12 per attempt


def test_interpolant_reproduces_the_steps_and_sees_an_in_step_excursion(thesis):
    """The rebuilt interpolant passes through the stored steps bitwise; t_dec on it sees problem A's
    excursion above H inside one step at rtol 1e-3 (cyrk's test), the crossing-only rule does not."""
    m = thesis[3]
    eng = ENGINES["rk-dop853"]
    s = simulate(m, None, PHI_A, t_end=2000.0, rtol=1e-3, atol=1e-8, engine="rk-dop853")
    ends = eng.dense(m, m.params(), s.t, s.y, s.t[1:], 1e-3, 1e-8)
    assert np.array_equal(ends, s.y[:, 1:])
    grid = np.arange(600.0, 1000.0, 0.002)
    r = np.hypot(*eng.dense(m, m.params(), s.t, s.y, grid, 1e-3, 1e-8)[:2])
    sup = float(grid[r >= 1e-3][-1])
    assert sup <= s.t_dec < sup + 0.002
    rs = np.hypot(s.y[0], s.y[1])
    assert float(s.t[np.nonzero(rs >= 1e-3)[0][-1] + 1]) < sup - 5.0  # negative control


def test_statuses(thesis):
    m = thesis[2]
    y0 = {"phi_1": 1.0}
    with pytest.raises(IntegrationError, match="step limit"):
        simulate(m, None, y0, t_end=100.0, max_steps=50, engine="rk-dop853")
    with pytest.raises(IntegrationError, match="non-finite"):
        simulate(m, {"mu": 1e308}, y0, t_end=10.0, engine="rk-dop853")
    with pytest.raises(IntegrationError, match="step size underflow"):
        simulate(m, None, y0, t_end=10.0, rtol=1e-15, atol=1e-300, engine="rk-dop853")
    ok = simulate(m, None, y0, t_end=10.0, engine="rk-dop853")
    assert ok.status == "success" and ok.t[-1] == 10.0


def _mixed_batch(m):
    """13 trajectories (not a multiple of any lane count): near the balanced state (stops early with a
    target region), far from it, and two parameter points."""
    start = np.array(m.module.START)
    Y0 = np.array([start + 1e-4 * (j + 1) for j in range(3)]
                  + [m.state({"phi_1": 0.3 + 0.4 * k, "phi_2": -1.0 + 0.1 * k}) for k in range(10)])
    P = np.array([m.params({"Omega": 4.0 if k % 2 else 3.0}) for k in range(13)])
    region = (start, np.full(m.n_states, 1e2))
    return P, Y0, [region]


@pytest.mark.parametrize("n_lanes", [1, 4, 8])
def test_batch_with_glibc_math_is_the_scalar_engine_bit_for_bit(thesis, n_lanes):
    """Per-lane steps reproduce the scalar engine exactly: every statement of the lanes rhs is the C rhs's
    on each lane, every step the same arithmetic (refills, idle lanes, early stop and all); both built
    with sin and cos called as written (never merged into sincos, which can differ in the last bit)."""
    m = thesis[2]
    P, Y0, targets = _mixed_batch(m)
    kw = dict(t_end=300.0, rtol=1e-8, atol=1e-10, threshold=1e-3, max_steps=10**6, check_dt=10.0, targets=targets,
              measures=False)
    one = RKEngine(exact_math=True).run_many(m, P, Y0, threads=2, **kw)
    batch = RKBatchEngine(exact_math=True, n_lanes=n_lanes).run_many(m, P, Y0, threads=2, **kw)
    assert np.array_equal(one["y_end"], batch["y_end"])
    assert np.array_equal(one["n_rhs"], batch["n_rhs"]) and np.array_equal(one["n_steps"], batch["n_steps"])
    assert list(one["status"]) == list(batch["status"]) and np.array_equal(one["target"], batch["target"])
    assert np.array_equal(one["t_last"], batch["t_last"])
    assert "stopped" in list(batch["status"]) and "success" in list(batch["status"])


def test_batch_with_libmvec_agrees_within_the_tolerance(thesis):
    """libmvec's sin/cos (4 ulp) move the trajectories by round-off only: same statuses and stops, final
    states closer than the tolerance's own error, and not bitwise (the negative control: the vector math
    is really used)."""
    m = thesis[2]
    P, Y0, targets = _mixed_batch(m)
    kw = dict(t_end=300.0, rtol=1e-8, atol=1e-10, threshold=1e-3, max_steps=10**6, check_dt=10.0, targets=targets,
              measures=False)
    one = ENGINES["rk-dop853"].run_many(m, P, Y0, **kw)
    fast = ENGINES["rk-dop853-batch"].run_many(m, P, Y0, **kw)
    assert list(one["status"]) == list(fast["status"]) and np.array_equal(one["target"], fast["target"])
    ref = ENGINES["rk-dop853"].run_many(m, P, Y0, **{**kw, "rtol": 1e-12, "atol": 1e-14})
    # the vector math moves the final states less than the tolerance itself does (its error against rtol 1e-12)
    assert np.max(np.abs(one["y_end"] - fast["y_end"])) < np.max(np.abs(one["y_end"] - ref["y_end"]))
    if lanes() > 1:
        assert not np.array_equal(one["y_end"], fast["y_end"])


def test_batch_falls_back_to_the_scalar_engine(thesis):
    """With r_max/t_dec asked for, or for a model the lanes target skips (a branching run-up law), the
    batch engine is rk-dop853 exactly."""
    m = thesis[2]
    P, Y0, _ = _mixed_batch(m)
    kw = dict(t_end=50.0, rtol=1e-8, atol=1e-10, threshold=1e-3, max_steps=10**6)
    a = ENGINES["rk-dop853"].run_many(m, P[:3], Y0[:3], **kw)
    b = ENGINES["rk-dop853-batch"].run_many(m, P[:3], Y0[:3], **kw)
    assert np.array_equal(a["r_max"], b["r_max"]) and np.array_equal(a["y_end"], b["y_end"])
    hill = load_model("two_plane_hill")
    assert lanes_source(hill) is None
    y = np.tile(np.asarray(hill.module.START if hill.module.START is not None else np.zeros(hill.n_states), float),
                (2, 1))
    c = ENGINES["rk-dop853"].run_many(hill, hill.params(), y, 5.0, 1e-8, 1e-10, 1e-3, 10**6, measures=False)
    d = ENGINES["rk-dop853-batch"].run_many(hill, hill.params(), y, 5.0, 1e-8, 1e-10, 1e-3, 10**6, measures=False)
    assert np.array_equal(c["y_end"], d["y_end"])


def test_lanes_header_per_model():
    """The lanes target renders every model whose rhs has no branch, and says why it skips the others."""
    from adbgen.codegen import targets

    assert "thesis_rotating_n3_rhs_lanes(adb_lanes t" in lanes_source(load_model("thesis_rotating_n3")).read_text()
    target = targets.get("lanes")
    text = lanes_source(load_model("two_plane_rotating")).read_text()
    assert "two_plane_rotating_rhs_lanes(adb_lanes t" in text and "adb_sin(" in text
    assert target.name == "lanes"


def test_every_lanes_header_is_its_models_c_rhs():
    """Every emitted lanes header computes its model's C rhs exactly, lane by lane: with glibc's sin/cos
    the batch engine's short run from 5 random states (random parameters near the defaults) is the scalar
    engine's bit for bit, for every model the lanes target renders."""
    from adbgen.analysis.loading import available_models

    rng = np.random.default_rng(7)
    rendered = [name for name in available_models() if lanes_source(load_model(name)) is not None]
    assert len(rendered) >= 9
    for name in rendered:
        m = load_model(name)
        y0 = np.asarray(m.module.START if m.module.START is not None else np.zeros(m.n_states), float)
        Y0 = y0 + 0.1 * rng.standard_normal((5, m.n_states))
        P = m.params() * (1 + 0.05 * rng.random((5, m.n_params)))
        kw = dict(t_end=0.5, rtol=1e-8, atol=1e-10, threshold=1e-3, max_steps=10**5, measures=False)
        one = RKEngine(exact_math=True).run_many(m, P, Y0, **kw)
        batch = RKBatchEngine(exact_math=True, n_lanes=4).run_many(m, P, Y0, **kw)
        assert list(one["status"]) == ["success"] * 5, name
        assert np.array_equal(one["y_end"], batch["y_end"]), name


def test_rhs_timed_along_a_runs_states():
    """bench rk's floor: the rhs timed once at each state of a run (positive, per call); a state array of
    the wrong shape is refused (negative control)."""
    model = load_model("thesis_rotating_n2")
    p = model.params()
    y0 = np.array(model.module.START, float)
    y0[list(model.angle_indices)] = (math.pi / 3, -math.pi / 3)
    rk = ENGINES["rk-dop853"]
    run = rk.run(model, p, y0, 50.0, 1e-8, 1e-10, 1e-3, 10**6, keep_trajectory=True)
    states = run["y"].T
    assert len(states) == run["n_steps"] + 1 > 50
    ns = rk.time_rhs_along(model, p, states)
    assert 0 < ns < 1e5
    with pytest.raises(ValueError):
        rk.time_rhs_along(model, p, states[:, :-1])
    with pytest.raises(ValueError):
        rk.time_rhs_along(model, p, states[:0])


def test_a_files_digest_follows_its_bytes(tmp_path):
    """The engines' cache key hashes a file once per (size, modification time): a changed file, even of the
    same size, gets a new digest."""
    import hashlib
    import os

    from adbgen.analysis.engines.compiled import _digest

    f = tmp_path / "driver.c"
    f.write_text("int a;\n")
    first = _digest(f)
    assert first == hashlib.sha256(b"int a;\n").digest() and _digest(f) == first
    f.write_text("int b;\n")
    st = f.stat()
    os.utime(f, ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000))  # a coarse clock could leave the time as it was
    assert _digest(f) == hashlib.sha256(b"int b;\n").digest()
