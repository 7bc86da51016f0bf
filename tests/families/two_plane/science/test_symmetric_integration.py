"""The race-symmetric two-plane integration keeps the race-exchange symmetry gamma_r bit-exact (issue 23).

Figure 12(a)'s set-up (static imbalance, chi = 0, equal balls) and start (balls at 0 and pi in both races,
rotor at rest) are gamma_r-symmetric.  With the rhs symmetrized under gamma_r (engines/symmetrized.py) every
output state satisfies S y = y exactly and the tilt is exactly 0; negative control: the same run with the
plain engine leaves the symmetric subspace by rounding (S y != y, a non-zero tilt).  At Omega = 4.4 B's
unstable multiplier is gamma_r-odd, so there the plain run's asymmetry grows.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbgen.analysis.engines.symmetrized import symmetric_parameters, symmetrized
from adbgen.analysis.loading import AnalysisError, load_model
from adbgen.analysis.simulate import simulate
from adbgen.families.two_plane.science import runs as tr


@pytest.fixture(scope="module")
def setup():
    m = load_model("two_plane_fixed")
    p = m.params({"epsilon": 1e-4, "chi": 0.0, "beta": 0.0, "Omega": 4.4, **tr._ball_values(1e-4, 0.01)})
    sym = next(s for s in m.symmetries if s["kind"] == "race-swap")
    y0 = m.state({"alpha_2": math.pi, "alpha_4": math.pi})
    return m, p, sym, y0


def _S(sym, Y):
    return np.asarray(sym["signs"], float)[:, None] * Y[list(sym["states"])]


def test_symmetric_start_stays_symmetric_bit_for_bit(setup):
    m, p, sym, y0 = setup
    assert symmetric_parameters(m, sym, p) and np.array_equal(_S(sym, y0[:, None])[:, 0], y0)
    sim = simulate(m, p, y0, t_end=400.0, rtol=1e-9, atol=1e-14, engine=symmetrized("cyrk-dop853", m, "race-swap"))
    assert sim.y.shape[1] > 1000
    assert np.array_equal(_S(sym, sim.y), sim.y)
    assert not np.any(sim.y[m.index("phi_X")]) and not np.any(sim.y[m.index("phi_Y")])


def test_negative_control_the_plain_engine_leaves_the_symmetric_subspace(setup):
    m, p, sym, y0 = setup
    sim = simulate(m, p, y0, t_end=400.0, rtol=1e-9, atol=1e-14, engine="cyrk-dop853")
    assert not np.array_equal(_S(sym, sim.y), sim.y)
    assert np.abs(sim.y[m.index("phi_X")]).max() > 0.0


def test_symmetrizing_asymmetric_parameters_is_refused(setup):
    m, p, sym, y0 = setup
    q = p.copy()
    q[m.param_names.index("chi")] = 1e-5
    with pytest.raises(AnalysisError, match="not symmetric"):
        simulate(m, q, y0, t_end=1.0, engine=symmetrized("cyrk-dop853", m, "race-swap"))


def test_figure_12a_uses_the_symmetrized_engine_and_12b_the_plain_one(setup):
    m, p, sym, y0 = setup
    assert getattr(tr.engine_for(m, p), "name", "") == "cyrk-dop853+race-swap"
    q = m.params({"epsilon": 5e-5, "chi": 5e-5, "beta": 1.0, "Omega": 4.4, **tr._ball_values(1e-4, 0.01)})
    assert tr.engine_for(m, q) == "cyrk-dop853"
