"""The `adbgen` command line (argparse: standard library), assembled from the registries.

    adbgen verify   [--n 1 2 3 4 6] [--model single-plane|two-plane|all]   every family's checks
    adbgen derive | steady | demo              the single-plane family's commands
    adbgen two-plane verify|derive|steady      the two-plane family's commands
    adbgen regenerate [--check] [--scene F] [--n N ...] [--family F ...] [--out DIR] [--targets ...]
    adbgen bench derive|codegen|sweep [--out FILE] [--n ...]
    adbgen bench simulate [--out FILE] [--repeats N] [--engines E ...] [--no-peers]
    adbgen bench failures|smallest [--out FILE] [--quick]
    adbgen simulate | stability | continue | sweep | reproduce ...   the analysis layer (adbgen/analysis/commands.py)
    adbgen notebooks [--check | --run] [--only NN ...]                 the derivation notebooks of derive/
    adbgen docs [--out DIR]                                            the documentation site (Sphinx, -W)

Every family in `families.REGISTRY` adds its own subcommands (`Family.register_commands`); other
command groups are listed once in `COMMAND_GROUPS` as "module:function", each function taking the
subparsers (and, if it asks for a second argument, the parser class, for nested subcommands).  Bad input gives one line on stderr, `adbgen: error: ...`, and exit status 2.
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import sys
from typing import Callable

from . import __version__, families
from .cli_types import UsageError
from .errors import AdbgenError

# Command groups besides the families', in the order of `adbgen --help`; one line per group.
COMMAND_GROUPS: list[str] = [
    "adbgen.codegen.commands:register",  # regenerate
    "adbgen.bench.commands:register",  # bench
    "adbgen.analysis.commands:register",  # simulate (the analysis layer over generated code)
    "adbgen.notebooks:register",  # notebooks (execute and render derive/)
    "adbgen.docsite:register",  # docs (build the documentation site)
]


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, not usage + line
        raise UsageError(message)


def _load(entry: str) -> Callable:
    module, attr = entry.split(":")
    return getattr(importlib.import_module(module), attr)


def command_groups() -> list[Callable]:
    """Every register(subparsers) function: verify, each family's commands, then COMMAND_GROUPS."""
    from .families.commands import register as register_verify

    return [register_verify] + [f.register_commands for f in families.all_families()] + [_load(e) for e in COMMAND_GROUPS]


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="adbgen", description="Equations of motion of automatic dynamic balancers.")
    p.add_argument("--version", action="version", version=f"adbgen {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for register in command_groups():
        takes = len(inspect.signature(register).parameters)
        register(sub, _Parser) if takes >= 2 else register(sub)
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
