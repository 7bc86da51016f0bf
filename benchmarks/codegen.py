"""Benchmark (not a test): size and speed of the emitted code against the number of balls.

Issue: code generation, "operation count of the emitted rhs and jac for n = 1..32 (linear), and ns
per rhs call of numba and C against sympy.lambdify, written to a committed results file".

Three parts, all for the model kinds indexed by n of the registered families (`adbgen.families.kinds`):

- ``ops``: SymPy's ``count_ops`` of the intermediate form's ``rhs`` and ``jac`` programs (the exact
  statements every target prints), the number of statements and the build time (derivation and
  lowering) for n = 1, 2, 4, ..., 32, with least-squares fits.  The rhs is fitted by a + b n.  The jac
  is split into its parts: the shared prefix (the rhs' statements it reuses), the derivative
  expressions (``v_*`` and ``dR_*``: O(n)), and the per-column structured solves and stores (one
  solve per column of the dense 2N x 2N Jacobian: O(n^2)); the whole is fitted by a + b n + c n^2.
- ``forms`` (issue 10): the loop form against the unrolled form, see `bench_forms`.
- ``speed``: ns per call of the rhs (and the jac) rendered from the templates into a temporary
  folder, all measured in one run so that the ratios are meaningful (absolute times are not
  comparable across machines or runs):

  * numba ``rhs_inplace``/``jac_inplace`` called in a jitted loop (no Python call overhead),
  * numba ``rhs`` called from Python (what ``solve_ivp`` sees),
  * C ``<model>_rhs``/``<model>_jac`` called in a loop by a timing program compiled with ``gcc -O2``,
  * ``sympy.lambdify`` of the closed form ``system.rhs()`` (``cse=True``; modules "math" and
    "numpy") called from Python.

  In the loops each call's input depends on the previous call's output (y[0] is nudged by 1e-300
  times an output), so a compiler cannot hoist the pure computation out of the loop; consecutive
  calls are serialised, as the stages of an integrator are.  Every figure is the median of
  ``repeats`` repeats (all repeats are recorded), each repeat about ``target_seconds`` long.
"""

from __future__ import annotations

import os
import re
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from adbgen.cli_types import positive_int

from .registry import BALL_COUNTS, Benchmark, option
from .report import machine, write
from . import symbolic
from .symbolic import closed_form, kinds, sample_point
from .timing import c_compiler, numba_loop, time_c, time_calls, time_python

OPS_NS = (1, 2, 4, 8, 16, 32)
SPEED_NS = (2, 4, 8, 16)
JAC_NS = (2, 4, 8)
# The closed form grows faster than n^2 (Cramer's rule on the full system): at n = 16 lambdify takes
# ~10 s per module, and for the thesis model its source exceeds CPython's compiler recursion limit
# (recorded as such).  Above LAMBDIFY_BOTH_MAX_N only modules="math" is tried.
LAMBDIFY_MAX_N = 16
LAMBDIFY_BOTH_MAX_N = 8

_JAC_DERIVATIVE = re.compile(r"^(v_\d+|dR_\d+_\d+)$")
_JAC_COLUMN = re.compile(r"^(gs|zs|xs)_\d+_\d+$")


# --------------------------------------------------------------------------------------------- ops

def _ops(exprs) -> int:
    import sympy as sp

    return int(sum(sp.count_ops(e) for e in exprs))


def _clear_derivation_cache() -> None:
    """Each build times its derivation from scratch (the single-plane derivation is cached per scene)."""
    from adbgen.families.single_plane.model import derive

    derive.cache_clear()


def jac_parts(program) -> dict:
    """Ops of the jac program split into shared prefix, derivative expressions and column solves."""
    import sympy as sp

    parts = {"shared": 0, "derivatives": 0, "column_solves": 0}
    for lhs, expr in program.assignments:
        key = "derivatives" if _JAC_DERIVATIVE.match(lhs.name) else \
            "column_solves" if _JAC_COLUMN.match(lhs.name) else "shared"
        parts[key] += int(sp.count_ops(expr))
    parts["column_solves"] += _ops(e for _, e in program.outputs)  # stores (mostly bare symbols)
    return parts


