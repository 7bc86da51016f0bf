"""The tail fits that decide a run not named at t_end (adbgen/analysis/approach.py), on synthetic r(t):
an exponential decay, r ~ 1/t, a band (a limit cycle) and a drift, each with its oscillation of r inside."""

import math

import numpy as np
import pytest

from adbgen.analysis.approach import tail, windings

T = np.linspace(3000.0, 6000.0, 200_001)
WOBBLE = 1.0 + 0.3 * np.cos(4.0 * T) ** 2  # r oscillates at about the spin inside its envelope


def test_an_exponential_decay_is_exponential_with_its_rate():
    fit = tail(T, 1e-4 * np.exp(-2.1e-3 * (T - T[0])) * WOBBLE)
    assert (fit.trend, fit.kind) == ("decays", "exponential")
    assert fit.rate == pytest.approx(-2.1e-3, rel=0.02)
    assert fit.residual_exponential < 0.5 * fit.residual_algebraic


def test_r_like_one_over_t_is_algebraic_with_exponent_one():
    fit = tail(T, 0.3 / T * WOBBLE)
    assert (fit.trend, fit.kind) == ("decays", "algebraic")
    assert fit.exponent == pytest.approx(1.0, abs=0.02)
    # negative control: the same data as an exponential in t is not mistaken for one
    assert tail(T, 0.3 * np.exp(-(T - T[0]) / T[0]) * WOBBLE).kind == "exponential"


def test_a_band_is_a_band_and_a_drift_is_not_a_decay():
    assert tail(T, 0.2 * WOBBLE).trend == "band"
    grows = tail(T, 1e-4 * (T / T[0]) ** 0.5 * WOBBLE)
    assert grows.trend == "grows" and grows.kind == ""
    # falls, then rises again: still drifting, never a decay
    dip = tail(T, 1e-4 * (1.0 + 0.5 * np.sin(2 * math.pi * (T - T[0]) / 3000.0)) * WOBBLE)
    assert dip.trend == "irregular" and dip.kind == ""


def test_the_tail_needs_times_from_the_launch():
    with pytest.raises(ValueError):
        tail(T - T[0], 0.3 / T)


def test_windings_count_whole_turns_of_a_lapping_ball():
    t = np.linspace(0.0, 100.0, 10_001)
    angles = np.vstack([np.remainder(-0.2 * t + math.pi, 2 * math.pi) - math.pi, 0.1 * np.sin(t)])
    assert windings(angles).tolist() == [-3, 0]  # 20 rad: three whole turns back; the second only rocks
