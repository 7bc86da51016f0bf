"""The ball split: the per-ball block of a balancer model (`ir.balls.BallSplit`), kept once with the
ball symbolic (issue 10).

Every ball of a balancer has the same equations with its own angle and parameters: ball i's column
b_i and row c_i of the mass matrix, its inertia d_i and forcing f_i (`core.structure`), and its share
of the core's mass block and forcing (the rotor's rows sum a term per ball), are one expression of

    ball_q, ball_qd, ball_qdd      (the ball's angle, rate and acceleration)
    ball_<slot>                    (its own parameters: mass, drag, race radius, plane, ...)

and of the core's states and the shared parameters.  `split` takes that generic block from ball 1 of
the symbolic model (its symbols renamed) and *verifies* that it equals every ball's block exactly
(SymPy, after expansion), so a model whose balls are not alike is refused here, not miscompiled.  The
core's rows are split term by term: a term that holds a symbol of exactly one ball (its angle, rate,
acceleration or one of its own parameters) is that ball's, a term of shared symbols only is the
core's (e.g. M + n m of equal balls), a term of two balls' symbols means there is no per-ball
structure.

A ball's own parameter (a *slot*) is c * p[k] for a parameter index k and a number c, per ball: the
generated loops read it through an index table (metadata of size n).  By default the slots are the
parameters named <stem>_<i> for ball i (m_1..m_n, D_1..D_n); a family declares others (two-plane
races: R_t for the balls of race t, and so on) through `ModelSpec.balls`.
"""

from __future__ import annotations

import re
from typing import Sequence

import sympy as sp

from ..ir.balls import BallSplit, Slot

BALL_PREFIX = "ball_"
# the default slots' naming convention, <stem>_<i> (m_1 .. m_n): read from the names because this pass is
# what first knows which parameters are a ball's (its result, `ir.balls.BallSplit`, is what later passes
# ask); a family whose names do not follow it declares its slots (`ModelSpec.balls`)
_INDEXED = re.compile(r"(.+)_(\d+)$")


class NoBallStructure(ValueError):
    """The model's balls are not alike (or not laid out as a loop can index them)."""


def default_slots(parameters: Sequence, n: int) -> list[dict]:
    """Ball i's own parameters by name: <stem>_<i> for every stem that every ball has."""
    stems: dict[str, dict[int, sp.Symbol]] = {}
    for p in parameters:
        m = _INDEXED.match(p.name)
        if m and 1 <= int(m.group(2)) <= n:
            stems.setdefault(m.group(1), {})[int(m.group(2))] = p.symbol
    return [{stem: by[i + 1] for stem, by in sorted(stems.items()) if len(by) == n} for i in range(n)]


def _slot_of(expr: sp.Expr, index: dict) -> tuple[int, float, sp.Symbol]:
    coef, rest = sp.sympify(expr).as_coeff_Mul()
    if rest not in index or not coef.is_number:
        raise NoBallStructure(f"a ball parameter must be a number times a parameter, not {expr}")
    return index[rest], float(coef), rest


