"""The two-plane models offered for generation (paper: Rodrigues et al. 2011), with start points and checks.

Default set of `generated/` (the paper's set-up (10): M = 1, J_t = 3.25, J_p = 0.5, bearings k = 0.5,
c = 0.01 at l = 3, races z = +-2, R = 1, two balls each; ball mass m = 0.003 > m_c = M eps/(4R) = 0.0025
so that the balanced state B of (9) exists with alpha_hat = arccos(m_c/m)):

- ``two_plane_rotating``: the symmetric set-up in the rotating frame (7)-(8), autonomous at Omega = 3;
  AUTO-07p follows B (stpnt) in Omega downwards through the critical speeds (11);
- ``two_plane_fixed``: the anisotropic rotor of (43) (k_Y = 5 k_X, c_Y = 5 c_X) in the fixed frame at
  constant speed, ball angles taken from the spin; periodically forced, so AUTO-07p continues the
  periodic orbits of its oscillator extension (40), from the exact orbit "B with the rotor at rest"
  (no support force acts, whatever the anisotropy), in Omega;
- ``two_plane_ramp``, ``two_plane_hill``: run-ups of section 6 with the spin prescribed, the constant-
  acceleration ramp and the Hill profile (45) (explicit time, no steady state: no AUTO files);
- ``two_plane_torque``: the rotor driven by the torque tau0 - kappa theta_0' with the torsional equation
  (3), theta_0 a coordinate (no steady state: it spins up; no AUTO files).
"""

from __future__ import annotations

import math

from ...core.model_spec import Check, Continuation, ModelSpec
from . import description, friction, verify
from .model import derive
from .reductions import balls_relative_to_spin, first_order, rotating_frame
from .scene import TwoPlaneScene
from .symbols import RACE_TAGS

FAMILY = "two-plane"
BALL_MASS = 0.003


def checks(*calls: tuple) -> tuple[Check, ...]:
    """Checks of `verify` by (function name, *args)."""
    return tuple(Check((FAMILY, name, *args), lambda fn=getattr(verify, name), args=args: fn(*args))
                 for name, *args in calls)


def scene(preset: str = "paper-10", speed: dict | None = None, m: float = BALL_MASS) -> TwoPlaneScene:
    data = {"preset": preset, "races": [{"z": z, "radius": 1.0, "masses": [m, m], "damping": 0.01 * m}
                                        for z in (2.0, -2.0)]}
    if speed is not None:
        data["speed"] = speed
    return TwoPlaneScene.from_mapping(data)


def race_slots(sc: TwoPlaneScene):
    """Each ball's own parameters for the loop form (`codegen.passes.ball_split`): its mass and its race's radius,
    plane and damping, by name (m_k or the symmetric m; R_t, z_t, c_bt for the balls of race t, or
    the section-3 R, +-z, c_b of `symbols.symmetric_substitution`)."""
    def slots(system) -> list[dict]:
        names = {p.name: p.symbol for p in system.parameters}
        out = []
        for k, race in enumerate(sc.ball_race):
            tag = RACE_TAGS[race]
            ball = {"m": names.get(f"m_{k + 1}", names.get("m")), "R": names.get(f"R_{tag}", names.get("R")),
                    "c_b": names.get(f"c_b{tag}", names.get("c_b"))}
            ball["z"] = names[f"z_{tag}"] if f"z_{tag}" in names else \
                (names["z"] if race == 0 else -names["z"]) if "z" in names else None
            for stem in ("stuck", "slip_dir", "mu_r", "mu_s"):  # a stiction model's modes and coefficients (issue 37)
                ball[stem] = names.get(f"{stem}_{k + 1}")
            out.append({key: value for key, value in ball.items() if value is not None})
        return out
    return slots


