"""Reductions of the two-plane model, each a function from one form to the next.

    derive(scene)              fixed frame, paper (2)-(4) (torque) or (2), (4) (prescribed spin)
      -> complex_rows          the rows combined as (2): X + iY and phi_Y - i phi_X
      -> rotating_frame        q = r e^{i Omega t}, theta_k = Omega t + alpha_k: paper (7)-(8), autonomous
      -> first_order           Schur complement of the ball block: 4x4 core (5x5 with the torsion (3))
      -> autonomous_extension  anisotropic supports: sin, cos of Omega t from the oscillator (40)
      -> single_plane_limit    no tilt, one race: the single-plane model of the thesis (same equations)
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import sympy as sp

from ...errors import ReductionError
from ...core import Coordinate, EquationsOfMotion, canonical_trig, time_derivative
from ...core.first_order import FirstOrderSystem, first_order as _first_order
from ...core.oscillator import OSC_COS, OSC_SIN, Oscillator
from ...core.frames import rotating_substitution
from .model import derive
from .scene import TwoPlaneScene
from .symbols import TwoPlaneSymbols, t

I = sp.I


def complex_rows(eom: EquationsOfMotion) -> tuple[sp.Expr, sp.Expr]:
    """Rows of the fixed frame combined as the complex equations (2): E_X + i E_Y, E_phiY - i E_phiX."""
    E = {c.name: eom.residual(k) for k, c in enumerate(eom.coordinates)}
    return E["X"] + I * E["Y"], E["phi_Y"] - I * E["phi_X"]


def _tilt_substitution(rate) -> tuple[tuple[Coordinate, Coordinate], dict]:
    """phi_Y - i phi_X = (phi_y - i phi_x) e^{i rate t} (paper (5)-(6)) with both time derivatives."""
    px, py = Coordinate.make("phi_x"), Coordinate.make("phi_y")
    C, S = sp.cos(rate * t), sp.sin(rate * t)
    pY, pX = py.q * C + px.q * S, px.q * C - py.q * S
    first = [time_derivative(e, (px, py), t) for e in (pX, pY)]
    second = [time_derivative(e, (px, py), t) for e in first]
    PX, PY = Coordinate.make("phi_X"), Coordinate.make("phi_Y")
    sub = {PX.q: pX, PY.q: pY, PX.qd: first[0], PY.qd: first[1], PX.qdd: second[0], PY.qdd: second[1]}
    return (px, py), sub


def non_autonomous_reasons(scene: TwoPlaneScene) -> list[str]:
    return [why for cond, why in (
        (scene.speed.law != "constant", "a varying spin speed"),
        (not scene.isotropic, "anisotropic supports (they turn in the rotating frame; use the oscillator (40))"),
    ) if cond]


def rotating_frame(scene: TwoPlaneScene, fixed: EquationsOfMotion | None = None) -> EquationsOfMotion:
    """Paper (7)-(8): coordinates x, y, phi_x, phi_y, alpha_1..alpha_n; checked free of t."""
    reasons = non_autonomous_reasons(scene)
    if reasons:
        raise ReductionError(", ".join(reasons) + ": not autonomous in a rotating frame")
    fixed = fixed if fixed is not None else derive(scene)
    Om = TwoPlaneSymbols.for_scene(scene).Omega
    (x, y), sub = rotating_substitution(Om)
    (px, py), tilt = _tilt_substitution(Om)
    sub.update(tilt)
    alphas = []
    for c in fixed.coordinates[4:]:
        a = Coordinate.make(c.name.replace("theta", "alpha"))
        alphas.append(a)
        sub.update({c.q: Om * t + a.q, c.qd: Om + a.qd, c.qdd: a.qdd})
    E = {c.name: fixed.residual(k).xreplace(sub) for k, c in enumerate(fixed.coordinates)}
    C, S = sp.cos(Om * t), sp.sin(Om * t)
    rows = [C * E["X"] + S * E["Y"], -S * E["X"] + C * E["Y"],  # (E_X + i E_Y) e^{-i Omega t}
            S * E["phi_Y"] + C * E["phi_X"], C * E["phi_Y"] - S * E["phi_X"]]  # -Im, Re of (E_phiY - i E_phiX) e^{-i..}
    rows += [E[c.name] for c in fixed.coordinates[4:]]
    rows = [canonical_trig(r) for r in rows]
    if any(t in r.free_symbols for r in rows):
        raise AssertionError("the rotating-frame equations still depend on t")
    return EquationsOfMotion.from_residuals(rows, (x, y, px, py, *alphas), t, parameters=fixed.parameters,
                                            reference="paper (7)-(8), derived")


def rotating_complex_rows(eom: EquationsOfMotion) -> tuple[sp.Expr, sp.Expr]:
    """Rows of the rotating frame combined as (7): E_x + i E_y, E_phiy - i E_phix."""
    E = {c.name: eom.residual(k) for k, c in enumerate(eom.coordinates)}
    return E["x"] + I * E["y"], E["phi_y"] - I * E["phi_x"]


def at_rest(eom: EquationsOfMotion, values: dict | None = None) -> list[sp.Expr]:
    """The steady-state equations: forcing with every rate (and acceleration) zero."""
    rest = {c.qd: sp.S.Zero for c in eom.coordinates}
    return [sp.expand(f.xreplace(rest).xreplace(values or {})) for f in eom.forcing]


CORE = ("X", "Y", "phi_X", "phi_Y")
ROTATING_CORE = ("x", "y", "phi_x", "phi_y")


def first_order(eom: EquationsOfMotion) -> FirstOrderSystem:
    """Schur complement of the ball block: the rotor's 4x4 core (5x5 with theta_0), balls back-substituted."""
    names = {c.name for c in eom.coordinates}
    core = ROTATING_CORE if "x" in names else CORE + (("theta_0",) if "theta_0" in names else ())
    return _first_order(eom, core)


