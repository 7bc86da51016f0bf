"""The scene: every field rejects impossible input with a one-line SceneError naming it.

Bad input is described per field (``BAD``); a guard test makes sure every field of ``Scene`` and
``SpeedLaw`` has at least one bad case, so a new field cannot slip in untested.
"""

from __future__ import annotations

import math
import struct
import subprocess
import sys
from dataclasses import fields

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adbgen.errors import AdbgenError, SceneError
from adbgen.families.single_plane.scene import SCHEDULE_KEYS, Scene, SpeedLaw, profile_expression

NAN, INF = float("nan"), float("inf")


def assert_scene_error(exc: SceneError, field: str) -> None:
    """``exc`` names ``field`` both as attribute and as the start of a single-line message."""
    assert isinstance(exc, SceneError) and isinstance(exc, AdbgenError)
    assert exc.field == field, f"expected field {field!r}, got {exc.field!r} ({exc})"
    message = str(exc)
    assert "\n" not in message and "\r" not in message, f"message is not one line: {message!r}"
    assert message.startswith(f"scene.{field}: "), message
    assert len(message) > len(f"scene.{field}: "), "the message must say what is wrong"


def raises_for(data, field: str) -> None:
    with pytest.raises(SceneError) as info:
        Scene.from_mapping(data)
    assert_scene_error(info.value, field)


# --- one bad value per row: (scene mapping, field the error must name) -------------------
def _bad_numbers(name, *, zero_ok):
    """Non-finite, wrong-typed and out-of-range values for a plain number field."""
    values = [NAN, INF, -INF, -1.0, -1, "1.0", True, False, None, [1.0], {"value": 1.0}]
    if not zero_ok:
        values += [0, 0.0, -0.0]
    return [({name: v}, name) for v in values]


def _bad_speed_numbers(law, name, *, zero_ok, negative_ok, extra=None):
    values = [NAN, INF, -INF, "1.0", True, None, [1.0]]
    if not negative_ok:
        values += [-1.0, -1]
    if not zero_ok:
        values += [0, 0.0]
    return [({"speed": {"law": law, name: v, **(extra or {})}}, f"speed.{name}") for v in values]


def _bad_per_ball(name, *, zero_ok):
    rows = _bad_numbers(name, zero_ok=zero_ok)
    rows += [
        ({"n": 2, name: []}, name),                      # wrong list lengths
        ({"n": 2, name: [0.05]}, name),
        ({"n": 2, name: [0.05, 0.05, 0.05]}, name),
        ({"n": 3, name: (0.05, 0.05)}, name),
        ({"n": 2, name: [0.05, -1.0]}, f"{name}[1]"),    # bad entries name their index
        ({"n": 2, name: [NAN, 0.05]}, f"{name}[0]"),
        ({"n": 3, name: [0.05, 0.05, INF]}, f"{name}[2]"),
        ({"n": 2, name: [0.05, "0.05"]}, f"{name}[1]"),
        ({"n": 2, name: [True, 0.05]}, f"{name}[0]"),
    ]
    if not zero_ok:
        rows.append(({"n": 2, name: [0.05, 0.0]}, f"{name}[1]"))
    return rows


def _bad_pair(name):
    return _bad_numbers(name, zero_ok=True) + [
        ({name: []}, name),
        ({name: [1.0e4]}, name),
        ({name: [1.0e4, 1.0e4, 1.0e4]}, name),
        ({name: [1.0e4, -1.0]}, f"{name}[1]"),
        ({name: [NAN, 1.0e4]}, f"{name}[0]"),
        ({name: [1.0e4, -INF]}, f"{name}[1]"),
        ({name: ["1e4", 1.0e4]}, f"{name}[0]"),
    ]


