"""Is a rigid model enough?  The rigid scene's critical speeds against ROSS's Campbell diagram (issue 38 item 2).

Two numbers decide, both stated in the verdict:

1. the rigid model's undamped critical speeds (`two_plane.critical_speeds`: paper (11), (32) and the
   fixed-frame determinant det(K - Omega^2 M + i Omega D) = 0 for anisotropic supports, the plain
   rotor without balls) against the k lowest lateral critical speeds of ROSS's full finite-element
   rotor (the crossings of its Campbell diagram with the line omega = Omega, k = how many the rigid
   model has): each within ``agreement`` (default 5 %: the rigid model places the rotor's own critical
   speeds, which the balancer must pass, where the flexible rotor has them);
2. the first bending critical speed (ROSS's (k+1)-th lateral crossing) at least ``margin`` times the top
   of the scene's speed range (default 2: at Omega = omega_b / 2 the bending mode's dynamic
   amplification is 1 / (1 - 1/4) = 4/3, so the shaft's bending under the imbalance stays within a
   third of its static value, which the rigid model neglects anyway; API 617's separation margins of
   15-26 % keep a machine off resonance, not a model valid).

A crossing is bracketed on ROSS's Campbell diagram (its damped natural frequencies `wd` from
`Rotor.run_modal` on a grid of speeds, what `Rotor.run_campbell` stacks, each frequency curve against
Omega; the same call is used for bracket and refinement so that the curves are ordered alike) and refined by Brent's method on `Rotor.run_modal(Omega).wd` to ``xtol``; a mode is
lateral when its shape (the displacement part of ROSS's eigenvector) moves mostly in x, y, alpha,
beta, not axially or in torsion.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

MARGIN = 2.0
AGREEMENT = 0.05
GRID = 61  # Campbell diagram's speeds over the scan


@dataclass(frozen=True)
class Crossing:
    speed: float  # rad/s, where ROSS's natural frequency equals the spin speed
    whirl: str  # ROSS's whirl direction of the mode there


def _lateral(rotor, modal, i: int) -> bool:
    """Most of the mode's displacement in x, y, alpha, beta (not z or theta)."""
    v = np.asarray(modal.evectors)[: rotor.ndof, i]
    lateral = np.zeros(rotor.ndof, dtype=bool)
    for elm in rotor.shaft_elements:
        dofs = list(elm.dof_global_index.values())
        for name, k in elm.dof_mapping().items():
            if name[:-2] in ("x", "y", "alpha", "beta"):
                lateral[dofs[k]] = True
    w = np.abs(v) ** 2
    return float(w[lateral].sum()) > 0.5 * float(w.sum())


def campbell_crossings(rotor, top: float, frequencies: int = 8, xtol: float = 1e-10) -> list[Crossing]:
    """Lateral critical speeds of a ROSS rotor in (0, top]: ROSS's Campbell diagram crossed with omega = Omega."""
    speeds = np.linspace(0.0, top, GRID)
    modal_at = lambda s: rotor.run_modal(s, num_modes=2 * frequencies, sparse=False)  # noqa: E731
    wd = np.array([np.asarray(modal_at(s).wd)[:frequencies] for s in speeds])
    out = []
    for i in range(wd.shape[1]):
        gap = wd[:, i] - speeds
        for j in np.nonzero(np.sign(gap[:-1]) * np.sign(gap[1:]) < 0)[0]:
            f = lambda s, i=i: float(modal_at(s).wd[i]) - s  # noqa: E731
            s = brentq(f, speeds[j], speeds[j + 1], xtol=xtol * top, rtol=xtol)
            modal = modal_at(s)
            if _lateral(rotor, modal, i):
                out.append(Crossing(float(s), str(modal.whirl_direction()[i])))
    return sorted(out, key=lambda c: c.speed)


