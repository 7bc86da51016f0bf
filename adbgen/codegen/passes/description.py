"""A model's self-description (`core.description.Description`, declared by its family) turned into what
the targets print: data by state and parameter index, and kernels (`loops.Kernel`) for the functions
the generated modules carry (issue 19, item 1):

- the measures: "r" (the hypot of the two amplitude states, for every model) and the family's own
  (e.g. "A", "spin_rate"), one kernel each and one for all of them, and the name of the one that is the
  model's residual imbalance (RESIDUAL_MEASURE);
- the closed-form steady states: one kernel per candidate of each closed form, reading its integer
  arguments from an array ``a`` (so one function serves every label of a family of states, e.g. the
  thesis' 3(k)+- for every k, and the per-ball values are a loop over the balls: emitted code does not
  grow with n), guarded in order; the labels are a table (label -> form, arguments);
- the manifold of equilibria (`core.description.Equilibria`, thesis (3.6)): the states that vanish on
  it, and one kernel for the gradients of its constraints with respect to every state (out[k, j]).

Every name is resolved and validated here (unknown coordinates, roles, parameters and malformed
symmetries are refused with `DescriptionError`); what needs the rendered code (periodicity, the
measures' values, the symmetries, the steady states being zeros) is checked in `checks`.
"""

from __future__ import annotations

from typing import Sequence

import sympy as sp

from ...core.description import BALL, ROLES, STATE_CONFIGURATIONS, TIME_UNITS, Candidate, Description, rate_unit
from ...core.first_order import FirstOrderSystem
from ...core.model_spec import ModelSpec
from ...errors import AdbgenError
from ..ir.description import ClosedFormIR, SelfDescription
from ..ir.loops import Balls, Guard, Kernel, Let, Pos, Put
from .cse import cse_lets

_RELATIONS = (sp.Ge, sp.Gt, sp.Le, sp.Lt, sp.Eq, sp.Ne)


class DescriptionError(AdbgenError):
    """A model's self-description names what the model does not have, or is malformed."""


def _refuse(model: str, what: str) -> None:
    raise DescriptionError(f"{model}: self-description: {what}")


def _measures(names: list[str], exprs: list[sp.Expr]) -> tuple[Kernel, tuple[Kernel, ...]]:
    """One kernel for every measure, and one per measure with just the statements it needs (the same
    statements, so measure(name) and measures_inplace give the same bits)."""
    lets, red = cse_lets(exprs, "w_m_")
    every = Kernel(tuple(lets) + tuple(Put(Pos(k), None, e) for k, e in enumerate(red)), (len(exprs),), False)
    alone = []
    for e in red:
        needed = set(e.free_symbols)
        for let in reversed(lets):
            if let.sym in needed:
                needed |= let.expr.free_symbols
        alone.append(Kernel(tuple(let for let in lets if let.sym in needed) + (Put(Pos(0), None, e),), (1,), False))
    return every, tuple(alone)