def split(coordinates, core: Sequence[int], leaves: Sequence[int], mass: dict, f: Sequence[sp.Expr],
          parameters: Sequence, slots: Sequence[dict] | None = None) -> BallSplit:
    """The generic per-ball block, verified against every ball (NoBallStructure if it does not hold)."""
    leaves = list(leaves)
    n = len(leaves)
    if n == 0 or leaves != list(range(leaves[0], leaves[0] + n)):
        raise NoBallStructure(f"the balls {[coordinates[k].name for k in leaves]} are not consecutive coordinates")
    slots = list(slots) if slots is not None else default_slots(parameters, n)
    if len(slots) != n:
        raise NoBallStructure(f"{len(slots)} sets of ball parameters for {n} balls")
    for i, s in enumerate(slots):
        if set(s) != set(slots[0]):
            raise NoBallStructure(f"ball {i + 1}'s parameter slots {sorted(s)} differ from ball 1's {sorted(slots[0])}")
    pindex = {p.symbol: k for k, p in enumerate(parameters)}
    names = sorted(slots[0])
    generic = {name: sp.Symbol(BALL_PREFIX + name, real=True) for name in names}
    q, qd, qdd = (sp.Symbol(BALL_PREFIX + s, real=True) for s in ("q", "qd", "qdd"))
    table = {name: [_slot_of(slots[i][name], pindex) for i in range(n)] for name in names}
    # symbols that name one ball: its coordinate, and parameters no other ball's slots use
    users: dict[sp.Symbol, set[int]] = {}
    for name in names:
        for i, (_, _, sym) in enumerate(table[name]):
            users.setdefault(sym, set()).add(i)
    owner: dict[sp.Symbol, int] = {sym: next(iter(b)) for sym, b in users.items() if len(b) == 1}
    for i, k in enumerate(leaves):
        c = coordinates[k]
        for sym in (c.q, c.qd, c.qdd):
            owner[sym] = i

    def to_ball(i: int) -> dict:
        c = coordinates[leaves[i]]
        out = {c.q: q, c.qd: qd, c.qdd: qdd}
        for name in names:
            _, coef, sym = table[name][i]
            if sym in out:
                raise NoBallStructure(f"parameter {sym} fills two slots of ball {i + 1}")
            out[sym] = generic[name] / coef
        return out

    def from_ball(i: int) -> dict:
        c = coordinates[leaves[i]]
        out = {q: c.q, qd: c.qd, qdd: c.qdd}
        for name in names:
            _, coef, sym = table[name][i]
            out[generic[name]] = coef * sym
        return out

    r = len(core)
    core_exprs = [[mass.get((a, b), sp.S.Zero) for b in core] for a in core]
    core_f = [f[a] for a in core]

    def parts(expr):
        """(core part, [ball i's part]) of a core-row expression."""
        shares = [[] for _ in range(n)]
        rest = []
        # top level only: expanding inside functions would turn sin(w (t - t0)) into sin(w t - w t0),
        # which rounds worse at large t (measured 3e-12 against 3e-16 on the two-plane ramp)
        for term in sp.Add.make_args(sp.expand(expr, deep=False)):
            balls = {owner[s] for s in term.free_symbols if s in owner}
            if len(balls) > 1:
                raise NoBallStructure(f"a term couples balls {sorted(b + 1 for b in balls)}: {term}")
            (shares[balls.pop()] if balls else rest).append(term)
        return sp.Add(*rest), [sp.Add(*s) for s in shares]

    A0, A = [[None] * r for _ in range(r)], [[None] * r for _ in range(r)]
    A_shares = {}
    for a in range(r):
        for b in range(r):
            A0[a][b], A_shares[(a, b)] = parts(core_exprs[a][b])
    f0, fc, f_shares = [None] * r, [None] * r, {}
    for a in range(r):
        f0[a], f_shares[a] = parts(core_f[a])
    rename = to_ball(0)

    def generic_of(per_ball: list) -> sp.Expr:
        g = sp.sympify(per_ball[0]).xreplace(rename)
        for i in range(1, n):
            if sp.expand(g.xreplace(from_ball(i)) - per_ball[i]) != 0:
                raise NoBallStructure(f"ball {i + 1}'s block differs from ball 1's: {per_ball[i]} vs {per_ball[0]}")
        return g

    for a in range(r):
        for b in range(r):
            A[a][b] = generic_of(A_shares[(a, b)])
        fc[a] = generic_of(f_shares[a])
    B = [generic_of([mass.get((core[a], k), sp.S.Zero) for k in leaves]) for a in range(r)]
    C = [generic_of([mass.get((k, core[a]), sp.S.Zero) for k in leaves]) for a in range(r)]
    D = generic_of([mass[(k, k)] for k in leaves])
    fl = generic_of([f[k] for k in leaves])
    for name, expr in (("A0", A0), ("f0", f0)):
        flat = [e for row in expr for e in row] if name == "A0" else expr
        stray = set().union(*(sp.sympify(e).free_symbols for e in flat)) & set(owner)
        if stray:
            raise NoBallStructure(f"the core part {name} holds ball symbols {sorted(map(str, stray))}")
    slot_objs = tuple(Slot(name, generic[name], tuple(k for k, _, _ in table[name]),
                           tuple(c for _, c, _ in table[name])) for name in names)
    return BallSplit(leaves[0], n, q, qd, qdd, slot_objs, tuple(map(tuple, A0)), tuple(f0), tuple(map(tuple, A)),
                     tuple(fc), tuple(B), tuple(C), D, fl)
