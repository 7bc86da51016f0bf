"""Independent numeric check of the single-plane derivation against Lagrange's equations.

The model of the thesis, section 2.1, eqs (2.3)-(2.9), is rebuilt here in plain mpmath: nothing
is taken from SymPy or from adbgen's expressions, only the positions of the bodies:

- rotor centre of mass W = (X + eps cos psi, Y + eps sin psi),
- ball i at B_i = (X + R cos(psi + phi_i), Y + R sin(psi + phi_i)),

written as complex numbers x + i y.  From them

- T = I_z psi'^2/2 + M |W'|^2/2 + sum m_i |B_i'|^2/2, with every velocity obtained by numerical
  differentiation of the position along the motion (P' = d/du P(q + u q') at u = 0),
- V = k_X X^2/2 + k_Y Y^2/2 + M g Im W + sum m_i g Im B_i,
- F = c_X X'^2/2 + c_Y Y'^2/2 + sum D_i phi_i'^2/2, and Q_psi = tau0 - kappa psi'.

For random states (q, q', q'') and random parameters (anisotropic support k_X != k_Y,
c_X != c_Y, gravity, unequal ball masses and drags) the Lagrange residual

    d/dt dL/dq'_k - dL/dq_k + dF/dq'_k - Q_k

is computed with `mpmath.diff` (nested; d/dt along q(t) = q0 + q0' t + q0'' t^2/2 at t = 0) at
40 significant digits and compared with row k of ``M q'' - f`` from `adbgen.families.single_plane.model.derive`,
evaluated at the same numbers.  Required agreement: |numeric - symbolic| <= 1e-12 * max(1, |symbolic|),
for the torque-driven law (psi a coordinate) with n = 1..6 and for the constant-speed law
(psi = omega t substituted, at a random time t).  A last test shows that the comparison is sensitive:
perturbing any single parameter of the numeric model by a relative 1e-6 breaks the agreement.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import mpmath
import pytest
import sympy as sp
from mpmath import mp, mpf

from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane.model import derive
from adbgen.families.single_plane.symbols import DimensionalSymbols, t

DPS = 40
RTOL = mpf("1e-12")
G = 9.81
STATES_PER_CASE = 3


# --------------------------------------------------------------------------------------------
# Random parameters and the scene built from them
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Params:
    n: int
    M: float
    eps: float
    R: float
    Iz: float
    m: tuple[float, ...]
    D: tuple[float, ...]
    kX: float
    kY: float
    cX: float
    cY: float
    g: float
    tau0: float
    kappa: float
    omega: float

    def perturbed(self, name: str, factor: float) -> "Params":
        """A copy with one parameter scaled (for the per-ball m and D, ball 1's only)."""
        values = dict(self.__dict__)
        if name in ("m", "D"):
            v = list(values[name])
            v[0] *= factor
            values[name] = tuple(v)
        else:
            values[name] *= factor
        return Params(**values)

    def exact(self) -> "Params":
        """The same values as mpf, so that products such as M g are not rounded to doubles."""
        values = {k: (v if k == "n" else tuple(map(mpf, v)) if isinstance(v, tuple) else mpf(v))
                  for k, v in self.__dict__.items()}
        return Params(**values)


def random_params(rng: random.Random, n: int, *, equal_balls=False, isotropic=False, gravity=True) -> Params:
    u = rng.uniform
    m = tuple(u(0.02, 0.3) for _ in range(n))
    D = tuple(u(1e-3, 5e-2) for _ in range(n))
    kX, kY = u(50.0, 500.0), u(50.0, 500.0)
    cX, cY = u(0.1, 5.0), u(0.1, 5.0)
    if equal_balls:
        m, D = (m[0],) * n, (D[0],) * n
    if isotropic:
        kY, cY = kX, cX
    return Params(n=n, M=u(0.5, 2.0), eps=u(0.01, 0.1), R=u(0.05, 0.3), Iz=u(5e-3, 5e-2), m=m, D=D,
                  kX=kX, kY=kY, cX=cX, cY=cY, g=G if gravity else 0.0, tau0=u(-1.0, 1.0),
                  kappa=u(1e-3, 0.1), omega=u(5.0, 50.0))


def scene_for(p: Params, law: str, *, equal_balls: bool, isotropic: bool, gravity: bool) -> Scene:
    speed = ({"law": "torque", "tau0": p.tau0, "motor_slope": p.kappa} if law == "torque"
             else {"law": "constant", "omega": p.omega})
    return Scene.from_mapping({
        "n": p.n,
        "rotor_mass": p.M,
        "eccentricity": p.eps,
        "race_radius": p.R,
        "polar_inertia": p.Iz,
        "ball_mass": p.m[0] if equal_balls else list(p.m),
        "ball_damping": p.D[0] if equal_balls else list(p.D),
        "stiffness": p.kX if isotropic else [p.kX, p.kY],
        "damping": p.cX if isotropic else [p.cX, p.cY],
        "gravity": gravity,
        "g": G,
        "speed": speed,
    })


# --------------------------------------------------------------------------------------------
# The numeric model: full configuration z = (X, Y, psi, phi_1..phi_n), plain mpmath
# --------------------------------------------------------------------------------------------
def bodies(p: Params, z):
    """(mass, position x + i y) of the rotor's centre of mass W and of each ball, (2.3)-(2.4)."""
    X, Y, psi, phis = z[0], z[1], z[2], z[3:]
    C = mpmath.mpc(X, Y)
    out = [(p.M, C + p.eps * mpmath.expj(psi))]
    for i, phi in enumerate(phis):
        out.append((p.m[i], C + p.R * mpmath.expj(psi + phi)))
    return out


def velocity(p: Params, z, zd, body: int):
    """d/du of the body's position along q + u q' at u = 0 (numerically, not by hand)."""
    return mpmath.diff(lambda u: bodies(p, [a + u * b for a, b in zip(z, zd)])[body][1], 0)


def kinetic(p: Params, z, zd):
    T = p.Iz * zd[2] ** 2 / 2
    for j, (mass, _) in enumerate(bodies(p, z)):
        v = velocity(p, z, zd, j)
        T += mass * (v.real ** 2 + v.imag ** 2) / 2
    return T


def potential(p: Params, z):
    V = p.kX * z[0] ** 2 / 2 + p.kY * z[1] ** 2 / 2
    for mass, pos in bodies(p, z):
        V += mass * p.g * pos.imag
    return V


def rayleigh(p: Params, zd):
    F = p.cX * zd[0] ** 2 / 2 + p.cY * zd[1] ** 2 / 2
    for i, phid in enumerate(zd[3:]):
        F += p.D[i] * phid ** 2 / 2
    return F


def generalised_force(p: Params, k: int, zd):
    return p.tau0 - p.kappa * zd[2] if k == 2 else mpf(0)


def lagrangian(p: Params, z, zd):
    return kinetic(p, z, zd) - potential(p, z)


def bumped(vec, k, u):
    out = list(vec)
    out[k] = out[k] + u
    return out


def numeric_residual(p: Params, k: int, curve):
    """d/dt dL/dq'_k - dL/dq_k + dF/dq'_k - Q_k at s = 0 of the motion s -> curve(s) = (z, z')."""
    p = p.exact()

    def momentum(s):
        z, zd = curve(s)
        return mpmath.diff(lambda u: lagrangian(p, z, bumped(zd, k, u)), 0)

    z0, zd0 = curve(mpf(0))
    dp_dt = mpmath.diff(momentum, 0)
    dL_dq = mpmath.diff(lambda u: lagrangian(p, bumped(z0, k, u), zd0), 0)
    dF_dqd = mpmath.diff(lambda u: rayleigh(p, bumped(zd0, k, u)), 0)
    return dp_dt - dL_dq + dF_dqd - generalised_force(p, k, zd0)


# --------------------------------------------------------------------------------------------
# Random states and the comparison
# --------------------------------------------------------------------------------------------
FULL_NAMES = ("X", "Y", "psi")


def full_names(n):
    return FULL_NAMES + tuple(f"phi_{i + 1}" for i in range(n))


def random_state(rng: random.Random, n: int):
    """(q, q', q'') for the full configuration X, Y, psi, phi_1..phi_n."""
    u = rng.uniform
    q = [u(-0.05, 0.05), u(-0.05, 0.05), u(-10.0, 10.0)] + [u(-3.2, 3.2) for _ in range(n)]
    qd = [u(-1.0, 1.0), u(-1.0, 1.0), u(-30.0, 30.0)] + [u(-3.0, 3.0) for _ in range(n)]
    qdd = [u(-10.0, 10.0), u(-10.0, 10.0), u(-50.0, 50.0)] + [u(-10.0, 10.0) for _ in range(n)]
    return [mpf(v) for v in q], [mpf(v) for v in qd], [mpf(v) for v in qdd]


def symbol_values(scene: Scene, p: Params) -> dict:
    s = DimensionalSymbols.for_scene(scene)
    values = {s.M: p.M, s.eps: p.eps, s.R: p.R, s.I_z: p.Iz, s.kX: p.kX, s.kY: p.kY, s.cX: p.cX,
              s.cY: p.cY, s.tau0: p.tau0, s.kappa: p.kappa, s.omega: p.omega}
    for i in range(p.n):
        values[s.m[i]] = p.m[i]
        values[s.D[i]] = p.D[i]
    if isinstance(s.g, sp.Symbol):
        values[s.g] = p.g
    else:
        assert s.g == 0 and p.g == 0.0
    return {sym: mpf(v) for sym, v in values.items()}


def compare(scene: Scene, p_symbolic: Params, p_numeric: Params, rng: random.Random, states: int):
    """Max over states and rows of |numeric - symbolic| / max(1, |symbolic|)."""
    law = scene.speed.law
    n = scene.n
    eom = derive(scene)
    names = [c.name for c in eom.coordinates]
    free = [i for i, name in enumerate(full_names(n)) if law == "torque" or name != "psi"]
    assert names == [full_names(n)[i] for i in free]

    params = symbol_values(scene, p_symbolic)
    kinematic = []
    for c in eom.coordinates:
        kinematic += [c.q, c.qd, c.qdd]
    args = kinematic + [t] + list(params)
    worst = mpf(0)
    for _ in range(states):
        q0, qd0, qdd0 = random_state(rng, n)
        t0 = mpf(rng.uniform(-2.0, 2.0)) if law == "constant" else mpf(0)
        if law == "constant":
            omega = mpf(p_numeric.omega)
            q0[2], qd0[2], qdd0[2] = omega * t0, omega, mpf(0)

        def curve(s, q0=q0, qd0=qd0, qdd0=qdd0, t0=t0):
            z = [a + b * s + c * s * s / 2 for a, b, c in zip(q0, qd0, qdd0)]
            zd = [b + c * s for b, c in zip(qd0, qdd0)]
            if law == "constant":  # psi = omega t is prescribed, not a coordinate
                z[2], zd[2] = mpf(p_numeric.omega) * (t0 + s), mpf(p_numeric.omega)
            return z, zd

        values = []
        for i in free:
            values += [q0[i], qd0[i], qdd0[i]]
        values += [t0] + list(params.values())
        for row, k in enumerate(free):
            expr = eom.residual(row)
            assert expr.free_symbols <= set(args), expr.free_symbols - set(args)
            symbolic = sp.lambdify(args, expr, modules="mpmath")(*values)
            numeric = numeric_residual(p_numeric, k, curve)
            err = abs(numeric - symbolic) / max(mpf(1), abs(symbolic))
            worst = max(worst, err)
    return worst


# --------------------------------------------------------------------------------------------
# Tests
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("n", range(1, 7))
def test_torque_law_matches_numeric_lagrangian(n):
    """psi is a coordinate; anisotropic support, gravity, unequal balls and drags."""
    rng = random.Random(20050 + n)
    with mp.workdps(DPS):
        p = random_params(rng, n)
        scene = scene_for(p, "torque", equal_balls=False, isotropic=False, gravity=True)
        worst = compare(scene, p, p, rng, STATES_PER_CASE)
        assert worst <= RTOL, f"n = {n}: relative disagreement {mpmath.nstr(worst, 5)}"


@pytest.mark.parametrize("n", [1, 3, 6])
def test_constant_law_matches_numeric_lagrangian(n):
    """psi = omega t substituted; residuals depend on t, checked at a random time."""
    rng = random.Random(20140 + n)
    with mp.workdps(DPS):
        p = random_params(rng, n)
        scene = scene_for(p, "constant", equal_balls=False, isotropic=False, gravity=True)
        worst = compare(scene, p, p, rng, STATES_PER_CASE)
        assert worst <= RTOL, f"n = {n}: relative disagreement {mpmath.nstr(worst, 5)}"


@pytest.mark.parametrize("law, n", [("torque", 2), ("constant", 2)])
def test_equal_balls_isotropic_without_gravity(law, n):
    """The scene's other structure: one m, one D, one k, one c (shared symbols), g = 0."""
    rng = random.Random(31 if law == "torque" else 32)
    with mp.workdps(DPS):
        p = random_params(rng, n, equal_balls=True, isotropic=True, gravity=False)
        scene = scene_for(p, law, equal_balls=True, isotropic=True, gravity=False)
        worst = compare(scene, p, p, rng, 1)
        assert worst <= RTOL, f"{law}, n = {n}: relative disagreement {mpmath.nstr(worst, 5)}"


@pytest.mark.parametrize("name", ["M", "eps", "R", "Iz", "m", "D", "kX", "kY", "cX", "cY", "g",
                                  "tau0", "kappa"])
def test_check_is_sensitive_to_every_parameter(name):
    """The comparison can fail: a relative 1e-6 change of one parameter in the numeric model only."""
    rng = random.Random(77)
    with mp.workdps(DPS):
        p = random_params(rng, 2)
        scene = scene_for(p, "torque", equal_balls=False, isotropic=False, gravity=True)
        worst = compare(scene, p, p.perturbed(name, 1 + 1e-6), rng, 1)
        assert worst > 1e3 * RTOL, f"perturbing {name} went unnoticed ({mpmath.nstr(worst, 5)})"