def _candidate(model: str, cand: Candidate, system: FirstOrderSystem, allowed: set, leaves: list[int],
               n_states: int, tag: str, unrolled: bool = False) -> Kernel:
    """One candidate as a kernel: each guard's statements and test, in order; the values' statements;
    the stores (core values, then the ball loop, then leaves named one by one).  `unrolled`: the ball
    loop written out ball by ball (the lowering's unrolled form)."""
    index = {c.name: k for k, c in enumerate(system.coordinates)}
    ops: list = []
    for g, guard in enumerate(cand.guards):
        if not isinstance(guard, _RELATIONS):
            _refuse(model, f"closed form guard {guard!r} is not a relation (>=, >, <=, <, ==, !=)")
        diff = sp.sympify(guard.lhs - guard.rhs)
        if not diff.free_symbols <= allowed:
            _refuse(model, f"guard {guard} uses {sorted(map(str, diff.free_symbols - allowed))}, not parameters")
        lets, (red,) = cse_lets([diff], f"w_{tag}g{g}_")
        ops += lets
        ops.append(Guard(type(guard)(red, 0, evaluate=False)))  # (a positive symbol > 0 stays a test)
    values = {}
    for name, expr in cand.values.items():
        if name not in index:
            _refuse(model, f"closed form value for {name!r}, not a coordinate")
        values[name] = sp.sympify(expr)
    exprs = list(values.values()) + ([sp.sympify(cand.balls)] if cand.balls is not None else [])
    for e in exprs:
        if not e.free_symbols <= allowed | {BALL}:
            _refuse(model, f"closed form value {e} uses {sorted(map(str, e.free_symbols - allowed - {BALL}))}")
    for name, e in values.items():
        if BALL in e.free_symbols:
            _refuse(model, f"closed form value for {name} uses the ball index (only `balls` may)")
    lets, red = cse_lets(exprs, f"w_{tag}v_")
    outer, inner, ball_syms = [], [], {BALL}
    for let in lets:  # what depends on the ball index goes into the loop
        if let.expr.free_symbols & ball_syms:
            ball_syms.add(let.sym)
            inner.append(let)
        else:
            outer.append(let)
    ops += outer
    named = list(zip(values, red[: len(values)]))
    leaf_names = {system.coordinates[k].name for k in leaves}
    ops += [Put(Pos(index[name]), None, e) for name, e in named if name not in leaf_names]
    if cand.balls is not None:
        if not leaves or leaves != list(range(leaves[0], leaves[0] + len(leaves))):
            _refuse(model, "closed form values per ball need the balls' angles to be consecutive states")
        if unrolled:
            for k in range(len(leaves)):
                at = {BALL: sp.Integer(k)} | {let.sym: sp.Symbol(f"{let.sym.name}_{k}", real=True) for let in inner}
                ops += [Let(at[let.sym], let.expr.xreplace(at)) for let in inner]
                ops.append(Put(Pos(leaves[0] + k), None, red[-1].xreplace(at)))
        else:
            ops.append(Balls(tuple(inner) + (Put(Pos(leaves[0], ball=True), None, red[-1]),), count=len(leaves)))
    ops += [Put(Pos(index[name]), None, e) for name, e in named if name in leaf_names]
    return Kernel(tuple(ops), (n_states,), True)


def _signed(model: str, what: str, mapping: dict, names: Sequence[str]) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """(images, signs) of the signed permutation {name: (image, sign)} over `names` (others fixed)."""
    position = {name: k for k, name in enumerate(names)}
    images, signs = list(range(len(names))), [1] * len(names)
    for name, (image, sign) in mapping.items():
        if name not in position or image not in position or sign not in (1, -1):
            _refuse(model, f"{what} maps {name!r} to ({image!r}, {sign!r}): unknown names or a sign not +-1")
        images[position[name]], signs[position[name]] = position[image], int(sign)
    if sorted(images) != list(range(len(names))):
        _refuse(model, f"{what} is not a permutation")
    return tuple(images), tuple(signs)


