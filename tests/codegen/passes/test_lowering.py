"""The intermediate form: structure, the oscillator extension, and the checks `regenerate` relies on."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import sympy as sp

from adbgen.codegen.passes import lowering as I
from adbgen.codegen.passes.checks import lowering_error
from adbgen.families.single_plane import models
from adbgen.codegen.plain_python import compile_program
from adbgen.codegen.passes.checks import CheckFailed, check_start as _check_start
from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane.model import derive
from adbgen.families.single_plane.reductions import first_order
from adbgen.codegen.spec import build as build_ir


@pytest.fixture(scope="module")
def fixed2():
    spec = models.single_plane_fixed(2)
    return spec.system(), build_ir(spec)


def test_lowering_is_pure():
    a, b = build_ir(models.thesis_rotating(2)), build_ir(models.thesis_rotating(2))
    assert a.fingerprint() == b.fingerprint()
    assert build_ir(models.thesis_rotating(3)).fingerprint() != a.fingerprint()


def test_structure_is_recorded_and_the_ball_block_is_diagonal():
    ir = build_ir(models.thesis_rotating(3))
    assert ir.core == ("x", "y") and ir.leaves == ("phi_1", "phi_2", "phi_3")
    balls = [ir.state_names.index(name) for name in ir.leaves]
    assert not [(i, j) for i, j in ir.mass_pattern if i in balls and j in balls and i != j]
    # the rhs never divides by anything but the ball inertias and the LU pivots of the 2x2 core, in
    # either form
    divisions = {lhs.name for lhs, e in ir.kernels()["rhs"].definitions()
                 if any(p.exp.is_negative for p in e.atoms(sp.Pow) if p.exp.is_number)}
    assert ir.form == "loops" and divisions <= {"Uinv_0", "Uinv_1", "LU_1_0", "ball_dinv"}
    unrolled = build_ir(models.thesis_rotating(3), form="unrolled")
    divisions = {lhs.name for lhs, e in unrolled.rhs.assignments
                 if any(p.exp.is_negative for p in e.atoms(sp.Pow) if p.exp.is_number)}
    assert divisions <= {"Uinv_0", "Uinv_1", "LU_1_0", "Mllinv_0", "Mllinv_1", "Mllinv_2"}


def test_the_lowering_check_catches_a_wrong_program():
    spec = models.thesis_rotating(2)
    system, ir = spec.system(), build_ir(spec, form="unrolled")
    assert lowering_error(ir, system) < 1e-12
    outputs = list(ir.rhs.outputs)
    k, e = outputs[5]
    outputs[5] = (k, e * (1 + sp.Rational(1, 10**6)))
    broken = dataclasses.replace(ir, rhs=dataclasses.replace(ir.rhs, outputs=tuple(outputs)))
    assert lowering_error(broken, system) > 1e-8


def test_the_start_check_catches_a_point_that_is_not_at_rest():
    ir = build_ir(models.thesis_rotating(2))
    _check_start(ir)
    moved = list(ir.start)
    moved[2] += 1e-3
    with pytest.raises(CheckFailed, match="not at rest"):
        _check_start(dataclasses.replace(ir, start=tuple(moved)))


def test_oscillator_extension_equals_the_forced_model_on_its_cycle(fixed2):
    """On s = sin(omega t), c = cos(omega t) the extension's rows are the forced model's rows, and the
    oscillator's rows are the cycle's derivatives, at random t, y, p: to 1e-13 of the largest term,
    omega^2 (the centripetal terms cancel in the ball rows, so the rows' own size is no scale)."""
    _, ir = fixed2
    ext = ir.autonomous_extension
    assert not ir.autonomous and ext.autonomous and ext.forcing_frequency == "omega"
    assert ext.state_names == ir.state_names + ("osc_sin", "osc_cos")
    forced, extended = compile_program(ir, "rhs"), compile_program(ext, "rhs")
    rng = np.random.default_rng(4)
    iw = ir.parameter_names.index("omega")
    for _ in range(200):
        p = np.array([q.default for q in ir.parameters]) * rng.uniform(0.5, 2.0, len(ir.parameters))
        t, y = rng.uniform(0, 1), rng.uniform(-1, 1, ir.n_states) * 0.01
        w = p[iw]
        a = extended(0.0, np.concatenate([y, [np.sin(w * t), np.cos(w * t)]]), p)
        b = forced(t, y, p)
        assert np.max(np.abs(a[:-2] - b)) <= 1e-13 * max(np.max(np.abs(b)), w**2)
        assert np.allclose(a[-2:], [w * np.cos(w * t), -w * np.sin(w * t)], rtol=1e-13, atol=1e-13 * w)


def test_oscillator_extension_jacobians_equal_finite_differences(fixed2):
    _, ir = fixed2
    ext = ir.autonomous_extension
    f, J, Jp = (compile_program(ext, k) for k in ("rhs", "jac", "jac_p"))
    rng = np.random.default_rng(5)
    p = np.array([q.default for q in ext.parameters])
    n = ext.n_states
    for _ in range(10):
        y = np.concatenate([rng.uniform(-1, 1, n - 2) * 0.01, rng.uniform(-1, 1, 2)])
        Jn = J(0.0, y, p).reshape(n, n)
        fd = np.column_stack([(f(0.0, y + 1e-7 * e, p) - f(0.0, y - 1e-7 * e, p)) / 2e-7 for e in np.eye(n)])
        assert np.max(np.abs(Jn - fd)) <= 1e-6 * np.max(np.abs(Jn))
        Jpn = Jp(0.0, y, p).reshape(n, len(p))
        h = 1e-6 * np.maximum(np.abs(p), 1e-3)
        fdp = np.column_stack([(f(0.0, y, p + h[k] * e) - f(0.0, y, p - h[k] * e)) / (2 * h[k])
                               for k, e in enumerate(np.eye(len(p)))])
        assert np.max(np.abs(Jpn - fdp)) <= 1e-5 * np.max(np.abs(Jpn))


def test_an_oscillator_needs_one_constant_frequency():
    run_up = Scene.from_mapping({"n": 2, "stiffness": [1e4, 1.2e4], "speed": {"law": "profile", "omega": "40*t"}})
    system = first_order(derive(run_up))
    with pytest.raises(ValueError, match="constant frequency"):
        I.build("run_up", system, title="run-up", n_balls=2, oscillator=True)


def test_statement_names_cannot_shadow_model_symbols():
    system = models.thesis_rotating(1).system()
    clash = dataclasses.replace(system, parameters=system.parameters + (
        dataclasses.replace(system.parameters[0], symbol=sp.Symbol("S_0_0", positive=True)),))
    with pytest.raises(ValueError, match="clash"):
        I.build("clash", clash, title="x", n_balls=1)


def test_a_four_by_four_core_lowers_too():
    """The two-plane rotor's rotating frame (x, y, phi_x, phi_y core; paper (7)-(8), preset (10), four
    balls): the unrolled LU of the 4x4 Schur complement equals a dense solve of the whole system."""
    from adbgen.families.two_plane import reductions
    from adbgen.families.two_plane.scene import TwoPlaneScene

    system = reductions.first_order(reductions.rotating_frame(TwoPlaneScene.from_mapping({"preset": "paper-10"})))
    # unrolled: without the race slots (two_plane.race_slots) the loop form is refused (issue 20)
    ir = I.build("two_plane_rotating", system, title="two-plane", n_balls=4, form="unrolled")
    assert ir.autonomous and ir.core == ("x", "y", "phi_x", "phi_y") and len(ir.leaves) == 4
    assert lowering_error(ir, system, samples=50) < 1e-12
