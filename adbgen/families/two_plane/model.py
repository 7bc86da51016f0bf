"""The two-plane balancer by Lagrange's equations, from the kinematics of paper section 2.1.

Kinematics (exact): the body frame is xi = R_3 R_2 R_1 X' (tilt phi_Y about Y', then phi_X about X'',
then the spin theta_0 about z).  The rotor's angular velocity comes from the rotation matrix
(omega~ = A A'^T with A = R_3 R_2 R_1), its inertia tensor is diag(J_t, J_t, J_p) turned by the
misalignment chi about eta, its centre of mass G is at (eps cos beta, eps sin beta, 0) in the body frame.
Ball k is a point mass at (R_k cos theta_k, R_k sin theta_k, z_k) in the Cxyz frame, theta_k = theta_0 +
alpha_k its absolute angle (paper (2)-(4)).  Bearings j = 1, 2 are springs and dampers at the shaft
points z = +l_1 and z = -l_2, in X and Y (paper (1)).

The small-vibration approximation (paper section 2.2), applied explicitly, with a bookkeeping order h
for the vibration (X, Y, phi_X, phi_Y and their rates) and e for the imbalance (eps, chi):

1. T, V, F are expanded (sines and cosines of phi_X, phi_Y, chi by Taylor) and kept to total order
   2 in (h, e): the standard linear rotordynamics (rows linear in the vibration), the imbalance
   forcing (order h e), and the modified polar inertia (order e^2);
2. of each ball's order-h^2 kinetic energy, the part proportional to m_k R_k^2 is dropped: the ball's
   axial motion R_k (phi_X sin - phi_Y cos) and the second-order lateral terms of the tilted race.  This
   is the ball's own rotary inertia about the transverse axes (a ring's m R^2/2, and its gyroscopic
   partner); the paper's M and G have no such terms, the balls enter the tilt only through their race
   centre (m_k z_k, m_k z_k^2);
3. the torsional row (3) and the ball rows (4) are kept to first order in the vibration (the
   torsional row's order-h^2 terms, -J_p d/dt(phi_X phi_Y'), are dropped), and with it, so that the
   mass matrix stays symmetric, its partner in the phi_Y row: -J_p phi_X theta_0'' (a spin acceleration
   times a tilt; the paper's (2) has theta_0'' only in the imbalance forcing).  For the run-ups of
   section 6 it is small: |theta_0''| <= 6e-4 (ramp) and 0.015 (Hill (45)) against theta_0'^2 ~ 1.

Nothing of (2)-(4) is transcribed here; the printed equations are in
`adbgen.references.two_plane_2011` and compared with the result in the tests.  The comparison found one
erratum: the modified polar inertia is J_p + (J_t - J_p) chi^2 + M eps^2 (the inertia about the shaft
of a rotor whose principal axis is tilted by chi is J_p cos^2 chi + J_t sin^2 chi), not the printed
J_p + J_t chi^2 + M eps^2, which is what a linearised (non-orthogonal) rotation by chi gives.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import sympy as sp

from ...core import (Coordinate, EnergyTerm, EquationsOfMotion, lagrange_equations, reduce_pythagorean,
                         speed_schedule, time_derivative)
from ...core.friction import race_reaction, slip_direction, stick_row
from .scene import TwoPlaneScene
from .symbols import TwoPlaneSymbols, t

h, e = sp.symbols("h e", positive=True)  # bookkeeping orders: vibration, imbalance


def rotations(phi_X, phi_Y, theta_0) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """R_1, R_2, R_3 of paper section 2.1 (exact)."""
    c, s = sp.cos, sp.sin
    R1 = sp.Matrix([[c(phi_Y), 0, -s(phi_Y)], [0, 1, 0], [s(phi_Y), 0, c(phi_Y)]])
    R2 = sp.Matrix([[1, 0, 0], [0, c(phi_X), s(phi_X)], [0, -s(phi_X), c(phi_X)]])
    R3 = sp.Matrix([[c(theta_0), s(theta_0), 0], [-s(theta_0), c(theta_0), 0], [0, 0, 1]])
    return R1, R2, R3


def truncate(expr: sp.Expr, gens=(h, e), order: int = 2) -> sp.Expr:
    """Keep the terms of total degree <= order in the bookkeeping symbols, then set them to 1."""
    poly = sp.Poly(sp.expand(expr), *gens)
    kept = sum((coeff * sp.prod([g**k for g, k in zip(gens, monom)])
                for monom, coeff in poly.terms() if sum(monom) <= order), sp.S.Zero)
    return sp.expand(kept.xreplace({g: 1 for g in gens}))


@dataclass(frozen=True)
class TwoPlaneLagrangian:
    scene: TwoPlaneScene
    symbols: TwoPlaneSymbols
    coordinates: tuple[Coordinate, ...]  # X, Y, phi_X, phi_Y, [theta_0], theta_1..theta_n
    driven: tuple[Coordinate, ...]  # (theta_0,) when the speed is prescribed
    terms: tuple[EnergyTerm, ...]  # rotor, bearings, ball_1..ball_n (already truncated)
    forces: dict[str, sp.Expr]
    scaling: dict  # X -> h X, ..., eps -> e eps: the bookkeeping of the approximation
    dropped_ball_terms: tuple[sp.Expr, ...]  # item 2 of the module docstring, per ball


def vibration_coordinates() -> tuple[Coordinate, ...]:
    return tuple(Coordinate.make(n) for n in ("X", "Y", "phi_X", "phi_Y"))


def lagrangian(scene: TwoPlaneScene) -> TwoPlaneLagrangian:
    s = TwoPlaneSymbols.for_scene(scene)
    X, Y, pX, pY = vib = vibration_coordinates()
    th0 = Coordinate.make("theta_0")
    balls = tuple(Coordinate.make(f"theta_{k + 1}") for k in range(scene.n))
    spin_free = scene.speed.law == "torque"
    coordinates = vib + ((th0,) if spin_free else ()) + balls
    driven = () if spin_free else (th0,)
    everything = coordinates + driven
    scaling = {e_: h * e_ for c in vib for e_ in (c.q, c.qd)}
    scaling.update({s.eps: e * s.eps, s.chi: e * s.chi})
    small_angle = {sp.sin(a): a - a**3 / 6 for a in (pX.q, pY.q, s.chi)}
    small_angle.update({sp.cos(a): 1 - a**2 / 2 for a in (pX.q, pY.q, s.chi)})

    def expand_small(expr):
        """Taylor in the small angles (to the order kept), bookkeeping scaled, truncated at order 2."""
        return reduce_pythagorean(truncate(sp.expand(expr).xreplace(small_angle).xreplace(scaling)))

    def small(matrix):  # truncating the factors first gives the same order-2 product, much faster
        return matrix.applyfunc(expand_small)

    R1, R2, R3 = rotations(pX.q, pY.q, th0.q)
    tilt_T = small((R2 * R1).T)  # Cxyz -> primed (space-parallel) coordinates
    A = R3 * tilt_T.T
    dot = lambda expr: expand_small(time_derivative(expr, everything, t))  # noqa: E731
    rC = sp.Matrix([X.q, Y.q, 0])

    # Rotor: translation of G, rotation with the misaligned inertia tensor.
    xi_G = sp.Matrix([s.eps * sp.cos(s.beta), s.eps * sp.sin(s.beta), 0])
    vG = (rC + A.T * xi_G).applyfunc(dot)
    W = small(A * A.T.applyfunc(dot))  # omega~ in the body frame
    omega = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
    Rchi = small(sp.Matrix([[sp.cos(s.chi), 0, sp.sin(s.chi)], [0, 1, 0], [-sp.sin(s.chi), 0, sp.cos(s.chi)]]))
    inertia = small(Rchi * sp.diag(s.Jt, s.Jt, s.Jp) * Rchi.T)
    T_rotor = expand_small(s.M * vG.dot(vG) / 2 + (omega.T * inertia * omega)[0, 0] / 2)
    rotor = EnergyTerm("rotor", T=T_rotor, F=s.c_r * th0.qd**2 / 2 if spin_free else sp.S.Zero)

    # Bearings: shaft points at z = +l_1 and z = -l_2.
    V = F = sp.S.Zero
    for j, zj in ((1, s.l1), (2, -s.l2)):
        p = rC + tilt_T * sp.Matrix([0, 0, zj])
        v = p.applyfunc(dot)
        V += (s.k[(j, "X")] * p[0] ** 2 + s.k[(j, "Y")] * p[1] ** 2) / 2
        F += (s.c[(j, "X")] * v[0] ** 2 + s.c[(j, "Y")] * v[1] ** 2) / 2
    bearings = EnergyTerm("bearings", V=expand_small(V), F=expand_small(F))

    terms, dropped = [rotor, bearings], []
    for k, ball in enumerate(balls):
        p = rC + tilt_T * sp.Matrix([s.R[k] * sp.cos(ball.q), s.R[k] * sp.sin(ball.q), s.z[k]])
        v = p.applyfunc(dot)
        T = expand_small(s.m[k] * v.dot(v) / 2)
        # Item 2: the order-h^2 part proportional to R_k^2 (re-scaled to find it).
        T_h = sp.Poly(sp.expand(T.xreplace({sym: h * sym for sym in scaling if sym not in (s.eps, s.chi)})), h, s.R[k])
        drop = sum((coeff * s.R[k] ** mon[1] for mon, coeff in T_h.terms() if mon == (2, 2)), sp.S.Zero)
        dropped.append(sp.expand(drop))
        terms.append(EnergyTerm(f"ball_{k + 1}", T=sp.expand(T - drop),
                                F=s.cb[k] * (ball.qd - th0.qd) ** 2 / 2))
    forces = {"theta_0": s.tau0 - s.kappa * th0.qd} if spin_free else {}
    return TwoPlaneLagrangian(scene, s, coordinates, driven, tuple(terms), forces, scaling, tuple(dropped))


def _first_order_rows(eom: EquationsOfMotion, lag: TwoPlaneLagrangian) -> EquationsOfMotion:
    """Item 3: the torsional and ball rows to first order in the vibration; drop -J_p phi_X theta_0''."""
    th0 = Coordinate.make("theta_0")
    vib_scale = {sym: h * sym for c in vibration_coordinates() for sym in (c.q, c.qd, c.qdd)}
    rows = []
    for k, c in enumerate(eom.coordinates):
        r = sp.expand(eom.residual(k).xreplace(vib_scale))
        poly = sp.Poly(r, h)
        kept = sp.S.Zero
        for (degree,), coeff in poly.terms():
            if c.name.startswith("theta_"):
                kept += coeff if degree <= 1 else 0
            else:  # rotor rows are linear already; only the spin acceleration times a tilt goes
                kept += sum((a for a in sp.Add.make_args(sp.expand(coeff)) if degree == 0 or not a.has(th0.qdd)),
                            sp.S.Zero)
        rows.append(sp.expand(kept))
    return EquationsOfMotion.from_residuals(rows, eom.coordinates, t, driven=eom.driven,
                                            parameters=eom.parameters, reference=eom.reference)


def ball_position(s: TwoPlaneSymbols, k: int, radius, tilt_T: sp.Matrix) -> sp.Matrix:
    """Ball k in the space frame: its race centre on the shaft at z_k, at `radius` along theta_k in the
    race plane turned by the tilt (paper (2)-(4), section 2.1)."""
    ball = Coordinate.make(f"theta_{k + 1}")
    X, Y = Coordinate.make("X"), Coordinate.make("Y")
    return sp.Matrix([X.q, Y.q, 0]) + tilt_T * sp.Matrix([radius * sp.cos(ball.q), radius * sp.sin(ball.q), s.z[k]])


def first_order(expr: sp.Expr) -> sp.Expr:
    """An exact expression in the vibration (X, Y, phi_X, phi_Y, their rates and accelerations) to first
    order in it, as the ball rows are kept (item 3 of the module docstring)."""
    small_angle = {sp.sin(a): a for a in (Coordinate.make("phi_X").q, Coordinate.make("phi_Y").q)}
    small_angle.update({sp.cos(a): 1 for a in (Coordinate.make("phi_X").q, Coordinate.make("phi_Y").q)})
    scale = {sym: h * sym for c in vibration_coordinates() for sym in (c.q, c.qd, c.qdd)}
    return truncate(sp.expand(sp.expand(expr).xreplace(small_angle)).xreplace(scale), gens=(h,), order=1)


def normal_forces(lag: TwoPlaneLagrangian) -> tuple[sp.Expr, ...]:
    """N_k, the race's push on ball k towards the shaft within the race plane (positive while the ball
    presses on the race's outer wall), from the ball's kinetic energy of the Lagrangian (paper section 2.1,
    exact rotations): ball k gets a radial coordinate rho_k in place of R_k, Lagrange's equation for rho_k
    carries the race constraint through its multiplier -N_k, evaluated on the race (`core.friction.
    race_reaction`), then kept to first order in the vibration like the ball rows.  Centrifugal and Coriolis
    (together m_k R_k theta_k'^2, theta_k the absolute angle), the rotor's translation and tilt accelerations
    appear without being written here; the paper's scene has no gravity."""
    s = lag.symbols
    R1, R2, _ = rotations(Coordinate.make("phi_X").q, Coordinate.make("phi_Y").q, Coordinate.make("theta_0").q)
    tilt_T = (R2 * R1).T
    out = []
    for k in range(lag.scene.n):
        rho = Coordinate.make(f"rho_{k + 1}")
        position = ball_position(s, k, rho.q, tilt_T)
        out.append(first_order(race_reaction(s.m[k], list(position), rho, s.R[k], lag.coordinates + lag.driven, t)))
    return tuple(out)


def friction_forces(lag: TwoPlaneLagrangian) -> dict[str, sp.Expr]:
    """{theta_k: -R_k mu_r_k N_k sign(theta_k' - theta_0'), [theta_0: minus their sum]}: the race's friction
    on a slipping ball, a tangential force mu_r_k N_k against the ball's motion relative to the race.  The
    pair of forces on ball and race does virtual work through the ball's angle relative to the race,
    theta_k - theta_0, only (tilt and translation move the ball and its contact point alike), so the ball's
    row gets R_k F_k and the spin's row, where the spin is free, -R_k F_k."""
    s = lag.symbols
    normal = normal_forces(lag)
    th0 = Coordinate.make("theta_0")
    out = {}
    for k in range(lag.scene.n):
        rate = Coordinate.make(f"theta_{k + 1}").qd - th0.qd
        # with stiction along the ball's mode slip_dir_k, set by the event driver (each mode's field smooth, as
        # single_plane.model.friction_forces says), else sign(theta_k' - theta_0')
        direction = s.slip_dir[k] if s.slip_dir else slip_direction(rate)
        out[f"theta_{k + 1}"] = -s.R[k] * s.mu_r[k] * direction * normal[k]
    if lag.scene.speed.law == "torque":
        out["theta_0"] = lag.forces["theta_0"] - sum(out.values(), sp.S.Zero)
    return out


def stick_rows(lag: TwoPlaneLagrangian, eom: EquationsOfMotion) -> list[sp.Expr]:
    """The hybrid system's rows (issue 37 item 2) from the slip model's `eom`: ball k's row is its slip row
    while stuck_k = 0 and the constraint m_k R_k^2 (theta_k'' - theta_0'') = 0 while stuck_k = 1
    (`core.friction.stick_row`).  Under a torque drive the spin's row holds the reaction of every ball's
    friction (`friction_forces`); for a stuck ball that reaction is the constraint's multiplier, the
    frictionless ball row, so the spin's row gets + stuck_k (ball k's slip row): its kinetic reaction cancels
    and the frictionless row is added (row_0 + row_k = frictionless row_0 + frictionless row_k, the ball
    carried by the rotor).  With every ball stuck no friction coefficient is left in the model."""
    s = lag.symbols
    names = [c.name for c in eom.coordinates]
    th0 = Coordinate.make("theta_0")
    slip = eom.residuals()
    out = list(slip)
    for k in range(lag.scene.n):
        i = names.index(f"theta_{k + 1}")
        out[i] = stick_row(slip[i], s.stuck[k], s.m[k], s.R[k], eom.coordinates[i].qdd - th0.qdd)
        if "theta_0" in names:
            out[names.index("theta_0")] += s.stuck[k] * slip[i]
    return out


def stick_forces(lag: TwoPlaneLagrangian) -> tuple[sp.Expr, ...]:
    """F_k, the tangential force the race must exert on ball k (positive along increasing theta_k) for the
    accelerations in it to hold: the frictionless ball row (paper (4), to first order in the vibration as
    derived here) over R_k, since with friction that row reads ... = Q_k = R_k F_k.  Evaluated at the
    constrained accelerations (theta_k'' = theta_0'') it is a stuck ball's required force, which holds while
    |F_k| <= mu_s_k N_k (the stiction cone)."""
    frictionless = _first_order_rows(lagrange_equations(lag.coordinates, lag.terms, t, forces=dict(lag.forces),
                                                        driven=lag.driven, parameters=lag.symbols.parameters), lag)
    th0 = Coordinate.make("theta_0")
    out = []
    for k in range(lag.scene.n):
        ball = Coordinate.make(f"theta_{k + 1}")
        row = frictionless.residual(frictionless.index(ball.name)) / lag.symbols.R[k]
        out.append(sp.expand(row.xreplace({ball.qdd: th0.qdd})))
    return tuple(out)


def speed_law(scene: TwoPlaneScene, s: TwoPlaneSymbols) -> dict[sp.Symbol, sp.Expr]:
    """theta_0, theta_0', theta_0'' in t for a prescribed speed; {} for the torque drive."""
    th0 = Coordinate.make("theta_0")
    law = scene.speed.law
    if law == "constant":
        return {th0.q: s.Omega * t, th0.qd: s.Omega, th0.qdd: sp.S.Zero}
    if law == "ramp":  # constant acceleration up to Omega_max at t_ramp, then constant (section 6)
        a = s.Omega_max / s.t_ramp
        return {th0.q: sp.Piecewise((a * t**2 / 2, t < s.t_ramp), (s.Omega_max * (t - s.t_ramp / 2), True)),
                th0.qd: sp.Piecewise((a * t, t < s.t_ramp), (s.Omega_max, True)),
                th0.qdd: sp.Piecewise((a, t < s.t_ramp), (0, True))}
    if law == "schedule":  # ramp, hold, temporary speed reduction (`core.speed_schedule`, issue 37)
        angle, speed, acceleration = speed_schedule.law(t, speed="Omega")
        return {th0.q: angle, th0.qd: speed, th0.qdd: acceleration}
    if law == "hill":  # (45): Omega = Omega_max tb^n / (t_half^n + tb^n), tb = Omega_cyl t
        n = scene.speed.n
        Om = s.Omega_max * (s.Omega_cyl * t) ** n / (s.t_half**n + (s.Omega_cyl * t) ** n)
        # The angle through u = Omega_cyl t / t_half: SymPy integrates v^n/(1 + v^n) correctly, but
        # not the same function with symbolic coefficients (wrong partial fractions for n = 3).
        v = sp.Symbol("v", positive=True)
        F = sp.integrate(v**n / (1 + v**n), v)
        F = F - F.subs(v, 0)
        if F.has(sp.Integral) or sp.simplify(sp.diff(F, v) - v**n / (1 + v**n)) != 0:
            raise AssertionError(f"no verified closed-form angle for the Hill exponent {n}")
        u = s.Omega_cyl * t / s.t_half
        angle = s.Omega_max * s.t_half / s.Omega_cyl * sp.Piecewise((hill_series(n, u), u < hill_switch(n)),
                                                                     (F.subs(v, u), True))
        return {th0.q: angle, th0.qd: Om, th0.qdd: sp.diff(Om, t)}
    return {}


def hill_switch(n: int) -> float:
    """Where the Hill angle switches from its series to the closed form (u = Omega_cyl t / t_half)."""
    return 0.25 if n <= 2 else 0.5


def hill_series(n: int, u: sp.Expr) -> sp.Expr:
    """int_0^u v^n / (1 + v^n) dv = sum_k (-1)^k u^(n(k+1)+1) / (n(k+1)+1) for u < 1, to double precision
    below `hill_switch`: the closed form cancels there (its terms are O(u), the angle O(u^(n+1))), so it
    loses digits as t -> 0 (relative error ~1e-16 / u^n); the series has none to lose."""
    u0 = hill_switch(n)
    terms = math.ceil(17 / (n * math.log10(1 / u0))) + 1
    return sum((sp.Integer(-1) ** k * u ** (n * (k + 1) + 1) / (n * (k + 1) + 1) for k in range(terms)), sp.S.Zero)


@lru_cache(maxsize=32)
def derive(scene: TwoPlaneScene) -> EquationsOfMotion:
    """Fixed-frame equations M q'' = f: paper (2)-(4) (torque) or (2), (4) with the spin prescribed.

    Coordinates X, Y, phi_X, phi_Y, [theta_0], theta_1..theta_n (absolute ball angles, as in (2)-(4)).
    With a constant speed theta_0 = Omega t is substituted; a run-up keeps theta_0, theta_0', theta_0''
    as inputs with ``driven_law`` giving them in t.
    """
    lag = lagrangian(scene)
    torque = scene.speed.law == "torque"
    forces = dict(lag.forces)
    reference = "paper (2)-(4)" if torque else "paper (2), (4)"
    if scene.friction:
        forces |= friction_forces(lag)
        reference += " with ball-race friction in slip (issue 37)"
    if scene.stiction:
        reference += " and stick"
    eom = lagrange_equations(lag.coordinates, lag.terms, t, forces=forces, driven=lag.driven,
                             parameters=lag.symbols.parameters, reference=reference)
    eom = _first_order_rows(eom, lag)
    if scene.stiction:
        eom = EquationsOfMotion.from_residuals(stick_rows(lag, eom), eom.coordinates, t, driven=eom.driven,
                                               parameters=eom.parameters, reference=eom.reference)
    law = speed_law(scene, lag.symbols)
    if scene.speed.law == "constant":
        eom = replace(eom.map(lambda x: sp.expand(x.xreplace(law))), driven=())
    elif law:
        eom = replace(eom, driven_law=law)
    return eom
