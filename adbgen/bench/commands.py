"""`adbgen bench derive|codegen|simulate|sweep|failures|smallest|precision [--out FILE] [--n ...] [--quick]`:
benchmarks, results written to a committed file."""

from __future__ import annotations

import argparse

from ..cli_types import UsageError, positive_int

from pathlib import Path

_BENCH_OUT = {"derive": "benchmarks/derive.json", "codegen": "benchmarks/codegen.json",
              "simulate": "benchmarks/simulate.json", "sweep": "benchmarks/sweep.json",
              "failures": "benchmarks/failures.json", "smallest": "benchmarks/smallest.json",
              "precision": "benchmarks/precision.json"}


def cmd_bench(args) -> int:
    from .. import bench
    from . import derive

    if args.what not in _BENCH_OUT:
        raise UsageError(f"unknown benchmark {args.what!r}; choose: {', '.join(_BENCH_OUT)}")
    out = args.out if args.out is not None else _BENCH_OUT[args.what]
    if args.what == "simulate":
        return _bench_simulate(args, out)
    if args.what == "precision":
        return _bench_precision(args, out)
    if args.what == "failures":
        from . import failures as bench_failures

        result = bench_failures.bench_failures(quick=args.quick, progress=lambda line: print(line, flush=True))
        path = bench.write(result, out)
        pngs = bench_failures.charts(result, Path(out))
        print(f"wrote {path} and {', '.join(map(str, pngs))} ({result['seconds']} s)")
        return 0
    if args.what == "smallest":
        from . import smallest as bench_smallest

        result = bench_smallest.bench_smallest(quick=args.quick, progress=lambda line: print(line, flush=True))
        path = bench.write(result, out)
        png = bench_smallest.chart(result, Path(out).with_suffix(".png"))
        print(f"wrote {path} and {png} ({result['seconds']} s)")
        return 0
    if args.what == "sweep":
        from . import sweep as bench_sweep

        if args.repeats is not None and args.repeats < 1:
            raise UsageError(f"--repeats must be >= 1, got {args.repeats}")
        result = bench_sweep.bench_sweep(progress=lambda line: print(line, flush=True), repeats=args.repeats or 2,
                                         only=args.only)
        path = bench.write(result, out)
        runs = ", ".join(f"{k} {v['wall_s']} s wall / {v['cpu_s']} CPU-s" for k, v in result["runs"].items())
        print(f"wrote {path} ({runs}; labels identical: {result.get('labels_identical', 'not compared')})")
        return 0
    if args.what == "codegen":
        from . import codegen as bench_codegen

        ns = tuple(args.n)  # op counts for every n; timings for n <= 16 (jac and lambdify up to 8)
        result = bench_codegen.bench_codegen(
            ns, tuple(n for n in ns if n <= max(bench_codegen.SPEED_NS)),
            progress=lambda r: print(bench_codegen.describe(r), flush=True),
            **({"forms_ns": tuple(args.forms_n)} if args.forms_n else {}),
            **({"parts": tuple(args.parts)} if args.parts else {}))
        path = bench.write(result, out)
        print(f"wrote {path} ({result['seconds']} s)")
        return 0
    result = derive.bench_derive(tuple(args.n), progress=lambda r: print(
        f"{r['model']:30s} n={r['n']:3d}  {r['seconds']:8.3f} s  eom ops {r['eom_ops']:7d}  first-order ops {r['first_order_ops']:7d}",
        flush=True), pipeline_ns=tuple(args.pipeline_n or derive.PIPELINE_NS), pipeline_progress=lambda r: print(
        f"pipeline {r['kind']:20s} n={r['n']:3d}  derive {r['derive_seconds']:.1f} s, reduction checks "
        f"{r['reduction_checks_seconds']:.1f} s, lower {r['lower_seconds']:.1f} s, program checks "
        f"{r['program_checks_seconds']:.1f} s, emit {r['emit_seconds']:.1f} s ({r['bytes']} bytes)", flush=True))
    path = bench.write(result, out)
    print(f"wrote {path}")
    return 0


def _bench_simulate(args, out) -> int:
    from . import simulate as bench_simulate
    from .. import bench

    if args.repeats is not None and args.repeats < 1:
        raise UsageError(f"--repeats must be >= 1, got {args.repeats}")
    if args.engines:
        from ..analysis.engines import engine

        for name in args.engines:
            engine(name)  # an unknown name: one line naming the engines, exit 2
    result = bench_simulate.bench_simulate(
        repeats=args.repeats or bench_simulate.DEFAULT_REPEATS, engines=args.engines, peers=not args.no_peers,
        progress=lambda line: print(line, flush=True))
    path = bench.write(result, out)
    png = bench_simulate.chart(result, Path(out).with_suffix(".png"))
    for line in bench_simulate.describe_targets(result):
        print(line)
    print(f"wrote {path} and {png} ({result['seconds']} s)")
    return 0


