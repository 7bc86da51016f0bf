"""`adbgen stability` and `adbgen continue`: steady states, their stability, and continuation.

    adbgen stability MODEL [--scene FILE] [--set NAME=VALUE]... [--y0 NAME=VALUE]... | [--state LABEL]
                     [--scan NAME=FROM:TO] [--json]
    adbgen continue MODEL --par NAME [--par2 NAME2] [--set NAME=VALUE]... [--to VALUE] [--range2 LO:HI] [--json]

Bad input: one line on stderr, exit 2 (AnalysisError through `adbgen.cli.main`).  The states they
start from are `adbgen.analysis.starts`'; the state they follow is named (`adbgen.analysis.identify`: JSON
followed_state, state_distance, identified_by) and a start that is not the one asked for (--state, or
START's) is refused; every verdict carries its margin (`adbgen.analysis.margins`).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from ..analysis.loading import AnalysisError
from ..analysis.units import assignments, show
from ..outputs import output_folder
from ..progress import activity, bar as progress_bar, wanted
from .arguments import Commands, _emit_json, _finite_positive, _load, _model_arguments, _positive_int, quantity_pair
from .orbit import add_continue_options, print_orbits

command = Commands()
register = command.register

# the default largest continuation step (in (state, parameter)): the parameter's range in this many steps
# (0.857 for omega from 400 to 100 rad/s), but at least STATE_STEP, what a step may move the state (the
# angles, in rad) by, the step of before (the thesis' scans: Omega from 4 to 0.5 takes 350 steps either
# way; a branch whose angles turn at a fold, mu from 0.05 to 0.002, needs the state's step, not 1/350 of
# its parameter range); AUTO-07p's runs take five times as many
STEPS_PER_RANGE = 350
STATE_STEP = 0.01
AUTO_STEPS_PER_RANGE = 1750
ENDED_EARLY = 3  # exit status of a scan or continuation that stopped before its range (`adbgen --help`)


def _fmt(z: complex) -> str:
    return f"{z.real: .9f} {'+' if z.imag >= 0 else '-'} {abs(z.imag):.9f}i"


def _start(model, args, p):
    """(state vector, label): --y0 (states not given 0, values with units), --state LABEL, or START."""
    from ..analysis.starts import start_state
    from ..analysis.units import units

    if args.y0 and args.state:
        raise AnalysisError("give --y0 or --state, not both")
    return start_state(model, p, assignments(args.y0, "--y0", units(model).states), args.state)


def _scan_range(text: str, model) -> tuple[str, float, float]:
    name, sep, rng = str(text).partition("=")
    if not sep or ":" not in rng or not name.strip():
        raise AnalysisError(f"--scan: expected NAME=FROM:TO, got {text!r}")
    name = name.strip()
    if name not in model.param_names:
        raise AnalysisError(f"--scan: {name!r} is not a parameter of {model.name}; parameters: "
                            f"{', '.join(model.param_names)}")
    from ..analysis.units import units

    a, b = quantity_pair(rng, units(model).params[name], "--scan", "NAME=FROM:TO",
                         (f"--scan {name} FROM", f"--scan {name} TO"))
    if a == b:
        raise AnalysisError(f"--scan: empty range {name}={rng}")
    return name, a, b


# -------------------------------------------------------------------------------------- stability

@command("stability", "refine a steady state of a generated model, its eigenvalues and stability; "
                      "with --scan, Hopf points, folds and stable intervals along a parameter (thesis ch. 3-4); "
                      "a forced model: its periodic response and Floquet multipliers (AUTO-07p, shooting); exit "
                      "status 3: the scan ended before TO")
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
    p.add_argument("--ds-max", type=_finite_positive, metavar="DS",
                   help="largest continuation step in (state, parameter) (default |TO - FROM| / "
                        f"{STEPS_PER_RANGE}, at least {STATE_STEP}: 0.857 for omega from 400 to 100 rad/s)")
    p.add_argument("--max-steps", type=_positive_int, default=20000,
                   help="continuation steps at most (default 20000); a scan stopped by it exits with status 3")
    p.add_argument("--out", help="with --scan: a folder for scan.csv (the branch: parameter, leading real part, "
                                 "number unstable, rotor amplitude) and scan.png")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(fn=run_stability)


def run_stability(args) -> int:
    from ..analysis import equilibrium_scan, steady
    from ..analysis.orbits.first_lyapunov import add_to_scan
    from ..analysis.units import params, units

    if args.out is not None:
        if not args.scan:
            raise AnalysisError("--out needs --scan")
        output_folder(args.out, "--out")
    show_progress = wanted(args.quiet, args.json)
    model = _load(args, show_progress)
    values = assignments(args.set, "--set", units(model).params)
    p = params(model, values)
    if not model.autonomous:
        return _forced_stability(model, p, args, show_progress)
    scan = _scan_range(args.scan, model) if args.scan else None
    if scan:
        p[model.param_names.index(scan[0])] = scan[1]
    y0, label = _start(model, args, p)
    y0, followed = _followed_start(model, p, y0, label)
    if scan is None:
        st = steady.refine(model, p, y0, label=label)
        u = units(model)
        if args.json:
            _emit_json({**st.to_json(), **followed.to_json(), "units": {"state": u.states, "parameters": u.params,
                                                                         "eigenvalues": "1" if u.time == "1" else f"1/{u.time}"}})
        else:
            _print_steady(st, followed)
        return 0
    name, a, b = scan
    ds_max = args.ds_max if args.ds_max is not None else max(abs(b - a) / STEPS_PER_RANGE, STATE_STEP)
    unit = units(model).params[name]
    with progress_bar(abs(b - a), f"{model.name}: {name} from {show(a, unit)} to {show(b, unit)}",
                      show_progress) as update:
        result = equilibrium_scan.scan(model, p, y0, name, a, b, ds=ds_max / 2, ds_max=ds_max, ds_min=ds_max * 1e-5,
                                   max_steps=args.max_steps, progress=lambda lam: update(abs(lam - a)))
    add_to_scan(result)
    if args.out is not None:
        write_scan(result, Path(args.out), values=values, scene=args.scene)
    if args.json:
        _emit_json({**result.to_json(), "state_label": label, "ds_max": ds_max, "max_steps": args.max_steps,
                    "units": {name: unit, "amplitude": units(model).length}, **followed.to_json()})
    else:
        print(_follows(followed))
        _print_scan(result, unit)
    if not result.complete:
        print(f"adbgen: ended early: {_scan_end(result, ds_max, args.max_steps, unit)}", file=sys.stderr)
        return ENDED_EARLY
    return 0


def _followed_start(model, p, y0, label: str):
    """(the start, its Identity at p once refined): the state the run follows, checked to be the one asked for
    (--state LABEL, or the state START is at START_PARAMETERS when it starts from START; a --y0 start is only
    named).  From START, where Newton lands on another state, START carried to p (`starts.default_start`) is
    tried before the run is refused (one line naming the state found)."""
    from ..analysis import steady
    from ..analysis.identify import check, default_label, identify
    from ..analysis.starts import default_start

    required = default_label(model) if label == "start" else None if label == "y0" else label
    y, _ = steady.newton(model, p, y0)
    if required is not None and label == "start" and identify(model, y, p).label != required:
        y0 = y = default_start(model, p, carried=True)
    return y0, check(model, y, p, required)


def _follows(found) -> str:
    if found.label is None:
        return "follows: a steady state that is none of the model's labelled ones"
    return f"follows: state {found.label} (distance {found.distance:.2g}, by its {found.how})"


def _scan_end(result, ds_max: float, max_steps: int, unit: str) -> str:
    """Why and where a scan stopped before TO."""
    name, at = result.name, result.end_at
    why = (f"the step limit ({max_steps} steps of at most {ds_max:.3g}; raise --max-steps or --ds-max)"
           if result.end_reason == "step limit" else
           "the step size fell below its minimum (Newton failed on shorter and shorter steps: a singular point?)")
    return (f"{name} reached {show(at, unit, 8)} of {show(result.start, unit)} -> {show(result.stop, unit)}: stopped by "
            f"{why}; the stable intervals cover only the part scanned")


def _forced_stability(model, p, args, show_progress) -> int:
    """`adbgen stability` on a periodically forced model: its periodic response at p and the response's
    Floquet multipliers (`auto_orbits.forced_response`)."""
    from ..analysis import auto_orbits

    if args.scan:
        raise AnalysisError(f"{model.name} is periodically forced: follow its response along a parameter with "
                            f"`adbgen continue {model.name} --par NAME --to VALUE` (AUTO-07p, periodic orbits)")
    if args.y0 or args.state:
        raise AnalysisError(f"{model.name} is periodically forced: its response is found from its AUTO files' "
                            f"start orbit; --y0 and --state do not apply")
    with activity(f"{model.name}: the forced response (AUTO-07p, shooting)", show_progress):
        try:
            response = auto_orbits.forced_response(model, p)
        except auto_orbits.ContinuationEnded as exc:
            print(f"adbgen: ended early: {exc}", file=sys.stderr)
            return ENDED_EARLY
    if args.json:
        _emit_json(response.to_json())
    else:
        _print_response(response)
    return 0


def _print_response(r) -> None:
    from ..analysis.units import show, units

    m, u = r.model, units(r.model)
    print(f"model {m.name}: periodic response (period {show(r.period, u.time, 8)}), |y(T) - y(0)| = "
          f"{r.closure:.1e} after {r.newton_steps} Newton steps on the period map")
    if r.route:
        print("reached by AUTO-07p: " + "; ".join(f"{s['parameter']} from {s['from']:g} to {s['to']:g} ({s['steps']} steps)"
                                                  for s in r.route))
    print(f"max r over the orbit: {show(_rounded(r.amplitude_max), u.length, 6)}")
    # a count of unstable multipliers is part of a verdict: a marginal headline gives none
    extra = f", {r.n_unstable} unstable" if r.classification == "unstable" and not r.margin.marginal else ""
    k = int(r.family.sum())
    print(f"classification: {r.margin.verdict(r.classification)}{extra} (Floquet multipliers, |mu| < 1: stable"
          + (f"; transverse to the {k}-dimensional family of balanced orbits)" if k else ")"))
    mg = r.margin
    print(f"margin: leading |mu| - 1 = {mg.value:.6g}, certain to {mg.uncertainty:.2g}"
          + (" (MARGINAL: inside what the computation can certify)" if mg.marginal else ""))
    print("multipliers (|mu|)" + (" (transverse)" if k else "") + ":")
    for z in sorted(r.transverse, key=lambda z: -abs(z)):
        print(f"  {_fmt(complex(z))}   ({abs(z):.9f})")
    if k:
        print(f"neutral (along the family): {k} x 1")


def _rounded(value: float, floor: float = 1e-15) -> float:
    """A length that is round-off (the rotor at rest on a balanced orbit) printed as 0."""
    return 0.0 if abs(value) < floor else value


def _print_steady(st, followed=None) -> None:
    from ..analysis.units import units

    m = st.model
    u = units(m)
    print(f"model {m.name}: steady state ({st.label}), |rhs| = {st.residual:.2e} after {st.iterations} Newton steps")
    if followed is not None:
        print(_follows(followed))
    print("parameters: " + ", ".join(f"{k} = {show(v, u.params[k], 6)}" for k, v in zip(m.param_names, st.p)))
    for name, v in zip(m.state_names, st.y):
        print(f"  {name:<12} {v: .12g}" + ("" if u.states[name] == "1" else f" {u.states[name]}"))
    k = st.tangent.shape[1]
    marginal = st.margin is not None and st.margin.marginal
    extra = f", {st.n_unstable} unstable" if st.classification == "unstable" and not marginal else ""
    verdict = st.margin.verdict(st.classification) if marginal else st.classification
    print(f"classification: {verdict}{extra}"
          + (f" (transverse to the {k}-dimensional family of balanced states (3.6))" if k else ""))
    if st.margin is not None:
        mg = st.margin
        print(f"margin: leading real part {mg.value:.6g}, certain to {mg.uncertainty:.2g}"
              + (" (MARGINAL: inside what the computation can certify)" if mg.marginal else ""))
    print("eigenvalues" + (" (transverse)" if k else "") + ":")
    for z in st.transverse:
        print("  " + _fmt(z))
    if k:
        print(f"neutral (along the family, |J T| = {st.tangent_residual:.1e}):")
        for z in st.neutral:
            print("  " + _fmt(z))


def _print_scan(result, unit: str = "1") -> None:
    state = "" if result.complete else ", ENDED EARLY"
    print(f"model {result.model.name}: {result.name} from {show(result.start, unit)} to {show(result.stop, unit)}, "
          f"{len(result.branch)} steps ({result.end_reason}{state}; last step at {show(result.end_at, unit, 8)})")
    for b in result.points:
        freq = "" if b.frequency is None else f", frequency {b.frequency:.9g}"
        crit = f", {b.extra['criticality']} (l1 = {b.extra['first_lyapunov']:.6g})" if "criticality" in b.extra else ""
        print(f"  {b.kind:<5} {result.name} = {b.value:.10g}{freq}, {b.direction or 'stability unchanged'}{crit}")
    for b in result.branch_points:
        print(f"  branch point {result.name} = {b.value:.10g}")
    intervals = ", ".join(f"[{a:.7g}, {b:.7g}]" for a, b in result.stable_intervals) or "none"
    scanned = "" if result.complete else f" (of the part scanned, down to {result.end_at:.7g})"
    print(f"stable for {result.name} in {intervals}" + ("" if unit == "1" else f" {unit}") + scanned)


# --------------------------------------------------------------------------------------- continue

@command("continue", "continue the model's START in one parameter with AUTO-07p (labelled points, stability); "
                     "with --par2, curves of Hopf points and folds in two parameters and codimension-two points; a "
                     "forced model: its periodic response (both stages of its AUTO files); exit status 3: the "
                     "continuation ended before --to")
def _add_continue(p) -> None:
    _model_arguments(p)
    p.add_argument("--par", required=True, metavar="NAME", help="the continuation parameter")
    p.add_argument("--par2", metavar="NAME2", help="second parameter: continue each Hopf point and fold in (NAME, NAME2)")
    p.add_argument("--to", metavar="VALUE", help="continue --par from its start value to VALUE, a number in the "
                                                 "parameter's unit or a value with a unit (100rad/s) (default: half "
                                                 "the start value; with --par2, the end of the range the model's AUTO "
                                                 "constants continue over, UZSTOP)")
    p.add_argument("--range2", metavar="LO:HI", help="bounds of --par2 (default 0 to ten times its value)")
    p.add_argument("--state", metavar="LABEL",
                   help="start from `start` (START, default) or one of the model's closed-form steady states at the "
                        "--set parameters, by label (its STEADY_STATES; n >= 3 balls: only the balanced family's "
                        "member of the AUTO files, whose func pins phi_3.. at START's values)")
    p.add_argument("--keep", metavar="DIR", help="run AUTO in DIR and keep its files (fort.7, fort.8, ...)")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    add_continue_options(p)
    p.set_defaults(fn=run_continue)


def run_continue(args) -> int:
    from ..analysis import auto07p, steady
    from ..analysis.orbits import branches, run_points
    from . import continue_orbits as glue
    from ..analysis.identify import check, default_label
    from ..analysis.starts import default_start, follower, pinned
    from ..analysis.units import params, quantity, units

    if args.keep is not None:
        output_folder(args.keep, "--keep")
    show_progress = wanted(args.quiet, args.json)
    model = _load(args, show_progress)
    u = units(model)
    for name in (args.par, args.par2):
        if name is not None and name not in model.param_names:
            raise AnalysisError(f"{name!r} is not a parameter of {model.name}; parameters: "
                                f"{', '.join(model.param_names)}")
    values = assignments(args.set, "--set", u.params)
    # --to as given (None: not given), before the defaults below: the chart's range1 reads it so
    given_to = to = quantity(args.to, u.params[args.par], "--to") if args.to is not None else None

    def emit(out):
        _emit_json(out) if args.json else _print_continue(out, args.par, args.par2)
    if not model.autonomous:
        if glue.wants_orbits(args) or args.par2 is not None:  # our own shooting (issue 21)
            return glue.run_forced(args, model, values, given_to, emit)
        return _continue_forced(model, params(model, values), args, to, show_progress)
    if getattr(model.module, "START", None) is None and not args.y0:
        raise AnalysisError(f"{model.name} has no START state to continue from (give --y0)")
    params(model, values)  # each --set value within its domain
    p = model.params({**glue.start_parameters(model), **values})
    k = model.param_names.index(args.par)
    if to is None and args.par2 is not None:  # the whole range the model's AUTO constants continue over
        to = auto07p.default_stop(model, args.par, float(p[k]))
    if to is None:
        to = 0.5 * p[k] if p[k] > 0 else p[k] - 1.0
    pmap = glue.pmap_for(model, p, [args.par, args.par2], args)
    p = pmap([p[j] for j in pmap.index])
    if args.tie and args.par2 is None and np.any(pmap.direction(p[k], 0) != np.eye(model.n_params)[k]):
        raise AnalysisError("--tie: a parameter tied to --par needs --par2 (AUTO-07p's one-parameter run cannot keep "
                            "it tied)")
    range2 = glue.range2_option(args, model)
    required = None  # the labelled state the run must start on (--state, or the one START is)
    if args.y0 and getattr(model.module, "START", None) is None:
        y, _ = steady.newton(model, p, model.state(assignments(args.y0, "--y0", u.states)))
    elif args.state in (None, "start"):
        y = default_start(model, p, pmap, carried=bool(glue.wants_chart(args) or args.tie))
        required = default_label(model)
    else:
        required = args.state
        from ..analysis.starts import labelled_state

        y = labelled_state(model, args.state, p)
        y, _ = steady.newton(model, p, y)
        start = np.asarray(model.module.START, float)
        free = list(model.role_indices("ball_angle"))[2:] if steady.on_balanced_family(model, start) else []
        if free and np.max(np.abs(np.angle(np.exp(1j * (y[free] - start[free]))))) > 1e-9:
            raise AnalysisError(f"state {args.state}: {model.name}'s AUTO files pin the free angles "
                                f"{', '.join(model.state_names[i] for i in free)} at START's values (the regularised "
                                f"balanced continuum), which this state does not share; use stability --scan")
    followed = check(model, y, p, required)
    if glue.wants_chart(args):
        return glue.chart_command(args, model, p, y, given_to, range2, lambda out: emit({**out, **followed.to_json()}))
    ds_max = abs(to - p[k]) / AUTO_STEPS_PER_RANGE
    with activity(f"{model.name}: AUTO-07p in {args.par}", show_progress):
        if args.par2 is None:
            if args.keep:
                with auto07p.Session(model, keep=args.keep) as session:
                    run = auto07p.continue_one(model, args.par, p, y, to, ds=ds_max / 2, ds_max=ds_max, session=session)
            else:
                run = auto07p.continue_one(model, args.par, p, y, to, ds=ds_max / 2, ds_max=ds_max)
            out = {"model": model.name, "parameter": args.par, "points": run.to_json()}
            one = run
        else:
            curves = auto07p.continue_two(model, args.par, args.par2, p, y, to, range2)
            curves.double_hopf = auto07p.double_hopf_points(model, curves.curves, p, args.par, args.par2,
                                                         follower(model, y))
            out = {"model": model.name, "parameter": args.par, "parameter2": args.par2,
                   "points": curves.one.to_json(), **curves.to_json()}
            one = curves.one
    col = one.column()
    last = one.points[-1] if one.points else None
    end_at = last.values[col] if last is not None else float(p[k])
    complete = bool(abs(end_at - to) <= 1e-6 * max(abs(to), abs(to - p[k])))
    out.update({"to": float(to), "complete": complete, "end": last.type if last is not None else "none",
                "end_at": float(end_at), "units": {args.par: u.params[args.par]}, **followed.to_json()})
    follow = lambda q, guess: pinned(model, y, q, guess)  # noqa: E731
    run_points.add_lyapunov(model, out["points"], args.par, p, follow)
    run_points.add_margins(model, out["points"], args.par, p, follow)
    if glue.wants_orbits(args):
        with activity(f"{model.name}: periodic orbits in {args.par} (shooting)", show_progress):
            result, found = glue.continue_orbits(model, args, p, out["points"], args.par, to, follow)
        out.update(result)
        if args.plot and args.par2 is None:
            branches.plot_branches(Path(args.plot), model, args.par, found)
    emit(out)
    if not complete:
        print(f"adbgen: ended early: {auto_end(args.par, end_at, to, u.params[args.par], out['end'])}", file=sys.stderr)
        return ENDED_EARLY
    return 0


def auto_end(name: str, end_at: float, to: float, unit: str, end: str) -> str:
    """Where AUTO-07p stopped, with the parameter's unit only where the model has one (`units.show`)."""
    return f"AUTO-07p stopped at {name} = {show(end_at, unit, 9)} before {show(to, unit, 9)} ({end})"


