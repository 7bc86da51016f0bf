"""The `adbgen` command line (argparse: standard library), assembled from the registries.

    adbgen verify   [--n 1 2 3 4 6] [--model single-plane|two-plane|all]   every family's checks
    adbgen derive | steady | demo              the single-plane family's commands
    adbgen two-plane verify|derive|steady      the two-plane family's commands
    adbgen regenerate [--check] [--scene F] [--n N ...] [--family F ...] [--out DIR] [--targets ...]
    adbgen bench derive|codegen|sweep [--out FILE] [--n ...]
    adbgen bench simulate [--out FILE] [--repeats N] [--engines E ...] [--no-peers]
    adbgen bench failures|smallest [--out FILE] [--quick]
    adbgen simulate | stability | continue | sweep | reproduce ...   the analysis layer (adbgen/cli/simulate.py, ...)
    adbgen notebooks [--check | --run] [--only NN ...]                 the derivation notebooks of derive/
    adbgen docs [--out DIR]                                            the documentation site (Sphinx, -W)

Every family in `families.REGISTRY` adds its own subcommands (`Family.register_commands`); other
command groups are listed once in `COMMAND_GROUPS` as "module:function", each function taking the
subparsers (and, if it asks for a second argument, the parser class, for nested subcommands).

Exit status (`EXIT_STATUS`, printed by `adbgen --help`): 0 done; 1 a failure the command reports
(an integration that failed, a stale file under --check, a failed check); 2 bad input, one line on
stderr `adbgen: error: ...`, before any work where the input can be checked first; 3 a scan or
continuation that ended before its range (it says why and where; --json: "complete": false); 130
interrupted (Ctrl-C), one line.  Whatever goes wrong, stderr gets one line, never a traceback: an
error of adbgen itself is reported as `adbgen: error: internal error: ...` (exit 70) with the
traceback only when ADBGEN_TRACEBACK=1.
"""

from __future__ import annotations

import argparse
import inspect
import sys
from typing import Callable

from .. import __version__, families
from ..cli_types import UsageError
from ..registry import load
from ..errors import AdbgenError

# Command groups besides the families', in the order of `adbgen --help`; one line per group.
COMMAND_GROUPS: list[str] = [
    "adbgen.cli.regenerate:register",  # regenerate
    "adbgen.cli.bench:register",  # bench
    "adbgen.cli.simulate:register",  # simulate (the analysis layer over generated code)
    "adbgen.cli.stability:register",  # stability, continue
    "adbgen.cli.orbit:register",  # orbit (periodic orbits by shooting)
    "adbgen.cli.sweep:register",  # sweep
    "adbgen.cli.design:register",  # design (a balancer over a speed range and an imbalance interval)
    "adbgen.cli.reproduce:register",  # reproduce (every family's reproductions)
    "adbgen.cli.notebooks:register",  # notebooks (execute and render derive/)
    "adbgen.cli.docs:register",  # docs (build the documentation site)
    "adbgen.cli.scene:register",  # scene from-ross (a ROSS rotor -> a two-plane scene)
]


EXIT_STATUS = {0: "done", 1: "failed (an integration, a check, stale files under --check)",
               2: "bad input (one line: adbgen: error: ...)",
               3: "a scan or continuation ended before its range (says why and where; --json: complete false)",
               70: "internal error of adbgen (ADBGEN_TRACEBACK=1 shows the traceback)", 130: "interrupted (Ctrl-C)"}
EPILOG = "exit status: " + "; ".join(f"{k} {v}" for k, v in EXIT_STATUS.items())


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, not usage + line
        raise UsageError(message)


def _family_commands() -> list[Callable]:
    """Each family's commands, then its science's (`Family.science_commands`, loaded by name; once, when
    families share them, as a family derived from another does)."""
    out, seen = [], set()
    for family in families.all_families():
        out.append(family.register_commands)
        science = getattr(family, "science_commands", lambda: "")()
        if science and science not in seen:
            seen.add(science)
            out.append(load(science))
    return out


def command_groups() -> list[Callable]:
    """Every register(subparsers) function: verify, each family's commands, then COMMAND_GROUPS."""
    from .verify import register as register_verify

    return [register_verify] + _family_commands() + [load(e) for e in COMMAND_GROUPS]


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="adbgen", description="Equations of motion of automatic dynamic balancers.", epilog=EPILOG)
    p.add_argument("--version", action="version", version=f"adbgen {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for register in command_groups():
        takes = len(inspect.signature(register).parameters)
        register(sub, _Parser) if takes >= 2 else register(sub)
    return p


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def main(argv: list[str] | None = None) -> int:
    try:
        args = build_parser().parse_args(argv)
        return args.fn(args)
    except AdbgenError as exc:
        print(f"adbgen: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("adbgen: error: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # output piped into e.g. `head`, which closed early: not an error
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except OSError as exc:  # a file that could not be read or written after the checks passed
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        print(f"adbgen: error: {where}{_one_line(exc.strerror or exc)}", file=sys.stderr)
        return 1
    except Exception as exc:  # a bug of adbgen's: one line, the traceback on request
        import os

        if os.environ.get("ADBGEN_TRACEBACK"):
            raise
        print(f"adbgen: error: internal error: {type(exc).__name__}: {_one_line(exc)} "
              "(ADBGEN_TRACEBACK=1 shows where)", file=sys.stderr)
        return 70

