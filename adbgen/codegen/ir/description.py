"""A model's self-description as the templates print it (`SelfDescription`; its closed forms,
`ClosedFormIR`): data by state and parameter index, and kernels (`ir.loops.Kernel`); made by
`passes.description` from the family's declaration (`core.description.Description`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from .loops import Balls, Kernel


@dataclass(frozen=True)
class ClosedFormIR:
    """One closed form: its argument names and one kernel per candidate (tried in order)."""

    name: str
    arguments: tuple[sp.Symbol, ...]
    candidates: tuple[Kernel, ...]


@dataclass(frozen=True)
class SelfDescription:
    """Everything the templates print of a model's self-description (see the module docstring)."""

    family: str
    kind: str
    time_unit: str
    state_units: tuple[str, ...]
    roles: tuple[str, ...]
    angles: tuple[str, ...]
    amplitude: tuple[str, str]
    measure_names: tuple[str, ...]
    measures: Kernel  # every measure: out[k] for MEASURES[k]
    measure_kernels: tuple[Kernel, ...]  # each measure alone: out[0]
    forcing_frequency: str
    symmetries: tuple[dict, ...]
    parameter_sets: tuple[tuple[str, tuple[tuple[str, float], ...]], ...]
    scales: tuple[tuple[str, str], ...]
    closed_forms: tuple[ClosedFormIR, ...]
    # (label, note, closed form index, its arguments)
    steady_states: tuple[tuple[str, str, int, tuple[float, ...]], ...]
    # (configuration, name) of the steady states' names (`core.description.STATE_CONFIGURATIONS`)
    steady_state_names: tuple[tuple[str, str], ...]
    # the manifold of equilibria: (name, the states that vanish on it, the number of constraints), and
    # the constraints' gradients with respect to the states (out[k, j]); None where none is declared
    equilibria: tuple[str, tuple[str, ...], int] | None
    equilibria_gradient: Kernel | None
    # the measure (one of measure_names) that is the model's residual imbalance (`Description.residual`)
    residual: str
    # the declaration and the measures' expressions, for the checks (not rendered)
    declared: Description = field(compare=False, repr=False)
    measure_exprs: tuple[sp.Expr, ...] = field(compare=False, repr=False, default=())

    @property
    def labels(self) -> tuple[str, ...]:
        return tuple(label for label, _, _, _ in self.steady_states)

    @property
    def max_arguments(self) -> int:
        return max((len(f.arguments) for f in self.closed_forms), default=0)

    def fingerprint_text(self) -> str:
        parts = [repr((self.family, self.kind, self.time_unit, self.state_units, self.roles, self.angles,
                       self.amplitude, self.measure_names, self.forcing_frequency, self.symmetries,
                       self.parameter_sets, self.scales, self.steady_states))
                 + (repr(self.steady_state_names) if self.steady_state_names else "")]
        kernels = [self.measures, *self.measure_kernels] + [k for f in self.closed_forms for k in f.candidates]
        for f in self.closed_forms:
            parts.append(repr((f.name, [a.name for a in f.arguments], len(f.candidates))))
        if self.residual != "r":  # (the default r: the fingerprints of the models it is stay as they were)
            parts.append(repr(("residual", self.residual)))
        if self.equilibria is not None:  # (absent: the fingerprints of models without one stay as they were)
            parts.append(repr(self.equilibria))
            kernels.append(self.equilibria_gradient)
        for k in kernels:
            parts.append(repr((k.shape, k.zero)))
            parts += [type(op).__name__ + ":" + ";".join(sp.srepr(v) if isinstance(v, sp.Basic) else repr(v)
                                                         for v in vars(op).values()) for op in _walk(k.ops)]
        return "\n".join(parts)


def _walk(ops):
    for op in ops:
        if isinstance(op, Balls):
            yield op
            yield from _walk(op.ops)
        else:
            yield op
