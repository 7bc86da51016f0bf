"""Parameter symbols of the two-plane model, named as in the paper (section 2).

One place creates every symbol with the assumptions the derivation relies on.  The scene decides which
exist: per-bearing k_1X, k_1Y (anisotropic) or k_1 (isotropic), the symbols of the speed law, one mass
m_k per ball, and radius, plane and race damping per race (R_t, z_t, c_bt for the first ("top") race,
R_b, z_b, c_bb for the second).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ...core import Parameter, ParameterTable, speed_schedule
from ...core.symbols import nonnegative, positive, t
from .scene import TwoPlaneScene

RACE_TAGS = ("t", "b")  # the paper's top race (balls 1, 2) and bottom race (balls 3, 4)


@dataclass(frozen=True)
class TwoPlaneSymbols:
    M: sp.Symbol
    Jt: sp.Symbol
    Jp: sp.Symbol
    eps: sp.Symbol
    beta: sp.Symbol
    chi: sp.Symbol
    l1: sp.Symbol
    l2: sp.Symbol
    k: dict  # {(bearing 1|2, 'X'|'Y'): symbol}
    c: dict
    m: tuple[sp.Symbol, ...]  # per ball
    R: tuple[sp.Symbol, ...]  # per ball (the race's symbol)
    z: tuple[sp.Symbol, ...]
    cb: tuple[sp.Symbol, ...]
    Omega: sp.Symbol  # constant speed (also the rotating frame's rate)
    c_r: sp.Symbol
    tau0: sp.Symbol
    kappa: sp.Symbol
    Omega_max: sp.Symbol
    t_ramp: sp.Symbol
    t_half: sp.Symbol
    Omega_cyl: sp.Symbol
    parameters: tuple[Parameter, ...]
    mu_r: tuple[sp.Expr, ...] = ()  # rolling resistance per ball (one symbol n times for one value); () without friction
    mu_s: tuple[sp.Expr, ...] = ()  # stiction per ball; () without static_friction
    stuck: tuple[sp.Symbol, ...] = ()  # each ball's mode: 1 stuck on its race (theta_k' = theta_0' held), 0 slipping
    slip_dir: tuple[sp.Symbol, ...] = ()  # the direction (+1 or -1) of ball k's slip (its mode), set by the driver
    accel: dict = None  # with stiction: {coordinate name: accel_<name>}, the core's accelerations as inputs of the
    #                     switching functions (the 4 x 4 / 5 x 5 core has no closed-form solve), filled by the driver

    @classmethod
    def for_scene(cls, scene: TwoPlaneScene) -> "TwoPlaneSymbols":
        params = ParameterTable()

        def add(symbol, description, unit, default):  # a dimensionless scene's parameters carry no unit
            return params.add(symbol, description, unit if scene.si else "dimensionless", default)

        M = add(positive("M"), "rotor mass", "kg", scene.rotor_mass)
        Jt = add(positive("J_t"), "transverse moment of inertia of the rotor", "kg m^2", scene.transverse_inertia)
        Jp = add(positive("J_p"), "polar moment of inertia of the rotor", "kg m^2", scene.polar_inertia)
        eps = add(nonnegative("epsilon"), "eccentricity C -> G (static imbalance)", "m", scene.eccentricity)
        beta = add(sp.Symbol("beta", real=True), "phase of the static imbalance from the xi axis", "rad",
                   scene.imbalance_phase)
        chi = add(sp.Symbol("chi", real=True), "misalignment of the principal axis (couple imbalance)", "rad",
                  scene.misalignment)
        l1 = add(nonnegative("l_1"), "axial position of bearing 1 (+l_1)", "m", scene.bearing_1.position)
        l2 = add(nonnegative("l_2"), "axial position of bearing 2 (-l_2)", "m", scene.bearing_2.position)
        k, c = {}, {}
        for j, b in ((1, scene.bearing_1), (2, scene.bearing_2)):
            (kx, ky), (cx, cy) = b.xy("stiffness"), b.xy("damping")
            if scene.isotropic:
                k[(j, "X")] = k[(j, "Y")] = add(nonnegative(f"k_{j}"), f"stiffness of bearing {j}", "N/m", kx)
                c[(j, "X")] = c[(j, "Y")] = add(nonnegative(f"c_{j}"), f"damping of bearing {j}", "N s/m", cx)
            else:
                for axis, kv, cv in (("X", kx, cx), ("Y", ky, cy)):
                    k[(j, axis)] = add(nonnegative(f"k_{j}{axis}"), f"stiffness of bearing {j} in {axis}", "N/m", kv)
                    c[(j, axis)] = add(nonnegative(f"c_{j}{axis}"), f"damping of bearing {j} in {axis}", "N s/m", cv)
        race_R, race_z, race_cb = [], [], []
        for tag, race in zip(RACE_TAGS, scene.races):
            race_R.append(add(positive(f"R_{tag}"), f"radius of race {tag}", "m", race.radius))
            race_z.append(add(sp.Symbol(f"z_{tag}", real=True), f"axial position of race {tag}", "m", race.z))
            race_cb.append(add(nonnegative(f"c_b{tag}"), f"race damping of each ball in race {tag}", "N m s/rad",
                               race.damping))
        masses = scene.masses()
        m = tuple(add(positive(f"m_{i + 1}"), f"mass of ball {i + 1}", "kg", masses[i]) for i in range(scene.n))
        races = scene.ball_race
        sp_ = scene.speed
        Omega, c_r, tau0, kappa = positive("Omega"), nonnegative("c_r"), sp.Symbol("tau_0", real=True), nonnegative("kappa")
        Om_max, t_ramp, t_half, Om_cyl = positive("Omega_max"), positive("t_ramp"), positive("t_half"), positive("Omega_cyl")
        if sp_.law == "constant":
            add(Omega, "spin speed", "rad/s", sp_.omega)
        elif sp_.law == "ramp":
            add(Om_max, "final spin speed of the run-up", "rad/s", sp_.omega_max)
            add(t_ramp, "duration of the constant acceleration", "s", sp_.t_ramp)
        elif sp_.law == "hill":
            add(Om_max, "final spin speed of the run-up (45)", "rad/s", sp_.omega_max)
            add(t_half, "half-speed time in units of 1/Omega_cyl (45)", "dimensionless", sp_.t_half)
            add(Om_cyl, "time scale Omega_cyl of (45)", "rad/s", sp_.omega_cyl)
        elif sp_.law == "schedule":  # ramp, hold, temporary speed reduction (issue 37); Omega the final speed
            speed_schedule.add_parameters(params, sp_.schedule, speed="Omega")
        else:
            add(c_r, "torsional damping c_r (3)", "N m s/rad", sp_.torsion_damping)
            add(tau0, "stall torque of the drive", "N m", sp_.tau0)
            add(kappa, "slope of the drive's torque-speed line", "N m s/rad", sp_.motor_slope)
        def coefficient(name, what, given, values):  # one symbol for every ball, or one each (issue 37)
            if isinstance(given, tuple):
                return tuple(params.add(nonnegative(f"{name}_{i + 1}"), f"{what}, ball {i + 1}", "dimensionless",
                                        values[i]) for i in range(scene.n))
            return (params.add(nonnegative(name), what, "dimensionless", values[0]),) * scene.n

        mu_r: tuple[sp.Expr, ...] = ()
        mu_s: tuple[sp.Expr, ...] = ()
        stuck: tuple[sp.Symbol, ...] = ()
        slip_dir: tuple[sp.Symbol, ...] = ()
        if scene.friction:
            mu_r = coefficient("mu_r", "rolling resistance of the balls on their race while slipping (tangential / "
                               "normal force)", scene.rolling_resistance, scene.rolling_resistances())
        if scene.stiction:  # the hybrid system's mode is a parameter of the model, set by the event driver
            mu_s = coefficient("mu_s", "stiction of a ball at rest on its race (largest tangential force / normal "
                               "force)", scene.static_friction, scene.static_frictions())
            stuck = tuple(params.add(sp.Symbol(f"stuck_{i + 1}", real=True), f"mode of ball {i + 1}: 1 stuck on its "
                                     "race, 0 slipping (set by the event driver)", "dimensionless", 0.0)
                          for i in range(scene.n))
            slip_dir = tuple(params.add(sp.Symbol(f"slip_dir_{i + 1}", real=True), f"direction (+1, -1) of ball "
                                        f"{i + 1}'s slip, its mode while slipping (set by the event driver)",
                                        "dimensionless", 0.0) for i in range(scene.n))
        accel = {}
        if scene.stiction:
            core = ("X", "Y", "phi_X", "phi_Y") + (("theta_0",) if sp_.law == "torque" else ())
            for name in core:
                unit = "m/s^2" if name in ("X", "Y") else "rad/s^2"
                accel[name] = add(sp.Symbol(f"accel_{name}", real=True), f"{name}'' as an input of the switching "
                                  "functions only (filled from the rhs by the event driver; not a parameter to set)",
                                  unit, 0.0)
        return cls(M, Jt, Jp, eps, beta, chi, l1, l2, k, c, m, tuple(race_R[r] for r in races),
                   tuple(race_z[r] for r in races), tuple(race_cb[r] for r in races), Omega, c_r, tau0, kappa,
                   Om_max, t_ramp, t_half, Om_cyl, params.sorted(), mu_r, mu_s, stuck, slip_dir, accel)


__all__ = ["TwoPlaneSymbols", "RACE_TAGS", "t"]


# The symmetric set-up of paper section 3: m_k = m, R_k = R, z_{1,2} = -z_{3,4} = z, l_1 = l_2 = l,
# k_{jX} = k_{jY} = k, c_{jX} = c_{jY} = c, one race damping c_b.
m, R, z, k, l, c, c_b = (positive("m"), positive("R"), positive("z"), positive("k"), positive("l"),
                         nonnegative("c"), nonnegative("c_b"))


def symmetric_substitution(s: TwoPlaneSymbols) -> dict:
    """Scene symbols -> the section-3 symbols (needs two balls per race and isotropic supports)."""
    if len(s.m) != 4:
        raise ValueError("the symmetric set-up of section 3 has two balls in each race")
    sub = {mk: m for mk in s.m}
    sub.update({Rk: R for Rk in s.R})
    sub.update({zk: (z if i < 2 else -z) for i, zk in enumerate(s.z)})
    sub.update({cb: c_b for cb in s.cb})
    sub.update({kk: k for kk in s.k.values()})
    sub.update({cc: c for cc in s.c.values()})
    sub.update({s.l1: l, s.l2: l})
    return sub
