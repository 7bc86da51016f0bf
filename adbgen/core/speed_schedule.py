"""A prescribed speed schedule every family offers (issue 37, item 4): a run-up ramp, a hold, and a
temporary speed reduction (fall, plateau, recovery), the profiles that Machines 2020, 8(4), 74 ("Let's
Make Ball Balancing Great Again: Why You Should Use Temporary Speed Reduction") and Wright and Peng
(arXiv 1906.04823, non-monotone speed to enlarge the balanced state's basin) study.

The speed is piecewise linear in t; the angle is its exact integral phase by phase, so angle, speed and
acceleration are one consistent law (`check` proves it symbolically).  Every value is a parameter of the
generated model (a run-time input: `adbgen simulate/sweep --set t_plateau=...`), never baked in.
"""

from __future__ import annotations

from typing import Any, Mapping

import sympy as sp

from ..errors import SceneError
from .scene_fields import number
from .symbols import nonnegative, positive

# the scene keys in the order of the phases, with what each means and its unit
KEYS = ("omega", "ramp_time", "hold_time", "reduction_depth", "reduction_rate", "plateau_time", "recovery_rate")
MEANINGS = {
    "omega": ("spin speed the schedule runs up to and returns to", "rad/s"),
    "ramp_time": ("duration of the run-up from rest to the final speed", "s"),
    "hold_time": ("time at the final speed before the temporary speed reduction", "s"),
    "reduction_depth": ("temporary speed reduction, a fraction of the final speed", "dimensionless"),
    "reduction_rate": ("rate of the fall to the reduced speed", "rad/s^2"),
    "plateau_time": ("time held at the reduced speed", "s"),
    "recovery_rate": ("rate of the return to the final speed", "rad/s^2"),
}
# the model's parameter names (the final speed's is the family's own speed symbol)
NAMES = {"ramp_time": "t_ramp", "hold_time": "t_hold", "reduction_depth": "depth", "reduction_rate": "drop_rate",
         "plateau_time": "t_plateau", "recovery_rate": "recovery_rate"}


def validate(data: Mapping[str, Any]) -> tuple[tuple[str, float], ...]:
    """A [speed] table's schedule values, checked: omega and ramp_time > 0; hold, depth and plateau >= 0
    (default 0: no hold, no reduction); depth below 1 (the rotor keeps turning); the rates > 0 (default the
    ramp's slope omega / ramp_time)."""
    for key in ("omega", "ramp_time"):
        if key not in data:
            raise SceneError(f"speed.{key}", "a schedule needs omega (rad/s) and ramp_time (s)")
    omega = number("speed.omega", data["omega"], positive=True)
    ramp = number("speed.ramp_time", data["ramp_time"], positive=True)
    values = {"omega": omega, "ramp_time": ramp}
    for key in ("hold_time", "reduction_depth", "plateau_time"):
        values[key] = number(f"speed.{key}", data.get(key, 0.0), nonnegative=True)
    if values["reduction_depth"] >= 1:
        raise SceneError("speed.reduction_depth", f"must be below 1 (a fraction of omega), got {values['reduction_depth']!r}")
    for key in ("reduction_rate", "recovery_rate"):
        values[key] = number(f"speed.{key}", data.get(key, omega / ramp), positive=True)
    return tuple((key, values[key]) for key in KEYS)


def symbols(speed: str = "omega") -> dict[str, sp.Symbol]:
    """{scene key: the model's symbol}; `speed`: the family's name of the final speed."""
    out = {"omega": positive(speed)}
    for key, name in NAMES.items():
        out[key] = (nonnegative if key in ("hold_time", "reduction_depth", "plateau_time") else positive)(name)
    return out


def add_parameters(table, values: Mapping[str, float] | tuple, speed: str = "omega") -> None:
    """Add the schedule's parameters with their defaults `values` to a `ParameterTable`."""
    values = dict(values)
    for key, symbol in symbols(speed).items():
        meaning, unit = MEANINGS[key]
        table.add(symbol, meaning, unit, values[key])


