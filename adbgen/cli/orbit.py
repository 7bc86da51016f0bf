"""`adbgen orbit` and the periodic-orbit options of `adbgen continue` (issue 21); the logic is in
`adbgen.analysis.orbits`.

    adbgen orbit MODEL [--scene FILE] [--set NAME=VALUE]... [--y0 NAME=VALUE]... | [--state LABEL] [--t-transient T]
                 [--period T] [--arcs M] [--out DIR] [--json]

JSON keys: period, multipliers ([re, im] pairs, by decreasing modulus), trivial_multiplier_error
(|mu - 1| of the flow direction's multiplier; null for a forced orbit), stable, windings (angle ->
k, the 2 pi k it gains per period), r_min, r_max, y (the point on the orbit, by state name), residual;
also model, parameters, n_unstable, newton_iterations, arcs, forced, subharmonic and <measure>_bar for
every amplitude measure the module emits (MEASURES, e.g. A_bar); margin, margin_uncertainty, marginal,
margin_estimate (issue 34 item 5: `adbgen.analysis.margins`), followed_state, followed_orbit, start_distance
(item 4: what the run followed, and how far the start was from it).

`continue` gains (`add_continue_options`): --orbits, --from-hopf VALUE, --tie NAME=EXPR, --max-points N,
--auto-orbits, --plot FILE, --log2, --grid N1:N2 (see `adbgen.cli.continue_orbits`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..analysis.loading import AnalysisError
from ..analysis.units import assignments, units
from ..cli_types import branch_points
from ..outputs import output_folder
from .arguments import Commands, _emit_json, _finite_positive, _load, _model_arguments, _positive_int

command = Commands()
register = command.register


@command("orbit", "the periodic orbit a trajectory settles on, by Newton shooting on the compiled variational "
                  "equations: period, Floquet multipliers, stability, windings, amplitude range")
def _add_orbit(p) -> None:
    _model_arguments(p)
    p.add_argument("--y0", action="append", default=[], metavar="NAME=VALUE",
                   help="the initial state by name (repeatable); states not given are 0")
    p.add_argument("--state", metavar="LABEL",
                   help="a periodically forced model: start on one of its labelled steady states (STEADY_STATES, "
                        "constant solutions such as B with the rotor at rest) at the --set parameters; the orbit "
                        "found must be that state, else the run is refused")
    p.add_argument("--t-transient", type=float, default=2000.0, metavar="T",
                   help="integrate this long before looking for the orbit (default 2000, in the model's time "
                        "unit; 0: --y0 is on the orbit already)")
    p.add_argument("--period", type=_finite_positive, metavar="T",
                   help="a guess of the period (default: detected from the first return of the trajectory)")
    p.add_argument("--arcs", type=_positive_int, metavar="M",
                   help="shooting arcs (default: as many as keep each arc's sensitivity below 1e4)")
    p.add_argument("--out", metavar="DIR", help="write orbit.csv (one period, by state name) and orbit.png")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.set_defaults(fn=run_orbit)


def run_orbit(args) -> int:
    from ..analysis.orbits import orbit as orbits
    from ..analysis.orbits.flow import Flow
    from ..analysis.orbits.output import write_orbit

    if args.out is not None:
        output_folder(args.out, "--out")
    if not (math.isfinite(args.t_transient) and args.t_transient >= 0):
        raise AnalysisError(f"--t-transient must be a finite number >= 0, got {args.t_transient}")
    model = _load(args)
    u = units(model)
    p = model.params(assignments(args.set, "--set", u.params))
    y0 = model.state(assignments(args.y0, "--y0", u.states))
    if args.state is not None:
        y0 = _labelled_start(model, p, args)
    flow = Flow(model)
    if args.period is not None:
        y = flow.end(y0, 0.0, args.t_transient, p) if args.t_transient > 0 else y0
        found = orbits.refine(model, p, y, args.period, orbits.windings_over(model, flow, y, args.period, p),
                              arcs=args.arcs, flow=flow)
    else:
        found = orbits.find(model, p, y0, args.t_transient, arcs=args.arcs, flow=flow)
    follows = _follows(model, found, y0, flow, args)  # before any output: a refusal writes nothing
    if args.out:
        write_orbit(found, flow, Path(args.out))
    if args.json:
        _emit_json({**found.to_json(), **follows})
    else:
        _print_orbit(found)
        print(f"follows: {follows['followed_orbit']}; the start is {follows['start_distance']:.3g} from it")
    return 0


def _labelled_start(model, p, args):
    """--state LABEL of `adbgen orbit`: a forced model's labelled steady state at p (a constant solution)."""
    from ..analysis.starts import labelled_state

    if args.y0:
        raise AnalysisError("give --y0 or --state, not both")
    if model.autonomous:
        raise AnalysisError(f"{model.name} is autonomous: its labelled states are steady states, not periodic orbits "
                            f"(see `adbgen stability {model.name} --state {args.state}`)")
    return labelled_state(model, args.state, p)


