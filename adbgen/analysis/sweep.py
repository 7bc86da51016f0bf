"""Sweeps over parameters and initial states: many trajectories (or steady states) on a grid, on Dask.

    spec = SweepSpec(model="NAME", grid=["phi_1=0:2*pi:32", "phi_2=0:2*pi:32"],
                     measure="attractor", t_end=2000)
    run_sweep(spec, "out/basins")        -> {"points", "computed", "reused", "wall_s", "store"}

Work is cut into blocks of the grid (the store's chunks).  A block is one Dask task that runs all its
trajectories together on the compiled ensemble path (`simulate_many`, one call, no Python per
trajectory or per segment);
the client writes each block's results into the Zarr store as it arrives, data first and its `done`
flags last, so a killed run (SIGKILL included) loses only the blocks in flight and the next run with
the same settings computes only the blocks not done.  Zarr's local store writes every chunk file
atomically (temporary file and rename), and the store itself is created in a temporary folder and
renamed into place, so no state of the folder is half written.

Outcomes are decided (`attractors.Classifier.decide`): a run not named at t_end is carried on to the cap
(`attractors.CARRY_FACTOR` t_end) and decided by r's rate of approach, or left `undecided` with its reason;
the store keeps the approach and the reason per point, and the summary counts undecided runs apart, never
as not balanced (`outcome_counts`).

Shortcuts (each switchable; tests show they give the labels of the full integration):

* early stop (measure `attractor`): every `check_dt` the trajectories inside the provable basin region
  of a stable steady state (`attractors.stop_region`: by default `basin_regions`, a cubic Lyapunov
  function with the nonlinear decrease condition) stop there with its label, checked inside the
  compiled driver.  The reference run without the shortcut integrates in the same segments, so both
  see bit-identical trajectories until the stop.
* exchange symmetry: if two grid axes are the angles of two balls the model treats identically (checked
  numerically: rhs(s y) = s rhs(y) for the swap s) over the same values, and their other states are
  equal, a point and its ball-swapped image share an answer (the final state swapped).  A block and
  its mirror image are one task; only one point of each pair is integrated, except for `attractor`
  labels that are not certain (no basin region reached), whose mirror is integrated too.

Tolerance check (`check_tolerance`, `adbgen sweep --check-tolerance`; measures attractor, r_max, t_dec):
every point is computed again at rtol/100, atol/100 and on a second engine of another method
(`tolerance.second_engine`), with the same shortcuts; a point whose label (or value, beyond 1 %) differs
is `tolerance_sensitive` (a variable of the store, both other outcomes beside it as
`<measure>_tighter` and `<measure>_second_engine`, the count in the summary, a mark on the figures).
"""

from __future__ import annotations

import json
import math
import os
import shutil
import sys
import time
from dataclasses import asdict, dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

from .. import __version__
from .engines import DEFAULT as DEFAULT_ENGINE
from .grid import Grid, axis_symbol, make_grid
from .loading import AnalysisError, Model, load_model, parse_assignments
from .residual import residual_measure

MEASURES = ("attractor", "r_max", "t_dec", "stability", "residual")
STORE = "sweep.zarr"
SETTINGS_ATTR = "adbgen_sweep"


@dataclass
class SweepSpec:
    """Everything that defines a sweep's results (stored in the store's attributes and compared on resume)."""

    model: str  # a generated model's name or a model folder (absolute)
    grid: list[str]
    measure: str
    set: list[str] = field(default_factory=list)
    y0: list[str] = field(default_factory=list)
    tie: list[str] = field(default_factory=list)  # initial states that follow a grid axis (phi_3=phi_1+pi)
    t_end: float = 1000.0
    rtol: float = 1e-8
    atol: float = 1e-10
    threshold: float = 1e-3
    engine: str = DEFAULT_ENGINE  # the command line's default too
    early_stop: bool = True
    symmetry: bool = True
    check_dt: float = 10.0
    stop_region: str = "lyapunov"  # attractors.REGION_METHODS
    chunk: int | None = None  # points per block (about); None: enough blocks to keep every worker busy
    check_tolerance: bool = False  # every point again at rtol/100 and on a second engine (`tolerance`)
    refine: bool = True  # stability maps: certify the stable windows between grid points (stability_map)
    # --measure residual: which of the model's measures (its MEASURES) at t_end is the residual; None: the one
    # the model names (its RESIDUAL_MEASURE, `residual_name`; "r", the AMPLITUDE states' hypot, for other measures)
    residual_measure: str | None = None

    def to_dict(self) -> dict:
        return asdict(self)


def residual_name(spec: SweepSpec, model: Model) -> str:
    """The measure the sweep reads at t_end as its residual: for `--measure residual` the model's residual
    imbalance as residual.residual_measure resolves it (an explicit --residual-measure wins, else
    Model.residual_measure; an unknown name refused in one line), "r" for other measures."""
    return residual_measure(model, spec.residual_measure) if spec.measure == "residual" else "r"


# --------------------------------------------------------------------------------------------- setup

@lru_cache(maxsize=16)
def _model(spec: str) -> Model:
    return load_model(spec)