BAD = (
    [({"n": v}, "n") for v in (0, -1, -(10**6), 1.5, NAN, INF, -INF, "2", True, False, None, [2], 0.0, -3.0)]
    + _bad_numbers("rotor_mass", zero_ok=False)
    + _bad_numbers("eccentricity", zero_ok=True)
    + _bad_numbers("polar_inertia", zero_ok=False)
    + _bad_numbers("race_radius", zero_ok=False)
    + _bad_per_ball("ball_mass", zero_ok=False)
    + _bad_per_ball("ball_damping", zero_ok=True)
    + _bad_pair("stiffness")
    + _bad_pair("damping")
    + [({"gravity": v}, "gravity") for v in (1, 0, "true", "yes", None, 1.0, [True])]
    + _bad_numbers("g", zero_ok=False)
    # speed: not a table, bad law
    + [({"speed": v}, "speed") for v in ("constant", 400.0, ["constant"], None)]
    + [({"speed": {"law": v}}, "speed.law") for v in ("linear", "Constant", "", None, 1, ["constant"])]
    # speed.omega, constant law: a positive finite number
    + _bad_speed_numbers("constant", "omega", zero_ok=False, negative_ok=False)
    + [({"speed": {"law": "constant", "omega": "400"}}, "speed.omega")]
    # speed.omega, profile law: a safe expression in t, finite and real at t = 0
    + [({"speed": {"law": "profile", **({} if v is None else {"omega": v})}}, "speed.omega") for v in (
        None, "", "   ", 400.0, 400, ["t"],
        "t +", "(t", "t t", "exp(", "t = 1",                      # unparsable
        "__import__('os')", "open('x')", "eval('t')", "lambda: t",  # unsafe
        "t.func", "exp(t).args", "exp.__call__(t)", "pi.__class__",
        "t + x", "x", "omega0*t", "y(t)",                           # unknown names
        "exp", "True", "(t, t)",                                    # not an expression
        "1/t", "log(t)", "sqrt(-1)",                                # not finite and real at t = 0
    )]
    # speed.tau0 (any finite number) and speed.motor_slope (non-negative), torque law
    + _bad_speed_numbers("torque", "tau0", zero_ok=True, negative_ok=True)
    + _bad_speed_numbers("torque", "motor_slope", zero_ok=True, negative_ok=False)
    # friction (issue 37): non-negative, one value or n; stiction needs the rolling resistance and >= it
    + [r for r in _bad_per_ball("rolling_resistance", zero_ok=True) if r[0].get("rolling_resistance", 0) is not None]
    + [({"static_friction": 0.01}, "static_friction"),
       ({"rolling_resistance": 0.02, "static_friction": 0.01}, "static_friction"),
       ({"n": 2, "rolling_resistance": [0.01, 0.03], "static_friction": 0.02}, "static_friction"),
       ({"rolling_resistance": 0.01, "static_friction": -0.1}, "static_friction"),
       ({"rolling_resistance": 0.01, "static_friction": NAN}, "static_friction")]
    # speed schedule (issue 37 item 4): omega, ramp_time needed and positive; depth in [0, 1); rates positive
    + [({"speed": {"law": "schedule", **v}}, f) for v, f in (
        ({"ramp_time": 1.0}, "speed.omega"), ({"omega": 400.0}, "speed.ramp_time"),
        ({"omega": 0.0, "ramp_time": 1.0}, "speed.omega"), ({"omega": 400.0, "ramp_time": -1.0}, "speed.ramp_time"),
        ({"omega": 400.0, "ramp_time": 1.0, "hold_time": -1.0}, "speed.hold_time"),
        ({"omega": 400.0, "ramp_time": 1.0, "reduction_depth": 1.0}, "speed.reduction_depth"),
        ({"omega": 400.0, "ramp_time": 1.0, "reduction_depth": -0.1}, "speed.reduction_depth"),
        ({"omega": 400.0, "ramp_time": 1.0, "reduction_rate": 0.0}, "speed.reduction_rate"),
        ({"omega": 400.0, "ramp_time": 1.0, "plateau_time": NAN}, "speed.plateau_time"),
        ({"omega": 400.0, "ramp_time": 1.0, "recovery_rate": -5.0}, "speed.recovery_rate"),
        ({"omega": 400.0, "ramp_time": 1.0, "tau0": 1.0}, "speed.tau0"))]
    # unknown options: top level and inside speed, also options of another speed law
    + [({v: 1.0}, v) for v in ("bogus", "ball_masses", "omega", "law", "N", "mu")]
    + [
        ({"speed": {"law": "constant", "bogus": 1.0}}, "speed.bogus"),
        ({"speed": {"law": "constant", "tau0": 1.0}}, "speed.tau0"),
        ({"speed": {"law": "constant", "motor_slope": 1.0}}, "speed.motor_slope"),
        ({"speed": {"law": "profile", "omega": "t", "tau0": 1.0}}, "speed.tau0"),
        ({"speed": {"law": "torque", "omega": 400.0}}, "speed.omega"),
        ({"speed": {"omega": 400.0, "Omega": 4.0}}, "speed.Omega"),   # default law: constant
    ]
)


