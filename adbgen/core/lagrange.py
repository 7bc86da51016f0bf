"""Lagrange's equations, thesis (2.1), for energies given as a sum of terms.

Coordinates, their rates and accelerations are plain SymPy symbols (not functions of time): the total
time derivative is applied by the chain rule in `time_derivative`, which is much faster than SymPy's
`Derivative` machinery and keeps the expressions free of unevaluated derivatives.

Each `EnergyTerm` (one body: the rotor, or one ball) contributes to the equations of only those
coordinates it depends on.  A ball depends on the rotor coordinates and its own angle, so the work and
the size of the result grow linearly with the number of balls, and the mass matrix is assembled
sparse (its ball-ball block is diagonal by construction, not by simplification).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Iterable, Mapping, Sequence

import sympy as sp

from .identities import reduce_pythagorean


@dataclass(frozen=True)
class Coordinate:
    """A generalised coordinate with its rate and acceleration symbols."""

    name: str
    q: sp.Symbol
    qd: sp.Symbol
    qdd: sp.Symbol

    @classmethod
    def make(cls, name: str) -> "Coordinate":
        return cls(name, sp.Symbol(name, real=True), sp.Symbol(f"{name}_dot", real=True),
                   sp.Symbol(f"{name}_ddot", real=True))


@dataclass(frozen=True)
class Parameter:
    """A model parameter: symbol, meaning, unit (or 'dimensionless') and default value."""

    symbol: sp.Symbol
    description: str
    unit: str
    default: float

    @property
    def name(self) -> str:
        return self.symbol.name


class ParameterTable(list):
    """Collects a model's parameters while its symbols are made: ``M = table.add(symbol, ...)``."""

    def add(self, symbol: sp.Symbol, description: str, unit: str, default: float) -> sp.Symbol:
        self.append(Parameter(symbol, description, unit, float(default)))
        return symbol

    def sorted(self) -> tuple[Parameter, ...]:
        """By name: the order of generated code's parameter vectors."""
        return tuple(sorted(self, key=lambda p: p.name))


@dataclass(frozen=True)
class EnergyTerm:
    """Kinetic energy T, potential V and Rayleigh dissipation F of one body."""

    label: str
    T: sp.Expr = sp.S.Zero
    V: sp.Expr = sp.S.Zero
    F: sp.Expr = sp.S.Zero

    def free_symbols(self) -> set:
        return set().union(*(sp.sympify(e).free_symbols for e in (self.T, self.V, self.F)))


def time_derivative(expr: sp.Expr, coordinates: Iterable[Coordinate], t: sp.Symbol) -> sp.Expr:
    """Total time derivative by the chain rule over the given coordinates (and explicit t)."""
    expr = sp.sympify(expr)
    free = expr.free_symbols
    out = sp.diff(expr, t) if t in free else sp.S.Zero
    for c in coordinates:
        if c.q in free:
            out += sp.diff(expr, c.q) * c.qd
        if c.qd in free:
            out += sp.diff(expr, c.qd) * c.qdd
    return out


