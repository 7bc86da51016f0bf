"""`adbgen stability` and `adbgen continue`: steady states, their stability, and continuation.

    adbgen stability MODEL [--scene FILE] [--set NAME=VALUE]... [--y0 NAME=VALUE]... | [--state LABEL]
                     [--scan NAME=FROM:TO] [--json]
    adbgen continue MODEL --par NAME [--par2 NAME2] [--set NAME=VALUE]... [--to VALUE] [--range2 LO:HI] [--json]

Bad input: one line on stderr, exit 2 (AnalysisError through `adbgen.cli.main`).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from .command_registry import _emit_json, _load, _model_arguments, command
from .loading import AnalysisError, parse_assignments, parse_value


def _fmt(z: complex) -> str:
    return f"{z.real: .9f} {'+' if z.imag >= 0 else '-'} {abs(z.imag):.9f}i"


def _start(model, args, p):
    """(state vector, label): --y0 (states not given 0), --state LABEL, or the model's START."""
    from . import closed_forms

    if args.y0 and args.state:
        raise AnalysisError("give --y0 or --state, not both")
    if args.y0:
        return model.state(parse_assignments(args.y0, "--y0")), "y0"
    label = args.state or "start"
    if label == "start":
        start = getattr(model.module, "START", None)
        if start is None:
            raise AnalysisError(f"{model.name} has no START state; give --y0 or --state")
        return np.array(start, float), "start"
    return closed_forms.state(model, label, p), label


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
                   help="start from `start` (the model's START, default) or a closed-form state of the thesis "
                        "models: 1 (balanced (3.6)), 2+, 2- (3.9), 3(k)+, 3(k)- (3.10, k balls opposite)")
    p.add_argument("--scan", metavar="NAME=FROM:TO",
                   help="follow the state from NAME = FROM to TO (pseudo-arclength), locate Hopf points and folds")
    p.add_argument("--ds-max", type=float, default=0.01, help="largest continuation step (default 0.01)")
    p.add_argument("--out", help="with --scan: a folder for scan.csv (the branch: parameter, leading real part, "
                                 "number unstable, rotor amplitude) and scan.png")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.set_defaults(fn=run_stability)


def run_stability(args) -> int:
    from . import continuation, steady

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
    y0, label = _start(model, args, p)
    if scan is None:
        st = steady.refine(model, p, y0, label=label)
        if args.json:
            _emit_json(st.to_json())
        else:
            _print_steady(st)
        return 0
    name, a, b = scan
    result = continuation.scan(model, p, y0, name, a, b, ds_max=args.ds_max)
    from .orbits.lyapunov import add_to_scan

    add_to_scan(result)
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