def _continue_forced(model, p, args, to, show_progress) -> int:
    """`adbgen continue` on a periodically forced model: its AUTO files' stages (`auto_orbits`)."""
    from ..analysis import auto_orbits
    from ..analysis.units import units

    if args.par2 is not None or args.range2 is not None or args.state not in (None, "start"):
        raise AnalysisError(f"{model.name} is periodically forced: `continue` follows its periodic response in one "
                            f"parameter (--par2, --range2 and --state are for steady states)")
    with activity(f"{model.name}: AUTO-07p, periodic orbits in {args.par}", show_progress):
        try:
            run = auto_orbits.continue_orbit(model, args.par, p, to, keep=args.keep)
        except auto_orbits.ContinuationEnded as exc:
            print(f"adbgen: ended early: {exc}", file=sys.stderr)
            return ENDED_EARLY
    out = run.to_json()
    out["units"] = {args.par: units(model).params[args.par], "amplitude_max": units(model).length,
                    "period": units(model).time}
    if args.json:
        _emit_json(out)
    else:
        _print_continue_forced(out, args.par, units(model))
    if not run.complete:
        print(f"adbgen: ended early: {auto_orbits.describe_stage_end(run)}", file=sys.stderr)
        return ENDED_EARLY
    return 0


def _print_continue_forced(out, name, u) -> None:
    unit = u.params[name]
    print(f"model {out['model']}: AUTO-07p, periodic orbits (the forced response) in {name}")
    for st in out["stages"]:
        print(f"  stage in {st['parameter']} from {st['from']:.9g} to {st['to']:.9g}: {st['steps']} steps"
              + ("" if st["reached"] else " (stopped early)"))
    for pt in out["points"]:
        amp = f", max r {show(_rounded(pt['amplitude_max']), u.length, 6)}" if "amplitude_max" in pt else ""
        print(f"  {pt['label']:>3} {pt['type']:<3} {name} = {show(pt[name], unit, 10)}  {pt['stability']}{amp}")
    for pt in out["unlabelled"]:
        print(f"  {pt['type']} at {name} = {show(pt[name], unit, 10)} ({pt['direction']}; {pt['located']})")


