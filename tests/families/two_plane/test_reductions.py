"""Rotating frame (7)-(8), balanced condition (9), single-plane limit, first-order core, oscillator (40)."""

import numpy as np
import pytest
import sympy as sp

from adbgen.errors import ReductionError
from adbgen.core import is_identity
from adbgen.references import two_plane_2011 as paper
from adbgen.families.two_plane import verify
from adbgen.families.two_plane.reductions import autonomous_extension, first_order, rotating_frame
from adbgen.families.two_plane.scene import TwoPlaneScene
from adbgen.families.two_plane.symbols import TwoPlaneSymbols
from adbgen.families.two_plane.transient import fixed_frame_rhs, simulate
from adbgen.core.numeric import NumericFirstOrder


@pytest.mark.parametrize("check", [verify.rotating, verify.balanced_condition, verify.balanced_state_b, verify.single_plane,
                                   lambda: verify.single_plane("constant"), verify.oscillator],
                         ids=["7-8", "9", "B-9", "single-plane-torque", "single-plane-constant", "40"])
def test_reduction_matches_paper(check):
    result = check()
    assert result.passed, result.detail


def test_rotating_frame_comparison_can_fail():
    """Negative control: drop the gyroscopic term of (7) and the comparison must fail."""
    scene = TwoPlaneScene()
    eom, s = rotating_frame(scene), TwoPlaneSymbols.for_scene(scene)
    ref = paper.rotating_frame(s, scene.n)
    from adbgen.families.two_plane.reductions import rotating_complex_rows

    r2 = rotating_complex_rows(eom)[1]
    py, px = sp.Symbol("phi_y_dot", real=True), sp.Symbol("phi_x_dot", real=True)
    wrong = ref["r2"] + sp.I * s.Omega * s.Jp * (py - sp.I * px)  # remove -i Omega G r'
    assert verify._split_identity(r2, ref["r2"])
    assert not verify._split_identity(r2, wrong)


@pytest.mark.parametrize("bad, message", [
    ({"preset": "paper-43"}, "anisotropic"),
    ({"speed": {"law": "torque"}}, "varying spin"),
])
def test_rotating_frame_refuses_non_autonomous_scenes(bad, message):
    with pytest.raises(ReductionError, match=message):
        rotating_frame(TwoPlaneScene.from_mapping(bad))


@pytest.mark.parametrize("law, core", [("torque", ("X", "Y", "phi_X", "phi_Y", "theta_0")),
                                       ("constant", ("X", "Y", "phi_X", "phi_Y"))])
def test_first_order_core_and_solve(law, core):
    """4x4 core (5x5 with the torsion); the structured solve equals a dense numeric solve of M q'' = f."""
    scene = verify.general_scene(law)
    from adbgen.families.two_plane.model import derive

    eom = derive(scene)
    fo = first_order(eom)
    assert tuple(eom.coordinates[i].name for i in fo.solve.core) == core
    f = NumericFirstOrder(fo)
    rng = np.random.default_rng(3)
    y = np.concatenate([rng.normal(0, 0.01, 4), rng.uniform(-3, 3, f.n - 4), rng.normal(0, 0.1, f.n)])
    params = [p.symbol for p in eom.parameters]
    coords = eom.coordinates
    lam = sp.lambdify((sp.Symbol("t", real=True), [c.q for c in coords], [c.qd for c in coords], params),
                      [eom.mass_matrix(), sp.Matrix(eom.forcing)])
    Mn, fn = (np.array(a, dtype=float) for a in lam(0.7, y[:f.n], y[f.n:], f.defaults))
    dense = np.linalg.solve(Mn, fn.ravel())
    assert np.allclose(f(0.7, y)[f.n:], dense, rtol=1e-10, atol=1e-13)


def test_oscillator_extension_reproduces_the_forced_system():
    """Anisotropic (43): integrating the autonomous extension from (s, c) = (0, 1) gives the forced solution
    (max difference <= 1e-8 over 30 time units, rtol 1e-11)."""
    from dataclasses import replace

    from scipy.integrate import solve_ivp

    from adbgen.core import Parameter
    from adbgen.families.two_plane.reductions import osc_c, osc_s

    scene = TwoPlaneScene.from_mapping({"preset": "paper-43", "misalignment": 0.002})
    ext = autonomous_extension(scene)
    eom = replace(ext.eom, parameters=ext.eom.parameters + (Parameter(osc_s, "s", "-", 0.0),
                                                            Parameter(osc_c, "c", "-", 1.0)))
    f = NumericFirstOrder(first_order(eom))
    Om = TwoPlaneSymbols.for_scene(scene).Omega
    osc = sp.lambdify([osc_s, osc_c, Om], list(ext.oscillator))
    i_s, i_c, i_om = (f.parameter_names.index(n) for n in ("osc_sin", "osc_cos", "Omega"))

    def rhs(t, y):
        p = f.defaults.copy()
        p[i_s], p[i_c] = y[-2], y[-1]
        return np.concatenate([f(t, y[:-2], p), osc(y[-2], y[-1], p[i_om])])

    y0 = np.zeros(2 * f.n)
    y0[f.index("theta_3")] = y0[f.index("theta_4")] = np.pi
    grid = np.linspace(0, 30, 61)
    ext_run = solve_ivp(rhs, (0, 30), np.concatenate([y0, [0.0, 1.0]]), method="DOP853", rtol=1e-11, atol=1e-14,
                        t_eval=grid)
    forced = simulate(fixed_frame_rhs(scene), y0, (0, 30), t_eval=grid, rtol=1e-11)
    assert ext_run.success
    assert np.abs(ext_run.y[:-2] - forced.y).max() <= 1e-8


def test_first_order_size_is_affine_in_the_number_of_balls():
    """Each ball adds the same number of operations to the structured first-order form (rotating frame,
    1, 2, 3 balls per race): no symbolic inverse, no ball-ball coupling."""
    sizes = []
    for n in (1, 2, 3):
        race = lambda z: {"z": z, "radius": 1.0, "masses": [0.001] * n, "damping": 1e-5}  # noqa: E731
        scene = TwoPlaneScene.from_mapping({"races": [race(2.0), race(-2.0)]})
        sizes.append(first_order(rotating_frame(scene)).count_ops())
    assert sizes[2] - sizes[1] == sizes[1] - sizes[0] > 0, sizes
