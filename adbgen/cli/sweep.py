"""`adbgen sweep`: a grid of trajectories or steady states on Dask, into a resumable Zarr store.

    adbgen sweep MODEL|--scene FILE --grid NAME=FROM:TO:COUNT [--grid ...] [--set NAME=VALUE]... [--y0 NAME=VALUE]...
                 --measure {attractor,r_max,t_dec,stability} [--t-end T] [--rtol R] --out DIR
                 [--scheduler ADDRESS | --workers N] [--check-tolerance] [--residual-measure NAME] [--json]

--json prints {"points", "computed", "reused", "wall_s", "store"} (and a few more keys).  With
--check-tolerance every point is computed again at rtol/100, atol/100 and on a second engine, and the
summary adds "tolerance_sensitive" (the count of points whose outcome differs) and "tolerance_check".  An
r_max or t_dec sweep's summary has "failed": the points whose run failed (no value, not "not settled").
"""

from __future__ import annotations

import argparse

from .arguments import Commands, _emit_json, _finite_positive, _positive_int, _quantity_text

command = Commands()
register = command.register


@command("sweep", "sweep parameters or initial states on Dask: basins, r_max/t_dec maps, stability maps")
def _add_sweep(p) -> None:
    from ..analysis.engines import DEFAULT, ENGINES
    from ..analysis.sweep import MEASURES

    p.add_argument("model", nargs="?", help="a generated model's name (one of generated/) or a model folder")
    p.add_argument("--scene", help="scene file (TOML) instead of MODEL: its smallest exact model, generated once "
                                   "into a cache (a speed schedule's values are parameters: --set, --grid)")
    p.add_argument("--grid", action="append", default=[], metavar="NAME=FROM:TO:COUNT",
                   help="a grid axis over a parameter or an initial state (repeatable; FROM and TO included, "
                        "numbers or expressions in pi)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", help="a fixed parameter")
    p.add_argument("--y0", action="append", default=[], metavar="NAME=VALUE",
                   help="a fixed initial state (states not given are 0)")
    p.add_argument("--tie", action="append", default=[], metavar="NAME=AXIS+OFFSET",
                   help="an initial state that follows a state axis, e.g. phi_3=phi_1+pi (thesis Fig. 5.19)")
    p.add_argument("--measure", required=True, choices=MEASURES,
                   help="attractor (where each trajectory ends), r_max, t_dec, or stability (spectrum of "
                        "the steady state continued from the model's START; no integration)")
    p.add_argument("--t-end", type=_quantity_text("--t-end"), metavar="T",
                   help="end time: a number in the model's time unit, a time (20s) or revolutions (640rev); default "
                        "2000/pi revolutions at the model's speed with --set (the thesis' t = 1000 at Omega = 4)")
    p.add_argument("--rtol", type=_finite_positive, default=1e-8, help="relative tolerance (default 1e-8)")
    p.add_argument("--atol", type=_finite_positive, default=1e-10, help="absolute tolerance (default 1e-10)")
    p.add_argument("--threshold", type=_quantity_text("--threshold"), metavar="H",
                   help="t_dec threshold: a number in the model's length unit or a length (0.05mm); default a "
                        "tenth of the eccentricity with --set (the thesis' 1e-3)")
    p.add_argument("--engine", default=DEFAULT, choices=sorted(ENGINES), metavar="E",
                   help=f"integration engine (default {DEFAULT})")
    p.add_argument("--out", required=True, help="folder: the store DIR/sweep.zarr and the figures")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler, e.g. tcp://host:8786")
    where.add_argument("--workers", type=_positive_int, default=None,
                       help="cores of the local cluster (default: all this process may use)")
    p.add_argument("--no-early-stop", dest="early_stop", action="store_false",
                   help="integrate every trajectory to t_end (attractor: no stop in a provable basin region)")
    p.add_argument("--no-symmetry", dest="symmetry", action="store_false",
                   help="integrate both of each pair of ball-swapped grid points")
    p.add_argument("--check-dt", type=_finite_positive, default=10.0,
                   help="attractor: integration segment between early-stop checks (default 10)")
    p.add_argument("--stop-region", choices=("lyapunov", "contraction"), default="lyapunov",
                   help="attractor: provable basin regions for the early stop, by the nonlinear Lyapunov "
                        "decrease condition (default, larger) or by contraction (smaller)")
    p.add_argument("--chunk", type=_positive_int, default=None,
                   help="grid points per task and store chunk (about; default: 16-256, 8 tasks per core)")
    p.add_argument("--no-figures", dest="figures", action="store_false", help="do not draw the figures")
    p.add_argument("--check-tolerance", action="store_true",
                   help="attractor, r_max, t_dec: every point again at rtol/100, atol/100 and on a second engine "
                        "of another method; points whose label (value: beyond 1 %%) differs are flagged "
                        "(tolerance_sensitive: stored, counted, marked on the figures)")
    p.add_argument("--residual-measure", default=None, metavar="NAME",
                   help="--measure residual: which of the model's measures at t_end is the residual imbalance "
                        "(default: the one the model names, its RESIDUAL_MEASURE: r, the rotor's amplitude, in one "
                        "plane; A, which also sees the tilt, in two)")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout, no progress bar")
    p.set_defaults(fn=run_sweep_command)


