"""Each reduction equals the thesis' printed form (errata corrected), and the reductions agree."""

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from adbgen.errors import ReductionError
from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane import verify
from adbgen.families.single_plane.model import derive
from adbgen.core.numeric import NumericFirstOrder
from adbgen.families.single_plane.reductions import (first_order, nondimensionalise, rotating_frame, rotating_frame_dimensional,
                                           thesis_chain)

NS = (1, 2, 3, 4, 6)


@pytest.mark.parametrize("n", NS)
@pytest.mark.parametrize("check", [verify.nondimensional, verify.rotating, verify.two_routes, verify.appendix_a],
                         ids=["2.20-2.22", "2.25-2.27", "two-routes", "appendix-A"])
def test_reduction_matches_thesis(check, n):
    result = check(n)
    assert result.passed, result.detail


def test_appendix_a_full_closed_form_for_n_3():
    result = verify.appendix_a(3, full_solve_up_to=3)
    assert result.passed, result.detail


@pytest.mark.parametrize("bad, message", [
    ({"ball_mass": [0.05, 0.06]}, "equal balls"),
    ({"stiffness": [1e4, 2e4]}, "isotropic"),
    ({"speed": {"law": "torque"}}, "constant speed"),
])
def test_reductions_refuse_scenes_they_do_not_apply_to(bad, message):
    with pytest.raises(ReductionError, match=message):
        nondimensionalise(Scene.from_mapping({"n": 2, **bad}))


def test_rotating_frame_refuses_gravity():
    with pytest.raises(ReductionError, match="gravity"):
        rotating_frame(Scene(n=2, gravity=True))


@settings(max_examples=20, deadline=None)
@given(st.permutations(range(4)), st.lists(st.floats(-3, 3), min_size=12, max_size=12))
def test_ball_permutation_equivariance(perm, values):
    """Relabelling identical balls maps solutions to solutions: F(P y) = P F(y)."""
    f = _numeric(4)
    y = np.array(values)
    idx = list(range(2)) + [2 + p for p in perm]
    P = np.array(idx + [6 + i for i in idx])
    assert np.allclose(f(0.0, y[P]), f(0.0, y)[P], rtol=1e-12, atol=1e-12)


_CACHE = {}


def _numeric(n):
    if n not in _CACHE:
        _CACHE[n] = NumericFirstOrder(thesis_chain(n)["first_order"])
    return _CACHE[n]


def test_fixed_and_rotating_frame_trajectories_agree():
    """The same thesis scene simulated in the dimensional fixed frame and in the rotating frame.

    Rotating (dimensionless, t' = omega_n t) mapped through (2.15), (2.23)-(2.24) must equal the fixed
    frame; both integrated at rtol 1e-11, compared to 1e-7 relative to the largest amplitude.
    """
    scene = Scene(n=2)
    fixed = NumericFirstOrder(first_order(derive(scene)))
    rot = _numeric(2)
    nd = scene.nondimensional()
    R, wn = scene.race_radius, np.sqrt(scene.stiffness / scene.rotor_mass)
    phi0 = np.array([np.pi / 2, -np.pi / 2])
    T = 30.0  # dimensionless
    y_rot0 = np.concatenate([[0.0, 0.0], phi0, np.zeros(4)])
    y_fix0 = np.concatenate([[0.0, 0.0], phi0, np.zeros(4)])
    ts = np.linspace(0, T, 61)
    sr = solve_ivp(rot, (0, T), y_rot0, t_eval=ts, method="DOP853", rtol=1e-11, atol=1e-14)
    sf = solve_ivp(fixed, (0, T / wn), y_fix0, t_eval=ts / wn, method="DOP853", rtol=1e-11, atol=1e-16)
    c, s = np.cos(nd["Omega"] * ts), np.sin(nd["Omega"] * ts)
    X = R * (sr.y[0] * c - sr.y[1] * s)
    Y = R * (sr.y[0] * s + sr.y[1] * c)
    scale = np.max(np.abs(sf.y[:2]))
    assert scale > 1e-5
    assert np.max(np.abs(sf.y[0] - X)) < 1e-7 * scale
    assert np.max(np.abs(sf.y[1] - Y)) < 1e-7 * scale
    assert np.allclose(sf.y[2:4], sr.y[2:4], rtol=0, atol=1e-7)
    assert np.allclose(sf.y[6:8] / wn, sr.y[6:8], rtol=0, atol=1e-7)  # rates scale by omega_n