@dataclass(frozen=True)
class EquationsOfMotion:
    """M(q, t) q'' = f(q, q', t) for the free coordinates.

    ``mass`` is sparse: {(row, col): entry}, symmetric, zero entries absent.  ``driven`` are
    coordinates whose motion is prescribed (their symbols are inputs, e.g. the spin psi of a rotor
    run at a given speed); ``driven_law`` maps their symbols to expressions in time when known.
    Rows may be scaled (non-dimensionalisation); ``row_scale`` records by what the Lagrange rows of
    the model this one came from were divided.
    """

    coordinates: tuple[Coordinate, ...]
    mass: Mapping[tuple[int, int], sp.Expr]
    forcing: tuple[sp.Expr, ...]
    time: sp.Symbol
    driven: tuple[Coordinate, ...] = ()
    driven_law: Mapping[sp.Symbol, sp.Expr] = field(default_factory=dict)
    parameters: tuple[Parameter, ...] = ()
    reference: str = ""

    @property
    def size(self) -> int:
        return len(self.coordinates)

    def index(self, name: str) -> int:
        for i, c in enumerate(self.coordinates):
            if c.name == name:
                return i
        raise KeyError(name)

    def mass_matrix(self) -> sp.Matrix:
        n = self.size
        return sp.Matrix(n, n, lambda i, j: self.mass.get((i, j), sp.S.Zero))

    def residual(self, k: int) -> sp.Expr:
        """Row k of M q'' - f (zero along solutions)."""
        out = -self.forcing[k]
        for j, c in enumerate(self.coordinates):
            entry = self.mass.get((k, j))
            if entry is not None:
                out += entry * c.qdd
        return out

    def residuals(self) -> list[sp.Expr]:
        return [self.residual(k) for k in range(self.size)]

    def symbols(self) -> set:
        out = set()
        for e in list(self.mass.values()) + list(self.forcing):
            out |= e.free_symbols
        return out

    def parameter_symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(p.symbol for p in self.parameters)

    def count_ops(self) -> int:
        """Expression size: operations in the mass matrix entries and forcing."""
        return int(sum(sp.count_ops(e) for e in list(self.mass.values()) + list(self.forcing)))

    def map(self, fn) -> "EquationsOfMotion":
        """Apply fn to every mass entry and forcing row (zeros dropped)."""
        mass = {}
        for key, value in self.mass.items():
            value = fn(value)
            if value != 0:
                mass[key] = value
        return replace(self, mass=mass, forcing=tuple(fn(f) for f in self.forcing))

    @classmethod
    def from_residuals(cls, residuals: Sequence[sp.Expr], coordinates: Sequence[Coordinate],
                       time: sp.Symbol, **kw) -> "EquationsOfMotion":
        """Split residuals that are linear in the accelerations into M q'' - f."""
        accel = [c.qdd for c in coordinates]
        mass, forcing = {}, []
        accel_set = set(accel)
        for k, r in enumerate(residuals):
            r = sp.expand(r)
            for j, a in enumerate(accel):
                coeff = sp.diff(r, a)
                if coeff.free_symbols & accel_set:
                    raise ValueError(f"row {k} is not linear in the accelerations")
                if coeff != 0:
                    mass[(k, j)] = coeff
            forcing.append(-sp.expand(r.xreplace({a: 0 for a in accel})))
        return cls(tuple(coordinates), mass, tuple(forcing), time, **kw)


def lagrange_equations(
    coordinates: Sequence[Coordinate],
    terms: Sequence[EnergyTerm],
    time: sp.Symbol,
    forces: Mapping[str, sp.Expr] | None = None,
    driven: Sequence[Coordinate] = (),
    **kw,
) -> EquationsOfMotion:
    """Thesis (2.1): d/dt dT/dq'_k - dT/dq_k + dV/dq_k + dF/dq'_k = Q_k, one term at a time.

    ``forces`` are the generalised forces Q_k not derived from V or F (e.g. a driving torque),
    keyed by coordinate name.  ``driven`` coordinates are prescribed: they get no equation, but the
    chain rule of d/dt runs over them (their rates and accelerations stay as input symbols).
    """
    coordinates = tuple(coordinates)
    all_coords = coordinates + tuple(driven)
    n = len(coordinates)
    mass: dict[tuple[int, int], sp.Expr] = {}
    forcing = [sp.S.Zero] * n
    for term in terms:
        # sin^2 + cos^2 of a body's angle cancels here, so mass entries come out as m R^2, not m R^2 (s^2 + c^2)
        T, V, F = (reduce_pythagorean(sp.sympify(e)) for e in (term.T, term.V, term.F))
        free = term.free_symbols()
        for k, ck in enumerate(coordinates):
            if ck.q not in free and ck.qd not in free:
                continue
            p = sp.diff(T, ck.qd)
            rest = sp.diff(p, time) if time in p.free_symbols else sp.S.Zero
            for j, cj in enumerate(all_coords):
                if cj.q in p.free_symbols:
                    rest += sp.diff(p, cj.q) * cj.qd
                if cj.qd in p.free_symbols:
                    d = sp.diff(p, cj.qd)
                    if j < n:
                        mass[(k, j)] = mass.get((k, j), sp.S.Zero) + d
                    else:
                        rest += d * cj.qdd
            forcing[k] += -rest + sp.diff(T, ck.q) - sp.diff(V, ck.q) - sp.diff(F, ck.qd)
    for name, Q in (forces or {}).items():
        k = [c.name for c in coordinates].index(name)
        forcing[k] += Q
    mass = {key: sp.expand(v) for key, v in mass.items()}
    mass = {key: v for key, v in mass.items() if v != 0}
    return EquationsOfMotion(coordinates, mass, tuple(sp.expand(f) for f in forcing), time,
                             driven=tuple(driven), **kw)
