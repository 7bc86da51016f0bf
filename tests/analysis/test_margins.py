"""Stability margins and what the computation can certify (issue 34 item 5, adbgen/analysis/margins.py):
planted spectra and multipliers near the boundary, with the verdicts the old fixed thresholds gave."""

from __future__ import annotations

import numpy as np
import pytest

from adbgen.analysis import margins
from adbgen.analysis.orbits.orbit import UNIT_TOL, PeriodicOrbit


def _rotation(a: float, w: float = 1.0) -> np.ndarray:
    return np.array([[a, w], [-w, a]])


def test_a_margin_near_zero_is_marginal_and_a_clear_one_is_not():
    far = margins.eigenvalue_margin(_rotation(-1e-3))
    near = margins.eigenvalue_margin(_rotation(-1e-17))
    assert far.value == pytest.approx(-1e-3) and not far.marginal and far.uncertainty < 1e-14
    assert near.marginal and abs(near.value) <= near.uncertainty


def test_the_uncertainty_grows_with_the_eigenvalue_condition_number():
    """A non-normal matrix (an eigenvalue ill-conditioned: kappa ~ 1e8) with the same margin as a normal one:
    the normal one is certified, the non-normal one is marginal (its eigenvalue is not known to 1e-9)."""
    normal = np.diag([-1e-9, -1.0])
    skew = np.array([[-1e-9, 1e8], [0.0, -1e-9 - 1e-8]])
    assert not margins.eigenvalue_margin(normal).marginal
    m = margins.eigenvalue_margin(skew)
    assert m.value == pytest.approx(-1e-9, rel=1e-3) and m.marginal


def test_the_state_error_enters_the_uncertainty():
    """The linearisation at the state moved by its Newton error changes the leading real part: the bound says so."""
    A = _rotation(-1e-6)
    assert not margins.eigenvalue_margin(A).marginal
    assert margins.eigenvalue_margin(A, _rotation(-1e-6 + 2e-6)).marginal


def _orbit(moduli, trivial_error: float = 1e-10) -> PeriodicOrbit:
    mu = np.array([1.0 + trivial_error, *moduli], complex)
    return PeriodicOrbit(None, np.zeros(1), np.zeros(len(mu)), 1.0, {}, mu, 0, 0.0, 0, np.zeros((1, len(mu))), False,
                         monodromy=np.diag(mu.real))


def test_an_orbit_just_inside_the_unit_circle_is_stable_not_unstable():
    """|mu|max = 1 - 1.5e-7: the old rule |mu| <= 1 - 1e-6 called it unstable; its margin is certified (the
    trivial multiplier is 1 to 1e-10) and it is stable, not marginal."""
    o = _orbit([1 - 1.5e-7, 0.5])
    assert not (abs(1 - 1.5e-7) <= 1 - UNIT_TOL)  # what the fixed threshold said
    assert o.stable and o.n_unstable == 0 and not o.margin.marginal
    assert o.margin.value == pytest.approx(-1.5e-7, rel=1e-6)
    assert o.margin.to_json()["margin"] == pytest.approx(-1.5e-7, rel=1e-6) and o.margin.to_json()["marginal"] is False


def test_an_orbit_inside_its_accuracy_is_marginal_and_neither_verdict_is_certified():
    """Negative control: the same orbit computed less accurately (trivial multiplier off by 1e-6) cannot tell
    1 - 1.5e-7 from 1: marginal, not called stable."""
    o = _orbit([1 - 1.5e-7, 0.5], trivial_error=1e-6)
    assert o.margin.marginal and not o.stable and o.n_unstable == 0
    assert _orbit([1 + 1e-3, 0.5]).n_unstable == 1 and not _orbit([1 + 1e-3, 0.5]).stable


def test_a_verdict_inside_the_uncertainty_says_marginal_with_its_side_and_a_certified_one_is_kept():
    """The headline `adbgen stability` prints (docs/flexible.md's response: |mu| - 1 = 5.7e-6, certain to 8.4e-5
    only, was headed "unstable").  Negative control: a margin outside its uncertainty keeps its classification."""
    flexible = margins.Margin(5.7e-6, 8.4e-5, "")
    assert flexible.verdict("unstable") == "marginal (unstable by 5.7e-06, uncertain to 8.4e-05)"
    assert margins.Margin(-1.2e-8, 3.1e-8, "").verdict("stable") == "marginal (stable by 1.2e-08, uncertain to 3.1e-08)"
    assert margins.Margin(0.0, 1e-12, "").verdict("neutral") == "marginal (on the boundary, uncertain to 1e-12)"
    assert margins.Margin(5.7e-6, 1e-7, "").verdict("unstable") == "unstable"


def test_widening_a_margin_adds_to_its_uncertainty_and_says_why():
    m = margins.Margin(-1.2e-8, 4.3e-9, "rounding").widened(2.7e-8, "location")
    assert m.uncertainty == pytest.approx(3.13e-8) and m.marginal and m.how == "rounding; location"
    assert not margins.Margin(-1.2e-8, 4.3e-9, "rounding").marginal