def _bench_precision(args, out) -> int:
    from . import precision as bench_precision
    from .. import bench

    problems = args.problems or list(bench_precision.PROBLEMS)
    unknown = [p for p in problems if p not in bench_precision.PROBLEMS]
    if unknown:
        raise UsageError(f"unknown problem {unknown[0]!r}; choose from {', '.join(bench_precision.PROBLEMS)}")
    if args.repeats is not None and args.repeats < 1:
        raise UsageError(f"--repeats must be >= 1, got {args.repeats}")
    for name, value in (("--max-run", args.max_run), ("--budget", args.budget), ("--t-end", args.t_end)):
        if value is not None and not (value > 0):
            raise UsageError(f"{name} must be > 0, got {value}")
    if args.engines:
        from ..analysis.engines import engine

        for name in args.engines:
            engine(name)  # an unknown name: one line naming the engines, exit 2
    if args.only_percall:
        import json

        previous = json.loads(Path(out).read_text()) if Path(out).exists() else None
        try:
            result = bench_precision.rerun_percall(previous, tuple(args.n) if args.n_given else None,
                                                   progress=lambda line: print(line, flush=True))
        except ValueError as exc:
            raise UsageError(f"{out}: {exc}") from None
        path = bench.write(result, out)
        chart = bench_precision.chart_percall(result, f"{Path(out).with_suffix('')}_percall.png")
        for line in bench_precision.describe_targets(result):
            print(line)
        print(f"wrote {path} (per-call part replaced) and {chart}")
        return 0
    result = bench_precision.bench_precision(
        tuple(problems), quick=args.quick, engines=args.engines, peers=not args.no_peers, repeats=args.repeats,
        max_run_s=args.max_run, budget_s=args.budget, t_end=args.t_end, percall=not args.no_percall,
        percall_ns=tuple(args.n) if args.n_given else None, progress=lambda line: print(line, flush=True))
    path = bench.write(result, out)
    stem = Path(out).with_suffix("")
    charts = [bench_precision.chart(result, label, f"{stem}_{label}.png") for label in result["problems"]]
    if "A" in result["problems"]:
        charts.append(bench_precision.chart(result, "A", f"{stem}_A_headline.png", only=bench_precision.HEADLINE))
        charts.append(bench_precision.chart_reliable(result, f"{stem}_A_reliable.png"))
    if result.get("percall"):
        charts.append(bench_precision.chart_percall(result, f"{stem}_percall.png"))
    for line in bench_precision.describe_targets(result):
        print(line)
    print(f"wrote {path} and {', '.join(map(str, charts))} ({result['seconds']} s)")
    return 0


class _NGiven(argparse.Action):
    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, values)
        namespace.n_given = True


def register(sub) -> None:
    b = sub.add_parser("bench", help="benchmarks (results to a committed file)")
    b.add_argument("what", help="derive, codegen, simulate, sweep, failures, smallest or precision")
    b.add_argument("--out", default=None, help="results file (default benchmarks/<what>.json; simulate also writes "
                   "its chart next to it, <out>.png)")
    b.add_argument("--n", type=positive_int, nargs="+", default=[1, 2, 4, 8, 16, 32], action=_NGiven,
                   help="derive/codegen: ball counts; precision: the per-call part's (default 2 4 8 16 32)")
    b.add_argument("--pipeline-n", type=positive_int, nargs="+", default=None,
                   help="derive: n of the regenerate-stage timings (default 1 2 4 8 16 32 64)")
    b.add_argument("--forms-n", type=positive_int, nargs="+", default=None,
                   help="codegen: n of the loop-versus-unrolled comparison (default 1 2 4 8 16 32 64)")
    b.add_argument("--parts", nargs="+", choices=("ops", "speed", "forms"), default=None,
                   help="codegen: only these parts (default: all)")
    b.add_argument("--repeats", type=int, default=None, help="simulate: best of N (default 7); sweep: each "
                   "configuration N times, alternating (default 2)")
    b.add_argument("--only", choices=("shortcuts", "full"), default=None,
                   help="sweep: run only this configuration (no label comparison)")
    b.add_argument("--engines", nargs="+", default=None, help="simulate, precision: only these engines (default: all)")
    b.add_argument("--no-peers", action="store_true", help="simulate, precision: skip JiTCODE and heyoka")
    b.add_argument("--problems", nargs="+", default=None, help="precision: problems (default A B C)")
    b.add_argument("--quick", action="store_true", help="failures, smallest: short runs (checks the machinery); "
                   "precision: 2 tolerances, 1/10 of the horizon, n = 2 4 (about a minute)")
    b.add_argument("--max-run", type=float, default=None, help="precision: skip a pathway's tighter tolerances once "
                   "a run is predicted to take longer than this [s] (default 20; quick 0.5)")
    b.add_argument("--budget", type=float, default=None, help="precision: time budget of the work-precision part "
                   "[s], shared by the problems (default 480; quick 40)")
    b.add_argument("--t-end", type=float, default=None, help="precision: integrate every problem to this time "
                   "(default: each problem's)")
    b.add_argument("--no-percall", action="store_true", help="precision: skip the per-call part")
    b.add_argument("--only-percall", action="store_true", help="precision: run the per-call part alone and put it "
                   "into the results file in place of its per-call part (the work-precision part is kept)")
    b.set_defaults(n_given=False)
    b.set_defaults(fn=cmd_bench)
