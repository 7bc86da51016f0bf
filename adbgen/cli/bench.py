"""`adbgen bench WHAT [--out FILE] [options]`: the benchmarks of `adbgen.bench.registry`, results written to a
committed file (default ``benchmarks/<what>.json``)."""

from __future__ import annotations

from ..bench import registry


def cmd_bench(args) -> int:
    from ..outputs import output_file

    benchmark = registry.get(args.what)
    out = args.out if args.out is not None else benchmark.default_out
    output_file(out, "--out")  # before minutes of timing, not after
    return benchmark.run(args, out)


def register(sub) -> None:
    benchmarks = registry.all_benchmarks()
    names = [b.name for b in benchmarks]
    b = sub.add_parser("bench", help="benchmarks (results to a committed file)")
    b.add_argument("what", help=f"{', '.join(names[:-1])} or {names[-1]}")
    b.add_argument("--out", default=None, help="results file (default benchmarks/<what>.json; simulate also writes "
                   "its chart next to it, <out>.png)")
    for option, help_ in registry.merged_options(benchmarks):
        b.add_argument(*option.flags, help=help_, **option.kwargs)
    b.set_defaults(n_given=False, fn=cmd_bench)
