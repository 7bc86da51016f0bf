"""`adbgen verify`: every registered family's checks, one line each, non-zero exit on a failure."""

from __future__ import annotations

from . import all_families, get, names
from ..cli_types import positive_int


def run_verify(models, ns) -> int:
    failed = 0
    results = []

    def show(r):
        nonlocal failed
        failed += not r.passed
        print(f"{r.label:14s} {r.seconds:6.2f}s  {r.name:40s} [{r.kind}] {r.reference:48s} {r.detail}", flush=True)

    for family in models:
        results += family.verify(show, tuple(ns))
    unreproduced = sum(r.passed and r.label != "ok" for r in results)
    print(f"{len(results) - failed} passed, {failed} failed"
          + (f" ({unreproduced} of the passed: printed values not reproduced, as the README's errata say)"
             if unreproduced else ""))
    return 1 if failed else 0


def cmd_verify(args) -> int:
    chosen = all_families() if args.model == "all" else (get(args.model),)
    return run_verify(chosen, args.n)


def register(sub) -> None:
    v = sub.add_parser("verify", help="check every reduction against the references, every family")
    v.add_argument("--n", type=positive_int, nargs="+", default=[1, 2, 3, 4, 6],
                   help="numbers of balls for the checks that take one (single-plane)")
    v.add_argument("--model", choices=names() + ("all",), default="all", help="one family, or all")
    v.set_defaults(fn=cmd_verify)
    from .scene_reference import register as register_scenes

    register_scenes(sub)
