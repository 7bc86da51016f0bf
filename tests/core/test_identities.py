"""The identity test must say yes to true trigonometric identities and no to near misses."""

import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from adbgen.core import assert_identity, canonical_trig, is_identity

a, b, c = sp.symbols("a b c", real=True)


def test_true_identities():
    assert is_identity(sp.sin(a + b), sp.sin(a) * sp.cos(b) + sp.cos(a) * sp.sin(b))
    assert is_identity(sp.sin(a) ** 2 + sp.cos(a) ** 2, 1)
    assert is_identity(sp.cos(2 * a + b) * sp.cos(b) + sp.sin(2 * a + b) * sp.sin(b), sp.cos(2 * a))
    assert is_identity(1 / (1 + sp.sin(a)), (1 - sp.sin(a)) / sp.cos(a) ** 2)


def test_near_misses_are_rejected():
    assert not is_identity(sp.sin(a + b), sp.sin(a) * sp.cos(b) - sp.cos(a) * sp.sin(b))
    assert not is_identity(sp.sin(a) ** 2 + sp.cos(a) ** 2, 1 + sp.Rational(1, 10**12))
    assert not is_identity(sp.cos(a) ** 4, sp.cos(a) ** 2)


def test_assert_identity_names_what_failed():
    try:
        assert_identity(sp.sin(a), sp.cos(a), what="test row")
    except AssertionError as exc:
        assert "test row" in str(exc)
    else:
        raise AssertionError("assert_identity accepted sin = cos")


@settings(max_examples=30, deadline=None)
@given(st.integers(-3, 3), st.integers(-3, 3), st.integers(-3, 3))
def test_canonical_form_of_rotated_vectors(i, j, k):
    """cos(x)cos(y) + sin(x)sin(y) = cos(x - y) for integer combinations of angles."""
    x, y = i * a + j * b, k * c + a
    lhs = sp.cos(x) * sp.cos(y) + sp.sin(x) * sp.sin(y)
    assert canonical_trig(lhs - sp.cos(x - y)) == 0
    # cos(x + y) differs from cos(x - y) by 2 sin x sin y, which vanishes only if x or y is 0.
    assert is_identity(lhs, sp.cos(x + y)) == (sp.sin(x) * sp.sin(y) == 0)
