"""The oscillator extension (paper (40), two-plane 2011): a periodically forced system made autonomous.

Used by both families (the two-plane anisotropic rotor, the single-plane fixed frame) and by the
AUTO-07p target, which continues the periodic orbits of the extension.  One class, one pair of state
names (osc_sin, osc_cos).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import sympy as sp

OSC_SIN = sp.Symbol("osc_sin", real=True)
OSC_COS = sp.Symbol("osc_cos", real=True)


@dataclass(frozen=True)
class Oscillator:
    """The autonomous extension of a periodically forced model (paper (40), two-plane 2011):

        s' = s + w c - s (s^2 + c^2),    c' = c - w s - c (s^2 + c^2),

    whose attracting limit cycle is s = sin(w t + theta), c = cos(w t + theta).  Every sin(w t + b),
    cos(w t + b) of the model is replaced by s cos b + c sin b, c cos b - s sin b, so the extended
    system is autonomous and equals the forced one on the cycle (theta = 0).  AUTO-07p continues its
    periodic orbits.
    """

    sin: sp.Symbol
    cos: sp.Symbol
    frequency: sp.Expr

    @classmethod
    def detect(cls, exprs: Sequence[sp.Expr], t: sp.Symbol) -> "Oscillator":
        freqs = set()
        for e in exprs:
            for atom in sp.sympify(e).atoms(sp.sin, sp.cos):
                if t in atom.free_symbols:
                    w = sp.diff(atom.args[0], t)
                    if t in w.free_symbols:
                        raise ValueError(f"{atom} is not forcing at a constant frequency")
                    freqs.add(w)
        if len(freqs) != 1:
            raise ValueError(f"the explicit time enters at {len(freqs)} frequencies; one is needed")
        return cls(OSC_SIN, OSC_COS, freqs.pop())

    def substitute(self, expr: sp.Expr, t: sp.Symbol) -> sp.Expr:
        expr = sp.sympify(expr)
        table = {}
        for atom in expr.atoms(sp.sin, sp.cos):
            if t in atom.free_symbols:
                phase = sp.expand(atom.args[0] - self.frequency * t)
                if t in phase.free_symbols:
                    raise ValueError(f"{atom} is not at the frequency {self.frequency}")
                s, c = self.sin, self.cos
                table[atom] = (s * sp.cos(phase) + c * sp.sin(phase)) if atom.func is sp.sin \
                    else (c * sp.cos(phase) - s * sp.sin(phase))
        out = sp.expand(expr.xreplace(table))
        if t in out.free_symbols:
            raise ValueError("explicit time is left after the oscillator substitution")
        return out

    def rates(self) -> tuple[sp.Expr, sp.Expr]:
        s, c, w = self.sin, self.cos, self.frequency
        r2 = s**2 + c**2
        return (s + w * c - s * r2, c - w * s - c * r2)
