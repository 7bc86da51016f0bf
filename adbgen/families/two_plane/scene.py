"""The two-plane scene: a rigid rotor on two bearings with balls in two races (paper section 2.1).

Units are whatever the user chooses consistently; the paper's sets (10), (41)-(43) are dimensionless
(M = R = 1, 2k = 1), and so is a scene unless it says ``units = "SI"`` (then its model's parameters and
states carry the units of the scene reference; a dimensionless model prints none, issue 34 item 5).  The scene fixes the model's *structure* (balls per race, isotropic or anisotropic
bearings, speed law) and the *defaults* of its symbolic parameters.

A scene in TOML::

    preset = "paper-10"          # optional: start from a named parameter set, then override
    units = "SI"                 # optional: "dimensionless" (default, as the paper) or "SI"
    eccentricity = 0.01
    misalignment = 0.001         # chi, couple imbalance (rad)
    [[races]]
    z = 2.0
    radius = 1.0
    masses = [0.0025, 0.0025]    # any number of balls per race
    damping = 2.5e-5             # c_b of each ball in this race
    [[races]]
    z = -2.0
    ...
    [bearing_1]                  # at +l_1 on the shaft axis; bearing_2 at -l_2
    position = 3.0
    stiffness = 0.5              # one value: isotropic; [k_X, k_Y]: anisotropic
    damping = 0.01
    [speed]
    law = "constant"             # "ramp" (omega_max, t_ramp), "hill" (omega_max, t_half, n, omega_cyl)
    omega = 3.0                  # or "torque" (tau0, motor_slope, torsion damping c_r)
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Mapping

from ...errors import SceneError
from ...core import speed_schedule
from ...core.scene_fields import (BallFriction, Key, friction_coefficients, number as _number, speed_law_name,
                                 xy as _xy)

_SPEED_FIELDS = {
    "constant": {"law", "omega"},
    "ramp": {"law", "omega_max", "t_ramp"},
    "hill": {"law", "omega_max", "t_half", "n", "omega_cyl"},
    "schedule": {"law", *speed_schedule.KEYS},
    "torque": {"law", "tau0", "motor_slope", "torsion_damping"},
}


@dataclass(frozen=True)
class TwoPlaneSpeed:
    """How the spin theta_0 is governed.

    - ``constant``: theta_0 = Omega t (paper section 3);
    - ``ramp``: constant acceleration from rest to omega_max in t_ramp, then constant (section 6);
    - ``hill``: Omega = omega_max tb^n / (t_half^n + tb^n), tb = omega_cyl t (paper (45));
    - ``schedule``: a ramp from rest to omega over ramp_time, a hold, a temporary speed reduction (depth,
      fall rate, plateau, recovery rate), each value a parameter (`core.speed_schedule`, issue 37);
    - ``torque``: theta_0 is a degree of freedom, paper (3), driven by tau = tau0 - motor_slope theta_0'
      with torsional damping c_r.
    """

    law: str = "constant"
    omega: float = 3.0
    omega_max: float = 3.6
    t_ramp: float = 6000.0
    t_half: float = 200.0
    n: int = 3
    omega_cyl: float = 1.0
    tau0: float = 0.0
    motor_slope: float = 0.0
    torsion_damping: float = 0.0
    schedule: tuple[tuple[str, float], ...] = ()  # (key, value) in speed_schedule.KEYS order (law = "schedule")

    @classmethod
    def from_mapping(cls, data: Any) -> "TwoPlaneSpeed":
        law = speed_law_name(data, _SPEED_FIELDS)
        d = cls()
        get = lambda key, **kw: _number(f"speed.{key}", data.get(key, getattr(d, key)), **kw)  # noqa: E731
        if law == "constant":
            return cls(law, omega=get("omega", positive=True))
        if law == "ramp":
            return cls(law, omega_max=get("omega_max", positive=True), t_ramp=get("t_ramp", positive=True))
        if law == "schedule":
            return cls(law, schedule=speed_schedule.validate(data))
        if law == "hill":
            n = data.get("n", d.n)
            if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 7:
                raise SceneError("speed.n", f"the Hill exponent must be a whole number 1..7, got {n!r}")
            return cls(law, omega_max=get("omega_max", positive=True), t_half=get("t_half", positive=True), n=n,
                       omega_cyl=get("omega_cyl", positive=True))
        return cls(law, tau0=get("tau0"), motor_slope=get("motor_slope", nonnegative=True),
                   torsion_damping=get("torsion_damping", nonnegative=True))


@dataclass(frozen=True)
class Race:
    """One balancing plane: axial position z, radius R, the ball masses, race damping c_b per ball."""

    z: float
    radius: float
    masses: tuple[float, ...]
    damping: float

    @classmethod
    def from_mapping(cls, where: str, data: Any) -> "Race":
        if not isinstance(data, Mapping):
            raise SceneError(where, "a race is a table with z, radius, masses, damping")
        for key in sorted(set(map(str, data)) - {"z", "radius", "masses", "damping"}):
            raise SceneError(f"{where}.{key}", "unknown option")
        masses = data.get("masses")
        if not isinstance(masses, (list, tuple)):
            raise SceneError(f"{where}.masses", "needs a list of ball masses (empty: a race without balls)")
        return cls(_number(f"{where}.z", data.get("z")), _number(f"{where}.radius", data.get("radius"), positive=True),
                   tuple(_number(f"{where}.masses[{i}]", m, positive=True) for i, m in enumerate(masses)),
                   _number(f"{where}.damping", data.get("damping", 0.0), nonnegative=True))


@dataclass(frozen=True)
class Bearing:
    """A support at axial position +l_1 (bearing 1) or -l_2 (bearing 2): paper (1)."""

    position: float
    stiffness: float | tuple[float, float]
    damping: float | tuple[float, float]

    @classmethod
    def from_mapping(cls, where: str, data: Any) -> "Bearing":
        if not isinstance(data, Mapping):
            raise SceneError(where, "a bearing is a table with position, stiffness, damping")
        for key in sorted(set(map(str, data)) - {"position", "stiffness", "damping"}):
            raise SceneError(f"{where}.{key}", "unknown option")
        return cls(_number(f"{where}.position", data.get("position"), nonnegative=True),
                   _xy(f"{where}.stiffness", data.get("stiffness"), nonnegative=True),
                   _xy(f"{where}.damping", data.get("damping", 0.0), nonnegative=True))

    def xy(self, what: str) -> tuple[float, float]:
        v = getattr(self, what)
        return v if isinstance(v, tuple) else (v, v)


def _paper_10(eps: float = 0.01, m: float = 0.0025) -> dict:
    """Paper (10) (k = 0.5 per bearing, l = 3, z = 2, c = 0.01, c_b/m = 0.01), i.e. (41) and (44)."""
    race = lambda z: {"z": z, "radius": 1.0, "masses": [m, m], "damping": 0.01 * m}  # noqa: E731
    return {"rotor_mass": 1.0, "transverse_inertia": 3.25, "polar_inertia": 0.5, "eccentricity": eps,
            "imbalance_phase": 0.0, "misalignment": 0.0,
            "bearing_1": {"position": 3.0, "stiffness": 0.5, "damping": 0.01},
            "bearing_2": {"position": 3.0, "stiffness": 0.5, "damping": 0.01},
            "races": [race(2.0), race(-2.0)], "speed": {"law": "constant", "omega": 3.0}}


def _preset(name: str) -> dict:
    base = _paper_10()
    if name in ("paper-10", "paper-41"):
        return base
    if name == "paper-42":  # K = [[1, 3], [3, 45]]: l_1 = 9, l_2 = 3, k = 0.5 each
        base["bearing_1"] = {"position": 9.0, "stiffness": 0.5, "damping": 0.01}
        return base
    if name == "paper-43":  # Y five times stiffer and more damped than X
        for b in ("bearing_1", "bearing_2"):
            base[b] = {"position": 3.0, "stiffness": [0.5, 2.5], "damping": [0.01, 0.05]}
        return base
    raise SceneError("preset", f"unknown preset {name!r}; choose one of {', '.join(PRESETS)}")


PRESETS = ("paper-10", "paper-41", "paper-42", "paper-43")
UNIT_SYSTEMS = ("dimensionless", "SI")
DEFAULT_PRESET = "paper-10"
KEY_DEFAULTS = {"preset": DEFAULT_PRESET}  # defaults that are no field of the scene (the reference reads them)

_LAW = lambda law: {"speed": {"law": law}}  # noqa: E731
# every key of a two-plane scene file (the scene reference docs/scenes.md is generated from this and the
# defaults of the preset "paper-10"; tests/families/test_scene_reference.py checks each domain against
# from_mapping).  The paper's sets are dimensionless; the units say what a consistent SI scene means.
KEYS = (
    Key("preset", "", "other", "start from a named parameter set, then override", " or ".join(f'"{p}"' for p in PRESETS)),
    Key("units", "", "other", "the units the values are in: the model's parameters and states carry the units "
        "below (SI) or none (dimensionless, as the paper's sets)", " or ".join(f'"{u}"' for u in UNIT_SYSTEMS)),
    Key("rotor_mass", "kg", "positive", "M, the rotor mass"),
    Key("transverse_inertia", "kg m^2", "positive", "J_t, transverse moment of inertia"),
    Key("polar_inertia", "kg m^2", "positive", "J_p, polar moment of inertia"),
    Key("eccentricity", "m", "nonnegative", "epsilon, C -> G (static imbalance)"),
    Key("imbalance_phase", "rad", "real", "beta, phase of the static imbalance"),
    Key("misalignment", "rad", "other", "chi, tilt of the principal axis (couple imbalance)", "|chi| < pi/4"),
    Key("bearing_1.position", "m", "nonnegative", "l_1, axial position of bearing 1 (+l_1)"),
    Key("bearing_1.stiffness", "N/m", "nonnegative", "k_1 or [k_1X, k_1Y]"),
    Key("bearing_1.damping", "N s/m", "nonnegative", "c_1 or [c_1X, c_1Y]"),
    Key("bearing_2.position", "m", "nonnegative", "l_2, axial position of bearing 2 (-l_2)"),
    Key("bearing_2.stiffness", "N/m", "nonnegative", "k_2 or [k_2X, k_2Y]"),
    Key("bearing_2.damping", "N s/m", "nonnegative", "c_2 or [c_2X, c_2Y]"),
    Key("races[].z", "m", "real", "axial position of the race (exactly two races, in different planes)"),
    Key("races[].radius", "m", "positive", "R, radius of the race"),
    Key("races[].masses", "kg", "positive", "the ball masses of the race (a list; any number of balls)"),
    Key("races[].damping", "N m s/rad", "nonnegative", "c_b, race damping of each ball"),
    Key("rolling_resistance", "", "nonnegative",
        "mu_r, ball-race friction while a ball slips: a tangential force mu_r N against the ball's motion relative "
        "to its race, N the race's normal force on the ball (derived); one value or a list (one per ball, race by "
        "race); absent: no friction (the paper's model)"),
    Key("static_friction", "", "nonnegative",
        "mu_s >= mu_r, stiction coefficient of a ball at rest on its race: one value or a list (one per ball, race "
        "by race); given, the stick phase is derived: a ball at rest on its race stays there while the tangential "
        "force it needs is within mu_s N (docs/friction.md)",
        context={"rolling_resistance": 0.0}),
    Key("speed.law", "", "other", "how the spin is governed", '"constant", "ramp", "hill", "schedule" or "torque"'),
    Key("speed.omega", "rad/s", "positive", "constant spin speed (law = \"constant\")"),
    Key("speed.omega_max", "rad/s", "positive", "final spin speed of a run-up (law = \"ramp\" or \"hill\")",
        context=_LAW("ramp")),
    Key("speed.t_ramp", "s", "positive", "duration of the constant acceleration (law = \"ramp\")", context=_LAW("ramp")),
    Key("speed.t_half", "s", "positive", "time of half the final speed, paper (45) (law = \"hill\")", context=_LAW("hill")),
    Key("speed.n", "", "other", "Hill exponent, paper (45) (law = \"hill\")", "a whole number 1..7", _LAW("hill")),
    Key("speed.omega_cyl", "1/s", "positive", "time scale of the Hill profile, paper (45) (law = \"hill\")",
        context=_LAW("hill")),
    *(Key(f"speed.{key}", speed_schedule.MEANINGS[key][1].replace("dimensionless", ""),
          "other" if key == "reduction_depth" else
          "positive" if key in ("omega", "ramp_time", "reduction_rate", "recovery_rate") else "nonnegative",
          f"{speed_schedule.MEANINGS[key][0]} (law = \"schedule\")", "a number in [0, 1)" if key == "reduction_depth" else "",
          {"speed": {"law": "schedule", "omega": 3.0, "ramp_time": 100.0}}) for key in speed_schedule.KEYS),
    Key("speed.tau0", "N m", "real", "stall torque of the drive (law = \"torque\")", context=_LAW("torque")),
    Key("speed.motor_slope", "N m s/rad", "nonnegative", "slope of the drive's torque-speed line (law = \"torque\")",
        context=_LAW("torque")),
    Key("speed.torsion_damping", "N m s/rad", "nonnegative", "c_r, torsional damping (law = \"torque\")",
        context=_LAW("torque")),
)


@dataclass(frozen=True)
class TwoPlaneScene(BallFriction):
    """A two-plane automatic ball balancer on a rigid rotor (paper Figure 1)."""

    rotor_mass: float = 1.0  # M
    transverse_inertia: float = 3.25  # J_t
    polar_inertia: float = 0.5  # J_p
    eccentricity: float = 0.01  # epsilon, C -> G
    imbalance_phase: float = 0.0  # beta
    misalignment: float = 0.0  # chi, principal axis p_3 tilted about eta
    bearing_1: Bearing = field(default_factory=lambda: Bearing(3.0, 0.5, 0.01))
    bearing_2: Bearing = field(default_factory=lambda: Bearing(3.0, 0.5, 0.01))
    races: tuple[Race, ...] = field(default_factory=lambda: (Race(2.0, 1.0, (0.0025,) * 2, 2.5e-5),
                                                               Race(-2.0, 1.0, (0.0025,) * 2, 2.5e-5)))
    speed: TwoPlaneSpeed = field(default_factory=TwoPlaneSpeed)
    units: str = "dimensionless"  # or "SI": the units of the scene reference (KEYS)
    rolling_resistance: float | tuple[float, ...] | None = None  # mu_r or mu_r_k; None: no friction (issue 37)
    static_friction: float | tuple[float, ...] | None = None  # mu_s or mu_s_k: the stick phase

    @property
    def si(self) -> bool:
        return self.units == "SI"

    @classmethod
    def preset(cls, name: str, **overrides) -> "TwoPlaneScene":
        return replace(cls.from_mapping({"preset": name}), **overrides)

    @classmethod
    def from_mapping(cls, data: Mapping[str, Any]) -> "TwoPlaneScene":
        if not isinstance(data, Mapping):
            raise SceneError("<root>", "a scene is a table of options")
        known = {"preset", "rotor_mass", "transverse_inertia", "polar_inertia", "eccentricity", "imbalance_phase",
                 "misalignment", "bearing_1", "bearing_2", "races", "speed", "units",
                 "rolling_resistance", "static_friction"}
        for key in sorted(map(str, data)):
            if key not in known:
                raise SceneError(key, "unknown option")
        preset = data.get("preset", DEFAULT_PRESET)
        if not isinstance(preset, str):
            raise SceneError("preset", f"must be a name, got {preset!r}")
        raw = {**_preset(preset), **{k: v for k, v in data.items() if k != "preset"}}
        races = raw["races"]
        if not isinstance(races, (list, tuple)) or len(races) != 2:
            raise SceneError("races", f"a two-plane balancer has exactly two races, got {races!r:.60}")
        speed = raw["speed"]
        units = data.get("units", "dimensionless")
        if units not in UNIT_SYSTEMS:
            raise SceneError("units", f"must be one of {', '.join(UNIT_SYSTEMS)}, got {units!r}")
        scene = cls(
            rotor_mass=_number("rotor_mass", raw["rotor_mass"], positive=True),
            transverse_inertia=_number("transverse_inertia", raw["transverse_inertia"], positive=True),
            polar_inertia=_number("polar_inertia", raw["polar_inertia"], positive=True),
            eccentricity=_number("eccentricity", raw["eccentricity"], nonnegative=True),
            imbalance_phase=_number("imbalance_phase", raw["imbalance_phase"]),
            misalignment=_number("misalignment", raw["misalignment"]),
            bearing_1=raw["bearing_1"] if isinstance(raw["bearing_1"], Bearing)
            else Bearing.from_mapping("bearing_1", raw["bearing_1"]),
            bearing_2=raw["bearing_2"] if isinstance(raw["bearing_2"], Bearing)
            else Bearing.from_mapping("bearing_2", raw["bearing_2"]),
            races=tuple(r if isinstance(r, Race) else Race.from_mapping(f"races[{i}]", r) for i, r in enumerate(races)),
            speed=speed if isinstance(speed, TwoPlaneSpeed) else TwoPlaneSpeed.from_mapping(speed),
            units=units,
        )
        rolling, static = friction_coefficients(raw.get("rolling_resistance"), raw.get("static_friction"), scene.n)
        if rolling is not None:
            scene = replace(scene, rolling_resistance=rolling, static_friction=static)
        scene.validate()
        return scene

    @classmethod
    def load(cls, path: str | Path) -> "TwoPlaneScene":
        path = Path(path)
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise SceneError("<file>", f"no scene file at {path}") from None
        except (OSError, UnicodeDecodeError) as exc:
            raise SceneError("<file>", f"cannot read {path}: {exc}") from None
        except tomllib.TOMLDecodeError as exc:
            raise SceneError("<file>", f"{path} is not valid TOML: {exc}") from None
        return cls.from_mapping(data)

    def validate(self) -> None:
        """Physical consistency that single fields cannot show."""
        if abs(self.misalignment) >= math.pi / 4:
            raise SceneError("misalignment", f"chi is a small angle (|chi| < pi/4), got {self.misalignment!r}")
        if self.bearing_1.position + self.bearing_2.position <= 0:
            raise SceneError("bearing_2.position", "the bearings must be at distinct axial positions (l_1 + l_2 > 0)")
        k1, k2 = self.bearing_1.xy("stiffness"), self.bearing_2.xy("stiffness")
        for axis in (0, 1):
            if k1[axis] + k2[axis] <= 0:
                raise SceneError("bearing_1.stiffness", "the rotor needs some support stiffness in X and in Y")
        if not self.masses():
            raise SceneError("races", "a balancer needs at least one ball")
        if self.races[0].z == self.races[1].z:
            raise SceneError("races[1].z", "the two races must be in different planes")

    # --- structure -------------------------------------------------------------------------
    @property
    def isotropic(self) -> bool:
        return all(not isinstance(getattr(b, w), tuple) for b in (self.bearing_1, self.bearing_2)
                   for w in ("stiffness", "damping"))

    @property
    def ball_race(self) -> tuple[int, ...]:
        """Race index (0 = the first race, 'top' in the paper) of each ball, balls numbered race by race."""
        return tuple(j for j, race in enumerate(self.races) for _ in race.masses)

    @property
    def n(self) -> int:
        return len(self.ball_race)

    def masses(self) -> tuple[float, ...]:
        return tuple(m for race in self.races for m in race.masses)

    @property
    def symmetric(self) -> bool:
        """The paper's symmetric set-up of section 3 (equal balls, mirror races, equal bearings, isotropic)."""
        r0, r1 = self.races
        return (self.isotropic and self.bearing_1 == self.bearing_2 and r0.z == -r1.z and r0.radius == r1.radius
                and len(set(self.masses())) == 1 and len(r0.masses) == len(r1.masses) and r0.damping == r1.damping)
