"""The scene: what a user describes in a few lines, validated before anything is derived.

A scene fixes the *structure* of the model (number of balls, whether balls are equal, whether the
support is isotropic, gravity on/off, the speed law) and supplies *default values* for its
parameters.  The derivation stays symbolic in every parameter; values only become defaults of the
generated code.  Units are SI throughout (kg, m, s, rad).

The default scene is the thesis' parameter set (5.1) with n = 2 realised physically:
M = 1 kg, k = 1e4 N/m (omega_n = 100 rad/s), R = 0.05 m, so that mu = 0.05, Omega = 4,
zeta = beta = delta = 0.01.

A scene in TOML::

    n = 3
    ball_mass = 0.05            # one value: equal balls; a list of n values: unequal balls
    stiffness = [1.0e4, 1.2e4]  # one value: isotropic; [k_X, k_Y]: anisotropic
    gravity = true
    [speed]
    law = "constant"            # or "profile" (omega = "expression in t"), "schedule" or "torque"
    omega = 400.0
"""

from __future__ import annotations

import ast
import math
import tomllib
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Mapping

from ...core import speed_schedule
from ...core.scene_fields import (BallFriction, Key, friction_coefficients, number as _number, per_ball as _per_ball,
                                 speed_law_name, xy as _xy)
from ...errors import SceneError

# a schedule's keys in the order of its phases: run-up ramp, hold, temporary speed reduction (fall, plateau,
# recovery); each a parameter of the generated model (adbgen simulate/sweep --set NAME=VALUE changes it)
SCHEDULE_KEYS = speed_schedule.KEYS
_SPEED_FIELDS = {
    "constant": {"law", "omega"},
    "profile": {"law", "omega"},
    "schedule": {"law", *SCHEDULE_KEYS},
    "torque": {"law", "tau0", "motor_slope"},
}
# Functions allowed in a speed profile expression; nothing else is evaluated.
_PROFILE_FUNCTIONS = ("exp", "sin", "cos", "tanh", "sqrt", "log", "Min", "Max", "pi")


@dataclass(frozen=True)
class SpeedLaw:
    """How the spin psi of the rotor is governed.

    - ``constant``: psi = omega t (thesis (2.14));
    - ``profile``: psi' = Omega(t) given as an expression in t (a run-up);
    - ``schedule``: psi' piecewise linear in t (`core.speed_schedule.law`): a ramp from rest to omega over
      ramp_time, a hold, then a temporary speed reduction by reduction_depth (a fraction of omega) at
      reduction_rate, a plateau of plateau_time and the recovery to omega at recovery_rate (Machines 2020,
      8(4), 74; Wright and Peng, arXiv 1906.04823); its values are parameters of the model;
    - ``torque``: psi is a degree of freedom driven by tau(psi') = tau0 - motor_slope psi' (2.9), the
      motor's linear torque-speed law (a run-up through resonance can be trapped: the Sommerfeld effect).
    """

    law: str = "constant"
    omega: float | str | None = 400.0
    tau0: float = 0.0
    motor_slope: float = 0.0
    schedule: tuple[tuple[str, float], ...] = ()  # (key, value) in SCHEDULE_KEYS order (law = "schedule")

    @classmethod
    def from_mapping(cls, data: Any) -> "SpeedLaw":
        law = speed_law_name(data, _SPEED_FIELDS)
        if law == "constant":
            return cls(law, omega=_number("speed.omega", data.get("omega", 400.0), positive=True))
        if law == "profile":
            expr = data.get("omega")
            if not isinstance(expr, str) or not expr.strip():
                raise SceneError("speed.omega", "a profile needs omega = 'expression in t' (rad/s)")
            profile_expression(expr)  # validates
            return cls(law, omega=expr)
        if law == "schedule":
            return cls(law, omega=None, schedule=speed_schedule.validate(data))
        return cls(
            law,
            omega=None,
            tau0=_number("speed.tau0", data.get("tau0", 0.0)),
            motor_slope=_number("speed.motor_slope", data.get("motor_slope", 0.0), nonnegative=True),
        )


_ALLOWED_BINOPS = (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow)
_MAX_CONSTANT_EXPONENT = 100  # exact integer powers are computed eagerly: 10**10**10 would never return