def prepare(spec: SweepSpec) -> tuple[Model, Grid]:
    """The model and grid of a spec; every bad input raises AnalysisError with one line."""
    if spec.measure not in MEASURES:
        raise AnalysisError(f"unknown measure {spec.measure!r}; measures: {', '.join(MEASURES)}")
    for name in ("t_end", "rtol", "atol", "threshold", "check_dt"):
        value = getattr(spec, name)
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise AnalysisError(f"{name} must be a finite number > 0, got {value!r}")
    from .attractors import REGION_METHODS

    if spec.stop_region not in REGION_METHODS:
        raise AnalysisError(f"unknown stop region {spec.stop_region!r}; choose: {', '.join(REGION_METHODS)}")
    if spec.chunk is not None and not (isinstance(spec.chunk, int) and spec.chunk >= 1):
        raise AnalysisError(f"chunk must be a whole number >= 1, got {spec.chunk!r}")
    model = _model(spec.model)
    grid = make_grid(model, spec.grid, parse_assignments(spec.set, "--set"), parse_assignments(spec.y0, "--y0"),
                     spec.tie)
    if spec.measure == "stability":
        states = [a.name for a in grid.axes if a.kind == "state"]
        if states:
            raise AnalysisError(f"--measure stability needs parameter axes (a steady state has no initial "
                                f"state); {', '.join(states)} is a state")
        if not model.autonomous:
            raise AnalysisError(f"{model.name} is not autonomous: it has no steady states (use r_max or t_dec)")
    elif spec.measure == "attractor" and not model.autonomous:
        raise AnalysisError(f"{model.name} is not autonomous: --measure attractor classifies steady states "
                            f"and limit cycles of autonomous models (use r_max or t_dec)")
    from .engines import engine_for, has_stick_phase

    if spec.measure == "residual" and not has_stick_phase(model):
        raise AnalysisError(f"{model.name} has no stick/slip modes: --measure residual is the imbalance left when "
                            f"the balls stick (a scene with static_friction)")
    if spec.measure == "residual":
        residual_name(spec, model)  # an unknown --residual-measure: refused here, before any computing
    if spec.measure != "residual" and spec.residual_measure not in (None, "r"):
        raise AnalysisError("--residual-measure is for --measure residual only")
    if spec.measure == "residual" and spec.check_tolerance:
        raise AnalysisError("--check-tolerance has no second engine for stick/slip modes: not with --measure residual")
    engine_for(model, spec.engine)  # an unknown engine, or one that cannot run the model's stick phase: refused
    return model, grid


# -------------------------------------------------------------------------------------- symmetry

@dataclass(frozen=True)
class Swap:
    """Exchange of two identical balls that swaps grid axes a and b; `perm` acts on state vectors."""

    a: int
    b: int
    perm: tuple[int, ...]


def _ball_states(model: Model, angle: str) -> list[int]:
    """A ball's angle and its rate."""
    k = model.index(angle)
    return [k, model.rate_index(k)]


def find_swap(model: Model, grid: Grid) -> Swap | None:
    """The ball exchange that maps the grid onto itself, if any (see the module docstring).

    Two angle axes over the same values swap their balls; balls `--tie`d to them with equal offsets swap
    with them (phi_3 = phi_1 + pi and phi_4 = phi_2 + pi: the exchange (1 2)(3 4)).  Every swapped ball's
    other states must be fixed and equal to its partner's."""
    leaves = {model.state_names[k] for k in model.role_indices("ball_angle")}
    axes = grid.axes
    grid_states = {x.name for x in axes if x.kind == "state"} | {t.state for t in grid.ties}
    for a in range(len(axes)):
        for b in range(a + 1, len(axes)):
            A, B = axes[a], axes[b]
            if not (A.name in leaves and B.name in leaves and (A.start, A.stop, A.count) == (B.start, B.stop, B.count)):
                continue
            pairs = [(A.name, B.name)]
            tied_a = sorted((t.sign, t.offset, t.state) for t in grid.ties if t.axis == A.name)
            tied_b = sorted((t.sign, t.offset, t.state) for t in grid.ties if t.axis == B.name)
            if [o[:2] for o in tied_a] != [o[:2] for o in tied_b]:
                continue
            pairs += [(ka, kb) for (*_, ka), (*_, kb) in zip(tied_a, tied_b)]
            if any(t.axis not in (A.name, B.name) and t.state in {x for pr in pairs for x in pr} for t in grid.ties):
                continue
            perm = list(range(model.n_states))
            ok = True
            for i_name, j_name in pairs:
                if i_name not in leaves or j_name not in leaves:
                    ok = False
                    break
                si, sj = _ball_states(model, i_name), _ball_states(model, j_name)
                rates_i, rates_j = si[1:], sj[1:]
                names = [model.state_names[k] for k in rates_i + rates_j]
                if (len(si) != len(sj) or any(n in grid_states for n in names)
                        or not np.array_equal(grid.base_state[rates_i], grid.base_state[rates_j])):
                    ok = False
                    break
                for i, j in zip(si, sj):
                    perm[i], perm[j] = j, i
            if ok and _equivariant(model, grid, perm):
                return Swap(a, b, tuple(perm))
    return None


def _equivariant(model: Model, grid: Grid, perm: list[int]) -> bool:
    """s exchanges identical balls (`attractors.equivariant`) at the base parameters and at each parameter
    axis' ends."""
    from .attractors import equivariant

    params = [grid.base_params]
    for axis in grid.axes:
        if axis.kind == "parameter":
            for v in (axis.start, axis.stop):
                p = grid.base_params.copy()
                p[model.param_names.index(axis.name)] = v
                params.append(p)
    return all(equivariant(model, p, perm) for p in params)


# ---------------------------------------------------------------------------------------- blocks

def chunk_shape(shape: tuple[int, ...], target: int, swap: Swap | None = None) -> tuple[int, ...]:
    """Block sides: grown round-robin (doubling, last axis first) while the block holds <= target points;
    the two swapped axes grow together, so a block's mirror image is a block."""
    sides = [1] * len(shape)
    order = list(range(len(shape)))[::-1]
    grown = True
    while grown:
        grown = False
        for d in order:
            group = [d]
            if swap is not None and d in (swap.a, swap.b):
                if d == swap.a:
                    continue  # grown with swap.b
                group = [swap.a, swap.b]
            new = list(sides)
            for g in group:
                new[g] = min(shape[g], sides[g] * 2)
            if new != sides and math.prod(new) <= max(target, 1):
                sides = new
                grown = True
    return tuple(sides)


