"""Lower a model as its family declares it (`core.model_spec.ModelSpec`) to the intermediate form.

The spec is data the family fills in (`core.model_spec`); building its intermediate form is code
generation's business: the start point and AUTO-07p's continuation resolved, the oscillator extension
of a periodically forced model lowered beside it, and the self-description (`core.description`)
turned into data and programs (`passes.description`).  `regenerate` reads the result.
"""

from __future__ import annotations

from ..core.first_order import FirstOrderSystem
from ..core.model_spec import Check, Continuation, ModelSpec, no_start, start_values
from .ir.model import ModelIR
from .passes.description import lower_description
from .passes.lowering import DEFAULT_FORM, build as lower

__all__ = ["Check", "Continuation", "ModelSpec", "build", "no_start", "start_values"]


def build(spec: ModelSpec, system: FirstOrderSystem | None = None, form: str = DEFAULT_FORM) -> ModelIR:
    """The intermediate form of `spec` (its system derived unless given) in the lowering's `form`."""
    system = system if system is not None else spec.system()
    slots = spec.balls(system) if spec.balls is not None else None
    extension = None
    orbit = start_values(system, spec.orbit_start(system)) if spec.orbit_start is not None else (None,)
    if orbit[0] is not None:  # (no exact orbit known, e.g. one ball: no extension)
        start, label, values = orbit
        extension = lower(spec.name, system, title=spec.title + ", autonomous extension (oscillator)",
                          n_balls=spec.n, start=start, start_label=label, start_parameters=values,
                          oscillator=True, continuation=spec.orbit_continuation, balls=slots, form=form)
    start, label, values = start_values(system, spec.start(system))
    continuation = spec.continuation
    if callable(continuation):
        continuation = continuation(system, (start, label, values))
    description = lower_description(spec, system, form) if spec.describe is not None else None
    return lower(spec.name, system, title=spec.title, n_balls=spec.n, start=start, start_label=label,
                 start_parameters=values, autonomous_extension=extension,
                 continuation=continuation if start is not None else None, balls=slots, form=form,
                 description=description)
