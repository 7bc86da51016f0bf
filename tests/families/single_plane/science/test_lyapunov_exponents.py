"""The largest Lyapunov exponent from the variational equations (the thesis' "chaotic" Omega = 1.6 motion is
decided with it in docs/reproduction.md; the long runs are there, here the estimator on equilibria whose
exponent is known: the largest real part of the Jacobian's eigenvalues)."""

from __future__ import annotations

import numpy as np
import pytest

from adbgen.analysis.loading import load_model
from adbgen.families.single_plane.science.lyapunov_exponents import largest_exponent


@pytest.fixture(scope="module")
def model():
    return load_model("thesis_rotating_n2")


def _leading(model, y, p) -> float:
    return float(np.linalg.eigvals(np.asarray(model.module.jac(0.0, y, p))).real.max())


def test_at_the_stable_balanced_state_the_exponent_is_the_leading_decay_rate(model):
    p = model.params({"zeta": 0.05, "beta": 0.05})
    y = model.steady_state("1", p)
    lam = largest_exponent(model, p, y, t_transient=1.0, t_average=400.0)
    assert _leading(model, y, p) == pytest.approx(-0.0248, abs=1e-4)
    assert lam["exponent"] == pytest.approx(_leading(model, y, p), abs=0.004)
    assert lam["r_window"] < 1e-12  # it stayed at the equilibrium


def test_at_an_unstable_state_the_exponent_is_its_growth_rate(model):
    """Negative control of the sign: a saddle (3(1)+, one real eigenvalue 0.101) gives a positive exponent."""
    p = model.params({"zeta": 0.05, "beta": 0.05})
    y = model.steady_state("3(1)+", p)
    lam = largest_exponent(model, p, y, t_transient=1.0, t_average=100.0)
    assert _leading(model, y, p) == pytest.approx(0.1011, abs=1e-4)
    assert lam["exponent"] == pytest.approx(_leading(model, y, p), abs=0.03)