def balanced_angles(sc: TwoPlaneScene) -> list[float] | None:
    """B of (9) for the symmetric races: alpha = pi +- arccos(m_c/m), m_c = M eps/(4R), in each race."""
    if len(sc.races) != 2 or sc.misalignment != 0:
        return None
    r0, r1 = sc.races
    mirrored = (r1.z == -r0.z and r1.radius == r0.radius and len(r0.masses) == 2
                and len(set(r0.masses + r1.masses)) == 1)
    m_c = sc.rotor_mass * sc.eccentricity / (4 * r0.radius)
    if not mirrored or r0.masses[0] <= m_c:
        return None  # (the bearings do not matter: at B the rotor is at rest, no support force acts)
    a = math.acos(m_c / r0.masses[0])
    return [math.pi + a, math.pi - a] * 2


def _b_label(sc: TwoPlaneScene) -> str:
    r0 = sc.races[0]
    m_c = sc.rotor_mass * sc.eccentricity / (4 * r0.radius)
    return f"balanced state B (9), alpha_hat = arccos(m_c/m) = {math.acos(m_c / r0.masses[0]):.12f}"


def rotating_start(sc: TwoPlaneScene):
    def start(system):
        angles = balanced_angles(sc)
        if angles is None:
            return None, ""
        n = len(system.coordinates)
        return tuple([0.0] * 4 + angles + [0.0] * n), _b_label(sc) + ", at the defaults"
    return start


def orbit_start(sc: TwoPlaneScene):
    def start(system):
        angles = balanced_angles(sc)
        if angles is None:
            return None, ""
        n = len(system.coordinates)
        return (tuple([0.0] * 4 + angles + [0.0] * n + [0.0, 1.0]),
                _b_label(sc) + ", rotor at rest: a periodic orbit at the defaults, t = 0 (exact)")
    return start


def two_plane_rotating() -> ModelSpec:
    sc = scene()
    return ModelSpec(
        "two_plane_rotating", "Two-plane balancer, symmetric set-up (10), 2 + 2 balls, rotating frame (7)-(8)",
        sc.n, lambda: first_order(rotating_frame(sc)), rotating_start(sc), family=FAMILY,
        checks=checks(("rotating",), ("balanced_condition",)), balls=race_slots(sc),
        continuation=Continuation("Omega", direction=-1, stop=(0.5, 6.0)), kind="two_plane_rotating",
        describe=lambda system: description.describe(system, sc, {"paper (10)": description.defaults(system)},
                                                      ("B", "C3"), forcing=""))


def two_plane_fixed() -> ModelSpec:
    sc = scene("paper-43")
    return ModelSpec(
        "two_plane_fixed", "Two-plane balancer, anisotropic bearings (43), 2 + 2 balls, fixed frame, constant speed",
        sc.n, lambda: first_order(balls_relative_to_spin(sc)), orbit_start=orbit_start(sc), family=FAMILY,
        checks=checks(("fixed_frame",), ("oscillator",)), balls=race_slots(sc),
        orbit_continuation=Continuation("Omega", direction=-1), kind="two_plane_fixed",
        describe=lambda system: description.describe(
            system, sc, {"paper (43)": description.defaults(system), **description.FIGURE_12A_SET}, ("B",),
            forcing="Omega"))


def run_up_description(sc: TwoPlaneScene):
    """The run-ups of section 6 (explicit time, not periodic): the paper's sets (10) and of section 6."""
    return lambda system: description.describe(
        system, sc, {"paper (10)": description.defaults(system), **description.RUN_UP_SETS}, forcing="")


def two_plane_ramp() -> ModelSpec:
    sc = scene(speed={"law": "ramp", "omega_max": 3.6, "t_ramp": 6000.0})
    return ModelSpec("two_plane_ramp", "Two-plane balancer (10), 2 + 2 balls, run-up at constant acceleration (section 6)",
                     sc.n, lambda: first_order(derive(sc)), family=FAMILY,
                     checks=checks(("fixed_frame",), ("prescribed_speed", "ramp")), balls=race_slots(sc),
                     kind="two_plane_ramp", describe=run_up_description(sc))