def _print_continue(out, name, name2) -> None:
    if out["points"]:
        print(f"model {out['model']}: AUTO-07p in {name}")
    if out.get("followed_state"):
        print(f"  follows: state {out['followed_state']} (distance {out['state_distance']:.2g}, by its "
              f"{out['identified_by']})")
    for pt in out["points"]:
        freq = f", frequency {pt['frequency']:.9g}" if pt.get("frequency") else ""
        crit = f", {pt['criticality']} (l1 = {pt['first_lyapunov']:.6g})" if "criticality" in pt else ""
        margin = f", margin {pt['margin']:.3g}" + (f" MARGINAL (uncertain to {pt['margin_uncertainty']:.2g})"
                                                   if pt["marginal"] else "") if "margin" in pt else ""
        # AUTO's flag is a sign; where the margin cannot support it the row says so first
        verdict = f"marginal (AUTO-07p: {pt['stability']})" if pt.get("marginal") else pt["stability"]
        print(f"  {pt['label']:>3} {pt['type']:<3} {name} = {pt[name]:.10g}  {verdict}{freq}{crit}{margin}")
    print_orbits(out, name)
    if name2:
        for c in out["curves"]:
            pts = c["points"]
            print(f"  {c['kind']} curve from {name} = {c['origin'][name]:.8g}: {len(pts)} points")
        for s in out["special"]:
            print(f"  {s['type']} ({s['name']}) at {name} = {s[name]:.8g}, {name2} = {s[name2]:.8g}")


