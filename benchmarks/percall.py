"""Benchmark (not a test): ns per rhs and per jac call for n = 2 .. 32 balls (issue 14, item 2).

Part of `adbgen bench precision`.  For the thesis model (`thesis_rotating`, n balls), rendered from
the intermediate form into a temporary folder (as `adbgen bench codegen` does), all in one run:

- ``numba_rhs_loop`` / ``handwritten_rhs_loop``: the generated ``rhs_inplace`` and the hand-written
  baseline of thesis Appendix A (`bench.baseline`), each in a jitted loop (`bench.timing.numba_loop`:
  y[0] fed back from the output so that calls cannot be hoisted), their repeats interleaved so that
  the machine's load hits both alike;
- ``numba_jac_loop``: the generated ``jac_inplace`` in the same loop;
- ``c_rhs_loop`` / ``c_jac_loop``: the generated C in a C loop (`bench.timing.build_c_timer`, gcc -O2);
- ``numba_rhs_python``: the generated ``rhs`` called from Python (what solve_ivp sees);
- ``lambdify_math`` / ``lambdify_numpy``: ``sympy.lambdify(cse=True)`` of the closed form, called from
  Python; ``lambdify_jac_math``: of the closed form's Jacobian (small n only: its size explodes).

The thesis gives no Jacobian, so the hand-written baseline has none.  Each figure is the median of
the repeats (``min_ns``: the fastest repeat; all repeats recorded).  Targets (`targets`): the
generated numba rhs within 1.2x of the hand-written one, and at least 50x faster than the best
lambdify variant (modules="math", cse=True), at every n measured.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from . import symbolic
from . import report
from .timing import numba_loop, paired_loops, time_c, time_python

NS = (2, 4, 8, 16, 32)
JAC_MAX_N = 64  # the loop form's jac compiles in about a second at any n (the unrolled one took 9-32 s at n = 16)
LAMBDIFY_BOTH_MAX_N = 8
LAMBDIFY_MAX_N = 16
LAMBDIFY_JAC_MAX_N = 2
FAMILY = "thesis_rotating"


def percall_one(n: int, workdir: Path, *, target: float = 0.05, repeats: int = 5, jac: bool = True,
                lambdify_modules=("math", "numpy"), lambdify_jac: bool = False, progress=None) -> dict:
    import sympy as sp

    from . import baseline as bench_baseline
    from adbgen.codegen.render_and_import import import_numba, render_into
    from adbgen.codegen.spec import build as build_ir
    from adbgen.families.single_plane.model import derive

    derive.cache_clear()
    spec = symbolic.kinds()[FAMILY](n)
    start = time.perf_counter()
    system = spec.system()
    ir = build_ir(spec, system)
    folder = render_into(ir, workdir / f"{FAMILY}_n{n}", ("numba", "c"))
    row: dict = {"n": n, "n_states": ir.n_states, "build_s": round(time.perf_counter() - start, 3)}
    mod = import_numba(folder, f"_adbgen_percall_{ir.name}")
    bench_baseline.check_layout(mod)
    y, p = symbolic.sample_point(system, ir.n_states)
    out = np.empty(ir.n_states)
    row["handwritten_max_relative_difference"] = bench_baseline.max_difference(mod, samples=50)

    start = time.perf_counter()
    gen, hand = numba_loop(mod.rhs_inplace), numba_loop(bench_baseline.rhs_inplace)
    gen(y, p, out, 1)
    hand(y, p, out, 1)
    loops = {"numba_rhs_loop": lambda k: gen(y, p, out, k), "handwritten_rhs_loop": lambda k: hand(y, p, out, k)}
    if jac and n <= JAC_MAX_N:
        jout = np.empty((ir.n_states, ir.n_states))
        jl = numba_loop(mod.jac_inplace)
        jl(y, p, jout, 1)
        loops["numba_jac_loop"] = lambda k: jl(y, p, jout, k)
    elif jac:
        row["numba_jac_loop"] = f"not measured: n > {JAC_MAX_N} (numba's compile time of the dense jac)"
    row["numba_compile_s"] = round(time.perf_counter() - start, 3)
    row.update(paired_loops(loops, target, repeats))
    row["numba_rhs_python"] = time_python(mod.rhs, (0.0, y, p), target, repeats)
    try:
        c = time_c(folder, ir.name, y, p, target, repeats, jac)  # gcc builds the n = 32 jac in seconds
        row["c_rhs_loop"] = c["rhs"]
        if "jac" in c:
            row["c_jac_loop"] = c["jac"]
    except Exception as exc:  # no compiler: recorded
        row["c_rhs_loop"] = f"not measured: {type(exc).__name__}: {exc}"

    if lambdify_modules:
        start = time.perf_counter()
        closed = symbolic.closed_form(system)
        row["closed_form_s"] = round(time.perf_counter() - start, 3)
        ref = np.asarray(mod.rhs(0.0, y, p))
        for modules in lambdify_modules:
            key = f"lambdify_{modules}"
            start = time.perf_counter()
            try:
                fn = symbolic.lambdify(system, closed, modules)
            except RecursionError as exc:
                row[key] = f"failed: {type(exc).__name__} in lambdify after {time.perf_counter() - start:.1f} s"
                continue
            setup = round(time.perf_counter() - start, 3)
            diff = float(np.max(np.abs(np.asarray(fn(0.0, y, p), float) - ref)) / np.max(np.abs(ref)))
            row[key] = {**time_python(fn, (0.0, y, p), target, repeats), "lambdify_s": setup,
                        "relative_difference_to_numba": diff}
        if lambdify_jac:
            start = time.perf_counter()
            J = sp.Matrix(closed).jacobian(list(system.states))
            fj = symbolic.lambdify(system, J.tolist(), "math")
            setup = round(time.perf_counter() - start, 3)
            jref = np.asarray(mod.jac(0.0, y, p))
            diff = float(np.max(np.abs(np.asarray(fj(0.0, y, p), float) - jref)) / np.max(np.abs(jref)))
            row["lambdify_jac_math"] = {**time_python(fj, (0.0, y, p), target, repeats),
                                        "jacobian_and_lambdify_s": setup, "relative_difference_to_numba": diff}
    _ratios(row)
    if progress:
        progress(describe(row))
    return row


def _ns(row, key):
    v = row.get(key)
    return v["ns"] if isinstance(v, dict) else None


def _ratios(row: dict) -> None:
    base = _ns(row, "numba_rhs_loop")
    r = {}
    for key in ("handwritten_rhs_loop", "c_rhs_loop", "numba_rhs_python", "lambdify_math", "lambdify_numpy"):
        if _ns(row, key) and base:
            r[f"{key}/numba_rhs_loop"] = round(_ns(row, key) / base, 3)
    for key in ("lambdify_math", "lambdify_numpy"):
        if _ns(row, key) and _ns(row, "numba_rhs_python"):
            r[f"{key}/numba_rhs_python"] = round(_ns(row, key) / _ns(row, "numba_rhs_python"), 2)
    if _ns(row, "numba_jac_loop"):
        for key in ("c_jac_loop", "lambdify_jac_math"):
            if _ns(row, key):
                r[f"{key}/numba_jac_loop"] = round(_ns(row, key) / _ns(row, "numba_jac_loop"), 3)
    row["ratios"] = r


def describe(row: dict) -> str:
    def f(key):
        v = _ns(row, key)
        return "-" if v is None else f"{v:.0f}"

    return (f"per call n={row['n']:2d}: rhs ns numba {f('numba_rhs_loop')}, hand-written {f('handwritten_rhs_loop')}, "
            f"C {f('c_rhs_loop')}, numba from Python {f('numba_rhs_python')}, lambdify math {f('lambdify_math')}, "
            f"numpy {f('lambdify_numpy')}; jac ns numba {f('numba_jac_loop')}, C {f('c_jac_loop')}, "
            f"lambdify {f('lambdify_jac_math')}")


def bench_percall(ns=NS, *, quick: bool = False, target: float | None = None, repeats: int | None = None,
                  progress=None) -> dict:
    target = target or (0.01 if quick else 0.05)
    repeats = repeats or (3 if quick else 7)
    rows = []
    with tempfile.TemporaryDirectory(prefix="adbgen-percall-") as tmp:
        for n in ns:
            if n <= LAMBDIFY_BOTH_MAX_N:
                modules = ("math", "numpy")
            elif n <= LAMBDIFY_MAX_N and not quick:
                modules = ("math",)
            else:
                modules = ()
            row = percall_one(n, Path(tmp), target=target, repeats=repeats, lambdify_modules=modules,
                              lambdify_jac=n <= LAMBDIFY_JAC_MAX_N, progress=progress)
            if not modules:
                row["lambdify_math"] = (f"not attempted: n > {LAMBDIFY_MAX_N if not quick else LAMBDIFY_BOTH_MAX_N} "
                                        "(the closed form grows faster than n^2)")
            rows.append(row)
    return {"family": FAMILY, "target_seconds": target, "repeats": repeats, "rows": rows,
            "notes": "ns per call, median of the repeats; loops are jitted (numba) or C (gcc -O2); lambdify and "
                     "numba_rhs_python are Python calls. The hand-written baseline (thesis Appendix A, "
                     "bench.baseline) has no jac: the thesis gives none."}


def targets(percall: dict) -> list[dict]:
    rows = percall["rows"]
    hand = [(r["n"], _ns(r, "handwritten_rhs_loop") / _ns(r, "numba_rhs_loop")) for r in rows
            if _ns(r, "handwritten_rhs_loop") and _ns(r, "numba_rhs_loop")]
    out = []
    if hand:
        n_worst, worst = min(hand, key=lambda v: v[1])
        out.append(report.target("per call: generated numba rhs within 1.2x of the hand-written baseline",
                           "hand-written ns / generated ns >= 1/1.2 at every n", worst, round(1 / 1.2, 4),
                           "hand-written / generated per n: " + ", ".join(f"n={n}: {v:.2f}" for n, v in hand)
                           + f"; worst at n={n_worst} (generated = {1 / worst:.2f}x hand-written)"))
    lam = []
    for r in rows:
        best = min((v for v in (_ns(r, "lambdify_math"), _ns(r, "lambdify_numpy")) if v), default=None)
        if best and _ns(r, "numba_rhs_loop"):
            lam.append((r["n"], best / _ns(r, "numba_rhs_loop"),
                        best / _ns(r, "numba_rhs_python") if _ns(r, "numba_rhs_python") else None))
    if lam:
        n_worst, worst, _ = min(lam, key=lambda v: v[1])
        out.append(report.target("per call: generated numba rhs >= 50x faster than the best lambdify variant",
                           "best lambdify ns / numba loop ns >= 50 at every n measured", worst, 50.0,
                           "per n (loop; from Python): " + ", ".join(
                               f"n={n}: {a:.0f}x" + (f" ({b:.1f}x)" if b else "") for n, a, b in lam)
                           + f"; worst at n={n_worst}"))
    return out


__all__ = ["NS", "bench_percall", "describe", "percall_one", "targets"]
