"""The flexible family's prescribed speed schedule (`core.speed_schedule` with a start speed): its model
equals the constant-speed model when the ramp has no rate, and Newton's law written directly on a ramp."""

import pytest

from adbgen.errors import SceneError
from adbgen.families.flexible import verify
from adbgen.families.flexible.models import for_scene
from adbgen.families.flexible.scene import FlexibleScene

from .test_models import THREE_MODES


@pytest.mark.parametrize("start", [1.0, 0.99])
def test_zero_rate_ramp_equals_constant_speed(start):
    """omega_start = omega: the same rhs as the constant-speed model to round-off.  Negative control: a
    ramp from 1 % below omega (a rate left in) differs."""
    diff = verify.zero_rate_difference(verify.ramp_scene(), start)
    assert (diff <= verify.RHS_TOLERANCE) if start == 1.0 else (diff > 1e-4)


@pytest.mark.parametrize("wrong", [False, True])
def test_run_up_equals_newtons_law(wrong):
    """On a ramp (psi'' = 50 rad/s^2, three coupled modes, gravity, three unequal balls) the Lagrange model
    equals the forces written directly.  Negative control: psi'' with its sign flipped is caught."""
    diff = verify.ramp_difference(verify.ramp_scene(), wrong)
    assert (diff > 1e-3) if wrong else (diff <= verify.RHS_TOLERANCE)


def test_schedule_scene_reads_and_its_model_has_no_period():
    data = {**THREE_MODES, "speed": {"law": "schedule", "omega": 160.0, "ramp_time": 200.0, "omega_start": 60.0,
                                     "hold_time": 10.0}}
    scene = FlexibleScene.from_mapping(data)
    assert scene.speed.omega_start == 60.0 and dict(scene.speed.schedule)["ramp_time"] == 200.0
    spec = for_scene(scene)
    assert spec.name == "scene_flexible_schedule_k3_n2" and spec.orbit_start is None
    system = spec.system()
    names = {p.name for p in system.parameters}
    assert {"omega", "omega_start", "t_ramp", "t_hold"} <= names
    d = spec.describe(system)
    assert d.forcing_frequency == "" and d.steady_states == ()
    # from rest: no start parameter
    rest = FlexibleScene.from_mapping({**THREE_MODES, "speed": {"law": "schedule", "omega": 160.0, "ramp_time": 2.0}})
    assert rest.speed.omega_start is None and "omega_start" not in {p.name for p in for_scene(rest).system().parameters}


@pytest.mark.parametrize("speed,field", [({"law": "ramp", "omega_max": 3.0}, "speed"),
                                         ({"law": "constant", "ramp_time": 1.0}, "speed.ramp_time"),
                                         ({"law": "schedule", "omega": 100.0}, "speed.ramp_time"),
                                         ({"law": "schedule", "omega": 100.0, "ramp_time": 1.0, "omega_start": -1.0},
                                          "speed.omega_start")])
def test_bad_speed_names_its_field(speed, field):
    with pytest.raises(SceneError) as err:
        FlexibleScene.from_mapping({**THREE_MODES, "speed": speed})
    assert err.value.field == field
