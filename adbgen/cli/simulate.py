"""`adbgen simulate`: one transient of a generated model (`adbgen.analysis.simulate`).

    adbgen simulate MODEL [--scene FILE] [--set NAME=VALUE]... [--y0 NAME=VALUE]... [--t-end T]
                    [--rtol R] [--atol A] [--engine E] [--threshold H] [--out DIR] [--json]

With --json one JSON object on stdout.  Bad input: one line on stderr, exit 2; a failed integration:
one line naming where it failed, exit 1.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..analysis.loading import parse_assignments
from .arguments import Commands, _emit_json, _finite_positive, _load, _model_arguments

command = Commands()
register = command.register


# --------------------------------------------------------------------------------------- simulate

@command("simulate", "integrate a transient of a generated model (compiled; thesis ch. 5)")
def _add_simulate(p) -> None:
    from ..analysis.engines import DEFAULT, ENGINES

    _model_arguments(p)
    p.add_argument("--y0", action="append", default=[], metavar="NAME=VALUE",
                   help="an initial state by name (repeatable); states not given are 0")
    p.add_argument("--t-end", type=_finite_positive, default=1000.0, help="end time (default 1000)")
    p.add_argument("--rtol", type=_finite_positive, default=1e-8, help="relative tolerance (default 1e-8)")
    p.add_argument("--atol", type=_finite_positive, default=1e-10, help="absolute tolerance (default 1e-10)")
    p.add_argument("--engine", default=DEFAULT, choices=sorted(ENGINES), metavar="E",
                   help=f"integration engine (default {DEFAULT}); one of: {', '.join(ENGINES)}")
    p.add_argument("--threshold", type=_finite_positive, default=1e-3,
                   help="t_dec = last time r >= threshold (default 1e-3, the thesis')")
    p.add_argument("--max-steps", type=int, default=10_000_000, help="step limit (default 10^7)")
    p.add_argument("--out", help="folder for the trajectory (trajectory.npz, trajectory.csv) and a plot")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.set_defaults(fn=run_simulate)


def run_simulate(args) -> int:
    from ..analysis.results import IntegrationError
    from ..analysis.simulate import simulate, write_trajectory

    model = _load(args)
    params = parse_assignments(args.set, "--set")
    y0 = parse_assignments(args.y0, "--y0")
    p = model.params(params)
    y = model.state(y0)
    sim = simulate(model, p, y, t_end=args.t_end, rtol=args.rtol, atol=args.atol, engine=args.engine,
                   threshold=args.threshold, keep_trajectory=args.out is not None, max_steps=args.max_steps,
                   check=False)
    if args.out is not None and sim.ok:
        write_trajectory(model, sim, Path(args.out))
    if args.json:
        _emit_json({**sim.to_json(), "out": args.out})
    else:
        _print_simulation(model, sim, args.out)
    if not sim.ok:
        err = IntegrationError(sim.status, sim.t_fail if sim.t_fail is not None else float("nan"), sim.engine,
                               sim.message)
        print(f"adbgen: error: {err}", file=sys.stderr)
        return 1
    return 0


def _print_simulation(model, sim, out) -> None:
    t_dec = "not settled by t_end" if sim.t_dec is None else f"{sim.t_dec:.6g}"
    rows = [("model", model.name), ("engine", sim.engine), ("rtol, atol", f"{sim.rtol:g}, {sim.atol:g}"),
            ("t_end", f"{sim.t_end:g}"), ("status", sim.status), ("r_max", f"{sim.r_max:.7g}"),
            (f"t_dec (r < {sim.threshold:g})", t_dec), ("rhs evaluations", str(sim.n_rhs)),
            ("steps", str(sim.n_steps)), ("wall (integration)", f"{sim.wall_s * 1e3:.3f} ms")]
    width = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"{k:<{width}}  {v}")
    print("final state:")
    for name, v in zip(sim.state_names, sim.y_end):
        print(f"  {name:<{width - 2}}  {v: .10g}")
    if out is not None and sim.ok:
        print(f"wrote {out}/trajectory.npz, trajectory.csv, trajectory.png")