def _time_and_threshold(args) -> tuple[float, float]:
    """--t-end and --threshold in the model's units, or their defaults at the --set parameters."""
    from ..analysis.loading import load_model
    from ..analysis.units import assignments, default_t_end, default_threshold, duration, quantity, units

    model = load_model(args.model)
    u = units(model)
    p = model.params(assignments(args.set, "--set", u.params))
    t_end = duration(args.t_end, model, p) if args.t_end else default_t_end(model, p)[0]
    threshold = quantity(args.threshold, u.length, "--threshold") if args.threshold else default_threshold(model, p)[0]
    return t_end, threshold


def run_sweep_command(args: argparse.Namespace) -> int:
    import os

    from ..analysis.sweep import SweepSpec, run_sweep
    from ..outputs import output_folder

    output_folder(args.out, "--out")
    if args.scene is not None or args.model is None:  # the scene's model (or the loader's one-line refusal)
        from .arguments import _load

        args.model = str(_load(args, show_progress=not args.json).folder)
    model = args.model
    if os.sep in model or os.path.isdir(model):
        model = os.path.abspath(model)  # workers load it by path
    t_end, threshold = _time_and_threshold(args)
    spec = SweepSpec(model=model, grid=list(args.grid), measure=args.measure, set=list(args.set),
                     y0=list(args.y0), tie=list(args.tie), t_end=t_end, rtol=args.rtol, atol=args.atol,
                     threshold=threshold, engine=args.engine, early_stop=args.early_stop,
                     symmetry=args.symmetry, check_dt=args.check_dt, stop_region=args.stop_region,
                     chunk=args.chunk, check_tolerance=args.check_tolerance,
                     residual_measure=args.residual_measure)
    summary = run_sweep(spec, args.out, scheduler=args.scheduler, workers=args.workers, progress=not args.json,
                        figures=args.figures)
    if args.json:
        _emit_json(summary)
    else:
        print(f"{summary['points']} points: {summary['computed']} computed ({summary['integrated']} integrated), "
              f"{summary['reused']} reused, {summary['wall_s']:.2f} s; store {summary['store']}")
        if summary.get("failed"):
            print(f"{summary['failed']} points failed: no value (marked on the figure, never drawn as one)")
        if "tolerance_sensitive" in summary:
            c = summary["tolerance_check"]
            print(f"tolerance check: {summary['tolerance_sensitive']} of {c['checked']} points tolerance-sensitive "
                  f"(outcome differs at rtol {c['rtol']:g} or on {c['second_engine']})")
        for f in summary["figures"]:
            print(f"wrote {f}")
    return 0