def _check_profile_syntax(text: str) -> None:
    """Whitelist the syntax tree: numbers, t, + - * / **, unary signs, calls of the named functions."""
    def fail(why: str):
        raise SceneError("speed.omega", f"profile {text!r}: {why}; use numbers, t, + - * / ** ( ) and "
                         f"{', '.join(_PROFILE_FUNCTIONS)}")

    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError:
        fail("not an expression")

    def has_t(node) -> bool:
        return any(isinstance(n, ast.Name) and n.id == "t" for n in ast.walk(node))

    for node in ast.walk(tree):
        if isinstance(node, (ast.Expression, ast.Load)):
            continue
        if isinstance(node, ast.BinOp):
            if not isinstance(node.op, _ALLOWED_BINOPS):
                fail(f"operator {type(node.op).__name__} is not allowed")
            if isinstance(node.op, ast.Pow) and not has_t(node):
                exponent = node.right.operand if isinstance(node.right, ast.UnaryOp) else node.right
                if not (isinstance(exponent, ast.Constant) and abs(exponent.value) <= _MAX_CONSTANT_EXPONENT):
                    fail(f"a constant power needs a number up to {_MAX_CONSTANT_EXPONENT} as exponent")
        elif isinstance(node, (ast.UnaryOp,)):
            if not isinstance(node.op, (ast.UAdd, ast.USub)):
                fail("only unary + and - are allowed")
        elif isinstance(node, (ast.UAdd, ast.USub, *_ALLOWED_BINOPS)):
            continue
        elif isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
                fail(f"{node.value!r} is not a number")
        elif isinstance(node, ast.Name):
            if node.id != "t" and node.id not in _PROFILE_FUNCTIONS:
                fail(f"unknown name {node.id}")
        elif isinstance(node, ast.Call):
            if not (isinstance(node.func, ast.Name) and node.func.id in _PROFILE_FUNCTIONS) or node.keywords:
                fail("only the named functions may be called")
        else:
            fail(f"{type(node).__name__} is not allowed")


def profile_expression(text: str):
    """Parse a speed profile Omega(t) safely: only t, numbers and a few named functions."""
    import sympy as sp
    from sympy.parsing.sympy_parser import parse_expr, standard_transformations

    _check_profile_syntax(text)  # parse_expr evaluates Python: vet the syntax tree first
    t = sp.Symbol("t", real=True)
    allowed = {name: getattr(sp, name) for name in _PROFILE_FUNCTIONS}
    allowed["t"] = t
    numbers = {"Integer": sp.Integer, "Float": sp.Float, "Rational": sp.Rational}
    try:
        expr = parse_expr(text.strip(), local_dict=allowed, global_dict={"__builtins__": {}, **numbers, **allowed},
                          transformations=standard_transformations, evaluate=True)
    except Exception as exc:  # parse_expr raises many types; all mean the same to a user
        raise SceneError("speed.omega", f"cannot parse profile {text!r}: {type(exc).__name__}") from None
    if not isinstance(expr, sp.Expr):
        raise SceneError("speed.omega", f"profile {text!r} is not an expression")
    value = expr.subs(t, 0)
    if not value.is_real or not value.is_finite:
        raise SceneError("speed.omega", f"profile {text!r} is not finite and real at t = 0")
    return expr


