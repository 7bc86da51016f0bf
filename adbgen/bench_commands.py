"""`adbgen bench derive|codegen|simulate|sweep [--out FILE] [--n ...]`: benchmarks, results written to a committed file."""

from __future__ import annotations

from .cli_types import UsageError, positive_int

from pathlib import Path

_BENCH_OUT = {"derive": "benchmarks/derive.json", "codegen": "benchmarks/codegen.json",
              "simulate": "benchmarks/simulate.json", "sweep": "benchmarks/sweep.json"}


def cmd_bench(args) -> int:
    from . import bench

    if args.what not in _BENCH_OUT:
        raise UsageError(f"unknown benchmark {args.what!r}; choose: {', '.join(_BENCH_OUT)}")
    out = args.out if args.out is not None else _BENCH_OUT[args.what]
    if args.what == "simulate":
        return _bench_simulate(args, out)
    if args.what == "sweep":
        from . import bench_sweep

        if args.repeats is not None and args.repeats < 1:
            raise UsageError(f"--repeats must be >= 1, got {args.repeats}")
        result = bench_sweep.bench_sweep(progress=lambda line: print(line, flush=True), repeats=args.repeats or 2,
                                         only=args.only)
        path = bench.write(result, out)
        runs = ", ".join(f"{k} {v['wall_s']} s wall / {v['cpu_s']} CPU-s" for k, v in result["runs"].items())
        print(f"wrote {path} ({runs}; labels identical: {result.get('labels_identical', 'not compared')})")
        return 0
    if args.what == "codegen":
        from . import bench_codegen

        ns = tuple(args.n)  # op counts for every n; timings for n <= 16 (jac and lambdify up to 8)
        result = bench_codegen.bench_codegen(
            ns, tuple(n for n in ns if n <= max(bench_codegen.SPEED_NS)),
            progress=lambda r: print(bench_codegen.describe(r), flush=True))
        path = bench.write(result, out)
        print(f"wrote {path} ({result['seconds']} s)")
        return 0
    result = bench.bench_derive(tuple(args.n), progress=lambda r: print(
        f"{r['model']:30s} n={r['n']:3d}  {r['seconds']:8.3f} s  eom ops {r['eom_ops']:7d}  first-order ops {r['first_order_ops']:7d}",
        flush=True))
    path = bench.write(result, out)
    print(f"wrote {path}")
    return 0


def _bench_simulate(args, out) -> int:
    from . import bench, bench_simulate

    if args.repeats is not None and args.repeats < 1:
        raise UsageError(f"--repeats must be >= 1, got {args.repeats}")
    if args.engines:
        from .analysis.engines import engine

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


def register(sub) -> None:
    b = sub.add_parser("bench", help="benchmarks (results to a committed file)")
    b.add_argument("what", help="derive, codegen, simulate or sweep")
    b.add_argument("--out", default=None, help="results file (default benchmarks/<what>.json; simulate also writes "
                   "its chart next to it, <out>.png)")
    b.add_argument("--n", type=positive_int, nargs="+", default=[1, 2, 4, 8, 16, 32])
    b.add_argument("--repeats", type=int, default=None, help="simulate: best of N (default 7); sweep: each "
                   "configuration N times, alternating (default 2)")
    b.add_argument("--only", choices=("shortcuts", "full"), default=None,
                   help="sweep: run only this configuration (no label comparison)")
    b.add_argument("--engines", nargs="+", default=None, help="simulate: only these engines (default: all)")
    b.add_argument("--no-peers", action="store_true", help="simulate: skip JiTCODE and heyoka")
    b.set_defaults(fn=cmd_bench)
