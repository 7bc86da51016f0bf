"""What a generated model says about itself, as its family declares it once (issue 19, item 1).

A family's `models.py` gives every model a `Description`: the role and unit of each coordinate, which
coordinates are angles, which two make the rotor's amplitude, the measures it wants emitted (SymPy
expressions), its exchange symmetries, the named parameter sets of the documents, its scales, and its
closed-form steady states (SymPy expressions, with the conditions under which each applies), and its
manifold of equilibria where it has one (thesis (3.6)).  Code
generation (`adbgen.codegen.passes.description`) turns it into data and compiled functions of every generated
module and checks each declaration against the rendered right-hand side before anything is written,
so a wrong declaration is refused, not emitted.

Everything is named by coordinate and parameter names (a rate follows its coordinate: its role is
"<role>_rate", its unit the coordinate's per unit of time); nothing here depends on the order of
states, which the lowering decides.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping, Sequence

import sympy as sp

from .lagrange import EquationsOfMotion
from .oscillator import Oscillator

# The index of a ball (0-based) in a closed form's per-ball values (`Candidate.balls`): the loop index.
BALL = sp.Symbol("i", integer=True, nonnegative=True)
# The roles of coordinates; a rate's role is its coordinate's + "_rate".
ROLES = ("translation", "tilt", "ball_angle", "spin_angle", "oscillator")
# Symmetry kinds with a meaning the checks know: "identical-balls" promises exact (bitwise) exchange
# symmetry of the generated code at states the exchange fixes (balls that start together stay together).
IDENTICAL_BALLS = "identical-balls"
RACE_SWAP = "race-swap"
TIME_UNITS = ("s", "1")
# The configurations a steady state of balls can be named by (`Description.steady_state_names`): the rotor at rest
# (amplitude zero), every ball at one angle, the balls in two opposite groups of m (the larger) and k = n - m.
STATE_CONFIGURATIONS = ("rest", "together", "opposed")


@dataclass(frozen=True)
class Symmetry:
    """A signed permutation S of the states that commutes with the right-hand side:
    rhs(t, S y, p) = S rhs(t, y, p) for every p with p[k] = sign_k p[image(k)] (the parameters the
    exchange needs equal, or zero where a parameter maps to minus itself).

    ``coordinates``: {name: (image name, sign)}, (S y)[name] = sign * y[image]; a coordinate not listed
    is fixed, and a rate goes with its coordinate.  ``parameters``: {name: (image name, sign)} likewise.
    """

    name: str
    kind: str
    coordinates: Mapping[str, tuple[str, int]]
    parameters: Mapping[str, tuple[str, int]] = field(default_factory=dict)


@dataclass(frozen=True)
class Candidate:
    """One closed form of a steady state, valid where all its ``guards`` hold.

    ``guards``: SymPy relations in the parameters and the form's arguments (>=, >, <=, <, ==, !=),
    checked in order, each evaluated only when the ones before it hold (so a later guard may divide by
    what an earlier one showed non-zero).  ``values``: {coordinate name: expression in the parameters
    and arguments}; ``balls``: every ball angle's value as an expression in `BALL` (its 0-based index),
    the parameters and the arguments (one loop over the balls, whatever n), overridden by the balls
    named in ``values``.  Coordinates given neither way are 0; every rate is 0.
    """

    guards: tuple[sp.Basic, ...]
    values: Mapping[str, sp.Expr] = field(default_factory=dict)
    balls: sp.Expr | None = None


@dataclass(frozen=True)
class ClosedForm:
    """Closed-form steady states: the first candidate whose guards hold gives the state, none: no state
    (it does not exist, or its closed form does not apply there: the labels' notes say which).

    ``arguments``: integer symbols named arg_* that pick one state of a family of them (the thesis'
    in-line states 3(k)+- have m = n - k and the sign); each label gives their values."""

    name: str
    arguments: tuple[sp.Symbol, ...]
    candidates: tuple[Candidate, ...]


@dataclass(frozen=True)
class SteadyState:
    """A labelled steady state: closed form `form` at `arguments` (its arg_* symbols' values).

    ``exists``: an independent criterion from the reference (e.g. thesis (3.16)), a SymPy boolean in
    the parameters; the check requires the closed form to give a state exactly where it holds, at
    random parameters.  None: no independent criterion (the state is still checked to be a zero of the
    rhs wherever it is given)."""

    label: str
    note: str
    form: str
    arguments: tuple[float, ...] = ()
    exists: sp.Basic | None = None


@dataclass(frozen=True)
class Equilibria:
    """A manifold of equilibria (thesis (3.6): the balanced states of n >= 3 balls form one of dimension
    n - 2): the states where every coordinate of ``zero`` and every rate vanish and every expression of
    ``constraints`` (SymPy, in the other coordinates and the parameters) is 0.  Its tangent at a point
    is the null space of the constraints' gradients in the other coordinates; code generation emits the
    gradients as a compiled function (`equilibria_gradient_inplace`), so the analysis layer computes
    the tangent without knowing the equations.  As many independent constraints as other coordinates:
    isolated equilibria, no manifold."""

    name: str
    zero: tuple[str, ...]
    constraints: tuple[sp.Expr, ...]


@dataclass(frozen=True)
class Description:
    """A model's self-description as its family declares it (see the module docstring).

    ``units``, ``roles``: per coordinate name.  ``amplitude``: two coordinate names, r = hypot of the
    two (the measure "r" is made from them).  ``measures``: {name: SymPy expression in t, the states
    and the parameters}, beside "r".  ``closed_forms``, ``steady_states``: the labelled closed-form steady
    states.  ``forcing_frequency``: the parameter whose 2 pi / value is the
    forcing period of a periodically forced model, "" otherwise.  ``parameter_sets``: {name: {parameter:
    value}} (parameters not named keep their defaults).  ``scales``: {"eccentricity": parameter,
    "speed": parameter} where the model has them.  ``steady_state_names``: the names of its steady states by their
    configuration (`STATE_CONFIGURATIONS`; "opposed" a template in {n} balls, {m} of them together, {k}
    opposite), as the reference names them (thesis: balanced 1, coincident 2, in-line 3(n-m)); a branch
    sign + or - is appended from the closed-form label the state is (`steady_states`).  ``equilibria``:
    the model's manifold of equilibria (`Equilibria`), None where it declares none.  ``residual``: the measure
    ("r" or a name of ``measures``) that is the model's residual imbalance, zero exactly where the imbalance is
    balanced (what `adbgen sweep --measure residual` and `adbgen design --objective residual` read at rest when
    not told another): "r" where the rotor's imbalance is its centre's amplitude (one plane, thesis (2.25)), a
    measure that also sees the moment where the rotor can tilt (two planes: paper (9) asks forces and moments in
    equilibrium, and a couple leaves r = 0).
    """

    time_unit: str
    units: Mapping[str, str]
    roles: Mapping[str, str]
    angles: tuple[str, ...]
    amplitude: tuple[str, str]
    measures: Mapping[str, sp.Expr] = field(default_factory=dict)
    forcing_frequency: str = ""
    symmetries: tuple[Symmetry, ...] = ()
    parameter_sets: Mapping[str, Mapping[str, float]] = field(default_factory=dict)
    scales: Mapping[str, str] = field(default_factory=dict)
    closed_forms: tuple[ClosedForm, ...] = ()
    steady_states: tuple[SteadyState, ...] = ()
    steady_state_names: Mapping[str, str] = field(default_factory=dict)
    equilibria: Equilibria | None = None
    residual: str = "r"


def rate_unit(unit: str, time_unit: str) -> str:
    """The unit of a coordinate's rate: "m" -> "m/s"; with dimensionless time ("1") the coordinate's own."""
    if time_unit == "1":
        return unit
    return f"1/{time_unit}" if unit == "1" else f"{unit}/{time_unit}"


def spin_measures(eom: EquationsOfMotion) -> dict[str, sp.Expr]:
    """{"spin_angle", "spin_rate"} of a model whose spin is prescribed (the run-up law of its one driven
    coordinate, as the derivation substituted it); {} when nothing is driven by a known law."""
    law = dict(eom.driven_law)
    driven = [c for c in eom.driven if c.q in law and c.qd in law]
    if len(driven) != 1:
        return {}
    c = driven[0]
    return {"spin_angle": law[c.q], "spin_rate": law[c.qd]}


def forcing_frequency(eom: EquationsOfMotion) -> sp.Expr | None:
    """The frequency of a periodic forcing in the equations with the run-up law substituted (paper (40)'s
    w), None where time does not enter at one constant frequency."""
    law = dict(eom.driven_law)
    exprs = [sp.sympify(v).xreplace(law) for v in eom.mass.values()] + [sp.sympify(e).xreplace(law) for e in eom.forcing]
    try:
        return Oscillator.detect(exprs, eom.time).frequency
    except ValueError:
        return None


def forcing_parameter(eom: EquationsOfMotion) -> str:
    """The parameter of a periodic forcing (e.g. the spin speed omega of a fixed frame), "" if there is
    none or its frequency is not one parameter."""
    w = forcing_frequency(eom)
    return w.name if isinstance(w, sp.Symbol) else ""


def ball_exchanges(balls: Sequence[str], parameters: Mapping[str, Sequence[str]] | None = None,
                   kind: str = IDENTICAL_BALLS, tag: str = "") -> tuple[Symmetry, ...]:
    """Generators of every permutation of `balls` (coordinate names): the exchange of the first two and,
    for three or more, the cyclic shift (ball k takes ball k+1's place).  ``parameters``: {ball: its own
    parameters} (e.g. its mass m_k), permuted with the balls; None when the balls share theirs."""
    def moved(pairs) -> tuple[dict, dict]:
        coords = {a: (b, 1) for a, b in pairs}
        params = {}
        for a, b in pairs:
            for pa, pb in zip((parameters or {}).get(a, ()), (parameters or {}).get(b, ())):
                if pa != pb:
                    params[pa] = (pb, 1)
        return coords, params

    out = []
    if len(balls) >= 2:
        a, b = balls[0], balls[1]
        out.append(Symmetry(f"exchange {a}, {b}{tag}", kind, *moved([(a, b), (b, a)])))
    if len(balls) >= 3:
        shift = list(zip(balls, balls[1:] + balls[:1]))
        out.append(Symmetry(f"cyclic shift of {', '.join(balls)}{tag}", kind, *moved(shift)))
    return tuple(out)