def _follows(model, found, y0, flow, args) -> dict:
    """What `adbgen orbit` followed: the labelled steady state the orbit is (a forced model's B, with the rotor at
    rest) or the orbit by its windings and period, and the start's distance from it (from the state the shooting
    began at: y0 after the transient, to the orbit's nearest sampled point, angles modulo 2 pi)."""
    from ..analysis.identify import check
    from ..analysis.orbits.orbit import trace, wrapped

    ident = check(model, found.y, found.p, args.state, "the orbit found") if not model.autonomous else None
    start = found.start if found.start is not None else y0
    _, Y = trace(found, flow, 400)
    distance = float(np.min(np.linalg.norm(wrapped(model, Y - start), axis=1)))
    if ident is not None and ident.label is not None:
        what = f"state {ident.label} (a constant solution: the rotor at rest)"
    else:
        laps = ", ".join(f"{k} {v:+d}" for k, v in found.windings.items() if v) or "no angle laps"
        what = f"periodic orbit of period {found.period:.10g} ({laps})"
    return {"followed_state": None if ident is None else ident.label, "followed_orbit": what,
            "start_distance": distance}


def _print_orbit(o) -> None:
    m = o.model
    kind = f"forced, {o.subharmonic} forcing period(s)" if o.forced else "autonomous"
    print(f"model {m.name}: periodic orbit ({kind}), period {o.period:.12g}, |F| = {o.residual:.2e} after "
          f"{o.iterations} Newton steps, {len(o.arcs)} arc(s)")
    laps = ", ".join(f"{k} {v:+d}" for k, v in o.windings.items() if v) or "none (no angle laps)"
    print(f"windings: {laps}")
    print(f"r in [{o.r_min:.8g}, {o.r_max:.8g}]" + "".join(f", {k}_bar = {v:.8g}" for k, v in o.measures.items()))
    err = o.trivial_multiplier_error
    print(f"{'stable' if o.stable else f'unstable ({o.n_unstable} outside the unit circle)'}"
          + ("" if err is None else f"; trivial multiplier |mu - 1| = {err:.2e}"))
    mg = o.margin
    print(f"margin: leading |mu| - 1 = {mg.value:.6g}, certain to {mg.uncertainty:.2g}"
          + (" (MARGINAL: inside what the computation can certify)" if mg.marginal else ""))
    print("multipliers (|mu|):")
    for i, z in enumerate(o.multipliers):
        tag = "  (trivial)" if i == o.trivial else ""
        print(f"  {z.real: .10f} {'+' if z.imag >= 0 else '-'} {abs(z.imag):.10f}i   {abs(z):.10f}{tag}")
    print("point on the orbit:")
    for name, v in zip(m.state_names, o.y):
        print(f"  {name:<12} {v: .12g}")


# ------------------------------------------------------------------ what `adbgen continue` gains

def add_continue_options(p) -> None:
    p.add_argument("--orbits", action="store_true",
                   help="continue the periodic orbits born at every Hopf point by Newton shooting (a forced model: "
                        "its forced response, instead of AUTO-07p's stages)")
    p.add_argument("--from-hopf", metavar="VALUE",
                   help="continue the orbits born at the Hopf point nearest VALUE of --par only (implies --orbits)")
    p.add_argument("--tie", action="append", default=[], metavar="NAME=EXPR",
                   help="keep parameter NAME = EXPR along every branch and curve, EXPR an expression in parameter "
                        "names, numbers, pi, + - * / ** and parentheses (repeatable, applied in order: a tie may use "
                        "one made before it), e.g. --tie m_1=epsilon*M/R_t; design's --tie takes NAME=VARIED, a "
                        "name only")
    p.add_argument("--y0", action="append", default=[], metavar="NAME=VALUE",
                   help="the start state by name where the model has no START (states not given are 0)")
    p.add_argument("--max-points", type=branch_points, default=200, metavar="N",
                   help="points per orbit branch, at least 2 (default 200)")
    p.add_argument("--auto-orbits", action="store_true",
                   help="with --orbits: also AUTO-07p's branches of the same orbits (IPS = 2 from the HB labels)")
    p.add_argument("--plot", metavar="FILE", help="draw the orbit branches (with --par2: the stability chart, its curves "
                                                  "also written as data into FILE's .json) into FILE")
    p.add_argument("--log2", action="store_true", help="with --par2: the second parameter on a log scale (range and plot)")
    p.add_argument("--grid", metavar="N1:N2", help="with --par2 on our own continuation: the chart's grid (default 81:25)")


def print_orbits(out: dict, name: str) -> None:
    """The orbit branches and their special points of `continue --orbits`."""
    for i, br in enumerate(out.get("orbits", [])):
        origin = br["from"]
        lam = br["parameter"]
        span = f"{name} from {lam[0]:.8g} to {lam[-1]:.8g}, period {br['period'][0]:.8g} to {br['period'][-1]:.8g}" \
            if lam else "no orbits"
        print(f"  orbit branch {i} from the {origin['kind']} at {name} = {origin[name]:.10g}: {len(lam)} orbits, {span} "
              f"({br['end']})")
    for sp in out.get("orbit_points", []):
        print(f"    {sp['kind']:<15} {name} = {sp[name]:.10g}, period {sp['period']:.10g} (branch {sp['branch']})")
