"""The floor of an integration: its rhs evaluations times the cost of one call of the generated rhs
in a tight loop.  An engine at its floor spends nothing but the rhs; wall / floor says how much the
method's own work (and the engine's overhead) adds.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Callable

import numpy as np

from .pathways import Pathway
from .timing import best_per_call, build_c_timer, c_compiler, calibrate, numba_loop, run_c_timer


def floor_pathways(model, y, p, folder: Path, target: float = 0.01, inner: int = 5) -> list[Pathway]:
    """ns per call of the generated rhs as pathways (timed in the round-robin with the integrations).

    "floor:c": the C rhs in a C loop (gcc -O2, as the engines are built; the timing program
    c/rhs_timer.c); "floor:numba": rhs_inplace in a jitted loop.  Each run times `inner` bursts of
    about `target` seconds of calls and keeps the fastest (short bursts find the quiet moments of a
    shared machine, as the integrations' best-of-N does); `wall_s` holds seconds per call."""
    y = np.ascontiguousarray(y, dtype=float)
    p = np.ascontiguousarray(p, dtype=float)
    out = []
    cc = c_compiler()
    if cc:
        src = model.c_source()
        for suffix in (".c", ".h"):
            shutil.copy(src.with_suffix(suffix), folder / (model.name + suffix))
        exe, _ = build_c_timer(folder, model.name, y, p, cc=cc)

        def run_c():
            return {"wall_s": 1e-9 * run_c_timer(exe, target, inner, False)["rhs"]["min_ns"], "status": "success"}

        out.append(Pathway("floor:c", "floor", "C rhs, gcc -O2, in a C loop", 0.0, run_c,
                           probe=lambda seconds: 1e-9 * run_c_timer(exe, seconds, 1, False)["rhs"]["min_ns"]))
    buf = np.empty(model.n_states)
    loop = numba_loop(model.module.rhs_inplace)
    loop(y, p, buf, 1)
    calls = calibrate(lambda k: loop(y, p, buf, k), target)

    def run_numba():
        return {"wall_s": best_per_call(lambda k: loop(y, p, buf, k), calls, inner), "status": "success"}

    out.append(Pathway("floor:numba", "floor", "numba rhs_inplace in a jitted loop", 0.0, run_numba))
    return out


def floor_record(floors: list[Pathway], engines: list[dict]) -> dict:
    """ns per call (best of the rounds) and, per engine, floor = n_rhs x ns and wall / floor."""
    out: dict = {"c_flags": "-std=c99 -O2"}
    for pw in floors:
        out[pw.key.split(":")[1] + "_rhs_loop"] = {"what": pw.name, "runs_ns": [round(1e9 * t, 2) for t in pw.runs_s],
                                                   "min_ns": round(1e9 * min(pw.runs_s), 2) if pw.runs_s else None}
    per_call = next((min(pw.runs_s) for pw in floors if pw.key == "floor:c" and pw.runs_s), None)
    out["basis"] = "C" if per_call else "numba"
    if per_call is None:
        per_call = next((min(pw.runs_s) for pw in floors if pw.runs_s), None)
    out["seconds_per_call"] = per_call
    out["floor_s"], out["ratio"] = {}, {}
    for rec in engines:
        if per_call and rec.get("n_rhs") and rec.get("wall_s"):
            out["floor_s"][rec["key"]] = round(rec["n_rhs"] * per_call, 6)
            out["ratio"][rec["key"]] = round(rec["wall_s"] / (rec["n_rhs"] * per_call), 3)
    return out


def paired_floor(engines: list[Pathway], probe: Callable[[float], float], rounds: int) -> dict:
    """wall / floor per round, the floor timed by a burst of C rhs calls just before each integration.

    On a shared machine the best-of-N wall time and the best-of-N ns per call may come from moments
    of different load; a ratio taken from two measurements seconds apart mostly cancels the load, so
    its median is the robust figure (the best-of ratio is kept beside it)."""
    out = {}
    for _ in range(max(1, rounds)):
        for pw in engines:
            per_call = probe(min(max(min(pw.runs_s), 0.005), 0.05))
            run = pw.run()
            if run.get("status") == "success" and run.get("n_rhs"):
                out.setdefault(pw.key, []).append(run["wall_s"] / (run["n_rhs"] * per_call))
    return {key: {"ratios": [round(v, 3) for v in values], "median": round(float(np.median(values)), 3)}
            for key, values in out.items()}


__all__ = ["floor_pathways", "floor_record", "paired_floor"]