def polyfit(ns, values, degree: int) -> dict:
    """Least-squares polynomial in n; coefficients from the constant up, worst residual / value."""
    x = np.asarray(ns, float)
    y = np.asarray(values, float)
    coeffs = np.polynomial.polynomial.polyfit(x, y, degree)
    resid = y - np.polynomial.polynomial.polyval(x, coeffs)
    return {"coefficients": [round(float(c), 4) for c in coeffs],
            "max_relative_residual": round(float(np.max(np.abs(resid) / np.abs(y))), 5)}


def build_spec(spec, system=None, form=None):
    """The model's intermediate form (`codegen.spec.build`), imported when a benchmark runs."""
    from adbgen.codegen.passes.lowering import DEFAULT_FORM
    from adbgen.codegen.spec import build

    return build(spec, system, form=form or DEFAULT_FORM)


def bench_ops(ns=OPS_NS, families=None, progress=None) -> dict:
    families = tuple(families or kinds())
    rows = []
    for family in families:
        for n in ns:
            _clear_derivation_cache()
            start = time.perf_counter()
            ir = build_spec(kinds()[family](n), form="unrolled")  # the straight-line programs' structure
            seconds = time.perf_counter() - start
            parts = jac_parts(ir.jac)
            row = {"family": family, "n": n, "build_seconds": round(seconds, 3),
                   "rhs_ops": ir.rhs.count_ops(), "rhs_statements": len(ir.rhs.assignments),
                   "jac_ops": ir.jac.count_ops(), "jac_statements": len(ir.jac.assignments),
                   "jac_nonzero_outputs": len(ir.jac.outputs),
                   "jac_ops_shared": parts["shared"], "jac_ops_derivatives": parts["derivatives"],
                   "jac_ops_column_solves": parts["column_solves"]}
            assert sum(parts.values()) == row["jac_ops"], (parts, row["jac_ops"])
            rows.append(row)
            if progress:
                progress(row)
    fits = {}
    for family in families:
        sel = [r for r in rows if r["family"] == family]
        if len(sel) < 2:
            continue
        n = [r["n"] for r in sel]
        fits[family] = {
            "rhs_ops_linear": polyfit(n, [r["rhs_ops"] for r in sel], 1),
            "rhs_ops_per_ball_first_last": [round(sel[0]["rhs_ops"] / sel[0]["n"], 2),
                                            round(sel[-1]["rhs_ops"] / sel[-1]["n"], 2)],
            "jac_ops_derivatives_linear": polyfit(n, [r["jac_ops_derivatives"] for r in sel], 1),
            "jac_ops_shared_linear": polyfit(n, [r["jac_ops_shared"] for r in sel], 1),
            "jac_ops_linear": polyfit(n, [r["jac_ops"] for r in sel], 1),
        }
        if len(sel) >= 3:
            fits[family]["jac_ops_quadratic"] = polyfit(n, [r["jac_ops"] for r in sel], 2)
            fits[family]["jac_ops_column_solves_quadratic"] = polyfit(
                n, [r["jac_ops_column_solves"] for r in sel], 2)
    return {"rows": rows, "fits": fits}


# ------------------------------------------------------------------------------------------- speed

