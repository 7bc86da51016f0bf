"""Integration engines, registered in one place (`ENGINES`); `DEFAULT` is the one users get.

`auto` (the default) picks one of the others per tolerance from measured work-precision data.
Every engine runs a generated model from t = 0 to t_end and reports the same things (status, r_max,
t_dec, final state, evaluations, steps, wall time); `symmetric` says whether it keeps identical balls
that start together bit-for-bit together (tested).  To add an engine: a class with `name`,
`description`, `symmetric`, `run(...)` and `run_many(...)` (see compiled.py) and one line below;
`register` adds one at run time (tests, plug-ins).  What an engine declares it can do (`capabilities`)
is what tests/analysis/test_engine_registry.py checks it for.
"""

from __future__ import annotations

from ..loading import AnalysisError
from .by_tolerance import AutoEngine
from .compiled import CyRKEngine, SundialsEngine
from .hybrid_engine import ENGINE as HYBRID
from .hybrid_engine import has_stick_phase
from .matlab_ode45 import ENGINE as MATLAB_ODE45
from .rk import RKBatchEngine, RKEngine
from .scipy_ivp import ScipyEngine
from .taylor import TaylorBatchEngine, TaylorEngine

DEFAULT = "auto"

ENGINES = {e.name: e for e in (
    TaylorEngine(),
    TaylorBatchEngine(),
    TaylorBatchEngine("taylor-batch-inf", norm="max", description=(
        "Taylor's method on SIMD lanes with heyoka's rule (the step in the state's inf norm, order from the "
        "tolerance, factor 1: heyoka's steps); ensembles of labels (sweeps, basin maps)")),
    CyRKEngine("DOP853"), CyRKEngine("Vern8"), CyRKEngine("Vern7"), CyRKEngine("RK45"), CyRKEngine("RK23"),
    RKEngine(), RKBatchEngine(),
    SundialsEngine("cvode-bdf", 10, "SUNDIALS CVODE BDF, Newton, dense LU with the generated Jacobian (stiff)",
                   symmetric=False),
    SundialsEngine("cvode-adams", 11, "SUNDIALS CVODE Adams-Moulton, fixed-point iteration", symmetric=True),
    SundialsEngine("arkode-erk8", 0, "SUNDIALS ARKODE ERKStep, Fehlberg 13-stage 7(8)", symmetric=True),
    SundialsEngine("arkode-dp5", 1, "SUNDIALS ARKODE ERKStep, Dormand-Prince 4(5)", symmetric=True),
    SundialsEngine("arkode-erk6", 2, "SUNDIALS ARKODE ERKStep, Verner 5(6)", symmetric=True),
    ScipyEngine("dop853"), ScipyEngine("rk45"), ScipyEngine("radau"), ScipyEngine("lsoda"), ScipyEngine("bdf"),
    ScipyEngine("radau", use_jac=False), ScipyEngine("lsoda", use_jac=False),
    MATLAB_ODE45,
    HYBRID,
)}
ENGINES["auto"] = AutoEngine(ENGINES)  # picks one of the above per tolerance (auto_table.json)


def engine(name: str | None):
    """The engine called `name` (None: the default); an engine object (e.g. `symmetrized.symmetrized(...)`)
    as it is."""
    if name is not None and not isinstance(name, str):
        return name
    key = DEFAULT if name in (None, "", "default") else name
    try:
        return ENGINES[key]
    except KeyError:
        raise AnalysisError(f"unknown engine {name!r}; engines: {', '.join(ENGINES)}") from None


def engine_for(model, name: str | None):
    """The engine that runs `model`: as `engine(name)`, except that a model with stick/slip modes (its
    self-description: parameters stuck_k) gets the stick-slip engine by default and refuses any other."""
    if not has_stick_phase(model):
        return engine(name)
    if name is None or (isinstance(name, str) and name in ("", "default", "auto")):
        return HYBRID
    eng = engine(name)
    if not getattr(eng, "stick_slip", False):
        raise AnalysisError(f"{model.name} has stick/slip modes (static friction): engine {eng.name!r} cannot run "
                            f"them; use {HYBRID.name} (its default)")
    return eng


def register(eng, replace: bool = False) -> None:
    """Add an engine object at run time (e.g. from a test or a plug-in), under its `name`."""
    if eng.name in ENGINES and not replace:
        raise ValueError(f"an engine named {eng.name!r} is registered already")
    ENGINES[eng.name] = eng


def unregister(name: str) -> None:
    ENGINES.pop(name, None)


def capabilities(eng) -> frozenset[str]:
    """What an engine declares: "symmetric" (identical balls started together stay together bit for bit),
    "dense" (the state between its steps, `dense(...)`), "batch" (`run_many`: trajectories at once),
    "native-events" (r_max and t_dec located by the solver itself, not on kept steps), "stick-slip" (runs a
    model's stick/slip modes as an event-driven hybrid system)."""
    out = set()
    if getattr(eng, "symmetric", False):
        out.add("symmetric")
    if callable(getattr(eng, "dense", None)):
        out.add("dense")
    if callable(getattr(eng, "run_many", None)):
        out.add("batch")
    if getattr(eng, "native_events", False):
        out.add("native-events")
    if getattr(eng, "stick_slip", False):
        out.add("stick-slip")
    return frozenset(out)
