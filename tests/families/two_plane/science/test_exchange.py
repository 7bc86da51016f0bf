"""The B/C3 exchange of paper 3.2.3 on the generated two_plane_rotating (the two-plane science's exchange)."""

import math

import numpy as np
import pytest

from adbgen.families.two_plane.science import exchange as tx
from adbgen.analysis.loading import load_model
from adbgen.families.two_plane import critical_speeds as cs
from adbgen.families.two_plane import models


@pytest.fixture(scope="module")
def pitchfork():
    return tx.Pitchfork(load_model(tx.MODEL), {"c_1": 0.0, "c_2": 0.0})


@pytest.fixture(scope="module")
def closed_form():
    """(32)'s critical speeds at m = m_c = 0.0025 (balls frozen) and (11)'s (plain rotor), SymPy route."""
    sc = models.scene(m=0.0025)
    return cs.critical_speeds(sc, with_balls=True), cs.critical_speeds(sc, with_balls=False)


def test_exchange_speeds_are_the_critical_speeds_of_32(pitchfork, closed_form):
    """kappa's zero and pole (the paper's branch method on the generated code) = (32) at m_c to 1e-6;
    the plain rotor's (11) (1, 1.809068) is more than 1e-3 away, so the tolerance discriminates."""
    with_balls, plain = closed_form
    ours = pitchfork.exchange_speeds()
    assert np.allclose(ours, with_balls, atol=1e-6, rtol=0)
    assert np.all(np.abs(np.array(ours) - plain) > 1e-3)
    assert np.allclose(tx.frozen_critical_speeds(pitchfork), with_balls, atol=1e-9, rtol=0)


def test_kappa_by_branches_equals_32(pitchfork):
    """a_1 + a_2 = M eps/(8R) (23) and kappa = z^2 (1 - (W/W_cyl)^2) / (l^2 (1 - (W/W_con)^2)) (32)."""
    mc = pitchfork.m_c
    for w in (0.6, 1.3, 2.5):
        a1, a2 = pitchfork.coefficients(w)
        assert a1 + a2 == pytest.approx(0.01 / 8, rel=1e-7)
        kappa = (4 / 9) * (1 - w**2 * (1 + 4 * mc)) / (1 - w**2 * (2.75 + 16 * mc) / 9)
        assert pitchfork.kappa(w) == pytest.approx(kappa, rel=1e-6)


def test_race_swap_commutes_at_B_and_splits_the_slow_modes(pitchfork):
    model = pitchfork.model
    P = tx.race_swap(model)
    damped = tx.Pitchfork(model, {})
    m = damped.m_c * 1.001
    a = math.acos(damped.m_c / m)
    y = damped.state([math.pi + a, math.pi - a] * 2)
    J = np.asarray(model.module.jac(0.0, y, damped.params(m, Omega=1.3)))
    assert np.abs(P @ J - J @ P).max() < 1e-12
    wrong = np.abs(P)  # the tilt not reversed: not a symmetry
    assert np.abs(wrong @ J - J @ wrong).max() > 1e-3
    # between the critical speeds B is unstable towards C3 (odd mode) and stable in the symmetric one
    # above Omega_cyl; above Omega_con both slow modes are stable (paper 3.2.3)
    between, above = damped.slow_spectrum(1.3), damped.slow_spectrum(2.2)
    assert between["odd"].real > 0 > between["even"].real
    assert above["odd"].real < 0 and above["even"].real < 0