_TORQUE = {"speed": {"law": "torque"}}
# every key of a single-plane scene file (the scene reference docs/scenes.md is generated from this and
# the defaults below; tests/families/test_scene_reference.py checks each domain against from_mapping)
KEYS = (
    Key("n", "", "other", "number of balls", "a whole number >= 1"),
    Key("rotor_mass", "kg", "positive", "M, the rotor (disc) mass"),
    Key("eccentricity", "m", "nonnegative", "eps, distance from the rotor's centre C to its centre of mass W"),
    Key("polar_inertia", "kg m^2", "positive", "I_z, the rotor's polar moment of inertia (used by law = \"torque\")"),
    Key("race_radius", "m", "positive", "R, radius of the balls' race"),
    Key("ball_mass", "kg", "positive", "m: one value (equal balls) or a list of n values (unequal balls)"),
    Key("ball_damping", "N m s/rad", "nonnegative", "D, viscous drag on each ball: one value or a list of n"),
    Key("rolling_resistance", "", "nonnegative",
        "mu_r, ball-race friction while a ball slips: a tangential force mu_r N against the ball's motion "
        "relative to the race, N the race's normal force on the ball (derived); one value or a list of n; "
        "absent: no friction (the models of the thesis)"),
    Key("static_friction", "", "nonnegative",
        "mu_s >= mu_r, stiction coefficient of a ball at rest on the race: one value or a list of n; "
        "given, the stick phase is modelled: a ball at rest on the race stays there while the tangential force it "
        "needs is within mu_s N (an event-driven hybrid system, docs/friction.md)",
        context={"rolling_resistance": 0.0}),
    Key("stiffness", "N/m", "nonnegative", "k (isotropic support) or [k_X, k_Y] (anisotropic)"),
    Key("damping", "N s/m", "nonnegative", "c (isotropic) or [c_X, c_Y]"),
    Key("gravity", "", "other", "gravity in -Y on (the model keeps explicit time)", "true or false"),
    Key("g", "m/s^2", "positive", "gravitational acceleration (used with gravity = true)"),
    Key("speed.law", "", "other", "how the spin is governed", "\"constant\", \"profile\", \"schedule\" or \"torque\""),
    Key("speed.omega", "rad/s", "positive", "constant spin speed (law = \"constant\")"),
    Key("speed.omega", "rad/s", "other", "run-up Omega(t) (law = \"profile\")",
        "an expression in t of numbers, + - * / **, " + ", ".join(_PROFILE_FUNCTIONS), {"speed": {"law": "profile"}}),
    Key("speed.omega", "rad/s", "positive", "the speed a schedule runs up to and returns to (law = \"schedule\")",
        context={"speed": {"law": "schedule", "ramp_time": 1.0}}),
    Key("speed.ramp_time", "s", "positive", "a schedule's run-up from rest to omega, at a constant rate",
        context={"speed": {"law": "schedule", "omega": 400.0}}),
    Key("speed.hold_time", "s", "nonnegative", "a schedule's time at omega before the temporary reduction (default 0)",
        context={"speed": {"law": "schedule", "omega": 400.0, "ramp_time": 1.0}}),
    Key("speed.reduction_depth", "", "other", "the temporary speed reduction, a fraction of omega (default 0: none)",
        "a number in [0, 1)", {"speed": {"law": "schedule", "omega": 400.0, "ramp_time": 1.0}}),
    Key("speed.reduction_rate", "rad/s^2", "positive", "how fast the speed falls to the reduced speed "
        "(default omega / ramp_time)", context={"speed": {"law": "schedule", "omega": 400.0, "ramp_time": 1.0}}),
    Key("speed.plateau_time", "s", "nonnegative", "time held at the reduced speed (default 0)",
        context={"speed": {"law": "schedule", "omega": 400.0, "ramp_time": 1.0}}),
    Key("speed.recovery_rate", "rad/s^2", "positive", "how fast the speed returns to omega (default omega / ramp_time)",
        context={"speed": {"law": "schedule", "omega": 400.0, "ramp_time": 1.0}}),
    Key("speed.tau0", "N m", "real", "stall torque of the drive, tau = tau0 - motor_slope psi' (law = \"torque\")",
        context=_TORQUE),
    Key("speed.motor_slope", "N m s/rad", "nonnegative", "slope of the drive's torque-speed line (law = \"torque\")",
        context=_TORQUE),
)