def write_scan(result, out: Path, values: dict | None = None, scene: str | None = None) -> None:
    """scan.csv (one row per continuation step) and scan.png: the leading real part of the transverse
    spectrum and the rotor amplitude along the parameter, stable stretches solid, Hopf points and folds
    marked and labelled (the thesis' one-parameter diagrams, Fig. 4.2, 4.6, 4.11); each file written
    whole."""
    import io

    from ..analysis.figure_style import latex_name, pyplot, title
    from ..analysis.units import axis_label, units
    from ..outputs import save_figure, writing

    out.mkdir(parents=True, exist_ok=True)
    m = result.model
    u = units(m)
    unit = u.params.get(result.name, "1")
    ix, iy = m.amplitude_indices[:2]
    lam = np.array([b.lam for b in result.branch])
    lead = np.array([float(np.max(b.spectrum.real)) for b in result.branch])
    amp = np.array([float(np.hypot(b.y[ix], b.y[iy])) for b in result.branch])
    amp[amp < 1e-14 * max(1.0, float(np.max(amp)))] = 0.0  # the balanced state: rounding only
    unstable = np.array([b.n_unstable for b in result.branch])
    body = io.StringIO()
    np.savetxt(body, np.column_stack([lam, lead, unstable, amp]), delimiter=",", fmt="%.17g")
    with writing(out / "scan.csv") as fh:
        fh.write(f"# model: {m.name}\n# source_hash: {m.source_hash}\n# scan: {result.name} from {result.start!r} "
                 f"to {result.stop!r}; complete: {str(result.complete).lower()} ({result.end_reason}, last step at "
                 f"{result.end_at!r}); units: {result.name} {unit}, amplitude {u.length}, leading_real_part "
                 f"{'1' if u.time == '1' else '1/' + u.time}\n")
        fh.write(f"{result.name},leading_real_part,n_unstable,amplitude\n")
        fh.write(body.getvalue())
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7.5, 5.5), sharex=True, constrained_layout=True)
    rate = "" if u.time == "1" else f"1/{u.time}"
    balanced = not np.any(amp > 0)
    # on the balanced state r = 0 all along: the lower panel counts the unstable eigenvalues instead
    lower = (unstable.astype(float), "eigenvalues with Re > 0") if balanced else \
        (amp, axis_label("$r = \\sqrt{x^2 + y^2}$", u.length))
    for ax, values_, label in ((a1, lead, axis_label("max Re $\\lambda$ (transverse)", rate)), (a2, *lower)):
        stable = np.where(unstable == 0, values_, np.nan)
        ax.plot(lam, values_, "--", color="C0", lw=0.8, label="unstable")
        ax.plot(lam, stable, "-", color="C0", lw=1.6, label="stable")
        ax.set_ylabel(label)
        for b in result.points:
            ax.axvline(b.value, color="C3" if b.kind == "hopf" else "C2", lw=0.6, ls=":")
    for b in result.points:
        a1.annotate(f"{'H' if b.kind == 'hopf' else 'LP'} {b.value:.6g}", (b.value, 1.0), xycoords=("data", "axes fraction"),
                    textcoords="offset points", xytext=(3, -4), ha="left", va="top", fontsize=7,
                    color="C3" if b.kind == "hopf" else "C2", rotation=90)
    a1.axhline(0.0, color="0.5", lw=0.5)
    a1.legend(loc="best", fontsize=7)
    if balanced:
        a2.set_yticks(range(int(unstable.max()) + 1))
        a2.set_title("r = 0 along the whole branch (the balanced state)", fontsize=8)
    a2.set_xlabel(axis_label(latex_name(result.name), unit))
    if not result.complete:
        for ax in (a1, a2):
            ax.axvspan(min(result.end_at, result.stop), max(result.end_at, result.stop), color="0.9", zorder=0)
        a2.text(0.5 * (result.end_at + result.stop), 0.02, "not scanned", ha="center", va="bottom", fontsize=8,
                color="0.4", transform=a2.get_xaxis_transform())
    name = f"{Path(scene).name} ({m.name})" if scene else m.name
    marks = ", ".join(f"{'H' if b.kind == 'hopf' else 'LP'} {b.value:.6g}" for b in result.points) or "no Hopf point or fold"
    a1.set_title(title(name, values or {}, u.params, f"solid stable, dashed unstable; {marks}"), fontsize=8)
    save_figure(fig, out / "scan.png", dpi=120)
