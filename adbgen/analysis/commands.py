"""Command-line commands of the analysis layer, registered into `adbgen`'s parser by `register`.

    adbgen simulate MODEL [--scene FILE] [--set NAME=VALUE]... [--y0 NAME=VALUE]... [--t-end T]
                    [--rtol R] [--atol A] [--engine E] [--threshold H] [--out DIR] [--json]

    adbgen stability ..., adbgen continue ...   (stability_commands.py)
    adbgen orbit ...                             (orbits/commands.py)
    adbgen sweep ...                             (sweep_commands.py)
    adbgen reproduce ...                         (reproduce.py)

Each command prints one JSON object on stdout with --json.  Bad input: one line on stderr, exit 2;
a failed integration: one line naming where it failed, exit 1.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from .command_registry import COMMANDS, _emit_json, _finite_positive, _json_number, _load, _model_arguments, command
from .loading import parse_assignments


def register(sub, parser_class) -> None:
    """Add this layer's commands to the `adbgen` subparsers."""
    # the command modules register themselves in COMMANDS when imported
    from . import reproduce, stability_commands, sweep_commands  # noqa: F401
    from .orbits import commands as _orbits  # noqa: F401

    for name, help_, add in COMMANDS:
        p = sub.add_parser(name, help=help_, description=help_)
        add(p)


# --------------------------------------------------------------------------------------- simulate

@command("simulate", "integrate a transient of a generated model (compiled; thesis ch. 5)")
def _add_simulate(p) -> None:
    from .engines import DEFAULT, ENGINES

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
    from .results import IntegrationError
    from .simulate import simulate

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


def write_trajectory(model, sim, out: Path) -> None:
    """trajectory.npz (t, y, names, metadata), trajectory.csv (metadata header) and a plot of r and the angles."""
    import numpy as np

    from .simulate import amplitude

    out.mkdir(parents=True, exist_ok=True)
    meta = {k: v for k, v in sim.to_json().items() if k != "y_end"}
    meta["source_hash"] = model.source_hash
    np.savez_compressed(out / "trajectory.npz", t=sim.t, y=sim.y, state_names=np.array(sim.state_names),
                        metadata=json.dumps(meta, default=_json_number))
    r = amplitude(model, sim.y)
    header = "\n".join(f"# {k}: {json.dumps(v, default=_json_number)}" for k, v in meta.items())
    table = np.column_stack([sim.t, r, sim.y.T])
    with open(out / "trajectory.csv", "w") as fh:
        fh.write(header + "\n")
        fh.write(",".join(["t", "r", *sim.state_names]) + "\n")
        np.savetxt(fh, table, delimiter=",", fmt="%.17g")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 5), sharex=True, constrained_layout=True)
    a1.plot(sim.t, r, lw=0.7)
    a1.axhline(sim.threshold, color="0.6", lw=0.6, ls="--")
    if sim.t_dec is not None:
        a1.axvline(sim.t_dec, color="C3", lw=0.6, ls=":")
    a1.set_ylabel("$r$")
    a1.set_yscale("log")
    a1.set_title(f"{model.name}: $r_{{max}}$ = {sim.r_max:.4g}, "
                 f"$t_{{dec}}$ = {'-' if sim.t_dec is None else f'{sim.t_dec:.2f}'}", fontsize=9)
    for i in model.angle_indices:
        a2.plot(sim.t, sim.y[i], lw=0.8, label=f"${model.state_names[i]}$".replace("phi", r"\phi"))
    a2.set_xlabel("$t$")
    a2.set_ylabel("ball angle")
    a2.legend(loc="best", fontsize=8)
    fig.savefig(out / "trajectory.png", dpi=120)
    plt.close(fig)

