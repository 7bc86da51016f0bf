"""The benchmarks' registry: each benchmark module declares one `Benchmark` (its name, its command-line
options and its run function) as ``BENCHMARK``, and `REGISTRY` lists the modules, one line each, in the
order of `adbgen bench --help`.

To add a benchmark: write ``bench/<name>.py`` ending in ``BENCHMARK = Benchmark("<name>", run, options)``
and add its line to `REGISTRY`.  ``run(args, out)`` gets the parsed command line and the results
file (``--out`` or ``benchmarks/<name>.json``), writes, prints what it wrote and returns the exit
status; bad input raises `UsageError` (one line, exit 2) before anything is written.

All benchmarks share one ``adbgen bench WHAT`` parser: an option several benchmarks declare is added
once (their declarations must agree but for the help, which lists each benchmark's), and an option
another benchmark declares is accepted and ignored, as it always was.
"""

from __future__ import annotations

import argparse
import importlib
from dataclasses import dataclass, field
from typing import Callable

from adbgen.cli_types import UsageError, positive_int

# name -> "module:attribute"; one line per benchmark, in the order of `adbgen bench --help`
REGISTRY: dict[str, str] = {
    "derive": "benchmarks.derive:BENCHMARK",
    "codegen": "benchmarks.codegen:BENCHMARK",
    "simulate": "benchmarks.simulate:BENCHMARK",
    "sweep": "benchmarks.sweep:BENCHMARK",
    "failures": "benchmarks.failures:BENCHMARK",
    "smallest": "benchmarks.smallest:BENCHMARK",
    "precision": "benchmarks.precision:BENCHMARK",
    "mutation": "benchmarks.mutation:BENCHMARK",
    "orbits": "benchmarks.orbits:BENCHMARK",
    "auto": "benchmarks.engine_table:BENCHMARK",
    "rk": "benchmarks.rk:BENCHMARK",
    "ensemble": "benchmarks.ensemble:BENCHMARK",
    "reproduce": "benchmarks.reproduce:BENCHMARK",
    "trust": "benchmarks.trust:BENCHMARK",
    "design": "benchmarks.design:BENCHMARK",
    "tolerance": "benchmarks.tolerance:BENCHMARK",
    "friction": "benchmarks.friction:BENCHMARK",
}


@dataclass(frozen=True)
class Option:
    """One command-line option: argparse's flags and keyword arguments, and its help for one benchmark."""

    flags: tuple[str, ...]
    help: str
    kwargs: dict = field(default_factory=dict)

    def but(self, help: str) -> "Option":
        """The same option with this benchmark's help."""
        return Option(self.flags, help, self.kwargs)

    @property
    def dest(self) -> str:
        return self.flags[0].lstrip("-").replace("-", "_")


def option(*flags: str, help: str = "", **kwargs) -> Option:
    return Option(tuple(flags), help, kwargs)


@dataclass(frozen=True)
class Benchmark:
    name: str
    run: Callable[[argparse.Namespace, str], int]
    options: tuple[Option, ...] = ()

    @property
    def default_out(self) -> str:
        return f"benchmarks/{self.name}.json"


class _NGiven(argparse.Action):
    """Stores the values and notes that the option was given (its default differs per benchmark)."""

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, values)
        namespace.n_given = True


# options more than one benchmark takes (each with its own help: `Option.but`)
BALL_COUNTS = option("--n", type=positive_int, nargs="+", default=[1, 2, 4, 8, 16, 32], action=_NGiven)
REPEATS = option("--repeats", type=int, default=None)
ENGINE_NAMES = option("--engines", nargs="+", default=None, help="only these engines (default: all)")
NO_PEERS = option("--no-peers", action="store_true", help="skip JiTCODE and heyoka")
QUICK = option("--quick", action="store_true")


def require_positive_repeats(args) -> None:
    if args.repeats is not None and args.repeats < 1:
        raise UsageError(f"--repeats must be >= 1, got {args.repeats}")


def require_known_engines(args) -> None:
    if args.engines:
        from adbgen.analysis.engines import engine

        for name in args.engines:
            engine(name)  # an unknown name: one line naming the engines, exit 2


def get(name: str) -> Benchmark:
    if name not in REGISTRY:
        raise UsageError(f"unknown benchmark {name!r}; choose: {', '.join(REGISTRY)}")
    module, attr = REGISTRY[name].split(":")
    return getattr(importlib.import_module(module), attr)


def all_benchmarks() -> tuple[Benchmark, ...]:
    return tuple(get(name) for name in REGISTRY)


def merged_options(benchmarks) -> list[tuple[Option, str]]:
    """Every option once, in the order of first use, with the help of each benchmark that takes it
    ("simulate, precision: ...; sweep: ...")."""
    first: dict[tuple, Option] = {}
    helps: dict[tuple, dict[str, list[str]]] = {}
    for bm in benchmarks:
        for opt in bm.options:
            if opt.flags in first and first[opt.flags].kwargs != opt.kwargs:
                raise ValueError(f"benchmark {bm.name!r} declares {'/'.join(opt.flags)} unlike another benchmark")
            first.setdefault(opt.flags, opt)
            helps.setdefault(opt.flags, {}).setdefault(opt.help, []).append(bm.name)
    return [(opt, "; ".join(f"{', '.join(names)}: {text}" if text else ", ".join(names)
                            for text, names in helps[flags].items()))
            for flags, opt in first.items()]


__all__ = ["BALL_COUNTS", "Benchmark", "ENGINE_NAMES", "NO_PEERS", "Option", "QUICK", "REGISTRY", "REPEATS",
           "all_benchmarks", "get", "merged_options", "option", "require_known_engines",
           "require_positive_repeats"]
