"""The name registry (`codegen.ir.symbol_kinds`, issue 33 item 4): a symbol's kind is what its maker
registered, not what its name looks like."""

from __future__ import annotations

import pytest
import sympy as sp

from adbgen.codegen.ir import symbol_kinds as kinds
from adbgen.codegen.ir.loops import Let
from adbgen.codegen.spec import build
from adbgen.codegen.targets.taylor.series import NotSeries, _find_solve, _solve_symbols
from adbgen.families.single_plane import models


@pytest.fixture(scope="module")
def rhs():
    spec = models.thesis_rotating(2)
    return build(spec, spec.system()).kernels()["rhs"]


def test_the_loop_forms_solve_is_found_by_the_kinds_its_maker_gave(rhs):
    """The structured solve (thesis (A.9)-(A.13)) of the rhs kernel: its LU factors, forward and back
    substitution, registered by `loops`, found by `series._find_solve`, and checked as x = S^-1 g."""
    found = _find_solve(rhs.ops)
    assert found is not None
    lets = rhs.ops[found[0]:found[1]]
    assert {kinds.kind_of(op.sym) for op in lets} == set(kinds.SOLVE)
    S, g, x, factor = _solve_symbols(lets)
    assert [kinds.index_of(s) for s in x] == [(a,) for a in range(len(x))]
    assert all(kinds.kind_of(s) == kinds.SCHUR_RHS for s in g) and kinds.kind_of(S[0][0]) == kinds.SCHUR
    assert factor and all(kinds.kind_of(s) == kinds.SOLVE_FACTOR for s in factor)


def test_a_name_alone_does_not_make_a_solve_statement(rhs):
    """Negative control: statements named like the solve's but made by no one are not taken for it."""
    a, b = sp.symbols("unregistered_a unregistered_b", real=True)
    lookalikes = [Let(sp.Symbol("LU_1_0", positive=True), a / b), Let(sp.Symbol("xa_0", positive=True), a)]
    assert kinds.kind_of(lookalikes[0].sym) is None
    assert _find_solve(lookalikes) is None
    found = _find_solve(rhs.ops)
    lets = list(rhs.ops[found[0]:found[1]])
    # the back substitution's results renamed (same name, made by no one): no solve is recognised
    renamed = [Let(sp.Symbol(op.sym.name, positive=True), op.expr) if kinds.kind_of(op.sym) == kinds.SOLVE_RESULT
               else op for op in lets]
    with pytest.raises(NotSeries):
        _solve_symbols(renamed)


def test_a_symbol_is_made_as_one_kind_only():
    sym = kinds.make("test_kinds_s_0_1", kinds.SCHUR, 0, 1)
    assert kinds.make("test_kinds_s_0_1", kinds.SCHUR, 0, 1) is sym  # made again, the same way: fine
    with pytest.raises(ValueError, match="already a Schur complement"):
        kinds.make("test_kinds_s_0_1", kinds.SOLVE_RESULT, 0)
    with pytest.raises(ValueError, match="already a Schur complement"):
        kinds.make("test_kinds_s_0_1", kinds.SCHUR, 1, 0)
    with pytest.raises(ValueError, match="unknown symbol kind"):
        kinds.make("test_kinds_other", "temporary")
    with pytest.raises(KeyError):
        kinds.index_of(sp.Symbol("test_kinds_never_made", real=True))
