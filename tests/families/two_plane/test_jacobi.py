"""The two-plane Jacobi integral (isotropic, rotating frame, constant speed): exact rate identity and
conservation along a trajectory without damping."""

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from adbgen.errors import ReductionError
from adbgen.core import is_identity
from adbgen.core.numeric import NumericFirstOrder
from adbgen.families.two_plane import verify
from adbgen.families.two_plane.jacobi import rotating_lagrangian, undamped
from adbgen.families.two_plane.reductions import first_order, rotating_frame
from adbgen.families.two_plane.scene import TwoPlaneScene

SCENE = TwoPlaneScene.from_mapping({"misalignment": 0.002, "imbalance_phase": 0.3,
                                    "bearing_1": {"position": 9.0, "stiffness": 0.7, "damping": 0.02}})


def test_two_routes_and_rate_identity():
    result = verify.jacobi_identity()
    assert result.passed, result.detail


def test_rate_identity_would_catch_a_wrong_integral():
    rl = rotating_lagrangian(SCENE)
    _, rate = rl.jacobi_rate_identities()
    assert is_identity(rate)
    assert not is_identity(rate + sp.Symbol("x_dot", real=True) ** 3)


def test_anisotropic_supports_have_no_autonomous_lagrangian():
    with pytest.raises(ReductionError, match="anisotropic"):
        rotating_lagrangian(TwoPlaneScene.preset("paper-43"))


def _h_run(scene, damping: bool, t_end: float = 100.0):
    rl = rotating_lagrangian(scene)
    eom = rotating_frame(scene)
    if not damping:
        eom = eom.map(lambda e: e.xreplace(undamped(scene)))
    fo = first_order(eom)
    f = NumericFirstOrder(fo)
    h = sp.lambdify([list(fo.states), [p.symbol for p in fo.parameters]], rl.jacobi_integral())
    rng = np.random.default_rng(7)
    y0 = np.concatenate([rng.normal(0, 0.05, 4), rng.uniform(-np.pi, np.pi, 4), rng.normal(0, 0.05, 4),
                         rng.normal(0, 0.1, 4)])
    sol = solve_ivp(f, (0, t_end), y0, args=(f.defaults,), method="DOP853", rtol=1e-12, atol=1e-14)
    assert sol.success
    return np.array([h(sol.y[:, i], f.defaults) for i in range(sol.y.shape[1])])


def test_h_conserved_without_damping():
    """c = c_b = 0, DOP853 at rtol 1e-12: |h(t) - h(0)| <= 1e-9 |h(0)| over 100 time units (three to four
    whirl periods of the slowest mode at Omega = 3)."""
    hs = _h_run(SCENE, damping=False)
    assert abs(hs[0]) > 1e-3
    assert np.max(np.abs(hs - hs[0])) <= 1e-9 * abs(hs[0])


def test_h_drifts_with_damping():
    """Control: with the scene's damping h is not conserved (change > 1e-6 relative)."""
    hs = _h_run(SCENE, damping=True)
    assert np.max(np.abs(hs - hs[0])) > 1e-6 * abs(hs[0])
