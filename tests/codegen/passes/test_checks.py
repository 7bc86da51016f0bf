"""`regenerate`'s pre-write checks see every program: rhs, jac, jac_p, mass_matrix and forcing of the
lowered model against evaluations that do not go through the lowering (issue 13, item 1).

The mutations are the issue's: `row -= entry*acc[j]` turned into `+=` in the Jacobian lowering
(monkeypatched, in both forms: the unrolled programs and the loop form's kernels), and one-line
changes of the functions themselves (a transposed M, a flipped forcing term, a dropped factor in
jac_p: stores of the loop form's kernels).  Each must be refused with one line naming the program,
before anything is written.
"""

from __future__ import annotations

import dataclasses

import pytest
import sympy as sp

from adbgen import cli
from adbgen.codegen.ir import loops
from adbgen.codegen.passes import loop_form, lowering
from adbgen.codegen.passes.checks import CheckFailed, check_programs, program_errors
from adbgen.families.single_plane import models
from adbgen.codegen.spec import build as build_ir


def _residual_rows_with_wrong_sign(builder):
    """The issue's mutation: the acceleration terms of R = f - M q'' added instead of subtracted."""
    acc = [c.qdd for c in builder.coordinates]
    rows = []
    for k in range(builder.N):
        row = builder.f[k]
        for j in range(builder.N):
            entry = builder.mass_entries.get((k, j))
            if entry is not None:
                row += entry * acc[j]
        rows.append(row)
    return rows


@pytest.fixture(scope="module")
def thesis2():
    spec = models.thesis_rotating(2)
    system = spec.system()
    return spec, system, build_ir(spec, system)


def _loop_residuals_with_wrong_sign(self):
    """The same mutation in the loop form: the acceleration terms of R0, the ball's share and its row."""
    s, r = self.s, self.r
    qdd = [self.coords[k].qdd for k in self.core]
    R0 = [s.f0[a] + sp.Add(*[s.A0[a][b] * qdd[b] for b in range(r)]) for a in range(r)]
    Rb = [s.fc[a] + sp.Add(*[s.A[a][b] * qdd[b] for b in range(r)]) + s.B[a] * s.qdd for a in range(r)]
    rho = s.f + sp.Add(*[s.C[a] * qdd[a] for a in range(r)]) + s.D * s.qdd
    return R0, Rb, rho, qdd


def _map_puts(ops, change, counter):
    out = []
    for op in ops:
        if isinstance(op, (loops.Balls, loops.Columns)):
            op = dataclasses.replace(op, ops=_map_puts(op.ops, change, counter))
        elif isinstance(op, loops.Put):
            op = change(counter[0], op)
            counter[0] += 1
        out.append(op)
    return tuple(out)


def _replace_outputs(ir, which, change):
    """ir with change(k, put) applied to the k-th store of the loop form's kernel `which`."""
    assert ir.loops is not None
    kernel = getattr(ir.loops, which)
    kernel = dataclasses.replace(kernel, ops=_map_puts(kernel.ops, change, [0]))
    return dataclasses.replace(ir, loops=dataclasses.replace(ir.loops, **{which: kernel}))


def _puts(ir, which) -> int:
    return sum(isinstance(op, loops.Put) for op in getattr(ir.loops, which).walk())


def test_the_committed_programs_pass(thesis2):
    _, system, ir = thesis2
    errors = check_programs(ir, system)
    assert set(errors) == {"rhs", "mass", "forcing", "jac", "jac_p"}
    assert errors["rhs"] < 1e-12 and errors["jac"] < 1e-7


@pytest.mark.parametrize("form", lowering.FORMS)
@pytest.mark.parametrize("make", [models.thesis_rotating, models.single_plane_fixed], ids=["thesis", "fixed"])
def test_a_wrong_sign_in_the_jacobian_lowering_is_refused(make, form, monkeypatch):
    spec = make(2)
    system = spec.system()
    monkeypatch.setattr(lowering, "_residual_rows", _residual_rows_with_wrong_sign)
    monkeypatch.setattr(loop_form._Kernels, "residuals", _loop_residuals_with_wrong_sign)
    ir = build_ir(spec, system, form=form)
    assert ir.form == form
    errors = program_errors(ir, system)
    assert errors["rhs"] < 1e-12 and errors["jac"] > 1e-3  # rhs untouched, the Jacobians wrong
    with pytest.raises(CheckFailed, match=rf"^{spec.name}: program jac differs from central differences"):
        check_programs(ir, system)


def test_regenerate_refuses_the_wrong_sign_before_writing(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(loop_form._Kernels, "residuals", _loop_residuals_with_wrong_sign)
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("untouched")
    code = cli.main(["regenerate", "--n", "2", "--family", "single-plane", "--skip-checks", "--quiet", "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code != 0
    assert len(err) == 1 and "program jac differs" in err[0], err
    assert sorted(p.name for p in out.iterdir()) == ["keep.txt"]


def test_a_transposed_mass_matrix_is_refused(thesis2):
    spec, system, ir = thesis2
    broken = _replace_outputs(ir, "mass", lambda k, put: dataclasses.replace(put, row=put.col, col=put.row))
    with pytest.raises(CheckFailed, match=rf"^{spec.name}: program mass differs from the symbolic M"):
        check_programs(broken, system)


def test_a_flipped_forcing_term_is_refused(thesis2):
    spec, system, ir = thesis2
    broken = _replace_outputs(ir, "forcing", lambda k, put: dataclasses.replace(put, expr=-put.expr) if k == 0 else put)
    with pytest.raises(CheckFailed, match=rf"^{spec.name}: program forcing differs"):
        check_programs(broken, system)


def test_a_dropped_factor_in_jac_p_is_refused(thesis2):
    spec, system, ir = thesis2
    last = _puts(ir, "jac_p") - 3  # a store of the ball loop's derivatives (the last two: the column solve)
    broken = _replace_outputs(ir, "jac_p", lambda k, put: dataclasses.replace(put, expr=put.expr * (1 + sp.Rational(1, 1000)))
                              if k == last else put)
    with pytest.raises(CheckFailed, match=rf"^{spec.name}: program jac_p differs"):
        check_programs(broken, system)


def test_a_wrong_oscillator_extension_is_refused():
    spec = models.single_plane_fixed(2)
    system = spec.system()
    ir = build_ir(spec, system)
    middle = _puts(ir.autonomous_extension, "jac") // 2
    ext = _replace_outputs(ir.autonomous_extension, "jac",
                           lambda k, put: dataclasses.replace(put, expr=2 * put.expr) if k == middle else put)
    with pytest.raises(CheckFailed, match=r"oscillator extension\): program jac differs"):
        check_programs(dataclasses.replace(ir, autonomous_extension=ext), system)


def test_an_overflowing_program_leaves_stderr_to_the_refusal():
    """A wrong program may overflow in the difference stencil: the NaN/inf it gives fails the comparison,
    and numpy warns nothing (the refusal is the one line on stderr; a mutant once added four)."""
    import warnings

    import numpy as np

    from adbgen.codegen.passes.checks import central_difference

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = central_difference(lambda z: np.array([1e308 * z[0] ** 3]), np.array([1e3]))
        assert not np.all(np.isfinite(d))  # the wrong value is still there for the comparison to refuse
        with pytest.raises(RuntimeWarning):  # negative control: unguarded, the same overflow warns
            np.array([1e308]) * np.array([1e3])