# --- anisotropic supports: the autonomous extension (40) -------------------------------------------------
osc_s, osc_c = OSC_SIN, OSC_COS  # the oscillator's states (core.oscillator: one extension for every family)


@dataclass(frozen=True)
class AutonomousExtension:
    """Fixed-frame equations at constant speed with sin(Omega t), cos(Omega t) replaced by the states
    osc_sin, osc_cos of the oscillator (40), whose stable limit cycle is (sin, cos)(Omega t)."""

    eom: EquationsOfMotion  # free of t; osc_sin, osc_cos appear as inputs
    oscillator: tuple[sp.Expr, sp.Expr]  # osc_sin', osc_cos' of (40)


def autonomous_extension(scene: TwoPlaneScene) -> AutonomousExtension:
    if scene.speed.law != "constant":
        raise ReductionError("the oscillator (40) replaces a constant-speed forcing; the speed varies")
    fixed = derive(scene)
    osc = Oscillator(OSC_SIN, OSC_COS, TwoPlaneSymbols.for_scene(scene).Omega)
    eom = fixed.map(lambda expr: osc.substitute(expr, t))
    return AutonomousExtension(replace(eom, reference="paper (2), (4) made autonomous by (40)"), osc.rates())


def balls_relative_to_spin(scene: TwoPlaneScene, fixed: EquationsOfMotion | None = None) -> EquationsOfMotion:
    """Constant speed: the rotor stays in the fixed frame, each ball's angle is taken from the spin,
    theta_k = Omega t + alpha_k (the alpha_k of (7)-(8)).  The rows are those of (2), (4) (the change of
    ball coordinates is a shift); a balanced state is then a periodic orbit with constant alpha_k,
    which AUTO-07p can continue through the oscillator (40) (absolute angles grow without bound)."""
    if scene.speed.law != "constant":
        raise ReductionError("ball angles relative to the spin need a constant speed")
    fixed = fixed if fixed is not None else derive(scene)
    Om = TwoPlaneSymbols.for_scene(scene).Omega
    sub, coords = {}, []
    for c in fixed.coordinates:
        if c.name.startswith("theta_"):
            a = Coordinate.make(c.name.replace("theta", "alpha"))
            sub.update({c.q: Om * t + a.q, c.qd: Om + a.qd, c.qdd: a.qdd})
            coords.append(a)
        else:
            coords.append(c)
    rows = [sp.expand(fixed.residual(k).xreplace(sub)) for k in range(fixed.size)]
    return EquationsOfMotion.from_residuals(rows, tuple(coords), t, parameters=fixed.parameters,
                                            reference=f"{fixed.reference}, ball angles from the spin")


# --- the single-plane limit -------------------------------------------------------------------------------
def single_plane_limit(eom: EquationsOfMotion) -> dict[str, sp.Expr]:
    """Tilt removed: phi_X = phi_Y = 0, their rows dropped (use a scene with one empty race).

    Returns rows keyed by the single-plane names: X, Y, phi_i and, with the torque drive, psi.  The
    single-plane coordinates are the spin psi and the relative angles phi_i = theta_i - psi, so the
    psi row is the theta_0 row plus the ball rows (chain rule).  Symbols are still the two-plane ones;
    `adbgen.families.two_plane.verify` maps them.
    """
    zero = {sym: 0 for c in eom.coordinates if c.name in ("phi_X", "phi_Y") for sym in (c.q, c.qd, c.qdd)}
    E = {c.name: sp.expand(eom.residual(k).xreplace(zero)) for k, c in enumerate(eom.coordinates)}
    balls = [c.name for c in eom.coordinates if c.name.startswith("theta_") and c.name != "theta_0"]
    out = {"X": E["X"], "Y": E["Y"]}
    out.update({f"phi_{i + 1}": E[name] for i, name in enumerate(balls)})
    if "theta_0" in E:
        out["psi"] = E["theta_0"] + sum((E[name] for name in balls), sp.S.Zero)
    return out