def _id(row):
    data, field = row
    return f"{field}={data!r}"[:80]


@pytest.mark.parametrize("data, field", BAD, ids=[_id(r) for r in BAD])
def test_bad_value_names_the_field(data, field):
    raises_for(data, field)


def test_every_field_has_bad_cases():
    """The table above covers each field of Scene and SpeedLaw, plus unknown options."""
    named = {field.split("[")[0] for _, field in BAD}
    assert {f.name for f in fields(Scene)} <= named
    assert {f"speed.{f.name}" for f in fields(SpeedLaw) if f.name != "schedule"} <= named
    assert {f"speed.{key}" for key in SCHEDULE_KEYS} <= named  # SpeedLaw.schedule holds these
    assert {"ball_mass[1]", "ball_damping[1]", "stiffness[0]", "damping[1]"} <= {f for _, f in BAD}


@pytest.mark.parametrize("data", [[("n", 2)], "n = 2", None, 2])
def test_scene_must_be_a_table(data):
    raises_for(data, "<root>")


def test_huge_integer_is_a_scene_error():
    raises_for({"rotor_mass": 10**400}, "rotor_mass")


# --- properties --------------------------------------------------------------------------
POSITIVE = ("rotor_mass", "polar_inertia", "race_radius", "ball_mass", "g")
NONNEGATIVE = ("eccentricity", "ball_damping", "stiffness", "damping")
NUMERIC = POSITIVE + NONNEGATIVE

non_positive = st.one_of(
    st.floats(max_value=0.0, allow_nan=False, allow_infinity=False),
    st.integers(min_value=-(10**12), max_value=0),
)
negative = st.one_of(
    st.floats(max_value=-math.ulp(0.0), allow_nan=False, allow_infinity=False),
    st.integers(min_value=-(10**12), max_value=-1),
)
# every non-finite double: all-ones exponent, any sign, any mantissa (0 = infinity, else a NaN payload)
non_finite = st.builds(
    lambda sign, mantissa: struct.unpack("<d", struct.pack("<Q", sign << 63 | 0x7FF << 52 | mantissa))[0],
    st.integers(0, 1), st.one_of(st.just(0), st.integers(0, 2**52 - 1)),
)
positive_finite = st.floats(min_value=math.ulp(0.0), max_value=1e300, allow_nan=False, allow_infinity=False)


def _put(name, value):
    """``value`` as scene field ``name`` (speed fields inside the speed table)."""
    if name == "speed.omega":
        return {"speed": {"law": "constant", "omega": value}}
    if name == "speed.motor_slope":
        return {"speed": {"law": "torque", "motor_slope": value}}
    if name == "speed.tau0":
        return {"speed": {"law": "torque", "tau0": value}}
    return {name: value}


@settings(max_examples=150, deadline=None)
@given(name=st.sampled_from(POSITIVE + ("speed.omega",)), value=non_positive)
def test_any_non_positive_value_of_a_positive_field_is_rejected(name, value):
    raises_for(_put(name, value), name)


@settings(max_examples=150, deadline=None)
@given(name=st.sampled_from(NONNEGATIVE + ("speed.motor_slope",)), value=negative)
def test_any_negative_value_of_a_non_negative_field_is_rejected(name, value):
    raises_for(_put(name, value), name)


@settings(max_examples=150, deadline=None)
@given(name=st.sampled_from(NUMERIC + ("n", "speed.omega", "speed.tau0", "speed.motor_slope")), value=non_finite)
def test_any_nan_or_infinity_is_rejected(name, value):
    raises_for(_put(name, value), name)


@settings(max_examples=100, deadline=None)
@given(name=st.sampled_from(NUMERIC + ("speed.omega",)), value=positive_finite)
def test_any_positive_finite_value_is_accepted(name, value):
    scene = Scene.from_mapping(_put(name, value))
    stored = scene.speed.omega if name == "speed.omega" else getattr(scene, name)
    assert stored == value and isinstance(stored, float)


@settings(max_examples=100, deadline=None)
@given(data=st.data(), n=st.integers(min_value=1, max_value=8),
       name=st.sampled_from(("ball_mass", "ball_damping")))
