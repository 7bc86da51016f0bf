"""The `adbgen` command line (argparse: standard library, nothing to install).

    adbgen verify   [--n 1 2 3 4 6] [--model single-plane|two-plane|all]   every reduction checked
    adbgen derive   [--scene F] [--n N] [--form ...] [--format text|latex|json]
    adbgen steady   [--n N] [--mu ..] [--Omega ..] [--zeta ..] [--delta ..] [--beta ..]
    adbgen demo     [--out DIR]               thesis Fig. 5.4: transients reproduced, plotted
    adbgen regenerate [--check] [--scene F] [--n N ...] [--out DIR] [--targets ...]
                                              derive, check, emit numba/C/CVODE/AUTO into generated/
    adbgen bench derive|codegen|sweep [--out FILE] [--n ...]
    adbgen two-plane verify|derive|steady     the two-plane rotor (see adbgen/two_plane/commands.py)
    adbgen simulate ...                       transients on the generated code (adbgen/analysis/commands.py)
    adbgen sweep ...                          grids of trajectories or steady states on Dask (analysis/sweep_commands.py)

Bad input gives one line on stderr, `adbgen: error: ...`, and exit status 2.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from . import __version__
from .errors import AdbgenError, SceneError


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, not usage + line
        raise _UsageError(message)


class _UsageError(AdbgenError):
    pass


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"n must be at least 1, got {value}")
    return value


def _finite(text: str) -> float:
    import math

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return value


def _identifier(text: str) -> str:
    if not text.isidentifier():
        raise argparse.ArgumentTypeError(f"not an identifier (letters, digits, _): {text!r}")
    return text


def _scene(args):
    from .scene import Scene

    data = {}
    if getattr(args, "scene", None):
        scene = Scene.load(args.scene)
        if args.n is None:
            return scene
        import dataclasses

        data = {f.name: getattr(scene, f.name) for f in dataclasses.fields(scene)}
        for key in ("ball_mass", "ball_damping"):
            if isinstance(data[key], tuple):
                raise SceneError("n", f"--n cannot resize a scene with per-ball {key}")
    if args.n is not None:
        data["n"] = args.n
    return Scene.from_mapping(data)


def cmd_verify(args) -> int:
    from .single_plane.verify import run_all

    failed = 0

    def show(r):
        nonlocal failed
        failed += not r.passed
        print(f"{'ok  ' if r.passed else 'FAIL'} {r.seconds:6.2f}s  {r.name:40s} {r.reference:48s} {r.detail}", flush=True)

    results = run_all(tuple(args.n), progress=show) if args.model in ("single-plane", "all") else []
    if args.model in ("two-plane", "all"):
        from .two_plane.commands import run_checks

        results += run_checks(show)
    print(f"{len(results) - failed} passed, {failed} failed")
    return 1 if failed else 0


def _form(scene, form: str):
    from .single_plane import reductions
    from .single_plane.model import derive
    from .single_plane.selection import smallest_model

    if form == "fixed":
        return derive(scene)
    if form == "nondimensional":
        return reductions.nondimensionalise(scene)
    if form == "rotating":
        return reductions.rotating_frame(scene)
    if form == "first-order":
        return smallest_model(scene).system
    raise AssertionError(form)


def cmd_derive(args) -> int:
    return print_model(_form(_scene(args), args.form), args.format)


def print_model(model, fmt: str) -> int:
    """An EquationsOfMotion (rows) or a FirstOrderSystem (Schur form) as text, LaTeX or JSON."""
    import sympy as sp

    from .single_plane.reductions import FirstOrderSystem

    if isinstance(model, FirstOrderSystem):
        solve = model.solve
        coords = solve.eom.coordinates
        data = {"reference": model.reference, "states": list(model.state_names),
                "parameters": [p.name for p in model.parameters],
                "schur": [[str(e) for e in solve.schur.row(i)] for i in range(solve.schur.rows)],
                "schur_rhs": [str(e) for e in solve.rhs],
                "ball_accelerations": {coords[k].qdd.name: str(a) for k, a in zip(solve.leaves, solve.leaf_accel)}}
        if solve.eom.driven_law:  # a prescribed run-up: the spin and its rates are inputs in t
            data["driven"] = {sym.name: str(expr) for sym, expr in sorted(solve.eom.driven_law.items(), key=str)}
    else:
        data = {"reference": model.reference, "coordinates": [c.name for c in model.coordinates],
                "parameters": [p.name for p in model.parameters],
                "rows": {c.name: str(model.residual(k)) for k, c in enumerate(model.coordinates)}}
    if fmt == "json":
        print(json.dumps(data, indent=2))
    elif fmt == "latex" and not isinstance(model, FirstOrderSystem):
        for k, c in enumerate(model.coordinates):
            print(f"% row {c.name}\n{sp.latex(model.residual(k))} = 0\n")
    else:
        print(f"# {data['reference']}")
        for key, value in data.items():
            if key in ("rows", "ball_accelerations", "driven"):
                for name, expr in value.items():
                    print(f"{name}: {expr}{' = 0' if key == 'rows' else ''}")
            elif key != "reference":
                print(f"{key}: {value}")
    return 0


def cmd_steady(args) -> int:
    import sympy as sp

    from .scene import Scene
    from .single_plane import steady_states as ss
    from .single_plane.reductions import rotating_frame
    from .single_plane.stability import Linearisation

    n = args.n or 2
    p = {"mu": args.mu, "Omega": args.Omega, "zeta": args.zeta, "delta": args.delta, "beta": args.beta}
    for name in ("mu", "Omega", "delta"):
        if p[name] <= 0:
            raise SceneError(name, f"must be positive, got {p[name]}")
    if p["zeta"] <= 0:
        raise SceneError("zeta", "the closed forms (3.9)-(3.10) need zeta > 0")
    if p["beta"] < 0:
        raise SceneError("beta", f"must be non-negative, got {p['beta']}")
    lin = Linearisation(rotating_frame(Scene(n=n)))
    pvec = lin.parameters(**p)
    print(f"n = {n}, " + ", ".join(f"{k} = {v:g}" for k, v in p.items()) + f", K = {1 - p['Omega']**2 * (1 + n * p['mu']):.6g}")
    rows = []
    if n >= 2:  # the thesis' representative of the family: phi_3 = ... = phi_n = pi (ch. 4)
        try:
            state = ss.evaluate(ss.balanced(n, [sp.pi] * (n - 2), branch=-1), p)
        except ValueError:  # arccos of more than 1: no balanced state with these free angles
            state = None
        rows.append(("1 (3.6)" + (", phi_3.. = pi" if n > 2 else ""), state))
    for m in range(n, 0, -1):
        for sign in (1, -1):
            label = f"2{'+' if sign > 0 else '-'} (3.9)" if m == n else f"3({n}-{m}){'+' if sign > 0 else '-'} (3.10)"
            ok = ss.inline_exists(n, m, p["mu"], p["Omega"], p["zeta"], p["delta"])
            rows.append((label, ss.evaluate(ss.inline(n, m, sign), p) if ok else None))
    for label, state in rows:
        if state is None:
            print(f"  {label:22s} does not exist here")
            continue
        spectrum = lin.spectrum(lin.point(state), pvec)
        verdict = "stable" if spectrum.stable else f"unstable ({spectrum.n_unstable})"
        text = "  ".join(f"{k} = {v:+.9f}" for k, v in state.items())
        print(f"  {label:22s} {verdict:14s} {text}")
    for m in range(n, 0, -1):
        speeds = ss.critical_speeds(n, m, p["mu"], p["zeta"], p["delta"])
        name = "2+-" if m == n else f"3({n}-{m})+-"
        if speeds:
            print(f"  {name} absent for {speeds[0]:.6f} < Omega < {speeds[1]:.6f}  ((3.16)/(3.18))")
    return 0


def cmd_demo(args) -> int:
    from .analysis.loading import load_model
    from .analysis.published import FIGURE_5_4
    from .analysis.simulate import amplitude, simulate
    from .single_plane import steady_states as ss
    from .single_plane.verify import rotating

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    check = rotating(2)
    print(f"rotating-frame model n = 2 derived and checked against (2.25)-(2.27): {'ok' if check.passed else 'FAIL'}")
    print(f"balanced state (3.6)/(5.2): phi_1 = {ss.evaluate(ss.balanced(2, branch=-1), {'mu': 0.05, 'delta': 0.01})['phi_1']:.14f}")
    model = load_model("thesis_rotating_n2")
    runs = {}
    for panel, (phi0, (r_ref, t_ref)) in FIGURE_5_4.items():
        tr = simulate(model, None, {"phi_1": phi0[0], "phi_2": phi0[1]}, t_end=1000.0, rtol=1e-10, atol=1e-12)
        runs[panel] = tr
        print(f"Fig. 5.4({panel}1): r_max = {tr.r_max:.4f} (thesis {r_ref}), t_dec = {tr.t_dec:.2f} (thesis {t_ref})"
              f"  [{tr.engine}, {tr.wall_s * 1e3:.1f} ms]")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(runs), figsize=(4 * len(runs), 5), sharex=True, constrained_layout=True)
    for col, (panel, tr) in enumerate(runs.items()):
        axes[0, col].plot(tr.t, amplitude(model, tr.y), lw=0.6)
        axes[0, col].set_title(f"Fig. 5.4({panel}): $\\phi(0)$ = ({FIGURE_5_4[panel][0][0]:.2f}, {FIGURE_5_4[panel][0][1]:.2f})")
        axes[0, col].set_ylabel("$r$")
        for i in range(2):
            axes[1, col].plot(tr.t, tr.y[2 + i], lw=0.8, label=f"$\\phi_{i + 1}$")
        axes[1, col].set_xlabel("$t$")
        axes[1, col].legend(loc="best")
    path = out / "fig5_4.png"
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")
    return 0 if check.passed else 1


_BENCH_OUT = {"derive": "benchmarks/derive.json", "codegen": "benchmarks/codegen.json",
              "sweep": "benchmarks/sweep.json"}


def cmd_bench(args) -> int:
    from . import bench

    if args.what not in _BENCH_OUT:
        raise _UsageError(f"unknown benchmark {args.what!r}; choose: {', '.join(_BENCH_OUT)}")
    out = args.out if args.out is not None else _BENCH_OUT[args.what]
    if args.what == "codegen":
        from . import bench_codegen

        ns = tuple(args.n)  # op counts for every n; timings for n <= 16 (jac and lambdify up to 8)
        result = bench_codegen.bench_codegen(
            ns, tuple(n for n in ns if n <= max(bench_codegen.SPEED_NS)),
            progress=lambda r: print(bench_codegen.describe(r), flush=True))
        path = bench.write(result, out)
        print(f"wrote {path} ({result['seconds']} s)")
        return 0
    if args.what == "sweep":
        from . import bench_sweep

        result = bench_sweep.bench_sweep(progress=lambda line: print(line, flush=True))
        path = bench.write(result, out)
        print(f"wrote {path} (shortcuts {result['runs']['shortcuts']['wall_s']} s, full "
              f"{result['runs']['full']['wall_s']} s, labels identical: {result['labels_identical']})")
        return 0
    result = bench.bench_derive(tuple(args.n), progress=lambda r: print(
        f"{r['model']:30s} n={r['n']:3d}  {r['seconds']:8.3f} s  eom ops {r['eom_ops']:7d}  first-order ops {r['first_order_ops']:7d}",
        flush=True))
    path = bench.write(result, out)
    print(f"wrote {path}")
    return 0


def cmd_regenerate(args) -> int:
    from .codegen import models
    from .codegen.regenerate import DEFAULT_OUT, render_all, stale, write
    from .codegen.render import TARGETS

    custom = args.scene is not None or args.n is not None
    if custom and args.out is None:
        raise _UsageError("--scene/--n generate models outside the default set: give --out DIR "
                          "(generated/ holds the default set only)")
    out = Path(args.out) if args.out is not None else DEFAULT_OUT
    if args.scene is not None:
        specs = [models.for_scene(_scene(args), args.name)]
    elif args.n is not None:
        specs = [spec for n in args.n for spec in (models.thesis_rotating(n), models.single_plane_fixed(n))]
    else:
        specs = models.default_set()
    log = (lambda line: None) if args.quiet else (lambda line: print(line, file=sys.stderr, flush=True))
    rendered = render_all(specs, tuple(args.targets), run_checks=not args.skip_checks, progress=log)
    if args.check:
        report = stale(rendered, out, extra=set(args.targets) == set(TARGETS))
        for rel, status in report.items():
            print(f"stale: {out / rel} ({status})")
        if report:
            print(f"{len(report)} file(s) out of date: run `adbgen regenerate`", file=sys.stderr)
            return 1
        print(f"{out}: {len(rendered.files)} files up to date")
        return 0
    changed = write(rendered, out, prune=set(args.targets) == set(TARGETS) and not custom)
    print(f"{out}: {len(rendered.files)} files, {len(changed)} changed")
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="adbgen", description="Equations of motion of automatic dynamic balancers.")
    p.add_argument("--version", action="version", version=f"adbgen {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    v = sub.add_parser("verify", help="check every reduction against the thesis")
    v.add_argument("--n", type=_positive_int, nargs="+", default=[1, 2, 3, 4, 6])
    v.add_argument("--model", choices=("single-plane", "two-plane", "all"), default="all")
    v.set_defaults(fn=cmd_verify)

    d = sub.add_parser("derive", help="derive and print a model")
    d.add_argument("--scene", help="scene file (TOML)")
    d.add_argument("--n", type=_positive_int)
    d.add_argument("--form", choices=("fixed", "nondimensional", "rotating", "first-order"), default="first-order",
                   help="first-order = the smallest exact model for the scene")
    d.add_argument("--format", choices=("text", "latex", "json"), default="text")
    d.set_defaults(fn=cmd_derive)

    s = sub.add_parser("steady", help="closed-form steady states and where they exist (thesis ch. 3)")
    s.add_argument("--n", type=_positive_int)
    for name, default in (("mu", 0.05), ("Omega", 4.0), ("zeta", 0.01), ("delta", 0.01), ("beta", 0.01)):
        s.add_argument(f"--{name}", type=_finite, default=default)
    s.set_defaults(fn=cmd_steady)

    m = sub.add_parser("demo", help="reproduce the thesis' Fig. 5.4 transients and plot them")
    m.add_argument("--out", default="out/demo")
    m.set_defaults(fn=cmd_demo)

    r = sub.add_parser("regenerate", help="derive, check and emit the generated code (numba, C, CVODE, AUTO-07p)")
    r.add_argument("--check", action="store_true", help="write nothing; exit 1 naming the files that are out of date")
    r.add_argument("--scene", help="scene file (TOML): its smallest exact model (needs --out)")
    r.add_argument("--n", type=_positive_int, nargs="+", help="the default families for these n (needs --out)")
    r.add_argument("--name", type=_identifier, help="model name for --scene")
    r.add_argument("--out", help="output folder (default: the repository's generated/)")
    r.add_argument("--targets", nargs="+", choices=("numba", "c", "cvode", "auto"),
                   default=["numba", "c", "cvode", "auto"])
    r.add_argument("--skip-checks", action="store_true", help="skip the reduction checks (the lowering check stays)")
    r.add_argument("--quiet", action="store_true", help="no progress lines")
    r.set_defaults(fn=cmd_regenerate)

    b = sub.add_parser("bench", help="benchmarks (results to a committed file)")
    b.add_argument("what", help="derive, codegen or sweep")
    b.add_argument("--out", default=None, help="results file (default benchmarks/<what>.json)")
    b.add_argument("--n", type=_positive_int, nargs="+", default=[1, 2, 4, 8, 16, 32])
    b.set_defaults(fn=cmd_bench)

    from .two_plane.commands import add_parser as add_two_plane

    add_two_plane(sub, _Parser)
    from .analysis.commands import register as add_analysis

    add_analysis(sub, _Parser)
    return p


def main(argv: list[str] | None = None) -> int:
    try:
        args = build_parser().parse_args(argv)
        return args.fn(args)
    except AdbgenError as exc:
        print(f"adbgen: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into e.g. `head`, which closed early: not an error
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
