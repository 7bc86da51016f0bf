"""Benchmarks (never timed tests): each module measures one question and writes its results to a committed
file under `benchmarks/` through `write` (`adbgen bench WHAT`, registered in `commands`).

derive      derivation time and expression size, and the regenerate stages, against n
codegen     emitted operations, source sizes, compile times, ns per call; loop form against unrolled
simulate    problem A on every engine and the peers, the floor, exchange symmetry, threads
peers       JiTCODE and heyoka fed the generated statements
precision   work-precision of problems A, B, C on every pathway; the loosest reliable tolerance
percall     ns per rhs/jac call: generated numba and C, lambdify, the hand-written baseline
baseline    the hand-written numba rhs of thesis Appendix A (the expert baseline)
failures    where methods fail (fixed_step, jacobi, pairs hold its parts)
smallest    one scene as the smallest exact model against the bigger ones
sweep       the 100 x 100 basin map with and without the shortcuts
"""

from __future__ import annotations

import json
from pathlib import Path


def write(result: dict, path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(json.dumps(result, indent=2, sort_keys=True) + "\n")
    tmp.replace(path)
    return path