@dataclass(frozen=True)
class Verdict:
    """Whether the rigid two-plane scene is enough for the rotor over speeds 0..top, with the numbers."""

    top: float  # rad/s, top of the scene's speed range
    rigid: tuple[float, ...]  # the rigid model's critical speeds (rad/s)
    ross: tuple[Crossing, ...]  # ROSS's lateral critical speeds found (ascending)
    margin: float
    agreement: float
    scanned_to: float
    reasons: list[str] = field(default_factory=list)

    @property
    def bending(self) -> float | None:
        """The first bending critical speed: ROSS's lateral crossing after the rigid-body ones."""
        k = len(self.rigid)
        return self.ross[k].speed if len(self.ross) > k else None

    @property
    def enough(self) -> bool:
        return not self.reasons

    def line(self) -> str:
        rigid = ", ".join(f"{w:.6g}" for w in self.rigid)
        flex = ", ".join(f"{c.speed:.6g}" for c in self.ross[: len(self.rigid)])
        b = self.bending
        bend = f"{b:.6g} rad/s = {b / self.top:.3g} x the top speed" if b is not None \
            else f"none below {self.scanned_to:.6g} rad/s"
        head = "rigid is enough" if self.enough else "rigid is not enough"
        why = "" if self.enough else ": " + "; ".join(self.reasons)
        return (f"{head}{why} (top speed {self.top:.6g} rad/s; rigid critical speeds {rigid} rad/s, ROSS's "
                f"{flex} rad/s; first bending critical {bend}; margin {self.margin:g} x, agreement {self.agreement:g})")

    def as_dict(self) -> dict:
        return {"enough": self.enough, "top_speed": self.top, "rigid_critical_speeds": list(self.rigid),
                "ross_critical_speeds": [c.speed for c in self.ross], "ross_whirl": [c.whirl for c in self.ross],
                "first_bending_critical": self.bending, "margin": self.margin, "agreement": self.agreement,
                "scanned_to": self.scanned_to, "reasons": list(self.reasons)}


def verdict(rotor, rigid: list[float], top: float, margin: float = MARGIN, agreement: float = AGREEMENT) -> Verdict:
    """Rule 1 and 2 of the module docstring on `rotor` (ROSS) and the rigid model's critical speeds."""
    rigid = tuple(sorted(rigid))
    scanned_to = max(margin * top, 1.5 * max(rigid, default=0.0))
    ross = tuple(campbell_crossings(rotor, scanned_to))
    reasons = []
    k = len(rigid)
    for w, c in zip(rigid, ross[:k]):
        if abs(w - c.speed) > agreement * c.speed:
            reasons.append(f"the rigid critical speed {w:.6g} rad/s is {abs(w / c.speed - 1):.3g} off ROSS's {c.speed:.6g}")
    if len(ross) < k:
        reasons.append(f"ROSS has {len(ross)} lateral critical speeds below {scanned_to:.6g} rad/s, the rigid model {k}")
    v = Verdict(top, rigid, ross, margin, agreement, scanned_to, reasons)
    if v.bending is not None and v.bending < margin * top:
        reasons.append(f"the first bending critical {v.bending:.6g} rad/s is below {margin:g} x {top:.6g} rad/s")
    return v


def stiff_shaft(rotor, factor: float = 1e3):
    """The same rotor with every shaft element's Young's and shear moduli times `factor` (the shear
    parameter 12 E I / (kappa G A L^2) unchanged, so each element's stiffness matrix scales by `factor`)."""
    from .rotor import import_ross

    ross = import_ross()
    shafts = []
    for sh in rotor.shaft_elements:
        mat = sh.material
        stiff = ross.Material(name=f"{mat.name}_x{factor:g}", rho=mat.rho, E=mat.E * factor, G_s=mat.G_s * factor)
        shafts.append(ross.ShaftElement(L=sh.L, idl=sh.idl, odl=sh.odl, idr=sh.idr, odr=sh.odr, material=stiff,
                                        n=sh.n, axial_force=sh.axial_force, torque=sh.torque,
                                        shear_effects=sh.shear_effects, rotary_inertia=sh.rotary_inertia,
                                        gyroscopic=sh.gyroscopic, shear_method_calc=sh.shear_method_calc,
                                        alpha=sh.alpha, beta=sh.beta))
    return ross.Rotor(shafts, list(rotor.disk_elements), list(rotor.bearing_elements),
                      list(rotor.point_mass_elements))