@pytest.mark.parametrize("bad", [{"stiffness": [1e4, 2e4]}, {"gravity": True}, {"speed": {"law": "torque"}}])
def test_dimensional_rotating_frame_refuses_non_autonomous_scenes(bad):
    with pytest.raises(ReductionError):
        rotating_frame_dimensional(Scene.from_mapping({"n": 2, **bad}))


def test_unequal_balls_rotating_frame_agrees_with_fixed_frame():
    """Unequal balls, isotropic, constant speed: the dimensional rotating-frame model is autonomous and its
    trajectories, turned back by (2.23)-(2.24), are the fixed-frame ones (rtol 1e-11 runs, 1e-7 agreement)."""
    scene = Scene.from_mapping({"n": 3, "ball_mass": [0.05, 0.03, 0.02], "ball_damping": [1e-4, 2e-4, 1.5e-4]})
    rot_eom = rotating_frame_dimensional(scene)
    assert all(sp.Symbol("t", real=True) not in f.free_symbols for f in rot_eom.forcing)
    fixed, rot = NumericFirstOrder(first_order(derive(scene))), NumericFirstOrder(first_order(rot_eom))
    omega = scene.speed.omega
    y0 = np.concatenate([[1e-4, 0.0], [1.0, 2.5, -2.0], np.zeros(5)])
    ts = np.linspace(0, 0.3, 31)
    sr = solve_ivp(rot, (0, ts[-1]), y0, t_eval=ts, method="DOP853", rtol=1e-11, atol=1e-16)
    y0_fixed = y0.copy()
    y0_fixed[5:7] = [-omega * y0[1], omega * y0[0]]  # X' = x' - omega y, Y' = y' + omega x at t = 0
    sf = solve_ivp(fixed, (0, ts[-1]), y0_fixed, t_eval=ts, method="DOP853", rtol=1e-11, atol=1e-16)
    c, s = np.cos(omega * ts), np.sin(omega * ts)
    X, Y = sr.y[0] * c - sr.y[1] * s, sr.y[0] * s + sr.y[1] * c
    scale = np.max(np.abs(sf.y[:2]))
    assert scale > 1e-5
    assert np.max(np.abs(sf.y[0] - X)) < 1e-7 * scale and np.max(np.abs(sf.y[1] - Y)) < 1e-7 * scale
    assert np.allclose(sf.y[2:5], sr.y[2:5], rtol=0, atol=1e-7)


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=8, max_size=8))
def test_dimensional_and_thesis_rotating_frames_are_the_same_system(values):
    """Equal balls: the dimensional rotating frame, scaled by (2.15)-(2.19), is (2.25)-(2.27) numerically:
    accelerations x'' = R omega_n^2 x_thesis'', phi'' = omega_n^2 phi_thesis'' at corresponding states."""
    scene = Scene(n=2)
    dim, nd = _numeric_dimensional(scene), _numeric(2)
    R, wn = scene.race_radius, np.sqrt(scene.stiffness / scene.rotor_mass)
    y = np.array(values) * np.array([0.1, 0.1, 3, 3, 0.5, 0.5, 1, 1])
    y_dim = y * np.array([R, R, 1, 1, R * wn, R * wn, wn, wn])
    a_dim, a_nd = dim(0.0, y_dim)[4:], nd(0.0, y)[4:]
    assert np.allclose(a_dim, a_nd * np.array([R * wn**2, R * wn**2, wn**2, wn**2]), rtol=1e-9, atol=1e-9)


def _numeric_dimensional(scene):
    key = ("dim", scene)
    if key not in _CACHE:
        _CACHE[key] = NumericFirstOrder(first_order(rotating_frame_dimensional(scene)))
    return _CACHE[key]
