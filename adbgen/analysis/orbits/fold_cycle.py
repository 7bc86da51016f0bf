"""The fold-of-cycles curve: a non-trivial real Floquet multiplier at +1 (two cycles meet), in two parameters.

Defining system (`boundary`): g = mu - 1 of the real multiplier tracked along the curve (the trivial one of an
autonomous orbit removed before), the orbit re-found by Newton shooting at each point (near the fold Newton's
matrix is nearly singular; its minimum-norm steps still converge to the tracked orbit).  No test functions.
"""

from __future__ import annotations

from .boundary import BoundaryCurve


class FoldCycleCurve(BoundaryCurve):
    kind = "fold of cycles"

    def value(self, z):
        return float(z.real - 1.0)