def bench_speed_one(family: str, n: int, workdir: Path, *, target: float = 0.1, repeats: int = 5,
                    jac: bool = True, lambdify: bool = True, cc: str | None = None, form: str | None = None,
                    native: bool = True) -> dict:
    """ns per call for one model in one form (`lowering.FORMS`): numba (jitted loop, from Python), C,
    sympy.lambdify; with the emitted source sizes and the first calls' (compilation) times."""
    from adbgen.codegen.passes.lowering import DEFAULT_FORM
    from adbgen.codegen.render_and_import import import_numba, render_into

    form = form or DEFAULT_FORM
    spec = kinds()[family](n)
    _clear_derivation_cache()
    system = spec.system()
    ir = build_spec(spec, system, form=form)
    folder = render_into(ir, workdir / f"{family}_n{n}_{form}", ("numba", "c"))
    y, p = sample_point(system, ir.n_states)
    row: dict = {"family": family, "n": n, "form": ir.form, "n_states": ir.n_states, "rhs_ops": ir.count_ops("rhs"),
                 "jac_ops": ir.count_ops("jac"),
                 "source_bytes": {"numba": len((folder / "__init__.py").read_bytes()),
                                  "c": len((folder / f"{ir.name}.c").read_bytes())}}

    # numba
    mod = import_numba(folder, f"_adbgen_bench_{ir.name}_{form}")
    out = np.empty(ir.n_states)
    start = time.perf_counter()
    mod.rhs_inplace(0.0, y, p, out)
    row["numba_first_call_seconds_rhs"] = round(time.perf_counter() - start, 3)
    loop = numba_loop(mod.rhs_inplace)
    loop(y, p, out, 1)
    row["numba_compile_seconds_rhs"] = round(time.perf_counter() - start, 3)
    reference = np.asarray(mod.rhs(0.0, y, p))
    row["numba_rhs_loop"] = time_calls(lambda calls: loop(y, p, out, calls), target, repeats)
    row["numba_rhs_python"] = time_python(mod.rhs, (0.0, y, p), target, repeats)
    if jac:
        jout = np.empty((ir.n_states, ir.n_states))
        start = time.perf_counter()
        mod.jac_inplace(0.0, y, p, jout)
        row["numba_first_call_seconds_jac"] = round(time.perf_counter() - start, 3)
        jloop = numba_loop(mod.jac_inplace)
        jloop(y, p, jout, 1)
        mod.jac(0.0, y, p)
        row["numba_compile_seconds_jac"] = round(time.perf_counter() - start, 3)
        row["numba_jac_loop"] = time_calls(lambda calls: jloop(y, p, jout, calls), target, repeats)
        row["numba_jac_python"] = time_python(mod.jac, (0.0, y, p), target, repeats)

    # C
    cc = cc or c_compiler()
    if cc:
        c = time_c(folder, ir.name, y, p, target, repeats, jac, cc=cc)
        row["c_compile_seconds"] = c["compile_seconds"]
        row["c_rhs_loop"] = c["rhs"]
        if jac:
            row["c_jac_loop"] = c["jac"]
        # numba compiles for the host CPU (like -march=native): the same C built that way, for fairness
        if native:
            try:
                c = time_c(folder, ir.name, y, p, target, repeats, jac, cc=cc, flags=("-O2", "-march=native"),
                            suffix="_native")
            except subprocess.CalledProcessError as exc:
                row["c_native_rhs_loop"] = f"skipped: {exc.stderr.strip()[:200]}"
            else:
                row["c_native_rhs_loop"] = c["rhs"]
                if jac:
                    row["c_native_jac_loop"] = c["jac"]
    else:
        row["c_rhs_loop"] = "skipped: no C compiler"

    # sympy.lambdify of the closed form
    if lambdify:
        closed = closed_form(system)
        row["closed_form_ops"] = _ops(closed)
        if n > LAMBDIFY_BOTH_MAX_N:
            row["lambdify_numpy"] = f"skipped: n > {LAMBDIFY_BOTH_MAX_N} (lambdify alone takes ~10 s)"
        for modules in ("math", "numpy") if n <= LAMBDIFY_BOTH_MAX_N else ("math",):
            key = f"lambdify_{modules}"
            start = time.perf_counter()
            try:
                fn = symbolic.lambdify(system, closed, modules)
            except RecursionError as exc:  # the closed form's source is too deep for CPython
                row[key] = f"failed: {type(exc).__name__} in lambdify after {time.perf_counter() - start:.1f} s"
                continue
            setup = time.perf_counter() - start
            err = float(np.max(np.abs(np.asarray(fn(0.0, y, p), float) - reference))
                        / np.max(np.abs(reference)))
            row[key] = {**time_python(fn, (0.0, y, p), target, repeats),
                        "lambdify_seconds": round(setup, 3), "relative_difference_to_numba": err}
    else:
        row["lambdify_math"] = row["lambdify_numpy"] = f"skipped: n > {LAMBDIFY_MAX_N}, see notes"

    # ratios of medians, all from this run
    def ns(key):
        v = row.get(key)
        return v["ns"] if isinstance(v, dict) else None

    base = ns("numba_rhs_loop")
    ratios = {}
    for key in ("c_rhs_loop", "c_native_rhs_loop", "numba_rhs_python", "lambdify_math", "lambdify_numpy"):
        if ns(key) is not None and base:
            ratios[f"{key}/numba_rhs_loop"] = round(ns(key) / base, 3)
    if ns("c_rhs_loop"):
        for key in ("numba_rhs_python", "lambdify_math", "lambdify_numpy"):
            if ns(key) is not None:
                ratios[f"{key}/c_rhs_loop"] = round(ns(key) / ns("c_rhs_loop"), 2)
    if ns("numba_rhs_python"):
        for key in ("lambdify_math", "lambdify_numpy"):
            if ns(key) is not None:
                ratios[f"{key}/numba_rhs_python"] = round(ns(key) / ns("numba_rhs_python"), 2)
    for key in ("c_jac_loop", "c_native_jac_loop"):
        if ns("numba_jac_loop") and ns(key):
            ratios[f"{key}/numba_jac_loop"] = round(ns(key) / ns("numba_jac_loop"), 3)
    if ns("numba_jac_loop") and base:
        ratios["numba_jac_loop/numba_rhs_loop"] = round(ns("numba_jac_loop") / base, 2)
    row["ratios"] = ratios
    return row


