"""What a two-plane model with stiction emits about it (issue 37 item 2): each ball's normal force N_k, its
slip rate theta_k' - theta_0' relative to its race, the tangential force F_k a stuck ball needs and the stick
margin mu_s_k N_k - |F_k| (the switching functions the event driver reads, `analysis.engines.hybrid`).

N_k (`model.normal_forces`) and F_k (`model.stick_forces`) hold the rotor core's accelerations X'', Y'',
phi_X'', phi_Y'' (and theta_0'' under a torque drive).  The core is 4 x 4 (5 x 5), beyond the closed-form solve
(`core.structure.cramer` stops at r = 3), so they are written with the parameters accel_<coordinate>
(`TwoPlaneSymbols.accel`), which the model's rhs never reads and the driver fills from the rhs at the same
state and modes before it evaluates a switching function.  The single-plane family writes the same measures
with its closed-form solve instead (`single_plane.friction`).
"""

from __future__ import annotations

import sympy as sp

from ...core import Coordinate
from ...core.first_order import FirstOrderSystem
from .model import lagrangian, normal_forces, speed_law, stick_forces
from .scene import TwoPlaneScene
from .symbols import TwoPlaneSymbols


def measures(scene: TwoPlaneScene, system: FirstOrderSystem) -> dict[str, sp.Expr]:
    """{normal_force_k, slip_rate_k, stick_force_k, stick_margin_k} of a stiction scene's model."""
    if not scene.stiction:
        return {}
    lag = lagrangian(scene)
    s = TwoPlaneSymbols.for_scene(scene)
    eom = system.solve.eom
    law = speed_law(scene, s) if scene.speed.law == "constant" else dict(eom.driven_law)
    inputs = {Coordinate.make(name).qdd: symbol for name, symbol in s.accel.items()}
    names = {c.name for c in eom.coordinates}
    th0 = Coordinate.make("theta_0")

    def written(expr):
        expr = expr.xreplace(inputs).xreplace(law)
        left = {c.qdd for c in eom.coordinates} & expr.free_symbols
        if left:  # every acceleration a measure holds must be an input the driver fills
            raise AssertionError(f"a switching function holds the accelerations {sorted(map(str, left))}")
        return expr

    normal = [written(N) for N in normal_forces(lag)]
    force = [written(F) for F in stick_forces(lag)]
    out = {}
    for k in range(scene.n):
        rate = Coordinate.make(f"theta_{k + 1}").qd - (th0.qd if "theta_0" in names else th0.qd.xreplace(law))
        out[f"normal_force_{k + 1}"] = normal[k]
        out[f"slip_rate_{k + 1}"] = rate
        out[f"stick_force_{k + 1}"] = force[k]
        out[f"stick_margin_{k + 1}"] = s.mu_s[k] * normal[k] - sp.Abs(force[k])
    return out
