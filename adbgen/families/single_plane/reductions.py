"""Reductions of the single-plane model, each a function from one form to the next.

    derive(scene)                fixed frame, dimensional          thesis (2.10)-(2.13)
      -> nondimensionalise       fixed frame, (2.14)-(2.19)         thesis (2.20)-(2.22)
      -> rotating_frame          (2.23)-(2.24), G = 0, autonomous   thesis (2.25)-(2.27)
      -> first_order             structured solve + states          thesis Appendix A (A.1)-(A.14)

Each step refuses a model it does not apply to (ReductionError) and checks its own result's
invariants (no dimensional symbol left after scaling; no explicit time left in the rotating frame).
The comparison with the printed equations is in the tests and in `adbgen verify`.
"""

from __future__ import annotations

import sympy as sp

from ...core import Coordinate, EquationsOfMotion, canonical_trig
from ...core.first_order import FirstOrderSystem, first_order as _first_order
from ...core.frames import rotating_substitution
from ...errors import ReductionError
from .scene import Scene
from .model import derive
from .symbols import DimensionalSymbols, G, Omega, beta, delta, mu, nondimensional_parameters, omega_n, t, zeta


def thesis_scene_check(scene: Scene) -> None:
    """(2.14) and (2.18): equal balls, constant speed, isotropic support with k > 0."""
    if not scene.equal_balls:
        raise ReductionError("the non-dimensional form (2.20)-(2.22) assumes equal balls (2.14)")
    if scene.speed.law != "constant":
        raise ReductionError("the non-dimensional form (2.20)-(2.22) assumes constant speed (2.14)")
    if not scene.isotropic:
        raise ReductionError("the non-dimensional form (2.20)-(2.22) assumes isotropic support (2.18)")


def scaling(scene: Scene) -> tuple[dict, dict]:
    """The substitution (2.15)-(2.19) and the row scales that make (2.20)-(2.22) come out.

    Returns (substitution of dimensional symbols, {coordinate name: row divisor}).  Positions scale
    by R, time by 1/omega_n (so rates by omega_n, accelerations by omega_n^2), and the parameters
    are written through mu, Omega, delta, G, zeta, beta with k = M omega_n^2 (2.17).
    """
    thesis_scene_check(scene)
    s = DimensionalSymbols.for_scene(scene)
    M, R = s.M, s.R
    sub = {
        s.kX: M * omega_n**2,
        s.cX: 2 * zeta * M * omega_n,  # zeta = c / (2 sqrt(k M))
        s.m[0]: mu * M,
        s.eps: delta * R,
        s.D[0]: beta * mu * M * R**2 * omega_n,  # beta = D / (m R^2 omega_n)
        s.omega: Omega * omega_n,
        t: t / omega_n,
    }
    if scene.gravity:
        sub[s.g] = G * delta * R * omega_n**2  # G = g / (eps omega_n^2)
    X, Y = Coordinate.make("X"), Coordinate.make("Y")
    for c in (X, Y):
        sub.update({c.q: R * c.q, c.qd: R * omega_n * c.qd, c.qdd: R * omega_n**2 * c.qdd})
    rows = {"X": M * R * omega_n**2, "Y": M * R * omega_n**2}
    for i in range(scene.n):
        f = Coordinate.make(f"phi_{i + 1}")
        sub.update({f.qd: omega_n * f.qd, f.qdd: omega_n**2 * f.qdd})
        rows[f.name] = mu * M * R**2 * omega_n**2  # m R^2 omega_n^2: (2.22) has phi'' with coefficient 1
    return sub, rows


def nondimensionalise(scene: Scene, eom: EquationsOfMotion | None = None) -> EquationsOfMotion:
    """Fixed-frame equations in the thesis' dimensionless form (2.20)-(2.22)."""
    eom = eom if eom is not None else derive(scene)
    sub, rows = scaling(scene)
    residuals = []
    for k, c in enumerate(eom.coordinates):
        residuals.append(sp.expand(eom.residual(k).xreplace(sub) / rows[c.name]))
    params = nondimensional_parameters(scene.nondimensional(), gravity=scene.gravity)
    allowed = {p.symbol for p in params} | {t}
    coords = eom.coordinates
    for c in coords:
        allowed |= {c.q, c.qd, c.qdd}
    for r in residuals:
        left = r.free_symbols - allowed
        if left:
            raise AssertionError(f"dimensional symbols survive the scaling: {sorted(map(str, left))}")
    return EquationsOfMotion.from_residuals(residuals, coords, t, parameters=params,
                                            reference="thesis (2.20)-(2.22)")