def lower_description(spec: ModelSpec, system: FirstOrderSystem, form: str = "loops") -> SelfDescription:
    """The spec's declared self-description, resolved against its system (`DescriptionError` if it names
    what the model does not have); `form`: the lowering's (in the unrolled form the closed forms' ball
    loops are written out too)."""
    d: Description = spec.describe(system)
    model = spec.name
    coords = [c.name for c in system.coordinates]
    states = list(system.state_names)
    params = [p.name for p in system.parameters]
    psym = {p.name: p.symbol for p in system.parameters}
    leaves = list(system.solve.leaves)
    if d.time_unit not in TIME_UNITS:
        _refuse(model, f"time unit {d.time_unit!r}: one of {', '.join(TIME_UNITS)}")
    for what, table in (("unit", d.units), ("role", d.roles)):
        missing, unknown = sorted(set(coords) - set(table)), sorted(set(table) - set(coords))
        if missing or unknown:
            _refuse(model, f"{what}s: " + "; ".join(x for x in (f"none for {missing}" if missing else "",
                                                              f"{unknown} are not coordinates" if unknown else "") if x))
    bad = {c: r for c, r in d.roles.items() if r not in ROLES}
    if bad:
        _refuse(model, f"roles {bad}: each one of {', '.join(ROLES)}")
    units = tuple(d.units[c] for c in coords) + tuple(rate_unit(d.units[c], d.time_unit) for c in coords)
    roles = tuple(d.roles[c] for c in coords) + tuple(d.roles[c] + "_rate" for c in coords)
    for name in list(d.angles) + list(d.amplitude):
        if name not in coords:
            _refuse(model, f"{name!r} (an angle or an amplitude state) is not a coordinate")
    if len(d.amplitude) != 2 or len(set(d.angles)) != len(d.angles):
        _refuse(model, "amplitude: two coordinates; angles: each once")
    if d.forcing_frequency and d.forcing_frequency not in params:
        _refuse(model, f"forcing frequency {d.forcing_frequency!r} is not a parameter")
    for key, name in d.scales.items():
        if key not in ("eccentricity", "speed") or name not in params:
            _refuse(model, f"scale {key!r} -> {name!r}: keys eccentricity, speed; values parameters")
    sets = []
    for set_name, values in d.parameter_sets.items():
        unknown = sorted(set(values) - set(params))
        if unknown:
            _refuse(model, f"parameter set {set_name!r} names {unknown}, not parameters")
        sets.append((set_name, tuple((k, float(values[k])) for k in params if k in values)))
    # measures: r first, from the amplitude states
    eom = system.solve.eom
    allowed_m = set(system.states) | set(psym.values()) | {eom.time}
    a, b = (system.coordinates[coords.index(n)].q for n in d.amplitude)
    names, exprs = ["r"], [sp.sqrt(a**2 + b**2)]
    for name, expr in d.measures.items():
        expr = sp.sympify(expr)
        if name in names or not name.isidentifier():
            _refuse(model, f"measure {name!r}: a new identifier (r is made from the amplitude)")
        if not expr.free_symbols <= allowed_m:
            _refuse(model, f"measure {name} uses {sorted(map(str, expr.free_symbols - allowed_m))}")
        names.append(name)
        exprs.append(expr)
    every, alone = _measures(names, exprs)
    if d.residual not in names:
        _refuse(model, f"residual imbalance {d.residual!r} is not one of its measures ({', '.join(names)})")
    # symmetries
    rates = {c.name: c.qd.name for c in system.coordinates}
    syms = []
    for s in d.symmetries:
        unknown = sorted(set(s.coordinates) - set(coords))
        if unknown:
            _refuse(model, f"symmetry {s.name!r} maps {unknown}, not coordinates")
        on_states = dict(s.coordinates) | {rates[c]: (rates.get(img, img), sign) for c, (img, sign) in s.coordinates.items()}
        st, sg = _signed(model, f"symmetry {s.name!r}", on_states, states)
        pp, ps = _signed(model, f"symmetry {s.name!r}", dict(s.parameters), params)
        syms.append({"name": s.name, "kind": s.kind, "states": st, "signs": sg, "params": pp, "param_signs": ps})
    # closed forms and the labels
    forms, form_index = [], {}
    n_states = len(states)
    unrolled = form == "unrolled"
    for k, form in enumerate(d.closed_forms):
        for arg in form.arguments:
            if arg.name in set(states) | set(params) or not arg.name.startswith("arg_"):
                _refuse(model, f"closed form {form.name!r}: argument {arg.name!r} must start with arg_ "
                               "(the names of states and parameters are the model's)")
        allowed = set(psym.values()) | set(form.arguments)
        kernels = tuple(_candidate(model, c, system, allowed, leaves, n_states, f"f{k}c{j}", unrolled)
                        for j, c in enumerate(form.candidates))
        form_index[form.name] = k
        forms.append(ClosedFormIR(form.name, tuple(form.arguments), kernels))
    labels = []
    for st in d.steady_states:
        if st.form not in form_index:
            _refuse(model, f"steady state {st.label!r}: no closed form {st.form!r}")
        k = form_index[st.form]
        if len(st.arguments) != len(forms[k].arguments):
            _refuse(model, f"steady state {st.label!r}: {len(forms[k].arguments)} arguments of {st.form!r}, "
                           f"got {len(st.arguments)}")
        labels.append((st.label, st.note, k, tuple(float(v) for v in st.arguments)))
    if len({lab for lab, *_ in labels}) != len(labels):
        _refuse(model, "steady-state labels must differ")
    unknown = sorted(set(d.steady_state_names) - set(STATE_CONFIGURATIONS))
    if unknown:
        _refuse(model, f"state names for {unknown}: configurations are {', '.join(STATE_CONFIGURATIONS)}")
    for key, name in d.steady_state_names.items():
        try:
            name.format(n=2, m=1, k=1)
        except (KeyError, IndexError, ValueError):
            _refuse(model, f"state name {name!r} ({key}): a template in {{n}}, {{m}}, {{k}} only")
    equilibria, gradient = _equilibria(model, d, system) if d.equilibria is not None else (None, None)
    return SelfDescription(
        family=spec.family, kind=spec.kind, time_unit=d.time_unit, state_units=units, roles=roles,
        angles=tuple(d.angles), amplitude=tuple(d.amplitude), measure_names=tuple(names), measures=every,
        measure_kernels=alone, forcing_frequency=d.forcing_frequency, symmetries=tuple(syms),
        parameter_sets=tuple(sets), scales=tuple((k, d.scales[k]) for k in ("eccentricity", "speed") if k in d.scales),
        closed_forms=tuple(forms), steady_states=tuple(labels),
        steady_state_names=tuple((k, d.steady_state_names[k]) for k in STATE_CONFIGURATIONS if k in d.steady_state_names),
        equilibria=equilibria, equilibria_gradient=gradient, residual=d.residual, declared=d, measure_exprs=tuple(exprs))


