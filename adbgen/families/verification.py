"""Running families' checks and reporting them, one line each (`adbgen verify`, `adbgen two-plane
verify`): exit status 1 on a failure."""

from __future__ import annotations


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
          + (f" ({unreproduced} of the passed: printed values not reproduced, see docs/errata.md)"
             if unreproduced else ""))
    return 1 if failed else 0
