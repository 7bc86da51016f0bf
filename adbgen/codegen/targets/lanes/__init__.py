"""The lanes target: the model's rhs over a lane dimension, for the SIMD ensemble engine (issue 22 item 4).

One header per model, `<model>_lanes.h`: `static inline void <model>_rhs_lanes(adb_lanes t, const
adb_lanes *y, const adb_lanes *p, adb_lanes *dydt)`, the C target's loop-form rhs printed with every
scalar a vector of trajectories (`adb_lanes`, a GCC vector type of 8, 4 or 1 doubles chosen by the
includer) and every math function `adb_<name>` (the includer maps sin/cos to glibc's libmvec and the
rest lane by lane).  y[k] is state k of every lane (structure of arrays), so each statement of the
scalar rhs is one vector instruction: the same operations in the same ball-invariant order as the C
target, lane by lane (exact exchange symmetry is kept in every lane).  The includer is
analysis/engines/lanes.h (rk_batch_driver.c).

Not rendered for a model whose rhs branches (Piecewise: C has no ?: on vectors; a run-up law with a
switch, e.g. two_plane_hill): its ensembles run one trajectory at a time (engines say so).
"""

import sympy as sp

from .. import Target, columns
from .dialect import LanesDialect
from .printer import LanesPrinter


class LanesTarget(Target):
    def dialect(self, which, kernel):
        return LanesDialect("y", "p", "dydt", columns(kernel))

    def skip_reason(self, ir):
        if ir.loops is None:
            return "no loop form (the lanes rhs prints the loop form)"
        for op in ir.loops.rhs.walk():
            expr = getattr(op, "expr", None)
            if isinstance(expr, sp.Basic) and expr.has(sp.Piecewise):
                return "the rhs branches (Piecewise): C vector types have no lane-wise ?:"
        return None


TARGET = LanesTarget(
    name="lanes",
    files=(("lanes/model_lanes.h.j2", "{name}/{name}_lanes.h"),),
    printer=LanesPrinter,
    loops=True,
    functions=("rhs",),
    description="C header: <model>_rhs_lanes, the rhs over a lane dimension (SIMD ensembles)",
)