def bench_speed(ns=SPEED_NS, families=None, *, jac_ns=JAC_NS, lambdify_max_n=LAMBDIFY_MAX_N,
                target: float = 0.1, repeats: int = 7, progress=None) -> list[dict]:
    families = tuple(families or kinds())
    rows = []
    with tempfile.TemporaryDirectory(prefix="adbgen-bench-") as tmp:
        for family in families:
            for n in ns:
                row = bench_speed_one(family, n, Path(tmp), target=target, repeats=repeats,
                                      jac=n in jac_ns, lambdify=n <= lambdify_max_n)
                rows.append(row)
                if progress:
                    progress(row)
    return rows


FORMS_NS = (1, 2, 4, 8, 16, 32, 64)
UNROLLED_MAX_N = 16  # the unrolled form's jac takes minutes to compile in numba beyond (230 s at n = 32)
UNROLLED_JAC_MAX_N = 8


def bench_forms(ns=FORMS_NS, families=None, *, unrolled_max_n: int = UNROLLED_MAX_N,
                unrolled_jac_max_n: int = UNROLLED_JAC_MAX_N, target: float = 0.1, repeats: int = 5,
                progress=None) -> dict:
    """Issue 10: the loop form against the unrolled form, per family and n: emitted source size, first
    calls of numba's rhs and jac (compilation), gcc -O2 time, ns per rhs and jac call (numba in a
    jitted loop, C from a C loop), all in one run; the unrolled form up to `unrolled_max_n` (its jac up
    to `unrolled_jac_max_n`)."""
    families = tuple(families or kinds())
    rows, ratios = [], []
    with tempfile.TemporaryDirectory(prefix="adbgen-bench-forms-") as tmp:
        for family in families:
            for n in ns:
                pair = {}
                for form in ("loops", "unrolled"):
                    if form == "unrolled" and n > unrolled_max_n:
                        continue
                    jac = form == "loops" or n <= unrolled_jac_max_n
                    row = bench_speed_one(family, n, Path(tmp), target=target, repeats=repeats, jac=jac,
                                          lambdify=False, form=form, native=False)
                    for key in ("lambdify_math", "lambdify_numpy", "numba_rhs_python", "numba_jac_python"):
                        row.pop(key, None)
                    rows.append(row)
                    pair[form] = row
                    if progress:
                        progress(row)
                if len(pair) == 2:
                    ratio = {"family": family, "n": n}
                    for key in ("numba_rhs_loop", "c_rhs_loop", "numba_jac_loop", "c_jac_loop"):
                        a, b = pair["loops"].get(key), pair["unrolled"].get(key)
                        if isinstance(a, dict) and isinstance(b, dict):
                            ratio[f"{key} loops/unrolled"] = round(a["ns"] / b["ns"], 3)
                    ratios.append(ratio)
    return {"rows": rows, "ratios_loops_over_unrolled": ratios}


