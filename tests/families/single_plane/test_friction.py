"""Ball-race friction in slip and speed schedules (issue 37, items 1 and 4): the family's checks pass for
several n (their wrong variants fail in tests/families/test_negative_controls.py), and the normal force the
model emits as a measure agrees with Newton's law along the race radius computed from the model's own
accelerations, with a negative control (a wrong kinematic formula is caught)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from adbgen.families.single_plane import friction, verify
from adbgen.families.single_plane.model import derive
from adbgen.families.single_plane.models import for_scene
from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane.selection import smallest_model


@pytest.mark.parametrize("n", [1, 2, 3])
def test_friction_checks_pass(n):
    for check in (verify.friction_zero_limit, verify.normal_force):
        result = check(n)
        assert result.passed, result.detail
        assert not check(n, wrong=True).passed


def test_energy_balance_over_a_run_with_friction():
    result = verify.friction_energy(1)
    assert result.passed, result.detail


def test_speed_schedule_check_passes_and_its_wrong_variant_fails():
    assert verify.speed_schedule().passed
    assert not verify.speed_schedule(wrong=True).passed


def test_no_friction_key_means_todays_model():
    plain, rough = Scene(n=2), Scene(n=2, rolling_resistance=0.01)
    assert not plain.friction and rough.friction
    assert derive(plain) is derive(Scene.from_mapping({"n": 2}))  # the same scene, the same cached model
    assert smallest_model(plain).kind == "rotating-frame"
    assert smallest_model(rough).kind == "rotating-frame-dimensional"
    assert all(not p.name.startswith("mu_") for p in derive(plain).parameters)


def _kinematic_normal_forces(state, accel, values, n, coriolis=2.0):
    """N_i = m (R (omega + phi_i')^2 - a_C . e_r) with a_C the rotor centre's inertial acceleration written
    in the rotating axes: (x'' - coriolis omega y' - omega^2 x, y'' + coriolis omega x' - omega^2 y);
    coriolis = 2 is right, anything else a planted error."""
    x, y = state[0], state[1]
    xd, yd = state[2 + n], state[3 + n]
    w, m, R = values["omega"], values["m"], values["R"]
    ax = accel[0] - coriolis * w * yd - w**2 * x
    ay = accel[1] + coriolis * w * xd - w**2 * y
    out = []
    for i in range(n):
        phi, phid = state[2 + i], state[2 + n + 2 + i]
        out.append(m * (R * (w + phid) ** 2 - ax * np.cos(phi) - ay * np.sin(phi)))
    return np.array(out)


def test_emitted_normal_force_is_newtons_law_along_a_solution_state():
    n = 2
    scene = Scene(n=n, rolling_resistance=0.05)
    spec = for_scene(scene)
    system = spec.system()
    measures = spec.describe(system).measures
    assert set(friction.normal_force_names(n)) | set(friction.slip_rate_names(n)) <= set(measures)
    values = {p.name: p.default for p in system.parameters}
    psyms = {p.symbol: p.default for p in system.parameters}
    states = list(system.states)
    rng = np.random.default_rng(37)
    rhs = sp.lambdify(states, [e.xreplace(psyms) for e in system.rhs()], "numpy")
    normal = sp.lambdify(states, [measures[k].xreplace(psyms) for k in friction.normal_force_names(n)], "numpy")
    for _ in range(5):
        state = rng.normal(size=len(states)) * np.array([1e-3, 1e-3, 1, 1, 0.1, 0.1, 50, 50])
        derivative = np.array(rhs(*state), dtype=float)
        accel = derivative[len(states) // 2:]
        emitted = np.array(normal(*state), dtype=float)
        right = _kinematic_normal_forces(state, accel, values, n)
        wrong = _kinematic_normal_forces(state, accel, values, n, coriolis=1.0)
        assert np.allclose(emitted, right, rtol=1e-10, atol=0), (emitted, right)
        assert not np.allclose(emitted, wrong, rtol=1e-6, atol=0)
    # the friction acts: with mu_r = 0 the ball accelerations at the same state differ
    smooth = {**psyms, **{p.symbol: 0.0 for p in system.parameters if p.name == "mu_r"}}
    rhs0 = sp.lambdify(states, [e.xreplace(smooth) for e in system.rhs()], "numpy")
    assert not np.allclose(np.array(rhs0(*state), dtype=float)[-n:], derivative[-n:], rtol=1e-6, atol=0)


def test_per_ball_rolling_resistance_goes_with_its_ball_in_the_exchanges():
    """Balls with their own mu_r_i are exchanged with their masses and their friction (without mu_r_i in the
    exchange, regenerate refused the model: the symmetry did not hold on the rhs)."""
    scene = Scene(n=2, ball_mass=(0.05, 0.04), rolling_resistance=(0.01, 0.02))
    spec = for_scene(scene)
    symmetries = spec.describe(spec.system()).symmetries
    exchange = next(s for s in symmetries if s.name.startswith("exchange"))
    assert exchange.parameters["mu_r_1"] == ("mu_r_2", 1) and exchange.parameters["m_1"] == ("m_2", 1)
