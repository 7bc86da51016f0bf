"""Closed-form steady states (3.6), (3.9), (3.10) are exact zeros of the derived equations; their
existence conditions (3.14)-(3.18) and the numbers printed in chapters 3-5 are reproduced."""

import math

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from adbgen.families.single_plane import steady_states as ss
from adbgen.families.single_plane import verify
from adbgen.families.single_plane.reductions import rotating_frame
from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane.symbols import Omega, delta, mu, zeta


@pytest.mark.parametrize("n", (1, 2, 3, 4, 6))
def test_every_closed_form_state_is_an_exact_zero(n):
    result = verify.steady_states(n)
    assert result.passed, result.detail


@pytest.mark.parametrize("n", (2, 5))
def test_the_proportionate_check_passes_and_can_fail(n):
    """regenerate's numeric form of the check (issue 10, above FULL_CHECKS_MAX_N): the same states in
    50-digit arithmetic; with the first angle turned by 1/10 rad every one of them is refused."""
    result = verify.steady_states_numeric(n)
    assert result.passed, result.detail
    wrong = verify.steady_states_numeric(n, wrong=True)
    assert not wrong.passed and wrong.detail.count("'") == 2 * (2 * (n - 1) + 3)


def test_the_family_runs_the_proportionate_form_above_the_limit():
    from adbgen.families.single_plane import models

    small = {c.key[1]: c for c in models.thesis_rotating(verify.FULL_CHECKS_MAX_N).checks}
    large = {c.key[1]: c for c in models.thesis_rotating(verify.FULL_CHECKS_MAX_N + 1).checks}
    assert all(c.scaled is None for c in small.values())
    assert large["steady_states"].scaled is not None and large["rotating"].scaled is None


def test_a_perturbed_state_is_not_steady():
    eom = rotating_frame(Scene(n=3))
    state = ss.inline(3, 2, 1)
    x = sp.Symbol("x", real=True)
    assert ss.is_steady_state(eom, state)
    assert not ss.is_steady_state(eom, {**state, x: state[x] * (1 + delta)})
    balanced = ss.balanced(3, [sp.pi])
    phi2 = sp.Symbol("phi_2", real=True)
    assert not ss.is_steady_state(eom, {**balanced, phi2: -balanced[phi2]})


@pytest.mark.parametrize("result", verify.thesis_numbers(), ids=lambda r: r.name)
def test_numbers_printed_in_the_thesis(result):
    assert result.passed, result.detail


def test_critical_speeds_are_where_the_arccos_argument_reaches_one():
    for n, m in ((3, 3), (3, 2), (4, 3)):
        w = ss.arccos_argument(n, m)
        for Om in ss.critical_speeds(n, m, 0.05, 0.01, 0.01):
            value = float(w.subs({mu: 0.05, zeta: 0.01, delta: 0.01, Omega: Om}))
            assert abs(abs(value) - 1) < 1e-12


@settings(max_examples=200, deadline=None)
@given(n=st.integers(1, 6), data=st.data(), mu_=st.floats(1e-3, 0.2), Om=st.floats(0.05, 5.0),
       zeta_=st.floats(1e-3, 0.3), delta_=st.floats(1e-3, 0.2))
def test_existence_condition_equals_real_state(n, data, mu_, Om, zeta_, delta_):
    """(3.16)/(3.18) hold exactly when the arccos argument of (3.9)/(3.10) lies in [-1, 1]."""
    m = data.draw(st.integers(1, n))
    w = float(ss.arccos_argument(n, m).subs({mu: mu_, zeta: zeta_, delta: delta_, Omega: Om}))
    exists = ss.inline_exists(n, m, mu_, Om, zeta_, delta_)
    if abs(abs(w) - 1) > 1e-9:  # away from the boundary itself, where rounding decides
        assert exists == (abs(w) <= 1)


@settings(max_examples=50, deadline=None)
@given(n=st.integers(2, 6), mu_=st.floats(1e-3, 0.2), delta_=st.floats(1e-3, 0.2))
def test_balanced_condition_3_14_for_pi_free_balls(n, mu_, delta_):
    """With phi_3.. = pi, (3.6) needs cos phi_1 + cos phi_2 = A = n - 2 - delta/mu: real iff |A| <= 2."""
    real = True
    try:
        ss.evaluate(ss.balanced(n, [sp.pi] * (n - 2)), {"mu": mu_, "delta": delta_})
    except ValueError:
        real = False
    A = n - 2 - delta_ / mu_
    if abs(abs(A) - 2) > 1e-9:
        assert real == (abs(A) <= 2)
        if n == 2:  # (3.14) is then necessary and sufficient
            assert real == ss.balanced_exists(n, mu_, delta_)


def test_wedge_tip_is_double_root():
    """At mu = delta/(2m - n) the two critical speeds meet at K = 0, (4.1)-(4.4)."""
    for n, m in ((2, 2), (3, 3), (3, 2), (4, 3)):
        mu_tip, om = ss.wedge_tip(n, m, 0.01)
        assert math.isclose(1 - om**2 * (1 + n * mu_tip), 0, abs_tol=1e-15)
        near = ss.critical_speeds(n, m, mu_tip * (1 + 1e-8), 0.01, 0.01)
        assert near is not None and abs(near[0] - om) < 1e-3 and abs(near[1] - om) < 1e-3
        assert ss.critical_speeds(n, m, mu_tip * (1 - 1e-3), 0.01, 0.01) is None
