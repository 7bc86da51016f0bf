"""Energy balance over a run with stick and slip (issue 37; adbgen.families.single_plane.science.stick_slip_energy,
the check "stick/slip energy balance" of `adbgen verify`): E(0) - E(t) = the work of damping, friction and the
motor, to the integrator's tolerance, over a braked rotor whose balls release from the stick phase and slip.
Negative controls: the friction's work counted twice, and the normal force from the race's speed (m R psi'^2,
the check's registered wrong variant), are caught."""

from __future__ import annotations

import pytest

from adbgen.families.single_plane.family import FAMILY
from adbgen.families.single_plane.science import stick_slip_energy as sse
from stick_slip_scene import braked_model


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    """The shared stick/slip scene's model (tests/stick_slip_scene.py), run at the check's values."""
    return braked_model(tmp_path_factory)


def test_energy_balance_with_stick_and_slip(model):
    error, share, events = sse.balance(model)
    modes = [mode for _, _, mode in events]
    assert "stick" in modes and any(mode.startswith("slip") for mode in modes), events
    assert share > 1e-3, share
    assert error < sse.TOLERANCE, (error, events)


def test_friction_counted_twice_is_caught(model):
    error, share, _ = sse.balance(model, friction_factor=2.0)
    assert error > 1e-4, (error, share)


def test_a_wrong_normal_force_is_caught(model):
    error, _, _ = sse.balance(model, normal="race")
    assert error > 1e-6, error


def test_the_check_is_in_verify_and_its_wrong_variant_fails():
    (registered,) = [c for c in FAMILY.checks((1,)) if c.name == "stick/slip energy balance"]
    (right,), (wrong,) = registered.results(), registered.results(wrong=True)
    assert right.passed, right.detail
    assert not wrong.passed, wrong.detail
