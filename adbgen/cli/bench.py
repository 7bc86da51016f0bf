"""`adbgen bench WHAT [--out FILE] [options]`: the benchmarks of the checkout's `benchmarks/registry.py`,
results written to a committed file (default ``benchmarks/<what>.json``).

The benchmarks are not part of the installed package (issue 33 item 6: the wheel ships no
`benchmarks`, and `adbgen` imports it nowhere, an import-linter contract): `registry()` finds them
beside the `adbgen/` this process runs, in a source checkout (an editable install or PYTHONPATH), and
imports them by name at run time.  From an installed wheel `adbgen bench` says so in one line (exit 2).
"""

from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path

from ..cli_types import UsageError

CHECKOUT = Path(__file__).resolve().parents[2]  # the source checkout's root, if this adbgen is one's
NEEDS_CHECKOUT = ("the benchmarks need a source checkout (benchmarks/ beside adbgen/; the installed package "
                  "has none): git clone, pip install -e ., then adbgen bench")


def has_checkout() -> bool:
    return (CHECKOUT / "pyproject.toml").is_file() and (CHECKOUT / "benchmarks" / "registry.py").is_file()


def registry():
    """The checkout's `benchmarks.registry` module; `UsageError` (one line) where there is no checkout."""
    if not has_checkout():
        raise UsageError(NEEDS_CHECKOUT)
    if str(CHECKOUT) not in sys.path:
        sys.path.insert(0, str(CHECKOUT))
    module = importlib.import_module("benchmarks.registry")
    if Path(module.__file__).resolve().parent != CHECKOUT / "benchmarks":  # another project's `benchmarks`
        raise UsageError(f"`benchmarks` is imported from {Path(module.__file__).parent}, not from this checkout's "
                         f"{CHECKOUT / 'benchmarks'}")
    return module


def cmd_bench(args) -> int:
    from ..outputs import output_file

    benchmark = registry().get(args.what)
    out = args.out if args.out is not None else benchmark.default_out
    output_file(out, "--out")  # before minutes of timing, not after
    return benchmark.run(args, out)


def _needs_checkout(args) -> int:
    raise UsageError(NEEDS_CHECKOUT)


def register(sub) -> None:
    if not has_checkout():  # an installed wheel: the command is listed and says what it needs
        b = sub.add_parser("bench", help="benchmarks (need a source checkout)", description=NEEDS_CHECKOUT)
        b.add_argument("what", nargs="?")
        b.add_argument("rest", nargs=argparse.REMAINDER)
        b.set_defaults(fn=_needs_checkout)
        return
    benchmarks = registry().all_benchmarks()
    names = [b.name for b in benchmarks]
    b = sub.add_parser("bench", help="benchmarks (results to a committed file)")
    b.add_argument("what", help=f"{', '.join(names[:-1])} or {names[-1]}")
    b.add_argument("--out", default=None, help="results file (default benchmarks/<what>.json; simulate also writes "
                   "its chart next to it, <out>.png)")
    for option, help_ in registry().merged_options(benchmarks):
        b.add_argument(*option.flags, help=help_, **option.kwargs)
    b.set_defaults(n_given=False, fn=cmd_bench)
