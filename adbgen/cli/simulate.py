"""`adbgen simulate`: one transient of a generated model (`adbgen.analysis.simulate`).

    adbgen simulate MODEL [--scene FILE] [--set NAME=VALUE]... [--y0 NAME=VALUE]... [--t-end T]
                    [--rtol R] [--atol A] [--engine E] [--threshold H] [--angles wrapped|unwrapped]
                    [--out DIR] [--json] [--quiet] [--check-tolerance]

With --json one JSON object on stdout.  Bad input: one line on stderr, exit 2; a failed integration:
one line naming where it failed, exit 1.  Values take units where a user would type them (`--set
omega=3000rpm`, `--t-end 20s`, `--t-end 640rev`, `--y0 X=1mm`; see `analysis.units`), and the defaults
scale with the model (t_end in revolutions of the spin, t_dec's threshold a tenth of the eccentricity:
what its generated module declares, `units.default_t_end`, `default_threshold`).

--check-tolerance runs the case again tighter (rtol/100, atol/100) and on a second engine of another
method, and compares the label, r_max and t_dec (`analysis.tolerance`); a disagreement is reported
(`tolerance_sensitive: true` and every outcome in --json, a mark in the table and on the plot), never
resolved.  It also estimates the error at t_end (`analysis.error_estimate`): the run as asked against a
run that truly is tighter, in tolerance units (--json: tolerance_check.error_estimate); above 2 (the
bound 10 over a safety factor of 5) the run is flagged.  Beside it a conditioning probe (--json:
error_estimate.conditioning): the run compared with, again from y0 moved an ulp, whose distance at t_end
measures the round-off the transient amplifies (where both runs err alike and the estimate under-reads);
above 2 units it flags the run too.  The default engine's promise: its error at t_end
is at most 10 tolerance units, or --check-tolerance says it may not be.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..analysis.loading import AnalysisError
from ..analysis.units import show
from ..progress import activity, wanted
from .arguments import Commands, _emit_json, _finite_positive, _load, _model_arguments, _positive_int, _quantity_text

command = Commands()
register = command.register


# --------------------------------------------------------------------------------------- simulate

@command("simulate", "integrate a transient of a generated model (compiled; thesis ch. 5)")
def _add_simulate(p) -> None:
    from ..analysis.engines import DEFAULT, ENGINES

    _model_arguments(p)
    p.add_argument("--y0", action="append", default=[], metavar="NAME=VALUE",
                   help="an initial state by name (repeatable; with a unit if you like: X=1mm, phi_1=90deg); "
                        "states not given are 0")
    p.add_argument("--t-end", type=_quantity_text("--t-end"), metavar="T",
                   help="end time: a number in the model's time unit, a time (20s, 2min) or revolutions of the "
                        "spin (640rev); default 2000/pi = 636.6 revolutions (the thesis' t = 1000 at Omega = 4; "
                        "10 s at 400 rad/s)")
    p.add_argument("--rtol", type=_finite_positive, default=1e-8, help="relative tolerance (default 1e-8)")
    p.add_argument("--atol", type=_finite_positive, default=1e-10, help="absolute tolerance (default 1e-10)")
    p.add_argument("--engine", default=DEFAULT, choices=sorted(ENGINES), metavar="E",
                   help=f"integration engine (default {DEFAULT}); one of: {', '.join(ENGINES)}")
    p.add_argument("--threshold", type=_quantity_text("--threshold"), metavar="H",
                   help="t_dec = last time r >= H: a number in the model's length unit or a length (0.05mm); "
                        "default a tenth of the eccentricity (the thesis' 1e-3 at delta = 0.01)")
    p.add_argument("--max-steps", type=_positive_int, default=10_000_000, help="step limit (default 10^7)")
    p.add_argument("--angles", choices=("wrapped", "unwrapped"), default="wrapped",
                   help="the plot's ball angles: wrapped into (-pi, pi] (default) or unwrapped")
    p.add_argument("--out", help="folder for the trajectory (trajectory.npz, trajectory.csv) and a plot")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.add_argument("--check-tolerance", action="store_true",
                   help="run again at rtol/100, atol/100 and on a second engine of another method; compare the "
                        "label, r_max and t_dec (1 %%) and flag a disagreement (tolerance_sensitive); estimate "
                        "the error at t_end against a truly tighter run, in tolerance units, and flag it above 2 "
                        "(the default engine's promise: at most 10, or this check says it may not be)")
    p.set_defaults(fn=run_simulate)


def run_simulate(args) -> int:
    from ..analysis.results import IntegrationError
    from ..analysis.simulate import simulate, simulation_units, write_trajectory
    from ..analysis.units import assignments, default_t_end, default_threshold, duration, params, quantity, units
    from ..outputs import output_folder

    if args.out is not None:
        output_folder(args.out, "--out")
    show_progress = wanted(args.quiet, args.json)
    model = _load(args, show_progress)
    u = units(model)
    values = assignments(args.set, "--set", u.params)
    p = params(model, values)
    y = model.state(assignments(args.y0, "--y0", u.states))
    t_end, t_end_why = (duration(args.t_end, model, p), "given") if args.t_end else default_t_end(model, p)
    if not t_end > 0:
        raise AnalysisError(f"--t-end must be > 0, got {args.t_end}")
    if args.threshold:
        threshold, threshold_why = quantity(args.threshold, u.length, "--threshold"), ""
        if not threshold > 0:
            raise AnalysisError(f"--threshold must be > 0, got {args.threshold}")
    else:
        threshold, threshold_why = default_threshold(model, p)
    with activity(f"{model.name}: integrating to t = {show(t_end, u.time)}", show_progress):
        sim = simulate(model, p, y, t_end=t_end, rtol=args.rtol, atol=args.atol, engine=args.engine,
                       threshold=threshold, keep_trajectory=args.out is not None, max_steps=args.max_steps,
                       check=False)
    check = None
    if getattr(args, "check_tolerance", False) and sim.ok:
        from ..analysis.tolerance import check_simulation

        with activity(f"{model.name}: checking the outcome tighter and on a second engine", show_progress):
            check = check_simulation(model, p, y, sim, t_end=t_end, threshold=threshold, engine=args.engine,
                                     max_steps=args.max_steps, estimate=True)
    defaults = {"t_end": t_end_why if not args.t_end else None, "threshold": threshold_why or None}
    if args.out is not None and sim.ok:
        write_trajectory(model, sim, Path(args.out), values=values, scene=args.scene,
                         wrap_angles=args.angles == "wrapped", threshold_why=threshold_why,
                         note=None if check is None else check.runs[0].label or "",
                         sensitive=check is not None and check.sensitive)
    if args.json:
        more = {} if check is None else {"label": check.runs[0].label, "tolerance_sensitive": check.sensitive,
                                         "tolerance_check": check.to_json()}
        _emit_json({**sim.to_json(), "out": args.out, "units": simulation_units(model, sim),
                    "defaults": {k: v for k, v in defaults.items() if v}, **more})
    else:
        _print_simulation(model, sim, args.out, defaults, check)
    if not sim.ok:
        err = IntegrationError(sim.status, sim.t_fail if sim.t_fail is not None else float("nan"), sim.engine,
                               sim.message)
        print(f"adbgen: error: {err}", file=sys.stderr)
        return 1
    return 0


def _print_simulation(model, sim, out, defaults, check=None) -> None:
    from ..analysis.units import show, units

    u = units(model)
    # a failed run's t_dec is not known (it never reached t_end), which is not "not settled"
    t_dec = (("not settled by t_end" if sim.ok else f"not known (the run ended {sim.status})") if sim.t_dec is None
             else show(sim.t_dec, u.time, 6))
    note = {k: f" ({v})" for k, v in defaults.items() if v}
    rows = [("model", model.name + (f" ({model.module.TITLE})" if getattr(model.module, "TITLE", "") else "")),
            ("engine", sim.engine), ("rtol, atol", f"{sim.rtol:g}, {sim.atol:g}"),
            ("t_end", show(sim.t_end, u.time, 6) + note.get("t_end", "")), ("status", sim.status),
            ("r_max", show(sim.r_max, u.length, 7)),
            (f"t_dec (r < {show(sim.threshold, u.length, 4)})", t_dec),
            ("threshold", show(sim.threshold, u.length, 4) + note.get("threshold", "")),
            ("rhs evaluations", str(sim.n_rhs)), ("steps", str(sim.n_steps)),
            ("wall (integration)", f"{sim.wall_s * 1e3:.3f} ms")]
    if check is not None:
        from ..analysis.tolerance import MARK

        rows.insert(5, ("attractor", (check.runs[0].label or "—") + (f" {MARK}" if check.sensitive else "")))
        rows.append(("tolerance check", check.text()))
        est = check.error_estimate
        if est is not None and est.get("ratio") is not None:
            rows.append(("error estimate", f"{est['ratio']:.3g} tolerance units at t_end against the {est['against']} "
                                           f"(bound {est['bound']:g})"))
        cond = (est or {}).get("conditioning")
        if cond is not None:
            rows.append(("conditioning probe", "failed" if cond["ratio"] is None else
                         f"{cond['ratio']:.3g} tolerance units at t_end from y0 moved {cond['ulps']:g} ulp "
                         f"(flagged above {cond['flag_above']:g})"))
        rows += [("  disagrees", r) for r in check.reasons]
    width = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"{k:<{width}}  {v}")
    print("final state:")
    for name, v in zip(sim.state_names, sim.y_end):
        unit = u.states.get(name, "1")
        print(f"  {name:<{width - 2}}  {v: .10g}" + ("" if unit == "1" else f" {unit}"))
    if out is not None and sim.ok:
        print(f"wrote {out}/trajectory.npz, trajectory.csv, trajectory.png")
