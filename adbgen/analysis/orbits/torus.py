"""The torus (Neimark-Sacker) curve: a complex pair of Floquet multipliers on the unit circle, in two
parameters (the paper's stability boundaries of B in the fixed frame, section 4).

Defining system (`boundary`): g = |mu| - 1 of the complex pair tracked along the curve, the orbit re-found
by Newton shooting at each point.  Test functions, on the pair's angle theta (mu = e^(i theta) on the curve),
the strong resonances where the curve's normal form degenerates:

    1:1   cos theta - 1        (theta -> 0: the pair meets at +1, a fold-torus point)
    1:2   cos theta + 1        (theta -> pi: at -1, a flip-torus point)
    1:3   cos theta + 1/2
    1:4   cos theta

A test function that reaches zero ends the curve there (the pair becomes real at 1:1 and 1:2).
"""

from __future__ import annotations

import numpy as np

from .boundary import BoundaryCurve


class TorusCurve(BoundaryCurve):
    kind = "torus"
    test_names = ("resonance 1:1", "resonance 1:2", "resonance 1:3", "resonance 1:4")

    def candidates(self, mu):
        mu = np.asarray(mu, complex)
        return mu[mu.imag > 1e-9]

    def value(self, z):
        return float(abs(z) - 1.0)

    def tests(self, x, data):
        c = np.cos(np.angle(data.critical))
        return np.array([c - 1.0, c + 1.0, c + 0.5, c])

    def special(self, name, x, data):
        lam1, lam2 = data.lam
        return {"kind": name, "angle": float(np.angle(data.critical))}
