"""Parameter symbols of the single-plane model, named as in the thesis (ch. 2).

One place creates every symbol, with the assumptions the derivation relies on (masses, radius and
stiffness positive; damping and eccentricity non-negative), so that equal names always mean equal
symbols.  The scene decides which symbols exist: one ``m`` for equal balls or ``m_1..m_n``, one
``k`` for isotropic support or ``k_X, k_Y``, and so on.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ...core import Parameter, ParameterTable, speed_schedule
from ...core.symbols import nonnegative, positive, t  # noqa: F401  (t: the family's time)
from .scene import Scene



# Dimensionless parameters (2.16), (2.19).
mu, Omega, delta = positive("mu"), positive("Omega"), positive("delta")
zeta, beta, G = nonnegative("zeta"), nonnegative("beta"), nonnegative("G")
# Natural frequency (2.17): used only inside the scaling substitution, never left in a result.
omega_n = positive("omega_n")


@dataclass(frozen=True)
class DimensionalSymbols:
    """The dimensional parameters of one scene's model and their defaults (SI)."""

    M: sp.Symbol
    eps: sp.Symbol
    R: sp.Symbol
    m: tuple[sp.Symbol, ...]  # one per ball (the same symbol n times for equal balls)
    D: tuple[sp.Symbol, ...]
    kX: sp.Symbol
    kY: sp.Symbol
    cX: sp.Symbol
    cY: sp.Symbol
    g: sp.Expr  # 0 without gravity
    I_z: sp.Symbol
    omega: sp.Symbol
    tau0: sp.Symbol
    kappa: sp.Symbol
    parameters: tuple[Parameter, ...]
    mu_r: tuple[sp.Expr, ...] = ()  # rolling resistance per ball (the same symbol n times for one value); () without friction
    mu_s: tuple[sp.Expr, ...] = ()  # stiction per ball; () without static_friction
    stuck: tuple[sp.Symbol, ...] = ()  # each ball's mode: 1 stuck on the race (phi_i' = 0 held), 0 slipping
    slip_dir: tuple[sp.Symbol, ...] = ()  # the direction (+1 or -1) of ball i's slip (its mode), set by the driver

    @classmethod
    def for_scene(cls, scene: Scene) -> "DimensionalSymbols":
        n = scene.n
        params = ParameterTable()
        add = params.add

        M = add(positive("M"), "rotor (disc) mass", "kg", scene.rotor_mass)
        eps = add(nonnegative("eps"), "eccentricity of the rotor's centre of mass W from C", "m",
                  scene.eccentricity)
        R = add(positive("R"), "race radius", "m", scene.race_radius)
        masses, drags = scene.masses(), scene.ball_dampings()
        if scene.equal_balls:
            m = (add(positive("m"), "ball mass", "kg", masses[0]),) * n
            D = (add(nonnegative("D"), "viscous drag on each ball", "N m s/rad", drags[0]),) * n
        else:
            m = tuple(add(positive(f"m_{i + 1}"), f"mass of ball {i + 1}", "kg", masses[i]) for i in range(n))
            D = tuple(add(nonnegative(f"D_{i + 1}"), f"viscous drag on ball {i + 1}", "N m s/rad", drags[i])
                      for i in range(n))
        (kx, ky), (cx, cy) = scene.stiffness_xy(), scene.damping_xy()
        if scene.isotropic:
            kX = kY = add(nonnegative("k"), "support stiffness", "N/m", kx)
            cX = cY = add(nonnegative("c"), "support damping", "N s/m", cx)
        else:
            kX = add(nonnegative("k_X"), "support stiffness in X", "N/m", kx)
            kY = add(nonnegative("k_Y"), "support stiffness in Y", "N/m", ky)
            cX = add(nonnegative("c_X"), "support damping in X", "N s/m", cx)
            cY = add(nonnegative("c_Y"), "support damping in Y", "N s/m", cy)
        g = add(positive("g"), "gravitational acceleration (-Y)", "m/s^2", scene.g) if scene.gravity else sp.S.Zero
        I_z = positive("I_z")
        omega, tau0, kappa = positive("omega"), sp.Symbol("tau0", real=True), nonnegative("kappa")
        law = scene.speed.law
        if law == "constant":
            add(omega, "spin speed", "rad/s", scene.speed.omega)
        elif law == "schedule":
            speed_schedule.add_parameters(params, scene.speed.schedule)
        elif law == "torque":
            add(I_z, "polar moment of inertia of the rotor", "kg m^2", scene.polar_inertia)
            add(tau0, "stall torque of the drive", "N m", scene.speed.tau0)
            add(kappa, "slope of the drive's torque-speed line", "N m s/rad", scene.speed.motor_slope)
        mu_r: tuple[sp.Expr, ...] = ()
        def coefficient(name, what, given, values):  # one symbol for every ball, or one each
            if isinstance(given, tuple):
                return tuple(add(nonnegative(f"{name}_{i + 1}"), f"{what}, ball {i + 1}", "dimensionless", values[i])
                             for i in range(n))
            return (add(nonnegative(name), what, "dimensionless", values[0]),) * n

        if scene.friction:
            mu_r = coefficient("mu_r", "rolling resistance of the balls on the race while slipping (tangential "
                               "force / normal force)", scene.rolling_resistance, scene.rolling_resistances())
        mu_s: tuple[sp.Expr, ...] = ()
        stuck: tuple[sp.Symbol, ...] = ()
        slip_dir: tuple[sp.Symbol, ...] = ()
        if scene.stiction:  # the hybrid system's mode is a parameter of the model, set by the event driver
            mu_s = coefficient("mu_s", "stiction of a ball at rest on the race (largest tangential force / normal "
                               "force)", scene.static_friction, scene.static_frictions())
            stuck = tuple(add(sp.Symbol(f"stuck_{i + 1}", real=True), f"mode of ball {i + 1}: 1 stuck on the race, "
                              "0 slipping (set by the event driver)", "dimensionless", 0.0) for i in range(n))
            slip_dir = tuple(add(sp.Symbol(f"slip_dir_{i + 1}", real=True), f"direction (+1, -1) of ball {i + 1}'s "
                                 "slip, its mode while slipping (set by the event driver)", "dimensionless", 0.0)
                             for i in range(n))
        return cls(M, eps, R, m, D, kX, kY, cX, cY, g, I_z, omega, tau0, kappa, params.sorted(), mu_r, mu_s, stuck,
                   slip_dir)


def nondimensional_parameters(values: dict[str, float] | None = None, gravity: bool = False) -> tuple[Parameter, ...]:
    """The thesis' parameters (2.16), (2.19) with the defaults of (5.1) unless values are given."""
    values = {"mu": 0.05, "Omega": 4.0, "zeta": 0.01, "beta": 0.01, "delta": 0.01, "G": 0.0, **(values or {})}
    table = [
        (beta, "ball damping D/(m R^2 omega_n) (2.19)"),
        (delta, "eccentricity eps/R (2.16)"),
        (mu, "ball mass ratio m/M (2.16)"),
        (Omega, "spin speed omega/omega_n (2.16)"),
        (zeta, "support damping ratio c/(2 sqrt(k M)) (2.19)"),
    ]
    if gravity:
        table.append((G, "gravity g/(eps omega_n^2) (2.16)"))
    out = [Parameter(s, d, "dimensionless", float(values[s.name])) for s, d in table]
    return tuple(sorted(out, key=lambda p: p.name))
