"""`adbgen stability` and `adbgen continue`: steady states, their stability, and continuation.

    adbgen stability MODEL [--scene FILE] [--set NAME=VALUE]... [--y0 NAME=VALUE]... | [--state LABEL]
                     [--scan NAME=FROM:TO] [--json]
    adbgen continue MODEL --par NAME [--par2 NAME2] [--set NAME=VALUE]... [--to VALUE] [--range2 LO:HI] [--json]

Bad input: one line on stderr, exit 2 (AnalysisError through `adbgen.cli.main`).  The states they
start from are `adbgen.analysis.starts`'.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..analysis.loading import AnalysisError, parse_assignments, parse_value
from .arguments import Commands, _emit_json, _load, _model_arguments

command = Commands()
register = command.register


def _fmt(z: complex) -> str:
    return f"{z.real: .9f} {'+' if z.imag >= 0 else '-'} {abs(z.imag):.9f}i"


def _scan_range(text: str, model) -> tuple[str, float, float]:
    name, sep, rng = str(text).partition("=")
    lo, sep2, hi = rng.partition(":")
    if not sep or not sep2 or not name.strip():
        raise AnalysisError(f"--scan: expected NAME=FROM:TO, got {text!r}")
    name = name.strip()
    if name not in model.param_names:
        raise AnalysisError(f"--scan: {name!r} is not a parameter of {model.name}; parameters: "
                            f"{', '.join(model.param_names)}")
    a, b = parse_value(lo, f"--scan {name} FROM"), parse_value(hi, f"--scan {name} TO")
    if a == b:
        raise AnalysisError(f"--scan: empty range {name}={lo}:{hi}")
    return name, a, b


# -------------------------------------------------------------------------------------- stability

@command("stability", "refine a steady state of a generated model, its eigenvalues and stability; "
                      "with --scan, Hopf points, folds and stable intervals along a parameter (thesis ch. 3-4)")
def _add_stability(p) -> None:
    _model_arguments(p)
    p.add_argument("--y0", action="append", default=[], metavar="NAME=VALUE",
                   help="the initial guess by state name (repeatable); states not given are 0")
    p.add_argument("--state", metavar="LABEL",
                   help="start from `start` (the model's START, default) or one of the model's closed-form steady "
                        "states by label (its STEADY_STATES; the thesis models': 1 (balanced (3.6)), 2+, 2- (3.9), "
                        "3(k)+, 3(k)- (3.10, k balls opposite))")
    p.add_argument("--scan", metavar="NAME=FROM:TO",
                   help="follow the state from NAME = FROM to TO (pseudo-arclength), locate Hopf points and folds")
    p.add_argument("--ds-max", type=float, default=0.01, help="largest continuation step (default 0.01)")
    p.add_argument("--out", help="with --scan: a folder for scan.csv (the branch: parameter, leading real part, "
                                 "number unstable, rotor amplitude) and scan.png")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.set_defaults(fn=run_stability)


def run_stability(args) -> int:
    from ..analysis import continuation, steady
    from ..analysis.continuation import write_scan
    from ..analysis.starts import start_state

    model = _load(args)
    steady._require_autonomous(model)
    values = parse_assignments(args.set, "--set")
    if not (args.ds_max > 0 and math.isfinite(args.ds_max)):
        raise AnalysisError(f"--ds-max must be a finite number > 0, got {args.ds_max}")
    scan = _scan_range(args.scan, model) if args.scan else None
    if args.out is not None and scan is None:
        raise AnalysisError("--out needs --scan")
    p = model.params(values)
    if scan:
        p[model.param_names.index(scan[0])] = scan[1]
    if args.y0 and args.state:
        raise AnalysisError("give --y0 or --state, not both")
    y0, label = start_state(model, p, parse_assignments(args.y0, "--y0"), args.state)
    if scan is None:
        st = steady.refine(model, p, y0, label=label)
        if args.json:
            _emit_json(st.to_json())
        else:
            _print_steady(st)
        return 0
    name, a, b = scan
    result = continuation.scan(model, p, y0, name, a, b, ds_max=args.ds_max)
    if args.out is not None:
        write_scan(result, Path(args.out))
    if args.json:
        _emit_json({**result.to_json(), "state_label": label})
    else:
        _print_scan(result)
    return 0


def _print_steady(st) -> None:
    m = st.model
    print(f"model {m.name}: steady state ({st.label}), |rhs| = {st.residual:.2e} after {st.iterations} Newton steps")
    print("parameters: " + ", ".join(f"{k} = {v:g}" for k, v in zip(m.param_names, st.p)))
    for name, v in zip(m.state_names, st.y):
        print(f"  {name:<12} {v: .12g}")
    k = st.tangent.shape[1]
    extra = f", {st.n_unstable} unstable" if st.classification == "unstable" else ""
    print(f"classification: {st.classification}{extra}"
          + (f" (transverse to the {k}-dimensional family of balanced states (3.6))" if k else ""))
    print("eigenvalues" + (" (transverse)" if k else "") + ":")
    for z in st.transverse:
        print("  " + _fmt(z))
    if k:
        print(f"neutral (along the family, |J T| = {st.tangent_residual:.1e}):")
        for z in st.neutral:
            print("  " + _fmt(z))


def _print_scan(result) -> None:
    print(f"model {result.model.name}: {result.name} from {result.start:g} to {result.stop:g}, "
          f"{len(result.branch)} steps ({result.end_reason})")
    for b in result.points:
        freq = "" if b.frequency is None else f", frequency {b.frequency:.9g}"
        print(f"  {b.kind:<5} {result.name} = {b.value:.10g}{freq}, {b.direction or 'stability unchanged'}")
    for b in result.branch_points:
        print(f"  branch point {result.name} = {b.value:.10g}")
    intervals = ", ".join(f"[{a:.7g}, {b:.7g}]" for a, b in result.stable_intervals) or "none"
    print(f"stable for {result.name} in {intervals}")


# --------------------------------------------------------------------------------------- continue

@command("continue", "continue the model's START in one parameter with AUTO-07p (labelled points, stability); "
                     "with --par2, curves of Hopf points and folds in two parameters and codimension-two points")
def _add_continue(p) -> None:
    _model_arguments(p)
    p.add_argument("--par", required=True, metavar="NAME", help="the continuation parameter")
    p.add_argument("--par2", metavar="NAME2", help="second parameter: continue each Hopf point and fold in (NAME, NAME2)")
    p.add_argument("--to", metavar="VALUE", help="continue --par from its start value to VALUE "
                                                 "(default: half the start value)")
    p.add_argument("--range2", metavar="LO:HI", help="bounds of --par2 (default 0 to ten times its value)")
    p.add_argument("--state", metavar="LABEL",
                   help="start from `start` (START, default) or one of the model's closed-form steady states at the "
                        "--set parameters, by label (its STEADY_STATES; n >= 3 balls: only the balanced family's "
                        "member of the AUTO files, whose func pins phi_3.. at START's values)")
    p.add_argument("--keep", metavar="DIR", help="run AUTO in DIR and keep its files (fort.7, fort.8, ...)")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.set_defaults(fn=run_continue)


def run_continue(args) -> int:
    from ..analysis import auto, steady
    from ..analysis.starts import follower, pinned_start

    model = _load(args)
    steady._require_autonomous(model)
    if getattr(model.module, "START", None) is None:
        raise AnalysisError(f"{model.name} has no START state to continue from")
    values = parse_assignments(args.set, "--set")
    for name in (args.par, args.par2):
        if name is not None and name not in model.param_names:
            raise AnalysisError(f"{name!r} is not a parameter of {model.name}; parameters: "
                                f"{', '.join(model.param_names)}")
    p = model.params({**dict(zip(model.param_names, model.module.START_PARAMETERS)), **values})
    to = parse_value(args.to, "--to") if args.to is not None else None
    range2 = None
    if args.range2 is not None:
        if args.par2 is None:
            raise AnalysisError("--range2 needs --par2")
        lo, sep, hi = args.range2.partition(":")
        if not sep:
            raise AnalysisError(f"--range2: expected LO:HI, got {args.range2!r}")
        range2 = (parse_value(lo, "--range2 LO"), parse_value(hi, "--range2 HI"))
        if not range2[0] < range2[1]:
            raise AnalysisError(f"--range2: LO must be below HI, got {args.range2!r}")
    if args.state in (None, "start"):
        y = pinned_start(model, p)
    else:
        from ..analysis.starts import labelled_state

        y = labelled_state(model, args.state, p)
        y, _ = steady.newton(model, p, y)
        start = np.asarray(model.module.START, float)
        free = list(model.role_indices("ball_angle"))[2:] if steady.on_balanced_family(model, start) else []
        if free and np.max(np.abs(np.angle(np.exp(1j * (y[free] - start[free]))))) > 1e-9:
            raise AnalysisError(f"state {args.state}: {model.name}'s AUTO files pin the free angles "
                                f"{', '.join(model.state_names[i] for i in free)} at START's values (the regularised "
                                f"balanced continuum), which this state does not share; use stability --scan")
    if args.par2 is None:
        if args.keep:
            with auto.Session(model, keep=args.keep) as session:
                run = auto.continue_one(model, args.par, p, y, to, session=session)
        else:
            run = auto.continue_one(model, args.par, p, y, to)
        out = {"model": model.name, "parameter": args.par, "points": run.to_json()}
    else:
        curves = auto.continue_two(model, args.par, args.par2, p, y, to, range2)
        curves.double_hopf = auto.double_hopf_points(model, curves.curves, p, args.par, args.par2,
                                                     follower(model, y))
        out = {"model": model.name, "parameter": args.par, "parameter2": args.par2,
               "points": curves.one.to_json(), **curves.to_json()}
    if args.json:
        _emit_json(out)
    else:
        _print_continue(out, args.par, args.par2)
    return 0


def _print_continue(out, name, name2) -> None:
    print(f"model {out['model']}: AUTO-07p in {name}")
    for pt in out["points"]:
        freq = f", frequency {pt['frequency']:.9g}" if pt.get("frequency") else ""
        print(f"  {pt['label']:>3} {pt['type']:<3} {name} = {pt[name]:.10g}  {pt['stability']}{freq}")
    if name2:
        for c in out["curves"]:
            pts = c["points"]
            print(f"  {c['kind']} curve from {name} = {c['origin'][name]:.8g}: {len(pts)} points")
        for s in out["special"]:
            print(f"  {s['type']} ({s['name']}) at {name} = {s[name]:.8g}, {name2} = {s[name2]:.8g}")