def law(t: sp.Symbol, speed: str = "omega", start: sp.Expr = sp.S.Zero) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(angle, speed, acceleration) of the schedule in t and its parameters: the speed piecewise linear
    through the phases ramp (`start`, default 0: from rest, to omega over t_ramp), hold (t_hold), fall (to omega (1 - depth) at
    drop_rate), plateau (t_plateau), recovery (back to omega at recovery_rate), then omega; the angle the
    exact integral of each phase from the angle reached at its start.  Nested two-branch Piecewise
    (value, t < end), (the later phases, True): the form every target prints, the Taylor series' included."""
    s = symbols(speed)
    w, t1, hold, depth = s["omega"], s["ramp_time"], s["hold_time"], s["reduction_depth"]
    fall, plateau, rise = s["reduction_rate"], s["plateau_time"], s["recovery_rate"]
    low = w * (1 - depth)
    # (end of the phase, speed at its start, its rate of change); after the last, omega for ever
    phases = [(t1, start, (w - start) / t1), (t1 + hold, w, sp.S.Zero)]  # start 0: w / t1 exactly
    phases.append((phases[-1][0] + depth * w / fall, w, -fall))
    phases.append((phases[-1][0] + plateau, low, sp.S.Zero))
    phases.append((phases[-1][0] + depth * w / rise, low, rise))
    pieces, start, angle0 = [], sp.S.Zero, sp.S.Zero
    for end, speed0, rate in phases:
        pieces.append((end, angle0 + speed0 * (t - start) + rate * (t - start) ** 2 / 2,
                       speed0 + rate * (t - start), rate))
        d = end - start
        angle0, start = angle0 + speed0 * d + rate * d**2 / 2, end
    pieces.append((None, angle0 + w * (t - start), w, sp.S.Zero))

    def nest(k: int):
        end, *exprs = pieces[k]
        if end is None:
            return exprs
        rest = nest(k + 1)
        return [sp.Piecewise((e, t < end), (r, True)) for e, r in zip(exprs, rest)]
    return tuple(nest(0))


def check(t: sp.Symbol, wrong: bool = False) -> tuple[bool, str]:
    """On each phase the angle's derivative is the speed and the speed's the acceleration; angle and speed
    continuous at every phase end; the speed omega t / t_ramp on the ramp, omega (1 - depth) on the
    plateau and omega at the end; all exact in the symbols.  wrong: the ramp's angle omega t^2 / t_ramp
    (its factor 1/2 dropped)."""
    angle, speed, acc = law(t)
    s = symbols()
    w, t1, depth = s["omega"], s["ramp_time"], s["reduction_depth"]

    def branches(e):
        out = []
        while isinstance(e, sp.Piecewise):
            (value, cond), (rest, _) = e.args
            out.append((value, cond))
            e = rest
        return out + [(e, None)]
    A, S, C = (branches(e) for e in (angle, speed, acc))
    if wrong:
        A[0] = (w * t**2 / t1, A[0][1])
    if not (len(A) == len(S) == len(C) == 6):
        return False, f"{len(A)} phases, not 6"
    bad = []
    for k in range(6):
        if sp.simplify(sp.diff(A[k][0], t) - S[k][0]) != 0 or sp.simplify(sp.diff(S[k][0], t) - C[k][0]) != 0:
            bad.append(f"phase {k + 1}: derivative")
        if k < 5:
            end = A[k][1].rhs if A[k][1].lhs == t else A[k][1].lhs
            for name, F in (("angle", A), ("speed", S)):
                if sp.simplify(F[k][0].subs(t, end) - F[k + 1][0].subs(t, end)) != 0:
                    bad.append(f"{name} jumps at the end of phase {k + 1}")
    if sp.simplify(S[0][0] - w * t / t1) != 0 or sp.simplify(S[3][0] - w * (1 - depth)) != 0 or S[5][0] != w:
        bad.append("ramp, plateau or final speed")
    return not bad, ("six phases: psi' = d psi/dt, psi'' = d psi'/dt, continuous; ramp, plateau and final "
                     "speeds as declared" if not bad else "; ".join(bad))