NOTES = (
    "ops: sympy count_ops of the intermediate form's programs (what every target prints). The rhs "
    "grows linearly in n (fit a + b n). The jac's differentiated expressions (v_*, dR_*) and its "
    "shared prefix (the rhs' statements) grow linearly too, but the Jacobian is dense (every "
    "acceleration depends on every angle through the rotor), so one structured solve per column of "
    "the 2N x 2N matrix costs O(n^2) in all: the whole jac is fitted by a + b n + c n^2. "
    "speed: ns per call, median of the repeats (min_ns: the fastest repeat, less sensitive to a "
    "loaded machine), all in one run: compare ratios, not absolute times across runs or machines. "
    "Loops feed y[0] back from the output so calls cannot be hoisted. numba loop = rhs_inplace in a "
    "jitted loop (numba may inline it); numba python = rhs(t, y, p) from Python incl. the call "
    "overhead and a new array; C = <model>_rhs from a C loop (separate translation unit, gcc -O2; "
    "c_native: -O2 -march=native, as numba targets the host CPU); lambdify = "
    "sympy.lambdify(cse=True) of the closed form system.rhs() called from Python (returns a list; "
    "solve_ivp would add an asarray). The closed form (Cramer's rule) grows faster than n^2 "
    "(closed_form_ops): at n = 16 only modules='math' is tried (lambdify alone takes ~10 s), and "
    "for the thesis model the generated source exceeds CPython's compiler recursion limit (recorded "
    "as failed). "
    "ops: the unrolled form's programs (`--form unrolled`; the default form's loops print each ball's "
    "block once, so its op counts do not grow with n). "
    "forms (issue 10): per family and n, the loop form (the default) and the unrolled form (up to "
    "unrolled_max_n, its jac up to unrolled_jac_max_n: beyond, its numba jac takes minutes to compile): "
    "source bytes of the numba module and the C file, first calls of numba's rhs_inplace and jac_inplace "
    "(compilation included, a fresh cache), gcc -O2 time of the timing program with the model's C file, "
    "ns per call in a jitted loop (numba) and a C loop; ratios loops/unrolled from this run."
)