def test_one_bad_entry_in_a_per_ball_list_is_named_by_index(data, n, name):
    values = data.draw(st.lists(positive_finite, min_size=n, max_size=n))
    index = data.draw(st.integers(min_value=0, max_value=n - 1))
    good = Scene.from_mapping({"n": n, name: values})
    assert getattr(good, name) == tuple(values)
    bad = data.draw(negative if name == "ball_damping" else non_positive) if data.draw(st.booleans()) \
        else data.draw(non_finite)
    values[index] = bad
    raises_for({"n": n, name: values}, f"{name}[{index}]")


@settings(max_examples=100, deadline=None)
@given(n=st.integers(min_value=1, max_value=8), length=st.integers(min_value=0, max_value=10),
       name=st.sampled_from(("ball_mass", "ball_damping")))
def test_a_per_ball_list_needs_exactly_n_entries(n, length, name):
    data = {"n": n, name: [0.05] * length}
    if length == n:
        assert getattr(Scene.from_mapping(data), name) == (0.05,) * n
    else:
        raises_for(data, name)


@settings(max_examples=50, deadline=None)
@given(length=st.integers(min_value=0, max_value=6), name=st.sampled_from(("stiffness", "damping")))
def test_stiffness_and_damping_take_one_value_or_a_pair(length, name):
    data = {name: [3.0] * length}
    if length == 2:
        assert getattr(Scene.from_mapping(data), name) == (3.0, 3.0)
    else:
        raises_for(data, name)


# --- good scenes -------------------------------------------------------------------------
def test_defaults_are_the_thesis_parameter_set():
    nd = Scene().nondimensional()
    expected = {"mu": 0.05, "Omega": 4.0, "zeta": 0.01, "beta": 0.01, "delta": 0.01, "G": 0.0}
    assert set(nd) == set(expected)
    for key, value in expected.items():
        assert nd[key] == pytest.approx(value, rel=1e-12, abs=1e-12), key


def test_an_empty_mapping_gives_the_defaults():
    scene = Scene.from_mapping({})
    assert scene == Scene()
    assert scene.n == 2 and scene.equal_balls and scene.isotropic and not scene.gravity
    assert scene.speed == SpeedLaw("constant", 400.0)


def test_gravity_gives_G():
    nd = Scene.from_mapping({"gravity": True}).nondimensional()
    assert nd["G"] == pytest.approx(9.80665 / (5.0e-4 * 1.0e4), rel=1e-12)


def test_whole_float_n_is_accepted_as_int():
    scene = Scene.from_mapping({"n": 3.0})
    assert scene.n == 3 and isinstance(scene.n, int)
    assert scene.masses() == (0.05, 0.05, 0.05)


@pytest.mark.parametrize("data, equal_balls, isotropic", [
    ({}, True, True),
    ({"n": 3, "ball_mass": 0.02, "ball_damping": 1e-4}, True, True),
    ({"n": 3, "ball_mass": [0.02, 0.03, 0.04]}, False, True),
    ({"n": 2, "ball_damping": [1e-4, 2e-4]}, False, True),
    ({"stiffness": [1.0e4, 1.2e4]}, True, False),
    ({"damping": [2.0, 3.0]}, True, False),
    ({"n": 2, "ball_mass": [0.02, 0.03], "stiffness": [1.0e4, 1.2e4], "damping": [2.0, 3.0]}, False, False),
])
def test_structure_flags(data, equal_balls, isotropic):
    scene = Scene.from_mapping(data)
    assert scene.equal_balls is equal_balls
    assert scene.isotropic is isotropic
    assert len(scene.masses()) == len(scene.ball_dampings()) == scene.n
    assert len(scene.stiffness_xy()) == len(scene.damping_xy()) == 2


def test_per_ball_and_pair_values_are_expanded():
    scene = Scene.from_mapping({"n": 3, "ball_mass": [1, 2, 3], "ball_damping": 0.5,
                                "stiffness": [10, 20], "damping": 4})
    assert scene.masses() == (1.0, 2.0, 3.0)
    assert scene.ball_dampings() == (0.5, 0.5, 0.5)
    assert scene.stiffness_xy() == (10.0, 20.0)
    assert scene.damping_xy() == (4.0, 4.0)


@pytest.mark.parametrize("data", [
    {"n": 2, "ball_mass": [0.05, 0.06]},
    {"stiffness": [1.0e4, 1.1e4]},
    {"speed": {"law": "torque", "tau0": 1.0}},
])
def test_thesis_scalings_refuse_scenes_outside_them(data):
    with pytest.raises(SceneError) as info:
        Scene.from_mapping(data).nondimensional()
    assert_scene_error(info.value, "speed")


