"""The periodic-orbit glue of `adbgen continue` (the command: cli/stability.py; its options: cli/orbit.py); the
computing is in `adbgen.analysis.orbits` (branches, hopf, charts, run_points).

    adbgen continue MODEL --par NAME [--orbits | --from-hopf VALUE] [--tie NAME=EXPR]... [--y0 NAME=VALUE]...
                    [--max-points N] [--auto-orbits] [--plot FILE] ...

* every Hopf point of the one-parameter run gets `first_lyapunov` and `criticality` ("supercritical" |
  "subcritical") in `points` (exact second and third derivatives: `lyapunov`, `jets`);
* `--orbits`: the cycles born at every Hopf point (`--from-hopf VALUE`: at the one nearest VALUE) are
  continued by Newton shooting on the compiled variational equations (`branches`): JSON `orbits` (one
  object per branch: arrays `parameter`, `period`, `stable`, `amplitude`, and `from`, `windings`, `end`)
  and `orbit_points` ({kind: "fold" | "period-doubling" | "torus", NAME, period, multipliers, branch});
  `--auto-orbits` adds `auto_orbits`, the same branches by AUTO-07p's collocation (IPS = 2 from the HB
  labels), for comparison;
* a periodically forced model (fixed frame) has no steady state: its forced response, the periodic
  orbit at the forcing period (a balanced state is one, with the rotor at rest), is
  continued from START (or --y0) recomputed at the --set parameters, its torus and period-doubling
  points in `orbit_points`;
* `--tie NAME=EXPR` keeps a parameter tied to others along every branch (m/M = eps/R in the paper's
  charts); `--plot FILE` draws the branches (amplitude and period against the parameter, stable solid).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..analysis.loading import AnalysisError, parse_value
from ..analysis.orbits import hopf
from ..analysis.units import assignments, units
from .arguments import quantity_pair


def parse_range2(text: str, unit: str) -> tuple[float, float]:
    """--range2 LO:HI -> (lo, hi) with lo < hi, each bound a number in --par2's `unit`, an expression in pi or a
    value with a unit (`units.quantity`)."""
    out = quantity_pair(text, unit, "--range2", "LO:HI", ("--range2 LO", "--range2 HI"))
    if not out[0] < out[1]:
        raise AnalysisError(f"--range2: LO must be below HI, got {text!r}")
    return out


def range2_option(args, model) -> tuple[float, float] | None:
    """`continue`'s --range2, read once by either path (steady states, forced response) in --par2's unit (None:
    not given); refused without --par2."""
    if args.range2 is None:
        return None
    if args.par2 is None:
        raise AnalysisError("--range2 needs --par2")
    return parse_range2(args.range2, units(model).params[args.par2])


def wants_orbits(args) -> bool:
    return bool(args.orbits or args.from_hopf is not None)


def wants_chart(args) -> bool:
    """--par2 on our own continuation (a chart) rather than AUTO-07p's Hopf and fold curves: with ties, a
    plot, a log scale or a grid asked for."""
    return args.par2 is not None and bool(args.tie or args.plot or args.log2 or args.grid)


def pmap_for(model, p, names, args):
    from ..analysis.orbits.parameters import ParameterMap

    return ParameterMap(model, p, [n for n in names if n is not None], ties=args.tie)


def orbit_settings(args, lam0: float, to: float | None):
    from ..analysis.orbits.continuer import Settings

    lo, hi = (min(lam0, to), max(lam0, to)) if to is not None else (-math.inf, math.inf)
    return Settings(ds=0.01, ds_max=0.05, max_points=args.max_points, bounds=(lo, hi))


def continue_orbits(model, args, p, points: list[dict], name: str, to: float | None, follower) -> dict:
    """`orbits` and `orbit_points` from the Hopf points of the one-parameter run (autonomous model)."""
    from ..analysis.orbits import branches

    pmap = pmap_for(model, p, [name], args)
    start = float(p[pmap.index[0]])
    hb = [row for row in points if row.get("type") == "HB" and "state" in row]
    if args.from_hopf is not None:
        value = parse_value(args.from_hopf, "--from-hopf")
        if not hb:
            raise AnalysisError(f"--from-hopf {value:g}: the run found no Hopf point")
        hb = [min(hb, key=lambda row: abs(row[name] - value))]
    out_branches, out_points = [], []
    for row in hb:
        y = np.array([row["state"][s] for s in model.state_names])
        hp = hopf.refine_hopf(model, pmap, y, row[name], row.get("frequency"), follower)
        br = branches.from_hopf(model, pmap, hp, orbit_settings(args, start, to), to=to)
        out_points += br.points_json(len(out_branches))
        out_branches.append(br)
    result = {"orbits": [b.to_json() for b in out_branches], "orbit_points": out_points}
    if args.auto_orbits:
        from ..analysis.orbits.auto_cycles import auto_branches

        result["auto_orbits"] = auto_branches(model, name, p, [row[name] for row in hb], to,
                                              nmx=args.max_points)
    return result, out_branches


def forced_start(model, args, p):
    """The start of a forced model's response at p, refined by Newton shooting: --y0, else START, else the
    first of the module's labelled steady states (STEADY_STATES: a constant solution of the forced model, such
    as B with the rotor at rest) that exists at p."""
    from ..analysis.orbits.orbit import refine

    y0 = None
    if args.y0:
        y0 = model.state(assignments(args.y0, "--y0", units(model).states))
    elif getattr(model.module, "START", None) is not None:
        y0 = np.array(model.module.START, float)
    elif hasattr(model.module, "steady_state"):
        for label in getattr(model.module, "STEADY_STATES", ()):
            y = model.module.steady_state(label, p)
            if y is not None:
                y0 = np.array(y, float)
                break
    if y0 is None:
        raise AnalysisError(f"{model.name} has no START (nor a labelled steady state at these parameters); give the "
                            f"start of its forced response with --y0 NAME=VALUE")
    return refine(model, p, y0, None)


def run_forced(args, model, values: dict, to: float | None, emit) -> int:
    """`adbgen continue` on a periodically forced model: its forced response continued in --par (and, with
    --par2, its torus and period-doubling curves); `values` (--set) and `to` (--to, None: not given) as
    `run_continue` read them."""
    from ..analysis.orbits import branches

    if not (wants_orbits(args) or args.par2 is not None):
        raise AnalysisError(f"{model.name} is periodically forced: it has periodic orbits, not steady states; continue "
                            f"its forced response with --orbits (or --par2 for its torus and period-doubling curves)")
    range2 = range2_option(args, model)
    p = model.params({**start_parameters(model), **values})
    pmap = pmap_for(model, p, [args.par], args)
    p = pmap(p[pmap.index[0]])
    k = model.param_names.index(args.par)
    given_to = to  # the chart's range reads --to as given
    if to is None:
        to = 0.5 * p[k] if p[k] > 0 else p[k] - 1.0
    if to == p[k]:
        raise AnalysisError(f"--to must differ from the start value {args.par} = {p[k]:g}")
    start = forced_start(model, args, p)
    from ..analysis.identify import identify

    # what the branch starts on: a labelled steady state (a constant solution, e.g. balanced with the rotor at
    # rest) or an unlabelled periodic response (issue 34 item 4)
    followed = identify(model, start.y, p).to_json()
    if args.par2 is not None:
        return chart_command(args, model, p, start, given_to, range2, lambda out: emit({**out, **followed}))
    br = branches.from_orbit(model, pmap, start, 1.0 if to > p[k] else -1.0, orbit_settings(args, float(p[k]), to), to=to)
    out = {"model": model.name, "parameter": args.par, "ties": list(args.tie), "points": [],
           "orbits": [br.to_json()], "orbit_points": br.points_json(0), **followed}
    if args.plot:
        branches.plot_branches(Path(args.plot), model, args.par, [br])
    emit(out)
    return 0


def start_parameters(model) -> dict:
    sp = getattr(model.module, "START_PARAMETERS", None)
    return {} if sp is None else dict(zip(model.param_names, map(float, sp)))


def chart_command(args, model, p, start, to: float | None, range2: tuple | None, emit) -> int:
    """`adbgen continue MODEL --par NAME --par2 NAME2 [--tie ...] [--range2 LO:HI] [--log2] [--plot FILE]` on our
    own continuation (forced models; autonomous ones with --tie, --plot or --log2); `to` (--to) and `range2`
    (--range2) as read once by the caller, None where not given."""
    from ..analysis.orbits.charts import compute, plot
    from ..analysis.orbits.parameters import ParameterMap

    pmap = ParameterMap(model, p, [args.par, args.par2], ties=args.tie)
    k1, k2 = pmap.index
    v1, v2 = float(p[k1]), float(p[k2])
    range1 = (min(v1, to), max(v1, to)) if to is not None else (0.5 * v1, 1.5 * v1)
    range2 = range2 or ((0.1 * v2, 10 * v2) if v2 > 0 else (v2 - 1.0, v2 + 1.0))
    log2 = bool(getattr(args, "log2", False))
    n1, n2 = 81, 25
    if getattr(args, "grid", None):
        a, sep, b = args.grid.partition(":")
        try:
            n1, n2 = int(a), int(b)
        except ValueError:
            raise AnalysisError(f"--grid: expected N1:N2 (whole numbers), got {args.grid!r}") from None
        if not sep or n1 < 3 or n2 < 2:
            raise AnalysisError(f"--grid: expected N1:N2 with N1 >= 3 and N2 >= 2, got {args.grid!r}")
    chart = compute(model, pmap, start, range1, range2, log2=log2, n1=n1, n2=n2)
    if args.plot:
        plot(chart, Path(args.plot))
    emit(chart.to_json())
    return 0
