"""`adbgen notebooks [--check | --run] [--only NN ...]`: execute the derivation notebooks of derive/ and
render them beside their sources (`adbgen.notebooks`)."""

from __future__ import annotations

import sys
import time

from ..cli_types import positive_int
from ..notebooks import NotebookError, rendered_path, run_all, sources, stale, write


def cmd_notebooks(args) -> int:
    paths = sources(args.only)
    if args.check:
        bad = stale(paths)
        for line in bad:
            print(line)
        if bad:
            print("re-render with: adbgen notebooks", file=sys.stderr)
        return 1 if bad else 0
    total = time.perf_counter()
    failed = []
    for src, result, seconds in run_all(paths, timeout=args.timeout, jobs=args.jobs):
        if isinstance(result, NotebookError):
            failed.append(src.name)
            print(f"FAIL {src.name} ({seconds:.1f} s): {result}", file=sys.stderr)
            continue
        if not args.run:
            write(result, rendered_path(src))
        print(f"ok   {src.name} ({seconds:.1f} s){'' if args.run else ' -> ' + rendered_path(src).name}")
    print(f"{len(paths) - len(failed)}/{len(paths)} notebooks in {time.perf_counter() - total:.1f} s (jobs={args.jobs})")
    return 1 if failed else 0


def register(sub) -> None:
    p = sub.add_parser("notebooks", help="execute the derivation notebooks of derive/ and render them beside their sources")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true",
                      help="write nothing; exit 1 naming each rendered notebook missing or stale against its source")
    mode.add_argument("--run", action="store_true", help="execute from a clean kernel, write nothing")
    p.add_argument("--only", nargs="+", metavar="NAME", help="notebooks whose name starts with NAME (e.g. 03)")
    p.add_argument("--timeout", type=positive_int, default=600, help="seconds per cell (default 600)")
    p.add_argument("--jobs", type=positive_int, default=2, help="notebooks executed at once, each in its own kernel (default 2)")
    p.set_defaults(fn=cmd_notebooks)