def test_torque_law():
    speed = Scene.from_mapping({"speed": {"law": "torque", "tau0": -1.5, "motor_slope": 0.2}}).speed
    assert speed == SpeedLaw("torque", omega=None, tau0=-1.5, motor_slope=0.2)
    assert Scene.from_mapping({"speed": {"law": "torque"}}).speed == SpeedLaw("torque", None, 0.0, 0.0)


def test_profile_without_numbers_is_accepted():
    speed = Scene.from_mapping({"speed": {"law": "profile", "omega": "pi*tanh(t)"}}).speed
    assert speed.law == "profile" and speed.omega == "pi*tanh(t)"
    expr = profile_expression("pi*tanh(t)")
    (t,) = expr.free_symbols
    assert float(expr.subs(t, 1)) == pytest.approx(math.pi * math.tanh(1.0), rel=1e-12)


@pytest.mark.parametrize("text, at_0, at_2", [
    ("100*(1-exp(-t/2))", 0.0, 100 * (1 - math.exp(-1.0))),
    ("Min(400, 50*t)", 0.0, 100.0),
    ("0.5*t**2 + sin(pi*t/4)", 0.0, 3.0),
])
def test_profile_run_up_is_accepted(text, at_0, at_2):
    speed = Scene.from_mapping({"speed": {"law": "profile", "omega": text}}).speed
    assert speed == SpeedLaw("profile", omega=text)
    expr = profile_expression(text)
    (t,) = expr.free_symbols
    assert t.name == "t"
    assert float(expr.subs(t, 0)) == at_0
    assert float(expr.subs(t, 2)) == pytest.approx(at_2, rel=1e-12)


def test_profile_cannot_reach_builtins(tmp_path):
    marker = tmp_path / "escaped"
    text = f"sqrt.__globals__['__builtins__']['open']('{marker}', 'w')"
    with pytest.raises(SceneError) as info:
        Scene.from_mapping({"speed": {"law": "profile", "omega": text}})
    assert_scene_error(info.value, "speed.omega")
    assert not marker.exists(), "the profile expression executed code"


_PROFILE_IN_CHILD = """
import sys
from adbgen.errors import SceneError
from adbgen.families.single_plane.scene import profile_expression
try:
    profile_expression(sys.argv[1])
except SceneError:
    sys.exit(0)
sys.exit(1)
"""


@pytest.mark.parametrize("text", ["10**10**10"])
def test_huge_power_in_profile_fails_fast(text):
    """Run in a child process: a hang must end the test, not the test run."""
    result = subprocess.run([sys.executable, "-c", _PROFILE_IN_CHILD, text], timeout=4, capture_output=True)
    assert result.returncode == 0, result.stderr.decode()


# --- TOML --------------------------------------------------------------------------------
FULL_TOML = """\
n = 3
rotor_mass = 2.5
eccentricity = 1.0e-3
polar_inertia = 4.0e-3
race_radius = 0.06
ball_mass = [0.01, 0.02, 0.03]
ball_damping = 2.0e-4
stiffness = [1.0e4, 1.2e4]
damping = 3
gravity = true
g = 9.81

[speed]
law = "torque"
tau0 = 0.5
motor_slope = 1.0e-3
"""