def write_scan(result, out: Path) -> None:
    """scan.csv (one row per continuation step) and scan.png: the leading real part of the transverse
    spectrum and the rotor amplitude along the parameter, stable stretches solid, Hopf points and folds
    marked (the thesis' one-parameter diagrams, Fig. 4.2, 4.6, 4.11)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    m = result.model
    ix, iy = m.amplitude_indices[:2]
    lam = np.array([b.lam for b in result.branch])
    lead = np.array([float(np.max(b.spectrum.real)) for b in result.branch])
    amp = np.array([float(np.hypot(b.y[ix], b.y[iy])) for b in result.branch])
    amp[amp < 1e-14] = 0.0  # the balanced state: rounding only
    unstable = np.array([b.n_unstable for b in result.branch])
    # written under temporary names and renamed: an interrupted run leaves the folder as it was
    with open(out / ".scan.csv.tmp", "w") as fh:
        fh.write(f"# model: {m.name}\n# source_hash: {m.source_hash}\n# scan: {result.name} from {result.start!r} "
                 f"to {result.stop!r}\n")
        fh.write(f"{result.name},leading_real_part,n_unstable,amplitude\n")
        np.savetxt(fh, np.column_stack([lam, lead, unstable, amp]), delimiter=",", fmt="%.17g")
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 5), sharex=True, constrained_layout=True)
    for ax, values, label in ((a1, lead, "max Re $\\lambda$ (transverse)"), (a2, amp, "$r = \\sqrt{x^2 + y^2}$")):
        stable = np.where(unstable == 0, values, np.nan)
        ax.plot(lam, values, "--", color="C0", lw=0.8)
        ax.plot(lam, stable, "-", color="C0", lw=1.6)
        ax.set_ylabel(label)
        for b in result.points:
            ax.axvline(b.value, color="C3" if b.kind == "hopf" else "C2", lw=0.6, ls=":")
    a1.axhline(0.0, color="0.5", lw=0.5)
    a2.set_xlabel(result.name)
    marks = ", ".join(f"{'H' if b.kind == 'hopf' else 'LP'} {b.value:.6g}" for b in result.points)
    a1.set_title(f"{m.name}: solid stable, dashed unstable; {marks}", fontsize=8)
    fig.savefig(out / ".scan.png.tmp", dpi=120, format="png")
    plt.close(fig)
    os.replace(out / ".scan.csv.tmp", out / "scan.csv")
    os.replace(out / ".scan.png.tmp", out / "scan.png")


def _print_scan(result) -> None:
    print(f"model {result.model.name}: {result.name} from {result.start:g} to {result.stop:g}, "
          f"{len(result.branch)} steps ({result.end_reason})")
    for b in result.points:
        freq = "" if b.frequency is None else f", frequency {b.frequency:.9g}"
        crit = f", {b.extra['criticality']} (l1 = {b.extra['first_lyapunov']:.6g})" if "criticality" in b.extra else ""
        print(f"  {b.kind:<5} {result.name} = {b.value:.10g}{freq}, {b.direction or 'stability unchanged'}{crit}")
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
    p.add_argument("--to", metavar="VALUE", help="continue --par from its start value to VALUE (default: half the "
                                                 "start value; with --par2, the end of the range the model's AUTO "
                                                 "constants continue over, UZSTOP)")
    p.add_argument("--range2", metavar="LO:HI", help="bounds of --par2 (default 0 to ten times its value)")
    p.add_argument("--state", metavar="LABEL",
                   help="start from `start` (START, default) or, for the thesis models, a closed-form state at the "
                        "--set parameters: 1, 2+, 2-, 3(k)+, 3(k)- (n >= 3: only the balanced family's member of the "
                        "AUTO files, whose func pins phi_3.. at START's values)")
    p.add_argument("--keep", metavar="DIR", help="run AUTO in DIR and keep its files (fort.7, fort.8, ...)")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    from .orbits import continue_command

    continue_command.add_options(p)
    p.set_defaults(fn=run_continue)


def _pinned(model, y0, p, guess=None):
    """The steady state near `guess` (default y0) at p; on the n >= 3 balanced family with the free
    angles kept at y0's (the member AUTO's regularised func follows)."""
    from . import steady

    free = list(model.angle_indices)[2:] if steady.on_balanced_family(model, y0) else []
    extra = None
    if free:
        rows = np.zeros((len(free), model.n_states))
        rows[range(len(free)), free] = 1.0
        extra = (lambda y: y[free] - y0[free], lambda y: rows)
    y, _ = steady.newton(model, p, y0 if guess is None else guess, extra=extra)
    return y


def _pinned_start(model, p):
    """START, re-solved at p (see `_pinned`)."""
    y0 = np.array(model.module.START, float)
    return y0 if np.array_equal(p, model.module.START_PARAMETERS) else _pinned(model, y0, p)


def _follower(model, y0):
    """p -> the followed steady state at p: the balanced state (3.6) from its closed form where y0 is
    one (x = y = 0), else Newton from y0."""
    from . import closed_forms, steady

    core = [model.index(c) for c in model.module.CORE]
    balanced = closed_forms.is_thesis_model(model) and np.max(np.abs(y0[core])) < 1e-12

    def at(p):
        guess = None
        if balanced:
            guess = closed_forms.state(model, "1", p)
            if steady.on_balanced_family(model, y0):
                guess[list(model.angle_indices)[2:]] = y0[list(model.angle_indices)[2:]]
        return _pinned(model, y0, p, guess)
    return at


def run_continue(args) -> int:
    from . import auto, steady
    from .orbits import continue_command

    model = _load(args)

    def emit(out):
        _emit_json(out) if args.json else _print_continue(out, args.par, args.par2)
    if not model.autonomous:  # a forced model: its forced response (periodic orbits), not steady states
        return continue_command.run_forced(args, model, emit)
    if getattr(model.module, "START", None) is None and not args.y0:
        raise AnalysisError(f"{model.name} has no START state to continue from (give --y0)")
    values = parse_assignments(args.set, "--set")
    for name in (args.par, args.par2):
        if name is not None and name not in model.param_names:
            raise AnalysisError(f"{name!r} is not a parameter of {model.name}; parameters: "
                                f"{', '.join(model.param_names)}")
    p = model.params({**continue_command._start_parameters(model), **values})
    to = parse_value(args.to, "--to") if args.to is not None else None
    if to is None and args.par2 is not None:  # the whole range the model's AUTO constants continue over
        to = auto.default_stop(model, args.par, float(p[model.param_names.index(args.par)]))
    if args.range2 is not None and args.par2 is None:
        raise AnalysisError("--range2 needs --par2")
    range2 = continue_command.parse_range2(args.range2)
    pmap = continue_command.pmap_for(model, p, [args.par, args.par2], args)
    p = pmap([p[k] for k in pmap.index])
    if args.tie and args.par2 is None and np.any(pmap.direction(p[pmap.index[0]], 0) != np.eye(model.n_params)[pmap.index[0]]):
        raise AnalysisError("--tie: a parameter tied to --par needs --par2 (AUTO-07p's one-parameter run cannot keep it tied)")
    if args.y0 and getattr(model.module, "START", None) is None:
        y, _ = steady.newton(model, p, model.state(parse_assignments(args.y0, "--y0")))
    elif args.state in (None, "start"):
        y = continue_command.carried_start(model, p, pmap) if (continue_command.wants_chart(args) or args.tie) \
            else _pinned_start(model, p)
    else:
        from . import closed_forms

        y = closed_forms.state(model, args.state, p)
        y, _ = steady.newton(model, p, y)
        start = np.asarray(model.module.START, float)
        free = list(model.angle_indices)[2:] if steady.on_balanced_family(model, start) else []
        if free and np.max(np.abs(np.angle(np.exp(1j * (y[free] - start[free]))))) > 1e-9:
            raise AnalysisError(f"state {args.state}: {model.name}'s AUTO files pin the free angles "
                                f"{', '.join(model.state_names[i] for i in free)} at START's values (the regularised "
                                f"balanced continuum), which this state does not share; use stability --scan")
    if continue_command.wants_chart(args):
        return continue_command.chart_command(args, model, p, y, emit)
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
                                                     _follower(model, y))
        out = {"model": model.name, "parameter": args.par, "parameter2": args.par2,
               "points": curves.one.to_json(), **curves.to_json()}
    continue_command.add_lyapunov(model, out["points"], args.par, p, lambda q, guess: _pinned(model, y, q, guess), args)
    if continue_command.wants_orbits(args):
        result, branches = continue_command.continue_orbits(model, args, p, out["points"], args.par, to,
                                                            lambda q, guess: _pinned(model, y, q, guess))
        out.update(result)
        if args.plot and args.par2 is None:
            continue_command.plot_branches(Path(args.plot), model, args.par, branches)
    emit(out)
    return 0


def _print_continue(out, name, name2) -> None:
    if out["points"]:
        print(f"model {out['model']}: AUTO-07p in {name}")
    for pt in out["points"]:
        freq = f", frequency {pt['frequency']:.9g}" if pt.get("frequency") else ""
        crit = f", {pt['criticality']} (l1 = {pt['first_lyapunov']:.6g})" if "criticality" in pt else ""
        print(f"  {pt['label']:>3} {pt['type']:<3} {name} = {pt[name]:.10g}  {pt['stability']}{freq}{crit}")
    for i, br in enumerate(out.get("orbits", [])):
        origin = br["from"]
        lam = br["parameter"]
        span = f"{name} from {lam[0]:.8g} to {lam[-1]:.8g}, period {br['period'][0]:.8g} to {br['period'][-1]:.8g}" \
            if lam else "no orbits"
        print(f"  orbit branch {i} from the {origin['kind']} at {name} = {origin[name]:.10g}: {len(lam)} orbits, {span} "
              f"({br['end']})")
    for sp in out.get("orbit_points", []):
        print(f"    {sp['kind']:<15} {name} = {sp[name]:.10g}, period {sp['period']:.10g} (branch {sp['branch']})")
    if name2:
        for c in out["curves"]:
            pts = c["points"]
            print(f"  {c['kind']} curve from {name} = {c['origin'][name]:.8g}: {len(pts)} points")
        for s in out["special"]:
            print(f"  {s['type']} ({s['name']}) at {name} = {s[name]:.8g}, {name2} = {s[name2]:.8g}")
