"""The derived fixed-frame equations equal the thesis' (2.10)-(2.13), exactly, and have the structure
the structured solve relies on."""

import pytest
import sympy as sp

from adbgen.core import is_identity
from adbgen.references import thesis
from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane import verify
from adbgen.families.single_plane.model import derive
from adbgen.families.single_plane.symbols import DimensionalSymbols, t

NS = (1, 2, 3, 4, 6)


@pytest.mark.parametrize("n", NS)
def test_fixed_frame_equals_2_10_to_2_13(n):
    result = verify.fixed_frame(n)
    assert result.passed, result.detail


@pytest.mark.parametrize("n", NS)
def test_prescribed_speed_equals_torque_model_with_psi_substituted(n):
    result = verify.prescribed_speed(n)
    assert result.passed, result.detail


def test_a_wrong_reference_is_detected():
    """Negative control: drop the ball's gravity term of (2.13) and the comparison must fail."""
    scene = verify.general_scene(2)
    eom = derive(scene)
    s = DimensionalSymbols.for_scene(scene)
    psi = eom.coordinates[eom.index("psi")]
    ref = thesis.fixed_frame(s, 2, torque=s.tau0 - s.kappa * psi.qd)
    phi = eom.coordinates[eom.index("phi_1")]
    wrong = ref["phi_1"] - s.m[0] * s.g * s.R * sp.cos(psi.q + phi.q)
    assert is_identity(eom.residual(eom.index("phi_1")), ref["phi_1"])
    assert not is_identity(eom.residual(eom.index("phi_1")), wrong)


@pytest.mark.parametrize("n", (1, 3, 8))
def test_mass_matrix_structure(n):
    """Balls couple only to the rotor: the ball block is diagonal; M is symmetric (unscaled rows)."""
    eom = derive(verify.general_scene(n))
    M = eom.mass_matrix()
    assert (M - M.T).applyfunc(sp.expand) == sp.zeros(*M.shape)
    balls = [k for k, c in enumerate(eom.coordinates) if c.name.startswith("phi_")]
    for i in balls:
        for j in balls:
            assert (i, j) not in eom.mass or i == j
    assert len(eom.mass) == 3 * 3 - 2 + n * (1 + 2 * 3)  # rotor block (X-Y uncoupled) + ball rows/columns


def test_profile_law_keeps_spin_as_time_dependent_input():
    scene = Scene.from_mapping({"n": 2, "speed": {"law": "profile", "omega": "100*(1 - exp(-t/2))"}})
    eom = derive(scene)
    psi_dot = sp.Symbol("psi_dot", real=True)
    assert [c.name for c in eom.coordinates] == ["X", "Y", "phi_1", "phi_2"]
    law = eom.driven_law
    assert sp.simplify(law[psi_dot] - 100 * (1 - sp.exp(-t / 2))) == 0
    psi, psi_ddot = sp.Symbol("psi", real=True), sp.Symbol("psi_ddot", real=True)
    assert sp.simplify(sp.diff(law[psi], t) - law[psi_dot]) == 0 and law[psi].subs(t, 0) == 0
    assert sp.simplify(law[psi_ddot] - sp.diff(law[psi_dot], t)) == 0
    assert psi_ddot in eom.symbols()  # angular acceleration of the run-up enters the equations


def test_parameters_are_runtime_symbols_with_defaults():
    scene = Scene(n=3)
    eom = derive(scene)
    names = [p.name for p in eom.parameters]
    assert names == sorted(names) == ["D", "M", "R", "c", "eps", "k", "m", "omega"]
    defaults = {p.name: p.default for p in eom.parameters}
    assert defaults["k"] == scene.stiffness and defaults["omega"] == scene.speed.omega
    assert eom.symbols() - set(eom.parameter_symbols()) - {t} <= {s for c in eom.coordinates for s in (c.q, c.qd, c.qdd)}