def test_toml_file_loads(tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(FULL_TOML)
    scene = Scene.load(path)
    assert scene == Scene(n=3, rotor_mass=2.5, eccentricity=1.0e-3, polar_inertia=4.0e-3, race_radius=0.06,
                          ball_mass=(0.01, 0.02, 0.03), ball_damping=2.0e-4, stiffness=(1.0e4, 1.2e4),
                          damping=3.0, gravity=True, g=9.81,
                          speed=SpeedLaw("torque", omega=None, tau0=0.5, motor_slope=1.0e-3))
    assert Scene.load(str(path)) == scene
    assert not scene.equal_balls and not scene.isotropic


def _to_toml(scene: Scene) -> str:
    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, tuple):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, str):
            return '"' + v + '"'
        return repr(v)

    lines = [f"{f.name} = {value(getattr(scene, f.name))}" for f in fields(scene)
             if f.name != "speed" and getattr(scene, f.name) is not None]  # None: a key left out (no friction)
    lines.append("[speed]")
    lines += [f"{f.name} = {value(getattr(scene.speed, f.name))}" for f in fields(scene.speed)
              if f.name == "law" or f.name in {"constant": ("omega",), "profile": ("omega",), "schedule": (),
                                                 "torque": ("tau0", "motor_slope")}[scene.speed.law]]
    lines += [f"{key} = {value(v)}" for key, v in scene.speed.schedule]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("scene", [
    Scene(),
    Scene(n=1, gravity=True, speed=SpeedLaw("constant", omega=123.25)),
    Scene(n=4, ball_mass=(0.01, 0.02, 0.03, 0.04), ball_damping=(1e-4, 2e-4, 3e-4, 4e-4),
          stiffness=(1.0e4, 0.0), damping=(0.0, 2.0), eccentricity=0.0),
    Scene(n=2, speed=SpeedLaw("torque", omega=None, tau0=-2.0, motor_slope=0.0)),
    Scene(n=2, speed=SpeedLaw("profile", omega="pi*tanh(t)")),
    Scene(n=3, rolling_resistance=(0.01, 0.0, 0.02), static_friction=0.03),
    Scene(n=2, speed=SpeedLaw("schedule", omega=None, schedule=(
        ("omega", 400.0), ("ramp_time", 2.0), ("hold_time", 1.0), ("reduction_depth", 0.5),
        ("reduction_rate", 100.0), ("plateau_time", 0.5), ("recovery_rate", 50.0)))),
], ids=["defaults", "gravity", "unequal-anisotropic", "torque", "profile", "friction", "schedule"])
def test_toml_round_trip(tmp_path, scene):
    path = tmp_path / "scene.toml"
    path.write_text(_to_toml(scene))
    loaded = Scene.load(path)
    assert loaded == scene
    assert (loaded.equal_balls, loaded.isotropic) == (scene.equal_balls, scene.isotropic)


@pytest.mark.parametrize("text, field", [
    ("n = 0\n", "n"),
    ("n = 2.5\n", "n"),
    ("rotor_mass = nan\n", "rotor_mass"),
    ("eccentricity = -1e-4\n", "eccentricity"),
    ("polar_inertia = -inf\n", "polar_inertia"),
    ("race_radius = 0\n", "race_radius"),
    ("ball_mass = -1\n", "ball_mass"),
    ("n = 2\nball_mass = [0.05, -0.05]\n", "ball_mass[1]"),
    ("n = 2\nball_damping = [1e-4]\n", "ball_damping"),
    ("stiffness = [1e4, 1e4, 1e4]\n", "stiffness"),
    ("damping = [2.0, nan]\n", "damping[1]"),
    ('gravity = "yes"\n', "gravity"),
    ("g = inf\n", "g"),
    ('speed = "constant"\n', "speed"),
    ('[speed]\nlaw = "warp"\n', "speed.law"),
    ("[speed]\nomega = 0\n", "speed.omega"),
    ('[speed]\nlaw = "profile"\nomega = "t + x"\n', "speed.omega"),
    ('[speed]\nlaw = "profile"\nomega = "__import__(\'os\')"\n', "speed.omega"),
    ('[speed]\nlaw = "torque"\ntau0 = nan\n', "speed.tau0"),
    ('[speed]\nlaw = "torque"\nmotor_slope = -1\n', "speed.motor_slope"),
    ('[speed]\nlaw = "torque"\nwarp = 9\n', "speed.warp"),
    ("bogus = 1\n", "bogus"),
    ("[ball]\nmass = 1\n", "ball"),
    ("n = \n", "<file>"),
    ("n = 2\nn = 3\n", "<file>"),
])
def test_bad_toml_file(tmp_path, text, field):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    with pytest.raises(SceneError) as info:
        Scene.load(path)
    assert_scene_error(info.value, field)


def test_missing_file(tmp_path):
    path = tmp_path / "no" / "such.toml"
    with pytest.raises(SceneError) as info:
        Scene.load(path)
    assert_scene_error(info.value, "<file>")
    assert str(path) in str(info.value)


@pytest.mark.parametrize("kind", ["directory", "binary"])
def test_unreadable_file(tmp_path, kind):
    path = tmp_path
    if kind == "binary":
        path = tmp_path / "scene.toml"
        path.write_bytes(b"\xff\xfe n = 2")
    with pytest.raises(SceneError) as info:
        Scene.load(path)
    assert_scene_error(info.value, "<file>")
