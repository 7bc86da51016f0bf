"""Benchmarks (not tests): derivation time and expression size against the number of balls.

Target (issue: single-plane model): n = 32 derived in under 30 s on the 2-core CI machine, with the
size of the structured first-order form growing linearly in n.  Results go to a committed JSON file;
compare ratios from one run, not absolute times across runs (the machine is noisy).
"""

from __future__ import annotations

import json
import platform
import time
from pathlib import Path

import sympy as sp

from .families.single_plane.model import derive
from .families.single_plane.reductions import first_order, nondimensionalise, rotating_frame
from .families.single_plane.verify import general_scene
from .families.single_plane.scene import Scene


def _derive_general(n: int):
    scene = general_scene(n)  # unequal balls, anisotropic, gravity, torque-driven: 3 + n coordinates
    eom = derive(scene)
    return eom, first_order(eom)


def _derive_thesis(n: int):
    scene = Scene(n=n)
    rot = rotating_frame(scene, nondimensionalise(scene, derive(scene)))
    return rot, first_order(rot)


def bench_derive(ns=(1, 2, 4, 8, 16, 32), progress=None) -> dict:
    rows = []
    for n in ns:
        for label, fn in (("general fixed frame (torque)", _derive_general),
                          ("thesis chain to first order", _derive_thesis)):
            derive.cache_clear()
            start = time.perf_counter()
            eom, fo = fn(n)
            seconds = time.perf_counter() - start
            row = {"model": label, "n": n, "seconds": round(seconds, 3), "eom_ops": eom.count_ops(),
                   "first_order_ops": fo.count_ops()}
            rows.append(row)
            if progress:
                progress(row)
    out = {"benchmark": "derive", "machine": f"{platform.machine()}, {platform.python_implementation()} "
           f"{platform.python_version()}, sympy {sp.__version__}", "rows": rows}
    for label in sorted({r["model"] for r in rows}):
        sel = [r for r in rows if r["model"] == label]
        first, last = sel[0], sel[-1]
        out.setdefault("summary", {})[label] = {
            "ops_per_ball_first": first["first_order_ops"] / first["n"],
            "ops_per_ball_last": last["first_order_ops"] / last["n"],
            "seconds_at_max_n": last["seconds"],
        }
    return out


def write(result: dict, path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(json.dumps(result, indent=2, sort_keys=True) + "\n")
    tmp.replace(path)
    return path