def two_plane_hill_scene() -> TwoPlaneScene:
    return scene(speed={"law": "hill", "omega_max": 3.6, "t_half": 200.0, "n": 3, "omega_cyl": 1.0})


def two_plane_hill() -> ModelSpec:
    sc = two_plane_hill_scene()
    return ModelSpec("two_plane_hill", "Two-plane balancer (10), 2 + 2 balls, Hill run-up (45)",
                     sc.n, lambda: first_order(derive(sc)), family=FAMILY,
                     checks=checks(("fixed_frame",), ("prescribed_speed", "hill")), balls=race_slots(sc),
                     kind="two_plane_hill", describe=run_up_description(sc))


def two_plane_torque() -> ModelSpec:
    sc = scene(speed={"law": "torque", "tau0": 0.036, "motor_slope": 0.01, "torsion_damping": 0.0})
    return ModelSpec("two_plane_torque", "Two-plane balancer (10), 2 + 2 balls, torque drive with the torsional equation (3)",
                     sc.n, lambda: first_order(derive(sc)), family=FAMILY, checks=checks(("fixed_frame",)),
                     balls=race_slots(sc), kind="two_plane_torque",
                     describe=lambda system: description.describe(
                         system, sc, {"paper (10)": description.defaults(system)}, forcing=""))


KINDS = {"two_plane_rotating": two_plane_rotating, "two_plane_fixed": two_plane_fixed,
         "two_plane_ramp": two_plane_ramp, "two_plane_hill": two_plane_hill, "two_plane_torque": two_plane_torque}


def default_set() -> list[ModelSpec]:
    return [kind() for kind in KINDS.values()]


def for_scene(sc: TwoPlaneScene, name: str | None = None) -> ModelSpec:
    """The smallest exact model of a two-plane scene: the rotating frame when it is autonomous there
    (isotropic bearings, constant speed), else the fixed frame (ball angles from the spin at constant
    speed), with theta_0 a coordinate under a torque drive.  With ball-race friction (issue 37) the fixed
    frame of `model.derive` whatever the speed law, without a start or steady state (its balanced states are
    stuck states, where Coulomb's law in slip says nothing)."""
    law = sc.speed.law
    extra = {}
    if sc.friction:  # issue 37: friction is derived in the fixed frame only; no closed-form steady state
        kind, system = f"friction_{law}", (lambda: first_order(derive(sc)))
        calls = (("friction_zero_limit",), ("friction_normal_force",))
        if sc.stiction:  # the hybrid system: modes as parameters, switching functions as measures
            kind = f"stick_{law}"
            calls += (("friction_stick_rows",), ("friction_stick_force",))
            extra = {"measures": lambda system: friction.measures(sc, system)}
    elif law == "constant" and sc.isotropic:
        kind, system, calls = "rotating", (lambda: first_order(rotating_frame(sc))), (("fixed_frame",), ("rotating",))
    elif law == "constant":
        kind, system, calls = "fixed", (lambda: first_order(balls_relative_to_spin(sc))), (("fixed_frame",), ("oscillator",))
    else:
        kind, system = law, (lambda: first_order(derive(sc)))
        calls = (("fixed_frame",),) + ((("prescribed_speed", law),) if law in ("ramp", "hill") else ())
    start = rotating_start(sc) if kind == "rotating" else (lambda system: (None, ""))
    two_each = len(sc.races) == 2 and sorted(sc.ball_race) == [0, 0, 1, 1]
    steady = (("B",) if two_each and kind in ("rotating", "fixed") else ()) + \
        (("C3",) if two_each and kind == "rotating" else ())
    return ModelSpec(name or f"scene_two_plane_{kind}_n{sc.n}", f"Two-plane balancer with {sc.n} balls ({kind})",
                     sc.n, system, start, family=FAMILY, checks=checks(*calls), balls=race_slots(sc),
                     continuation=Continuation("Omega", direction=-1) if kind == "rotating" else None, kind="scene",
                     describe=lambda system: description.describe(
                         system, sc, steady=steady, **{k: f(system) for k, f in extra.items()}))