@dataclass(frozen=True)
class Scene(BallFriction):
    """A single-plane automatic dynamic balancer (thesis ch. 2, Figure 2.1)."""

    n: int = 2
    rotor_mass: float = 1.0  # M
    eccentricity: float = 5.0e-4  # epsilon, distance C -> W
    polar_inertia: float = 2.5e-3  # I_z, used only when the spin is a degree of freedom
    race_radius: float = 0.05  # R
    ball_mass: float | tuple[float, ...] = 0.05  # m or m_i
    ball_damping: float | tuple[float, ...] = 1.25e-4  # D or D_i
    stiffness: float | tuple[float, float] = 1.0e4  # k or (k_X, k_Y)
    damping: float | tuple[float, float] = 2.0  # c or (c_X, c_Y)
    gravity: bool = False
    g: float = 9.80665
    speed: SpeedLaw = field(default_factory=SpeedLaw)
    rolling_resistance: float | tuple[float, ...] | None = None  # mu_r or mu_r_i; None: no friction
    static_friction: float | tuple[float, ...] | None = None  # mu_s or mu_s_i: the stick phase (hybrid)

    # --- construction ------------------------------------------------------------------
    @classmethod
    def from_mapping(cls, data: Mapping[str, Any]) -> "Scene":
        if not isinstance(data, Mapping):
            raise SceneError("<root>", "a scene is a table of options")
        known = {f.name for f in fields(cls)}
        for key in sorted(map(str, data)):
            if key not in known:
                raise SceneError(key, "unknown option")
        defaults = cls()
        raw = {f.name: data.get(f.name, getattr(defaults, f.name)) for f in fields(cls)}
        n = raw["n"]
        if isinstance(n, bool) or not isinstance(n, int):
            if isinstance(n, float) and math.isfinite(n) and n.is_integer():
                n = int(n)
            else:
                raise SceneError("n", f"must be a whole number of balls, got {n!r}")
        if n < 1:
            raise SceneError("n", f"needs at least one ball, got {n}")
        gravity = raw["gravity"]
        if not isinstance(gravity, bool):
            raise SceneError("gravity", f"must be true or false, got {gravity!r}")
        speed = raw["speed"]
        if not isinstance(speed, SpeedLaw):
            speed = SpeedLaw.from_mapping(speed)
        rolling, static = friction_coefficients(raw["rolling_resistance"], raw["static_friction"], n)
        return cls(
            n=n,
            rotor_mass=_number("rotor_mass", raw["rotor_mass"], positive=True),
            eccentricity=_number("eccentricity", raw["eccentricity"], nonnegative=True),
            polar_inertia=_number("polar_inertia", raw["polar_inertia"], positive=True),
            race_radius=_number("race_radius", raw["race_radius"], positive=True),
            ball_mass=_per_ball("ball_mass", raw["ball_mass"], n, positive=True),
            ball_damping=_per_ball("ball_damping", raw["ball_damping"], n, nonnegative=True),
            stiffness=_xy("stiffness", raw["stiffness"], nonnegative=True),
            damping=_xy("damping", raw["damping"], nonnegative=True),
            gravity=gravity,
            g=_number("g", raw["g"], positive=True),
            speed=speed,
            rolling_resistance=rolling,
            static_friction=static,
        )

    @classmethod
    def load(cls, path: str | Path) -> "Scene":
        path = Path(path)
        try:
            text = path.read_text(encoding="utf-8")
        except FileNotFoundError:
            raise SceneError("<file>", f"no scene file at {path}") from None
        except OSError as exc:
            raise SceneError("<file>", f"cannot read {path}: {exc.strerror or exc}") from None
        except UnicodeDecodeError:
            raise SceneError("<file>", f"{path} is not UTF-8 text") from None
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise SceneError("<file>", f"{path} is not valid TOML: {exc}") from None
        return cls.from_mapping(data)

    # --- structure -----------------------------------------------------------------------
    @property
    def equal_balls(self) -> bool:
        return not any(isinstance(v, tuple) for v in (self.ball_mass, self.ball_damping, self.rolling_resistance))

    @property
    def isotropic(self) -> bool:
        return not isinstance(self.stiffness, tuple) and not isinstance(self.damping, tuple)

    def masses(self) -> tuple[float, ...]:
        return self.ball_mass if isinstance(self.ball_mass, tuple) else (self.ball_mass,) * self.n

    def ball_dampings(self) -> tuple[float, ...]:
        d = self.ball_damping
        return d if isinstance(d, tuple) else (d,) * self.n

    def stiffness_xy(self) -> tuple[float, float]:
        k = self.stiffness
        return k if isinstance(k, tuple) else (k, k)

    def damping_xy(self) -> tuple[float, float]:
        c = self.damping
        return c if isinstance(c, tuple) else (c, c)

    def nondimensional(self) -> dict[str, float]:
        """The thesis' dimensionless parameters (2.15)-(2.19); needs (2.14) and (2.18) to hold."""
        if not (self.equal_balls and self.isotropic and self.speed.law == "constant"):
            raise SceneError("speed", "the thesis scalings (2.14)-(2.19) need equal balls, "
                             "isotropic support and constant speed")
        k = self.stiffness_xy()[0]
        if k <= 0:
            raise SceneError("stiffness", "the scalings (2.15)-(2.19) need a positive stiffness")
        if self.eccentricity <= 0 and self.gravity:
            raise SceneError("eccentricity", "G = g/(eps omega_n^2) (2.16) needs eps > 0")
        M, m, R = self.rotor_mass, self.masses()[0], self.race_radius
        omega_n = math.sqrt(k / M)
        out = {
            "mu": m / M,
            "Omega": float(self.speed.omega) / omega_n,
            "zeta": self.damping_xy()[0] / (2.0 * math.sqrt(k * M)),
            "beta": self.ball_dampings()[0] / (m * R**2 * omega_n),
            "delta": self.eccentricity / R,
        }
        out["G"] = self.g / (self.eccentricity * omega_n**2) if self.gravity else 0.0
        # 15 significant digits: the ratios of values given in decimal come out as printed ((5.1):
        # beta = 0.01, not 0.009999999999999998), which the generated code's defaults show
        return {key: float(f"{value:.15g}") for key, value in out.items()}