def to_rotating(eom: EquationsOfMotion, rate: sp.Symbol, reference: str) -> EquationsOfMotion:
    """Rewrite fixed-frame equations in axes turning at `rate` (2.23)-(2.24).

    The rotor rows are projected on the rotating axes (E_x = cos E_X + sin E_Y,
    E_y = -sin E_X + cos E_Y), the ball rows only change variables.  The result must be free of t
    (autonomous), which is checked: it is when the support is isotropic, the speed constant and
    gravity absent.
    """
    (x, y), sub = rotating_substitution(rate)
    res = {c.name: eom.residual(k).xreplace(sub) for k, c in enumerate(eom.coordinates)}
    C, S = sp.cos(rate * t), sp.sin(rate * t)
    rows = [C * res["X"] + S * res["Y"], -S * res["X"] + C * res["Y"]]
    rows += [res[c.name] for c in eom.coordinates[2:]]
    rows = [canonical_trig(r) for r in rows]
    for r in rows:
        if t in r.free_symbols:
            raise AssertionError("the rotating-frame equations still depend on t")
    return EquationsOfMotion.from_residuals(rows, (x, y) + eom.coordinates[2:], t, parameters=eom.parameters,
                                            reference=reference)


def non_autonomous_reasons(scene: Scene) -> list[str]:
    """Why the scene is not autonomous in a rotating frame (empty when it is)."""
    return [why for cond, why in (
        (scene.speed.law != "constant", "a varying spin speed"),
        (not scene.isotropic, "anisotropic support (it turns in the rotating frame)"),
        (scene.gravity, "gravity (it turns in the rotating frame; the thesis sets G = 0 for (2.25)-(2.27))"),
    ) if cond]


def _autonomous_check(scene: Scene) -> None:
    reasons = non_autonomous_reasons(scene)
    if reasons:
        raise ReductionError(", ".join(reasons) + ": not autonomous in a rotating frame; use the fixed-frame model")


def rotating_frame(scene: Scene, nondim: EquationsOfMotion | None = None) -> EquationsOfMotion:
    """The autonomous system (2.25)-(2.27): (2.23)-(2.24) applied to (2.20)-(2.22) with G = 0."""
    _autonomous_check(scene)
    nondim = nondim if nondim is not None else nondimensionalise(scene)
    return to_rotating(nondim, Omega, "thesis (2.25)-(2.27)")


def rotating_frame_dimensional(scene: Scene) -> EquationsOfMotion:
    """The rotating-frame system of any isotropic scene at constant speed without gravity.

    Unlike (2.25)-(2.27) it keeps the dimensional parameters, so unequal balls (m_i, D_i) are
    allowed; for equal balls it is (2.25)-(2.27) before the scalings (2.15)-(2.19) (tested).
    """
    _autonomous_check(scene)
    omega = DimensionalSymbols.for_scene(scene).omega
    return to_rotating(derive(scene), omega, "thesis (2.10), (2.11), (2.13) in the rotating frame (2.23)-(2.24)")


def first_order(eom: EquationsOfMotion, core: tuple[str, ...] | None = None) -> FirstOrderSystem:
    """First-order form of any single-plane EquationsOfMotion: Appendix A's construction."""
    if core is None:
        core = tuple(c.name for c in eom.coordinates if not c.name.startswith("phi_"))
    return _first_order(eom, core, f"thesis Appendix A (A.1)-(A.14) applied to {eom.reference}")


def thesis_chain(n: int, gravity: bool = False) -> dict[str, object]:
    """The whole chain for the thesis scene with n balls: every form, in order."""
    scene = Scene(n=n, gravity=gravity)
    fixed = derive(scene)
    nondim = nondimensionalise(scene, fixed)
    out = {"scene": scene, "fixed": fixed, "nondimensional": nondim}
    if not gravity:
        rot = rotating_frame(scene, nondim)
        out["rotating"] = rot
        out["first_order"] = first_order(rot)
    return out
