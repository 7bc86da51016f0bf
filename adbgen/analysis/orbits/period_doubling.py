"""The period-doubling (flip) curve: a real Floquet multiplier at -1, in two parameters.

Defining system (`boundary`): g = mu + 1 of the real multiplier tracked along the curve (the one nearest -1
where the curve starts), the orbit re-found by Newton shooting at each point.  Test function: the
distance of the next real multiplier from -1 (two at -1: a degenerate flip, reported as "double flip").
"""

from __future__ import annotations

import numpy as np

from .boundary import BoundaryCurve


class PeriodDoublingCurve(BoundaryCurve):
    kind = "period-doubling"
    test_names = ("double flip",)

    def value(self, z):
        return float(z.real + 1.0)

    def tests(self, x, data):
        real = self.candidates(data.spectrum)
        others = real[np.abs(real - data.critical) > 1e-12]
        return np.array([float(np.min(others.real + 1.0, initial=1.0)) if len(others) else 1.0])

    def special(self, name, x, data):
        return {"kind": name}
