"""The derived fixed-frame equations equal the paper's (2)-(4) (errata corrected) and have the structure
the structured solve needs; the small-vibration approximation drops exactly what the docs say."""

import pytest
import sympy as sp

from adbgen.core import Coordinate, is_identity
from adbgen.references import two_plane_2011 as paper
from adbgen.families.two_plane import verify
from adbgen.families.two_plane.model import derive, lagrangian
from adbgen.families.two_plane.scene import TwoPlaneScene
from adbgen.families.two_plane.symbols import TwoPlaneSymbols


def test_fixed_frame_equals_2_to_4_and_printed_errata_fail():
    result = verify.fixed_frame()
    assert result.passed, result.detail


@pytest.mark.parametrize("law", ["ramp", "hill"])
def test_prescribed_run_up(law):
    result = verify.prescribed_speed(law)
    assert result.passed, result.detail


def test_modified_polar_inertia_erratum():
    """The theta_0'' coefficient of (3) is J_p + (J_t - J_p) chi^2 + M eps^2, not the printed J_p + J_t chi^2 + M eps^2."""
    scene = verify.general_scene()
    eom, s = derive(scene), TwoPlaneSymbols.for_scene(scene)
    i = eom.index("theta_0")
    coeff = eom.mass[(i, i)]
    assert is_identity(coeff, paper.modified_polar_inertia(s, printed=False))
    assert not is_identity(coeff, paper.modified_polar_inertia(s, printed=True))
    # and it is the exact inertia about the shaft, J_p cos^2 chi + J_t sin^2 chi + M eps^2, to order chi^2
    exact = s.Jp * sp.cos(s.chi) ** 2 + s.Jt * sp.sin(s.chi) ** 2 + s.M * s.eps**2
    assert sp.simplify(sp.series(exact, s.chi, 0, 3).removeO() - coeff) == 0


def test_anisotropic_damping_erratum_needs_conjugate():
    """With C_X = C_Y the printed C_d q' is harmless (C_d = 0): with equal damping in X and Y only the
    tilde J_p erratum is left, so it is the anisotropic damping that needs conj(q')."""
    from dataclasses import replace

    scene = verify.general_scene()
    eom, s = derive(scene), TwoPlaneSymbols.for_scene(scene)
    same = {s.c[(j, "Y")]: s.c[(j, "X")] for j in (1, 2)}
    eom = eom.map(lambda e: e.xreplace(same))
    s = replace(s, c={key: s.c[(key[0], "X")] for key in s.c})
    assert verify._compare_fixed(eom, s, scene.n, printed=True) == ["theta_0"]
    assert verify._compare_fixed(eom, s, scene.n, printed=False) == []


def test_mass_matrix_structure():
    """Balls couple only to X, Y, phi_X, phi_Y: ball block diagonal, M symmetric, theta_0 uncoupled from balls."""
    eom = derive(verify.general_scene())
    M = eom.mass_matrix()
    assert (M - M.T).applyfunc(sp.expand) == sp.zeros(*M.shape)
    balls = [k for k, c in enumerate(eom.coordinates) if c.name.startswith("theta_") and c.name != "theta_0"]
    th0 = eom.index("theta_0")
    for i in balls:
        assert (i, th0) not in eom.mass
        for j in balls:
            assert (i, j) not in eom.mass or i == j


def test_dropped_terms_are_the_balls_transverse_rotary_inertia():
    """Item 2 of the model's approximation: what is dropped from each ball is nonzero, of second order in the
    tilt and proportional to m_k R_k^2; and the rotor rows are linear in the vibration."""
    scene = TwoPlaneScene()
    lag = lagrangian(scene)
    s = lag.symbols
    tilt = [Coordinate.make(n) for n in ("phi_X", "phi_Y")]
    h = sp.Symbol("h")
    for k, dropped in enumerate(lag.dropped_ball_terms):
        assert dropped != 0
        scaled = dropped.xreplace({sym: h * sym for c in tilt for sym in (c.q, c.qd)})
        assert sp.Poly(scaled, h).monoms() == [(2,)]
        assert sp.simplify(dropped / (s.m[k] * s.R[k] ** 2)).free_symbols.isdisjoint({s.m[k], s.R[k]})
    eom = derive(scene)
    vib = [Coordinate.make(n) for n in ("X", "Y", "phi_X", "phi_Y")]
    scale = {sym: h * sym for c in vib for sym in (c.q, c.qd, c.qdd)}
    for k, c in enumerate(eom.coordinates):
        assert sp.Poly(sp.expand(eom.residual(k).xreplace(scale)), h).degree() <= 1, c.name


def test_parameters_have_defaults_from_the_scene():
    scene = TwoPlaneScene.preset("paper-43")
    eom = derive(scene)
    d = {p.name: p.default for p in eom.parameters}
    assert d["k_1Y"] == 2.5 and d["c_2X"] == 0.01 and d["Omega"] == 3.0 and d["z_b"] == -2.0
    assert [p.name for p in eom.parameters] == sorted(d)