def auto_chunk(size: int, workers: int) -> int:
    """Points per block: about 8 tasks per worker (load balance, fine-grained resume), 16 to 256 points
    (each task a batch on the compiled path; Dask's overhead per task is a few milliseconds)."""
    return int(min(256, max(16, size // (8 * max(workers, 1)))))


def blocks(shape, chunks):
    """Block coordinates in C order."""
    counts = [math.ceil(n / c) for n, c in zip(shape, chunks)]
    return [tuple(int(i) for i in idx) for idx in np.ndindex(*counts)]


def block_slices(block, chunks, shape) -> tuple[slice, ...]:
    return tuple(slice(b * c, min((b + 1) * c, n)) for b, c, n in zip(block, chunks, shape))


def block_flat(block, chunks, shape) -> np.ndarray:
    """C-order flat indices of a block's points (in the block's own C order)."""
    ranges = [np.arange(s.start, s.stop) for s in block_slices(block, chunks, shape)]
    mesh = np.meshgrid(*ranges, indexing="ij")
    return np.ravel_multi_index([m.ravel() for m in mesh], shape)


def mirror_block(block, swap: Swap | None):
    if swap is None:
        return block
    b = list(block)
    b[swap.a], b[swap.b] = b[swap.b], b[swap.a]
    return tuple(b)


def mirror_flat(flat: np.ndarray, shape, swap: Swap) -> np.ndarray:
    idx = list(np.unravel_index(flat, shape))
    idx[swap.a], idx[swap.b] = idx[swap.b], idx[swap.a]
    return np.ravel_multi_index(idx, shape)


def tasks_for(shape, chunks, swap: Swap | None) -> list[tuple[tuple[int, ...], ...]]:
    """Each task: one block, or a block and its mirror image (computed together)."""
    out, seen = [], set()
    for b in blocks(shape, chunks):
        if b in seen:
            continue
        m = mirror_block(b, swap)
        seen.update({b, m})
        out.append((b,) if m == b else (b, m))
    return out


# ---------------------------------------------------------------------------------------- compute

def compute_points(spec: SweepSpec, flat: np.ndarray, threads: int = 1) -> dict:
    """Results at the grid points `flat` (C-order indices): {"value", "y_end", "t_last", ...}.

    With the symmetry shortcut only one point of each ball-swapped pair is computed; its partner gets
    the same value and the swapped final state.  For `attractor` only where the label is certain: the
    trajectory stopped in (or ended inside) a provable basin region.  Elsewhere (limit cycles,
    undecided runs, states reached without a region) the partner is integrated too: the integration is
    equivariant only up to rounding (the step-size control sums its error norm in state order, the
    rhs its ball terms in ball order), and near a basin boundary rounding can decide the label, so the
    full integration's own map need not be symmetric there (benchmarks/sweep.json)."""
    model, grid = prepare(spec)
    flat = np.asarray(flat, dtype=np.int64)
    swap = find_swap(model, grid) if spec.symmetry and spec.measure != "stability" else None
    if swap is not None:
        partner = mirror_flat(flat, grid.shape, swap)
        canonical = np.minimum(flat, partner)
    else:
        canonical = flat
    unique, inverse = np.unique(canonical, return_inverse=True)
    out = _compute(spec, model, grid, unique, threads)
    integrated, n_rhs, cpu = out.pop("integrated"), out.pop("n_rhs"), out.pop("cpu_s", {})
    res = {k: v[inverse] for k, v in out.items()}
    if swap is not None:
        mirrored = flat != canonical
        res["y_end"][mirrored] = res["y_end"][mirrored][:, list(swap.perm)]
        if spec.measure == "residual" and residual_name(spec, model) != "r" and mirrored.any():
            # a measure of the model need not be invariant under the ball exchange (r is): read it again at the
            # partner's own end state, the swapped one
            from .residual import residual_at_end

            P, _ = grid.points(model, flat[mirrored])
            rows = res["value"][mirrored]
            res["value"][mirrored] = residual_at_end(model, residual_name(spec, model), rows, res["t_last"][mirrored],
                                                     res["y_end"][mirrored], P, ~np.isfinite(rows))
        if "certain" in res:
            again = mirrored & ~res["certain"].astype(bool)
            if again.any():
                more = _compute(spec, model, grid, flat[again], threads)
                integrated += more.pop("integrated")
                n_rhs += more.pop("n_rhs")
                for k, v in more.pop("cpu_s", {}).items():
                    cpu[k] = cpu.get(k, 0.0) + v
                for k, v in more.items():
                    res[k][again] = v
    res.pop("certain", None)
    res["integrated"] = integrated
    res["n_rhs"] = n_rhs
    res["cpu_s"] = cpu
    return res


def _compute(spec: SweepSpec, model: Model, grid: Grid, flat: np.ndarray, threads: int) -> dict:
    out = _compute_once(spec, model, grid, flat, threads)
    if not checks_tolerance(spec):
        return out
    from dataclasses import replace

    from .tolerance import differ, tightened_tolerances

    c0 = time.thread_time()
    rtol, atol = tightened_tolerances(spec.rtol, spec.atol)
    sensitive = np.zeros(len(flat), dtype=bool)
    for key, other in (("tighter", replace(spec, rtol=rtol, atol=atol)),
                       ("second_engine", replace(spec, engine=second_engine_of(spec, model)))):
        more = _compute_once(other, model, grid, flat, threads)
        out[f"{spec.measure}_{key}"] = more["value"]
        out["n_rhs"] += more["n_rhs"]
        sensitive |= differ(out["value"], more["value"])
        if "failed" in out:
            sensitive |= out["failed"] != more["failed"]
    out["tolerance_sensitive"] = sensitive.astype(np.int8)
    cpu = out.setdefault("cpu_s", {})
    cpu["tolerance_check"] = cpu.get("tolerance_check", 0.0) + time.thread_time() - c0
    return out


def checks_tolerance(spec: SweepSpec) -> bool:
    return bool(spec.check_tolerance) and spec.measure != "stability"


def second_engine_of(spec: SweepSpec, model: Model) -> str:
    """The tolerance check's second engine for this sweep (`tolerance.second_engine` of the engine that runs
    its ensembles)."""
    from .engines import ENGINES
    from .tolerance import resolved, second_engine

    labels_only = spec.measure == "attractor"
    name = second_engine(resolved(spec.engine, model, spec.rtol, spec.atol, ensemble=True, measures=not labels_only),
                         model)
    # labels without r_max/t_dec: its SIMD-lanes variant where there is one (as the auto engine's ENSEMBLE)
    batch = f"{name}-batch"
    return batch if labels_only and batch in ENGINES else name


def _compute_once(spec: SweepSpec, model: Model, grid: Grid, flat: np.ndarray, threads: int) -> dict:
    P, Y0 = grid.points(model, flat)
    if spec.measure == "stability":
        return _stability(model, P)
    if spec.measure == "attractor":
        return _attractors(spec, model, P, Y0, threads)
    from .simulate import simulate_many

    ens = simulate_many(model, P, Y0, t_end=spec.t_end, rtol=spec.rtol, atol=spec.atol, engine=spec.engine,
                        threshold=spec.threshold, threads=threads)
    failed = np.array([s not in ("success", "stopped") for s in ens.status])
    extra = {}
    if spec.measure == "residual":  # r at t_end, and whether the balls are at rest there (residual.py)
        from .residual import at_rest_codes, residual_at_end

        value = residual_at_end(model, residual_name(spec, model), ens.r_end, ens.t_last, ens.y_end, P, failed)
        extra["at_rest"] = at_rest_codes(ens.stuck, failed)
    else:
        value = ens.r_max if spec.measure == "r_max" else ens.t_dec
    value = np.where(failed, np.nan, value)
    return {"value": value, "y_end": ens.y_end, "t_last": ens.t_last, "failed": failed.astype(np.uint8),
            "integrated": len(flat), "n_rhs": int(ens.n_rhs.sum()), **extra}


FAILURES = ("computed", "not computed: Newton failed from START and from the closed form",
            "does not exist: the closed form of START's steady state has no solution here (another state found "
            "by Newton from START, if any, is kept)",
            "not computed: Newton failed from START (START is no closed-form steady state to retry from)")


def _stability(model: Model, P: np.ndarray) -> dict:
    """The steady state continued from START (Newton) at each point, its deflated spectrum.  Where Newton from
    START fails, it is retried from the closed form of the steady state START is (the module's STEADY_STATES);
    `failure` says why a point has none (FAILURES: not computed, or does not exist)."""
    from .attractors import labels, name_steady_state, newton, spectrum
    from .identify import default_label

    n = len(P)
    codes = {name: k for k, name in enumerate(labels(model))}
    value = np.full(n, -1, dtype=np.int8)
    kind = np.full(n, -1, dtype=np.int8)
    abscissa = np.full(n, np.nan)
    neutral = np.zeros(n, dtype=np.int8)
    failure = np.zeros(n, dtype=np.int8)
    y_end = np.full((n, model.n_states), np.nan)
    seed = np.array(model.module.START, float)
    label = default_label(model)
    start = codes[name_steady_state(model, seed, np.array(model.module.START_PARAMETERS, float))]
    for k, p in enumerate(P):
        y = newton(model, seed, p)
        named = codes[name_steady_state(model, y, p)] if y is not None else -1
        if named != start:  # failed, or Newton from START reached another state: retry from START's closed form
            guess = model.steady_state(label, p) if label is not None else None
            z = newton(model, guess, p) if guess is not None else None
            if z is not None and codes[name_steady_state(model, z, p)] == start:
                y = z
            elif label is not None and guess is None:
                failure[k] = 2  # START's state does not exist here (Newton may have found another one: kept)
            elif y is None:
                failure[k] = 3 if label is None else 1
        if y is None:
            continue
        s = spectrum(model, y, p)
        value[k], abscissa[k], neutral[k], y_end[k] = s.unstable(), s.abscissa, s.neutral, y
        kind[k] = codes[name_steady_state(model, y, p)]
    return {"value": value, "abscissa": abscissa, "neutral": neutral, "steady_state": kind, "y_end": y_end,
            "failure": failure, "t_last": np.zeros(n), "integrated": 0, "n_rhs": 0}


def _attractors(spec: SweepSpec, model: Model, P: np.ndarray, Y0: np.ndarray, threads: int) -> dict:
    """Labels (codes into attractors.labels(model)) by segmented integration with optional early stop."""
    from .attractors import APPROACHES, classifier

    n = len(P)
    value = np.full(n, -1, dtype=np.int8)
    y_end = np.array(Y0, float)
    t_last = np.zeros(n)
    certain = np.zeros(n, dtype=np.uint8)  # the label comes from a provable basin region
    approach = np.zeros(n, dtype=np.int8)  # attractors.APPROACHES code: how r approached, where that decided
    undecided = np.zeros(n, dtype=np.int8)  # attractors.UNDECIDED_REASONS code (0: decided)
    t_decided = np.zeros(n)  # t_end, or the cap a run not named at t_end was carried on to
    keys, groups = np.unique(P, axis=0, return_inverse=True)
    n_rhs = 0
    cpu = {"regions": 0.0, "integrate": 0.0, "classify": 0.0}  # this thread's CPU time by phase
    for g, p in enumerate(keys):
        rows = np.flatnonzero(groups.ravel() == g)
        c0 = time.thread_time()
        clf = classifier(model, p, spec.stop_region)
        c1 = time.thread_time()
        status, stop, evals = _segmented(spec, model, clf, p, Y0[rows], y_end, t_last, rows, threads)
        c2 = time.thread_time()
        n_rhs += evals
        inside = clf.inside(y_end[rows])
        for k, row in enumerate(rows):
            out = clf.decide(status[k], y_end[row], stop[k], engine=spec.engine, rtol=spec.rtol, atol=spec.atol,
                             t=t_last[row], threshold=spec.threshold)
            value[row] = clf.code(out.label)
            approach[row] = APPROACHES.index(out.approach)
            undecided[row] = out.reason_code
            t_decided[row] = t_last[row] if out.t_decided is None else out.t_decided
            certain[row] = status[k] == "stopped" or (status[k] == "success" and inside[k] >= 0)
        c3 = time.thread_time()
        cpu["regions"] += c1 - c0
        cpu["integrate"] += c2 - c1
        cpu["classify"] += c3 - c2
    return {"value": value, "y_end": y_end, "t_last": t_last, "certain": certain, "approach": approach,
            "undecided": undecided, "t_decided": t_decided, "integrated": n, "n_rhs": n_rhs, "cpu_s": cpu}


def _segmented(spec, model, clf, p, Y0, y_end, t_last, rows, threads):
    """Integrate in segments of check_dt inside the compiled library (one call for all trajectories:
    each segment a fresh solve from the previous end with the last step size); with the early stop, a
    trajectory inside a stop region at a segment's end stops there.  Without it the same segments are
    run, so both see bit-identical trajectories until the stop."""
    from .simulate import simulate_many

    targets = [r.target() for r in clf.regions] if spec.early_stop else []
    ens = simulate_many(model, p[None], Y0, t_end=spec.t_end, rtol=spec.rtol, atol=spec.atol, engine=spec.engine,
                        threshold=spec.threshold, threads=threads, check_dt=spec.check_dt, targets=targets,
                        measures=False)
    y_end[rows] = ens.y_end
    t_last[rows] = ens.t_last
    return ens.status, np.asarray(ens.target), int(ens.n_rhs.sum())


# ----------------------------------------------------------------------------------------- storage

def settings(spec: SweepSpec, model: Model) -> dict:
    s = spec.to_dict()
    s["residual_measure"] = residual_name(spec, model)
    if s["residual_measure"] == "r":
        s.pop("residual_measure")  # as stores written before the option: they resume
    if not s.get("check_tolerance"):
        s.pop("check_tolerance", None)  # as stores written before the option: they resume
    s["model"] = model.name
    s["source_hash"] = model.source_hash
    if spec.measure == "attractor":  # the labels are decided (carried on, `attractors.Classifier.decide`)
        s["outcomes"] = "decided"
    return s


def _variables(spec: SweepSpec, model: Model):
    """(name, dtype, fill, extra dims) of the stored variables."""
    main = {"attractor": ("attractor", "int8", -1), "r_max": ("r_max", "float64", np.nan),
            "t_dec": ("t_dec", "float64", np.nan), "stability": ("stability", "int8", -1),
            "residual": ("residual", "float64", np.nan)}[spec.measure]
    out = [(*main, ()), ("y_end", "float64", np.nan, ("state",)), ("t_last", "float64", np.nan, ())]
    if spec.measure == "stability":
        out += [("abscissa", "float64", np.nan, ()), ("neutral", "int8", -1, ()), ("steady_state", "int8", -1, ()),
                ("failure", "int8", 0, ())]
    if spec.measure in ("r_max", "t_dec", "residual"):
        out += [("failed", "uint8", 0, ())]
    if spec.measure == "residual":
        out += [("at_rest", "int8", -1, ())]
    if checks_tolerance(spec):
        out += [(f"{main[0]}_tighter", *main[1:], ()), (f"{main[0]}_second_engine", *main[1:], ()),
                ("tolerance_sensitive", "int8", -1, ())]
    if spec.measure == "attractor":
        out += [("approach", "int8", -1, ()), ("undecided", "int8", -1, ()), ("t_decided", "float64", np.nan, ())]
    out.append(("done", "uint8", 0, ()))
    return out


def create_store(path: Path, spec: SweepSpec, model: Model, grid: Grid, chunks) -> None:
    """An empty store (metadata and coordinates only) built in a temporary folder, renamed into place."""
    import dask.array as da
    import xarray as xr

    from .attractors import labels

    dims = grid.names
    coords = {a.name: a.values for a in grid.axes}
    coords["state"] = np.array(model.state_names, dtype=object)  # variable-length strings (zarr v3 "string")
    data, encoding = {}, {}
    for name, dtype, fill, extra in _variables(spec, model):
        shape = grid.shape + tuple(model.n_states for _ in extra)
        ch = tuple(chunks) + tuple(model.n_states for _ in extra)
        data[name] = (dims + extra, da.full(shape, fill, dtype=dtype, chunks=ch))
        encoding[name] = {"chunks": ch, "fill_value": fill}
    ds = xr.Dataset(data, coords=coords)
    for a in grid.axes:
        ds[a.name].attrs.update(kind=a.kind, long_name=axis_symbol(a.name, a.kind),
                                angle=a.kind == "state" and model.index(a.name) in model.angle_indices)
    desc = {"attractor": "label code: index into the attribute `labels` (-1: not computed)",
            "r_max": "largest rotor amplitude r = sqrt(x^2 + y^2) over [0, t_end]",
            "t_dec": "last time r >= threshold (NaN: not settled by t_end, or not computed)",
            "stability": "number of unstable eigenvalues of the steady state (deflated; -1: none found)",
            "residual": "residual imbalance: r = sqrt(x^2 + y^2) at t_end (at rest where at_rest = 1)"}
    if spec.measure == "residual" and residual_name(spec, model) != "r":
        desc["residual"] = (f"residual imbalance: the model's measure {residual_name(spec, model)!r} at t_end (at rest "
                            f"where at_rest = 1)")
    ds[spec.measure].attrs["description"] = desc[spec.measure]
    if spec.measure == "residual":
        ds["residual"].attrs["measure"] = residual_name(spec, model)
    if spec.measure in ("attractor", "stability"):
        names = labels(model)
        var = "attractor" if spec.measure == "attractor" else "steady_state"
        ds[var].attrs.update(flag_values=list(range(len(names))), flag_meanings=names)
    ds["y_end"].attrs["description"] = ("final state (attractor: where the trajectory stopped or ended; "
                                        "stability: the steady state)")
    ds["done"].attrs["description"] = "1 where the point's block is written (resumable sweeps)"
    if checks_tolerance(spec):
        from .tolerance import REL_TOL, tightened_tolerances

        rtol, atol = tightened_tolerances(spec.rtol, spec.atol)
        other = second_engine_of(spec, model)
        ds[f"{spec.measure}_tighter"].attrs["description"] = f"{spec.measure} at rtol {rtol:g}, atol {atol:g}"
        ds[f"{spec.measure}_second_engine"].attrs["description"] = f"{spec.measure} on {other}"
        ds["tolerance_sensitive"].attrs["description"] = (
            f"1 where the tighter run (rtol {rtol:g}) or the second engine ({other}) gives another "
            + ("label" if spec.measure == "attractor" else f"value (beyond {100 * REL_TOL:g} % relative)")
            + " (-1: not computed)")
        if spec.measure == "attractor":
            names = labels(model)
            for key in ("tighter", "second_engine"):
                ds[f"attractor_{key}"].attrs.update(flag_values=list(range(len(names))), flag_meanings=names)
        ds.attrs["tolerance_check"] = json.dumps({"rtol": rtol, "atol": atol, "second_engine": other,
                                                 "rel_tol": REL_TOL})
    import dask
    import distributed
    import xarray
    import zarr

    ds.attrs.update({
        "model": model.name, "SOURCE_HASH": model.source_hash, "measure": spec.measure,
        SETTINGS_ATTR: json.dumps(settings(spec, model), sort_keys=True),
        "parameters": json.dumps(dict(zip(model.param_names, map(float, grid.base_params)))),
        "initial_state": json.dumps(dict(zip(model.state_names, map(float, grid.base_state)))),
        "ties": json.dumps([[t.state, t.axis if t.sign > 0 else "-" + t.axis, t.offset] for t in grid.ties]),
        "versions": json.dumps({"adbgen": __version__, "numpy": np.__version__, "xarray": xarray.__version__,
                                "zarr": zarr.__version__, "dask": dask.__version__,
                                "distributed": distributed.__version__, "python": sys.version.split()[0]}),
        "reference": str(getattr(model.module, "REFERENCE", "")),
    })
    if spec.measure in ("attractor", "stability"):
        ds.attrs["labels"] = json.dumps(labels(model))
    if spec.measure == "attractor":
        from .attractors import APPROACHES, CARRY_FACTOR, UNDECIDED_REASONS, balanced_labels

        ds.attrs["balanced_labels"] = json.dumps(list(balanced_labels(model)))
        ds["approach"].attrs.update(description="how r approached the state where that decided the label "
                                                "(attractors.Classifier.decide): index into `approaches`",
                                    flag_values=list(range(len(APPROACHES))), flag_meanings=list(APPROACHES))
        ds["undecided"].attrs.update(description="why the label is undecided (0: decided): index into "
                                                 "`undecided_reasons`", flag_values=list(range(len(UNDECIDED_REASONS))),
                                     flag_meanings=list(UNDECIDED_REASONS))
        ds["t_decided"].attrs["description"] = ("the time the label was decided at: t_end, the early stop, or the "
                                                "cap a run not named at t_end was carried on to")
        ds.attrs["approaches"] = json.dumps(list(APPROACHES))
        ds.attrs["undecided_reasons"] = json.dumps(list(UNDECIDED_REASONS))
        ds.attrs["carry_on"] = (f"a run not named at t_end is carried on to {CARRY_FACTOR:g} t_end (the cap) and "
                                "decided by the rate of approach of r (adbgen.analysis.approach)")
    if spec.measure == "residual":
        ds["at_rest"].attrs["description"] = ("1: every ball stuck at t_end (the residual is at rest), 0: some ball "
                                              "still slipping (undecided), -1: failed or not computed")
    if spec.measure == "stability":
        ds["failure"].attrs.update(description="why a point has no steady state (0: it has one)",
                                   flag_values=list(range(len(FAILURES))), flag_meanings=list(FAILURES))
        ds["steady_state"].attrs["description"] = ("which steady state Newton reached from START: index "
                                                   "into the attribute `labels`")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise AnalysisError(f"--out {path.parent}: {exc.strerror}") from None
    tmp = path.parent / f".{path.name}.tmp-{os.getpid()}"
    if tmp.exists():
        shutil.rmtree(tmp)
    ds.to_zarr(tmp, mode="w", encoding=encoding, compute=False, zarr_format=3, consolidated=False)
    os.replace(tmp, path)


def open_store(path: Path, spec: SweepSpec, model: Model):
    """The existing store's zarr group if it holds this sweep; a clear error if it holds another."""
    import zarr

    try:
        group = zarr.open_group(str(path), mode="r+")
        stored = group.attrs.get(SETTINGS_ATTR)
    except Exception:  # not a zarr group at all
        stored = None
        group = None
    if stored is None:
        raise AnalysisError(f"{path} exists and is not an adbgen sweep store; choose another --out or remove it")
    ours = settings(spec, model)
    theirs = json.loads(stored)
    diff = [k for k in sorted(set(ours) | set(theirs)) if k not in ("chunk", "refine") and ours.get(k) != theirs.get(k)]
    if diff:
        k = diff[0]
        raise AnalysisError(f"{path} holds a sweep with other settings ({k}: stored {theirs.get(k)!r}, "
                            f"asked {ours.get(k)!r}); use another --out or remove it")
    return group


def write_block(group, spec: SweepSpec, model: Model, grid: Grid, block, chunks, res: dict, rows) -> None:
    """One block's results: the data arrays first, the `done` flags last."""
    sl = block_slices(block, chunks, grid.shape)
    shape = tuple(s.stop - s.start for s in sl)
    for name, _, _, extra in _variables(spec, model):
        if name == "done":
            continue
        key = "value" if name == spec.measure else name
        values = res[key][rows]
        group[name][sl + tuple(slice(None) for _ in extra)] = values.reshape(shape + values.shape[1:])
    group["done"][sl] = np.ones(shape, dtype=np.uint8)


# ------------------------------------------------------------------------------------------ driver

def _task(spec_dict: dict, flat: np.ndarray) -> dict:
    """A Dask task: one block (or a block and its mirror) on one core."""
    _single_threaded()
    return compute_points(SweepSpec(**spec_dict), flat, threads=1)


def _single_threaded() -> None:
    """One core per task: Dask runs one task per worker thread; OpenMP and numba must not add threads."""
    os.environ["OMP_NUM_THREADS"] = "1"
    try:
        import numba

        numba.set_num_threads(1)
    except Exception:  # numba's threading layer may be unavailable; nothing then to limit
        pass


def default_workers() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def run_sweep(spec: SweepSpec, out, *, scheduler: str | None = None, workers: int | None = None,
              progress: bool = True, figures: bool = True) -> dict:
    """Run (or resume) a sweep into out/sweep.zarr; returns the --json summary."""
    start = time.perf_counter()
    model, grid = prepare(spec)
    spec.model = str(model.folder) if os.sep in spec.model else model.name
    spec.residual_measure = residual_name(spec, model)  # the workers and the store get the name, not "the model's"
    out = Path(out)
    path = out / STORE
    swap = find_swap(model, grid) if spec.symmetry and spec.measure != "stability" else None
    fresh = not path.exists()
    if fresh:
        chunks = chunk_shape(grid.shape, spec.chunk or auto_chunk(grid.size, workers or default_workers()), swap)
        done = np.zeros(grid.shape, dtype=bool)
    else:
        group = open_store(path, spec, model)
        chunks = tuple(group["done"].chunks)
        done = np.asarray(group["done"][...], dtype=bool)
    if swap is not None and chunks[swap.a] != chunks[swap.b]:
        swap = None  # a store written without the shortcut's block shape: compute every point
    pending = [task for task in tasks_for(grid.shape, chunks, swap)
               if not all(done[block_slices(b, chunks, grid.shape)].all() for b in task)]
    computed = sum(int(np.prod([s.stop - s.start for s in block_slices(b, chunks, grid.shape)]))
                   for t in pending for b in t)
    integrated = n_rhs = 0
    timing: dict = {}
    if pending:
        t0 = time.perf_counter()
        client, cluster = _connect(scheduler, workers)  # before anything is written: a bad address writes nothing
        timing["cluster_start_s"] = round(time.perf_counter() - t0, 3)
        try:
            if fresh:
                create_store(path, spec, model, grid, chunks)
                group = open_store(path, spec, model)
            t0 = time.perf_counter()
            integrated, n_rhs, more = _run_tasks(client, spec, model, grid, group, chunks, pending, progress)
            timing["tasks_wall_s"] = round(time.perf_counter() - t0, 3)
            timing.update(more)
        finally:
            t0 = time.perf_counter()
            client.close()
            if cluster is not None:
                cluster.close()
            timing["cluster_close_s"] = round(time.perf_counter() - t0, 3)
    summary = {"points": grid.size, "computed": computed, "reused": grid.size - computed,
               "wall_s": None, "store": str(path), "integrated": integrated, "rhs_evaluations": n_rhs,
               "figures": [], "timing": timing}
    if checks_tolerance(spec):
        summary.update(tolerance_summary(path))
    if spec.measure == "attractor":
        summary["outcomes"] = outcome_counts(path)
    if spec.measure in ("r_max", "t_dec"):
        summary["failed"] = failed_count(path)
    if spec.measure == "residual":
        summary["residual"] = residual_summary(path, write=True)
    if spec.measure == "stability" and len(grid.shape) == 2 and spec.refine:
        from .stability_map import certify_store

        t0 = time.perf_counter()
        summary["resolution"] = certify_store(path, model, grid)
        timing["certify_s"] = round(time.perf_counter() - t0, 3)
    if figures:
        from .sweep_figures import write_figures

        t0 = time.perf_counter()
        summary["figures"] = [str(p) for p in write_figures(path)]
        timing["figures_s"] = round(time.perf_counter() - t0, 3)
    summary["wall_s"] = time.perf_counter() - start
    return summary


def tolerance_summary(path: Path) -> dict:
    """{"tolerance_sensitive": count of flagged points, "tolerance_check": what was compared} of a store."""
    import zarr

    group = zarr.open_group(str(path), mode="r")
    flags = np.asarray(group["tolerance_sensitive"][...])
    done = np.asarray(group["done"][...], dtype=bool)
    check = json.loads(group.attrs["tolerance_check"])
    return {"tolerance_sensitive": int((flags[done] == 1).sum()),
            "tolerance_check": {**check, "checked": int(done.sum())}}


def failed_count(store: Path) -> int:
    """An r_max or t_dec store's computed points whose run failed (no value: NaN, as a t_dec not settled by t_end
    is, so counted here and marked on the figure, never read as one)."""
    import zarr

    group = zarr.open_group(str(store), mode="r")
    done = np.asarray(group["done"][...], dtype=bool)
    return int((np.asarray(group["failed"][...])[done] == 1).sum())


def residual_summary(store: Path, write: bool = False) -> dict:
    """A residual store's distribution of r at rest over its computed points (`residual.distribution`); with
    `write`, also kept in the store as the attribute `residual_distribution`."""
    import zarr

    from .residual import distribution

    group = zarr.open_group(str(store), mode="r+" if write else "r")
    done = np.asarray(group["done"][...], dtype=bool)
    out = distribution(np.asarray(group["residual"][...])[done], np.asarray(group["at_rest"][...])[done])
    if write:
        group.attrs["residual_distribution"] = json.dumps(out)
    return out


def outcome_counts(store: Path) -> dict:
    """An attractor store's decided labels counted (computed points only): {"counts": {label: n}, "balanced",
    "not_balanced", "undecided" and "failed" (never counted as not balanced), "undecided_reasons": {reason: n},
    "approaches": {kind: n}, "carry_on": the cap the undecided runs were carried on to}."""
    import zarr

    group = zarr.open_group(str(store), mode="r")
    names = json.loads(group.attrs["labels"])
    rest = set(json.loads(group.attrs.get("balanced_labels", json.dumps(names[:1]))))  # older stores: the first
    done = np.asarray(group["done"][...], dtype=bool)
    codes = np.asarray(group["attractor"][...])[done]
    labels_ = [names[int(c)] if c >= 0 else "not computed" for c in codes]
    counts = {k: labels_.count(k) for k in sorted(set(labels_))}
    out = {"counts": counts, "balanced": sum(v for k, v in counts.items() if k in rest),
           "undecided": counts.get("undecided", 0), "failed": counts.get("failed", 0)}
    out["not_balanced"] = len(labels_) - out["balanced"] - out["undecided"] - out["failed"]
    if "undecided" in group:  # stores written before outcomes were decided have no reasons
        reasons = json.loads(group.attrs["undecided_reasons"])
        kinds = json.loads(group.attrs["approaches"])
        r = np.asarray(group["undecided"][...])[done]
        a = np.asarray(group["approach"][...])[done]
        out["undecided_reasons"] = {reasons[k]: int((r == k).sum()) for k in sorted(set(r.tolist())) if k > 0}
        out["approaches"] = {kinds[k]: int((a == k).sum()) for k in sorted(set(a.tolist())) if k > 0}
        out["carry_on"] = group.attrs["carry_on"]
    return out


def _connect(scheduler: str | None, workers: int | None):
    """(client, cluster): the scheduler at `scheduler`, or a new local cluster (cluster None otherwise)."""
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout=10), None
        except (OSError, TimeoutError) as exc:
            raise AnalysisError(f"cannot reach the Dask scheduler at {scheduler}: {exc}") from None
    n = workers or default_workers()
    # threads: the compiled path releases the GIL, so one process with a thread per core has no Python
    # contention to speak of and starts in a fraction of a second
    cluster = LocalCluster(n_workers=1, threads_per_worker=n, processes=False, dashboard_address=":0")
    return Client(cluster), cluster


def _run_tasks(client, spec, model, grid, group, chunks, pending, progress) -> tuple[int, int]:
    """Submit the pending tasks; write each block as its task finishes; (trajectories, rhs evaluations)."""
    from distributed import as_completed
    from tqdm import tqdm

    integrated = n_rhs = 0
    cpu: dict[str, float] = {}
    write_s = 0.0
    # the store's arrays opened once (each group[name] reads the array's metadata from disk again)
    arrays = {name: group[name] for name, *_ in _variables(spec, model)}
    spec_dict = spec.to_dict()
    futures = {}
    for task in pending:
        flat = np.concatenate([block_flat(b, chunks, grid.shape) for b in task])
        fut = client.submit(_task, spec_dict, flat, pure=False)
        futures[fut] = task
    bar = tqdm(total=len(pending), disable=not progress, file=sys.stderr, unit="task",
               desc=f"sweep {model.name}")
    for fut in as_completed(futures):
        res = fut.result()
        integrated += int(res["integrated"])
        n_rhs += int(res["n_rhs"])
        for k, v in res.get("cpu_s", {}).items():
            cpu[k] = cpu.get(k, 0.0) + v
        task = futures.pop(fut)
        offset = 0
        w0 = time.perf_counter()
        for b in task:
            size = int(np.prod([s.stop - s.start for s in block_slices(b, chunks, grid.shape)]))
            write_block(arrays, spec, model, grid, b, chunks, res, slice(offset, offset + size))
            offset += size
        write_s += time.perf_counter() - w0
        bar.update(1)
    bar.close()
    return integrated, n_rhs, {"tasks_cpu_s": {k: round(v, 3) for k, v in cpu.items()}, "store_writes_s": round(write_s, 3)}
