"""Equivariance (13)-(14): exact for the symmetric set-up; property tests over random parameters and states."""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from adbgen.families.two_plane import verify
from adbgen.families.two_plane.reductions import rotating_frame
from adbgen.families.two_plane.scene import TwoPlaneScene
from adbgen.families.two_plane.symmetry import NumericEquivariance


def test_symbolic_equivariance_and_gamma_r_broken_by_chi():
    result = verify.equivariance()
    assert result.passed, result.detail


@pytest.fixture(scope="module")
def numeric():
    return NumericEquivariance(rotating_frame(TwoPlaneScene()))


positive = st.floats(0.1, 5.0)
small = st.floats(1e-4, 0.05)


def _parameters(numeric, d, chi=0.0, m2=None):
    values = {"M": d["M"], "J_t": d["Jt"], "J_p": d["Jp"], "epsilon": d["eps"], "beta": d["beta"], "chi": chi,
              "l_1": d["l"], "l_2": d["l"], "k_1": d["k"], "k_2": d["k"], "c_1": d["c"], "c_2": d["c"],
              "R_t": d["R"], "R_b": d["R"], "z_t": d["z"], "z_b": -d["z"], "c_bt": d["cb"], "c_bb": d["cb"],
              "m_1": d["m"], "m_2": d["m"] if m2 is None else m2, "m_3": d["m"], "m_4": d["m"], "Omega": d["Om"]}
    return np.array([values[n] for n in numeric.parameter_names])


draws = st.fixed_dictionaries({"M": positive, "Jt": positive, "Jp": positive, "eps": small, "beta": st.floats(-3, 3),
                               "l": positive, "k": positive, "c": st.floats(0, 0.5), "R": positive, "z": positive,
                               "cb": st.floats(0, 0.1), "m": small, "Om": positive})
states = st.lists(st.floats(-2.0, 2.0), min_size=16, max_size=16).map(np.array)


@settings(max_examples=40, deadline=None)
@given(d=draws, u=states)
def test_static_imbalance_is_d4_equivariant(numeric, d, u):
    p = _parameters(numeric, d)
    for g in ("gamma_12", "gamma_34", "gamma_r"):
        assert numeric.residue(g, u, p) <= 1e-12, g


@settings(max_examples=40, deadline=None)
@given(d=draws, u=states, chi=st.floats(1e-3, 0.1), sign=st.sampled_from([-1, 1]))
def test_misalignment_leaves_only_d2(numeric, d, u, chi, sign):
    """gamma_12, gamma_34 hold; gamma_r fails (residue >= 1e-9) once chi != 0 (the couple imbalance
    chi (J_t - J_p) vanishes when J_t = J_p, so those draws are excluded)."""
    assume(abs(d["Jt"] - d["Jp"]) > 0.1)
    p = _parameters(numeric, d, chi=sign * chi)
    for g in ("gamma_12", "gamma_34"):
        assert numeric.residue(g, u, p) <= 1e-12, g
    assert numeric.residue("gamma_r", u, p) >= 1e-9


@settings(max_examples=20, deadline=None)
@given(d=draws, u=states, extra=st.floats(1e-3, 0.05))
def test_unequal_balls_break_gamma_12_only(numeric, d, u, extra):
    p = _parameters(numeric, d, m2=d["m"] + extra)
    assert numeric.residue("gamma_12", u, p) >= 1e-9
    assert numeric.residue("gamma_34", u, p) <= 1e-12