def bench_codegen(ops_ns=OPS_NS, speed_ns=SPEED_NS, *, families=None, jac_ns=JAC_NS,
                  lambdify_max_n=LAMBDIFY_MAX_N, target: float = 0.1, repeats: int = 7,
                  progress=None, forms_ns=FORMS_NS, parts=("ops", "speed", "forms")) -> dict:
    families = tuple(families or kinds())
    start = time.perf_counter()
    out = {"benchmark": "codegen", "machine": machine(), "notes": NOTES,
           "settings": {"ops_n": list(ops_ns), "speed_n": list(speed_ns), "jac_speed_n": list(jac_ns),
                        "lambdify_max_n": lambdify_max_n, "families": list(families), "forms_n": list(forms_ns),
                        "unrolled_max_n": UNROLLED_MAX_N, "unrolled_jac_max_n": UNROLLED_JAC_MAX_N,
                        "repeat_target_seconds": target, "repeats": repeats, "parts": list(parts)}}
    if "ops" in parts:
        out["ops"] = bench_ops(tuple(ops_ns), families, progress=progress)
    if "speed" in parts:
        out["speed"] = bench_speed(tuple(speed_ns), families, jac_ns=tuple(jac_ns), lambdify_max_n=lambdify_max_n,
                                   target=target, repeats=repeats, progress=progress)
    if "forms" in parts:
        out["forms"] = bench_forms(tuple(forms_ns), families, target=target, repeats=min(repeats, 5),
                                   progress=progress)
    out["load_average_at_end"] = list(os.getloadavg())
    out["seconds"] = round(time.perf_counter() - start, 1)
    return out


def describe(row: dict) -> str:
    """One progress line for a row of either part."""
    if "rhs_statements" in row:
        return (f"ops   {row['family']:18s} n={row['n']:3d}  rhs {row['rhs_ops']:6d}  jac {row['jac_ops']:7d} "
                f"(shared {row['jac_ops_shared']}, derivatives {row['jac_ops_derivatives']}, "
                f"column solves {row['jac_ops_column_solves']})  build {row['build_seconds']:.2f} s")

    def ns(key):
        v = row.get(key)
        return f"{v['ns']:.0f}" if isinstance(v, dict) else "-"

    if "source_bytes" in row and "numba_rhs_python" not in row:
        return (f"forms {row['family']:18s} n={row['n']:3d} {row['form']:8s} source {row['source_bytes']['numba']} B "
                f"(C {row['source_bytes']['c']} B), first calls rhs {row['numba_first_call_seconds_rhs']:.2f} s, jac "
                f"{row.get('numba_first_call_seconds_jac', float('nan')):.2f} s, gcc {row.get('c_compile_seconds', 0):.2f} s; "
                f"ns rhs numba {ns('numba_rhs_loop')} C {ns('c_rhs_loop')}, jac numba {ns('numba_jac_loop')} "
                f"C {ns('c_jac_loop')}")
    return (f"speed {row['family']:18s} n={row['n']:3d}  rhs ns: numba loop {ns('numba_rhs_loop')}, "
            f"numba python {ns('numba_rhs_python')}, C {ns('c_rhs_loop')} (native {ns('c_native_rhs_loop')}), "
            f"lambdify math "
            f"{ns('lambdify_math')}, numpy {ns('lambdify_numpy')}; jac ns: numba {ns('numba_jac_loop')}, "
            f"C {ns('c_jac_loop')}")


def run(args, out: str) -> int:
    ns = tuple(args.n)  # op counts for every n; timings for n <= 16 (jac and lambdify up to 8)
    result = bench_codegen(ns, tuple(n for n in ns if n <= max(SPEED_NS)), progress=lambda r: print(describe(r), flush=True),
                           **({"forms_ns": tuple(args.forms_n)} if args.forms_n else {}),
                           **({"parts": tuple(args.parts)} if args.parts else {}))
    path = write(result, out)
    print(f"wrote {path} ({result['seconds']} s)")
    return 0


BENCHMARK = Benchmark("codegen", run, (
    BALL_COUNTS.but("ball counts"),
    option("--forms-n", type=positive_int, nargs="+", default=None,
           help="n of the loop-versus-unrolled comparison (default 1 2 4 8 16 32 64)"),
    option("--parts", nargs="+", choices=("ops", "speed", "forms"), default=None, help="only these parts (default: all)"),
))


__all__ = ["BENCHMARK", "bench_codegen", "bench_forms", "bench_ops", "bench_speed", "bench_speed_one", "describe",
           "jac_parts", "polyfit"]
