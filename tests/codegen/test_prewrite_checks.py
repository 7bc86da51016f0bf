"""`regenerate`'s pre-write checks see every program: rhs, jac, jac_p, mass_matrix and forcing of the
lowered model against evaluations that do not go through the lowering (issue 13, item 1).

The mutations are the issue's: `row -= entry*acc[j]` turned into `+=` in the Jacobian lowering
(monkeypatched), and one-line changes of the programs themselves (a transposed M, a flipped forcing
term, a dropped factor in jac_p).  Each must be refused with one line naming the program, before
anything is written.
"""

from __future__ import annotations

import dataclasses

import pytest
import sympy as sp

from adbgen import cli
from adbgen.codegen import lowering
from adbgen.codegen.checks import CheckFailed, check_programs, program_errors
from adbgen.families.single_plane import models


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
    return spec, system, spec.build(system)


def _replace_outputs(ir, which, change):
    program = getattr(ir, which)
    return dataclasses.replace(ir, **{which: dataclasses.replace(program, outputs=tuple(change(list(program.outputs))))})


def test_the_committed_programs_pass(thesis2):
    _, system, ir = thesis2
    errors = check_programs(ir, system)
    assert set(errors) == {"rhs", "mass", "forcing", "jac", "jac_p"}
    assert errors["rhs"] < 1e-12 and errors["jac"] < 1e-7


@pytest.mark.parametrize("make", [models.thesis_rotating, models.single_plane_fixed], ids=["thesis", "fixed"])
def test_a_wrong_sign_in_the_jacobian_lowering_is_refused(make, monkeypatch):
    spec = make(2)
    system = spec.system()
    monkeypatch.setattr(lowering, "_residual_rows", _residual_rows_with_wrong_sign)
    ir = spec.build(system)
    errors = program_errors(ir, system)
    assert errors["rhs"] < 1e-12 and errors["jac"] > 1e-3  # rhs untouched, the Jacobians wrong
    with pytest.raises(CheckFailed, match=rf"^{spec.name}: program jac differs from central differences"):
        check_programs(ir, system)


def test_regenerate_refuses_the_wrong_sign_before_writing(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(lowering, "_residual_rows", _residual_rows_with_wrong_sign)
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
    N = ir.n_coordinates
    broken = _replace_outputs(ir, "mass", lambda outs: [((i % N) * N + i // N, e) for i, e in outs])
    with pytest.raises(CheckFailed, match=rf"^{spec.name}: program mass differs from the symbolic M"):
        check_programs(broken, system)


def test_a_flipped_forcing_term_is_refused(thesis2):
    spec, system, ir = thesis2
    broken = _replace_outputs(ir, "forcing", lambda outs: [(i, -e if k == 0 else e) for k, (i, e) in enumerate(outs)])
    with pytest.raises(CheckFailed, match=rf"^{spec.name}: program forcing differs"):
        check_programs(broken, system)


def test_a_dropped_factor_in_jac_p_is_refused(thesis2):
    spec, system, ir = thesis2
    broken = _replace_outputs(ir, "jac_p", lambda outs: [(i, e * (1 + sp.Rational(1, 1000)) if k == len(outs) - 1 else e)
                                                          for k, (i, e) in enumerate(outs)])
    with pytest.raises(CheckFailed, match=rf"^{spec.name}: program jac_p differs"):
        check_programs(broken, system)


def test_a_wrong_oscillator_extension_is_refused():
    spec = models.single_plane_fixed(2)
    system = spec.system()
    ir = spec.build(system)
    ext = _replace_outputs(ir.autonomous_extension, "jac",
                           lambda outs: [(i, 2 * e if k == len(outs) // 2 else e) for k, (i, e) in enumerate(outs)])
    with pytest.raises(CheckFailed, match=r"oscillator extension\): program jac differs"):
        check_programs(dataclasses.replace(ir, autonomous_extension=ext), system)
