"""`adbgen orbit`: the periodic orbit a trajectory settles on, refined by Newton shooting.

    adbgen orbit MODEL [--scene FILE] [--set NAME=VALUE]... [--y0 NAME=VALUE]... [--t-transient T]
                 [--period T] [--arcs M] [--out DIR] [--json]

JSON keys: period, multipliers ([re, im] pairs, by decreasing modulus), trivial_multiplier_error
(|mu - 1| of the flow direction's multiplier; null for a forced orbit), stable, windings (angle ->
k, the 2 pi k it gains per period), r_min, r_max, y (the point on the orbit, by state name), residual;
also model, parameters, n_unstable, newton_iterations, arcs, forced, subharmonic and <measure>_bar for
every amplitude measure the module emits (MEASURES, e.g. A_bar).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from ..command_registry import _emit_json, _finite_positive, _load, _model_arguments, command
from ..loading import AnalysisError, parse_assignments


@command("orbit", "the periodic orbit a trajectory settles on, by Newton shooting on the compiled variational "
                  "equations: period, Floquet multipliers, stability, windings, amplitude range")
def _add_orbit(p) -> None:
    _model_arguments(p)
    p.add_argument("--y0", action="append", default=[], metavar="NAME=VALUE",
                   help="the initial state by name (repeatable); states not given are 0")
    p.add_argument("--t-transient", type=float, default=2000.0, metavar="T",
                   help="integrate this long before looking for the orbit (default 2000, in the model's time "
                        "unit; 0: --y0 is on the orbit already)")
    p.add_argument("--period", type=_finite_positive, metavar="T",
                   help="a guess of the period (default: detected from the first return of the trajectory)")
    p.add_argument("--arcs", type=int, metavar="M",
                   help="shooting arcs (default: as many as keep each arc's sensitivity below 1e4)")
    p.add_argument("--out", metavar="DIR", help="write orbit.csv (one period, by state name) and orbit.png")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.set_defaults(fn=run_orbit)


def run_orbit(args) -> int:
    from . import orbit as orbits
    from .flow import Flow

    model = _load(args)
    p = model.params(parse_assignments(args.set, "--set"))
    y0 = model.state(parse_assignments(args.y0, "--y0"))
    if args.arcs is not None and args.arcs < 1:
        raise AnalysisError(f"--arcs must be >= 1, got {args.arcs}")
    if not (math.isfinite(args.t_transient) and args.t_transient >= 0):
        raise AnalysisError(f"--t-transient must be a finite number >= 0, got {args.t_transient}")
    flow = Flow(model)
    if args.period is not None:
        y = flow.end(y0, 0.0, args.t_transient, p) if args.t_transient > 0 else y0
        found = orbits.refine(model, p, y, args.period, _windings_of(model, flow, y, args.period, p), arcs=args.arcs,
                              flow=flow)
    else:
        found = orbits.find(model, p, y0, args.t_transient, arcs=args.arcs, flow=flow)
    if args.out:
        write_orbit(found, flow, Path(args.out))
    if args.json:
        _emit_json(found.to_json())
    else:
        _print_orbit(found)
    return 0


def _windings_of(model, flow, y, T, p) -> dict:
    from . import describe

    end = flow.end(y, 0.0, T, p)
    return {model.state_names[i]: int(round((end[i] - y[i]) / (2 * math.pi))) for i in describe.angle_indices(model)}


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
    print("multipliers (|mu|):")
    for i, z in enumerate(o.multipliers):
        tag = "  (trivial)" if i == o.trivial else ""
        print(f"  {z.real: .10f} {'+' if z.imag >= 0 else '-'} {abs(z.imag):.10f}i   {abs(z):.10f}{tag}")
    print("point on the orbit:")
    for name, v in zip(m.state_names, o.y):
        print(f"  {name:<12} {v: .12g}")


def write_orbit(o, flow, out: Path) -> None:
    """orbit.csv (t and the states over one period) and orbit.png (r against t and the x-y whirl), written
    under temporary names and renamed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from . import describe
    from .orbit import trace

    out.mkdir(parents=True, exist_ok=True)
    t, Y = trace(o, flow, 1000)
    m = o.model
    with open(out / ".orbit.csv.tmp", "w") as fh:
        fh.write(f"# model: {m.name}\n# source_hash: {m.source_hash}\n# period: {o.period!r}\n")
        fh.write(",".join(("t",) + m.state_names) + "\n")
        np.savetxt(fh, np.column_stack([t, Y]), delimiter=",", fmt="%.17g")
    ix, iy = describe.amplitude_indices(m)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
    a1.plot(t, np.hypot(Y[:, ix], Y[:, iy]), lw=1)
    a1.set_xlabel("t")
    a1.set_ylabel("r")
    a2.plot(Y[:, ix], Y[:, iy], lw=1)
    a2.set_aspect("equal", "datalim")
    a2.set_xlabel(m.state_names[ix])
    a2.set_ylabel(m.state_names[iy])
    fig.suptitle(f"{m.name}: period {o.period:.8g}, {'stable' if o.stable else 'unstable'}", fontsize=9)
    fig.savefig(out / ".orbit.png.tmp", dpi=110, format="png")
    plt.close(fig)
    os.replace(out / ".orbit.csv.tmp", out / "orbit.csv")
    os.replace(out / ".orbit.png.tmp", out / "orbit.png")
