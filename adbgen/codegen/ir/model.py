"""The intermediate form: data only, one per model; everything a template needs and nothing of SymPy's API.

A model's first-order system y' = F(t, y; p) (y = positions, then rates) is lowered (`passes.lowering`) to
straight-line *programs*: ordered assignments ``name = expression`` followed by stores into an output
array.  Every target (`targets/`) prints the same programs, so each equation exists once.  By
default a balancer is lowered to the loop form instead (`ir.loops.LoopForm`, issue 10): each ball's
block kept once, and kernels that loop over the balls; `ModelIR.kernels()` gives either form as
kernels, which `emit` prints for every target.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable

import sympy as sp

from ...core import Parameter
from ...core.symbols import t as TIME  # the t of y' = F(t, y; p): the derivation's one time symbol
from ...core.model_spec import Continuation  # noqa: F401  (the family decides it; the AUTO target prints it)

if TYPE_CHECKING:
    from .description import SelfDescription
    from .loops import LoopForm

KERNELS = ("rhs", "jac", "jac_p", "mass", "forcing")


@dataclass(frozen=True)
class Program:
    """Straight-line code: ``assignments`` in order, then ``out[index] = expr`` for ``outputs``.

    ``shape`` is the output array's shape (row-major flat indices); entries not listed are zero.
    """

    assignments: tuple[tuple[sp.Symbol, sp.Expr], ...]
    outputs: tuple[tuple[int, sp.Expr], ...]
    shape: tuple[int, ...]

    def count_ops(self) -> int:
        """Arithmetic operations of the program (assignments and stored expressions)."""
        exprs = [e for _, e in self.assignments] + [e for _, e in self.outputs]
        return int(sum(sp.count_ops(e) for e in exprs))


@dataclass(frozen=True)
class State:
    name: str
    symbol: sp.Symbol
    description: str


@dataclass(frozen=True)
class ModelIR:
    """Everything the templates render for one model."""

    name: str  # identifier: module name, C prefix, AUTO equation name
    title: str
    reference: str
    n_balls: int
    autonomous: bool
    states: tuple[State, ...]
    parameters: tuple[Parameter, ...]
    core: tuple[str, ...]  # coordinate names of the Schur core (the rotor)
    leaves: tuple[str, ...]  # coordinate names of the diagonal block (the balls)
    mass_pattern: tuple[tuple[int, int], ...]  # nonzero entries of M, sorted
    rhs: Program | None  # the unrolled form's programs (None in the loop form: `ir.loops`)
    jac: Program | None
    jac_p: Program | None
    mass: Program | None
    forcing: Program | None
    start: tuple[float, ...] | None = None  # a steady state (AUTO's stpnt) at start_parameters
    start_label: str = ""
    start_parameters: tuple[float, ...] | None = None  # the defaults unless the start needs others
    forcing_frequency: str = ""  # set on an oscillator extension: the frequency it replaces time by
    autonomous_extension: "ModelIR | None" = None  # of a periodically forced model (for AUTO-07p)
    continuation: Continuation | None = None  # what AUTO-07p continues from the start (None: no AUTO files)
    extras: dict = field(default_factory=dict)
    loops: "LoopForm | None" = None  # the loop form (issue 10): kernels over the balls, size independent of n
    # what the generated module says about itself (`passes.description`; None: the spec declares nothing)
    description: "SelfDescription | None" = None
    # the same model lowered unrolled, made on demand (for targets that print programs one by one)
    unrolled_form: Callable[[], "ModelIR"] | None = field(default=None, compare=False, repr=False)

    def as_unrolled(self) -> "ModelIR":
        """This model with the unrolled programs (rhs, jac, ... set): itself unless in the loop form."""
        if self.loops is None:
            return self
        if self.unrolled_form is None:
            raise ValueError(f"{self.name}: no unrolled form recorded")
        return self.unrolled_form()

    def kernels(self) -> dict:
        """{function: kernel} of what the targets print: the loop form's, or the unrolled programs as
        straight-line kernels."""
        if self.loops is not None:
            return self.loops.kernels()
        from .loops import straight_line

        return {name: straight_line(getattr(self, name), zero=name != "rhs") for name in KERNELS}

    @property
    def time(self) -> sp.Symbol:
        """The independent variable t of y' = F(t, y; p) (`TIME`): what the passes and printers recognise as
        the time by the symbol itself, never by its name."""
        return TIME

    @property
    def form(self) -> str:
        return "loops" if self.loops is not None else "unrolled"

    def count_ops(self, which: str) -> int:
        """Arithmetic operations of one function as printed (a loop body counted once)."""
        return self.kernels()[which].count_ops()

    @property
    def n_states(self) -> int:
        return len(self.states)

    @property
    def n_coordinates(self) -> int:
        return len(self.core) + len(self.leaves)

    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.states)

    @property
    def parameter_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    def fingerprint(self) -> str:
        """sha256 of everything rendered: metadata and every program, in a canonical text form."""
        h = hashlib.sha256()
        for item in (self.name, self.title, self.reference, self.n_balls, self.autonomous,
                     self.state_names, [(p.name, p.description, p.unit, repr(p.default)) for p in self.parameters],
                     self.core, self.leaves, self.mass_pattern, self.start, self.start_label, self.start_parameters,
                     self.forcing_frequency, self.continuation):
            h.update(repr(item).encode())
        if self.loops is not None:
            h.update(self.loops.fingerprint_text().encode())
        for prog in (p for p in (self.rhs, self.jac, self.jac_p, self.mass, self.forcing) if p is not None):
            h.update(repr(prog.shape).encode())
            for lhs, rhs in prog.assignments:
                h.update(f"{lhs}={sp.srepr(rhs)};".encode())
            for idx, rhs in prog.outputs:
                h.update(f"[{idx}]={sp.srepr(rhs)};".encode())
        if self.description is not None:
            h.update(self.description.fingerprint_text().encode())
        if self.autonomous_extension is not None:
            h.update(self.autonomous_extension.fingerprint().encode())
        return h.hexdigest()