def _equilibria(model: str, d: Description, system: FirstOrderSystem) -> tuple[tuple, Kernel]:
    """The manifold's data (name, the states vanishing on it: its `zero` coordinates and every rate,
    the number of constraints) and the kernel out[k, j] = d constraint_k / d state_j (thesis (3.6)'s
    gradients for the balanced states)."""
    e = d.equilibria
    coords = {c.name: c for c in system.coordinates}
    unknown = sorted(set(e.zero) - set(coords))
    if unknown or not e.constraints:
        _refuse(model, f"equilibria {e.name!r}: " + (f"{unknown} are not coordinates" if unknown else "no constraints"))
    free = [c.q for c in system.coordinates if c.name not in e.zero]
    allowed = set(free) | {p.symbol for p in system.parameters}
    exprs = []
    for g in e.constraints:
        g = sp.sympify(g)
        if not g.free_symbols <= allowed:
            _refuse(model, f"equilibria {e.name!r}: constraint {g} uses {sorted(map(str, g.free_symbols - allowed))}, "
                           "not the free coordinates and the parameters")
        exprs.append(g)
    states = list(system.states)
    entries = [(k, states.index(q), sp.diff(g, q)) for k, g in enumerate(exprs) for q in free]
    entries = [(k, j, v) for k, j, v in entries if v != 0]
    lets, red = cse_lets([v for _, _, v in entries], "w_e_")
    ops = tuple(lets) + tuple(Put(Pos(k), Pos(j), v) for (k, j, _), v in zip(entries, red))
    zero = tuple(c.name for c in system.coordinates if c.name in e.zero) + tuple(
        c.qd.name for c in system.coordinates)
    return (e.name, zero, len(exprs)), Kernel(ops, (len(exprs), len(states)), True)
