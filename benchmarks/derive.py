"""Benchmark (not a test): derivation time and expression size against the number of balls, and the
stages of `adbgen regenerate --n N` (`adbgen bench derive [--n N ...] [--pipeline-n N ...]`).

Target (issue: single-plane model): n = 32 derived in under 30 s on the 2-core CI machine, with the
size of the structured first-order form growing linearly in n.  Results go to a committed JSON file;
compare ratios from one run, not absolute times across runs (the machine is noisy).
"""

from __future__ import annotations

import os
import platform
import time

from adbgen.cli_types import positive_int

from .registry import BALL_COUNTS, Benchmark, option
from .report import write


def _derive_general(n: int):
    from adbgen.families.single_plane.model import derive
    from adbgen.families.single_plane.reductions import first_order
    from adbgen.families.single_plane.verify import general_scene

    scene = general_scene(n)  # unequal balls, anisotropic, gravity, torque-driven: 3 + n coordinates
    eom = derive(scene)
    return eom, first_order(eom)


def _derive_thesis(n: int):
    from adbgen.families.single_plane.model import derive
    from adbgen.families.single_plane.reductions import first_order, nondimensionalise, rotating_frame
    from adbgen.families.single_plane.scene import Scene

    scene = Scene(n=n)
    rot = rotating_frame(scene, nondimensionalise(scene, derive(scene)))
    return rot, first_order(rot)


def bench_derive(ns=(1, 2, 4, 8, 16, 32), progress=None, pipeline_ns=None, pipeline_progress=None) -> dict:
    """The derivation's time and size for `ns`; with `pipeline_ns`, also `bench_pipeline` (issue 10)."""
    import sympy as sp

    from adbgen.families.single_plane.model import derive

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
    if pipeline_ns:
        out["load_average_at_start"] = list(os.getloadavg())
        out["pipeline"] = bench_pipeline(tuple(pipeline_ns), progress=pipeline_progress)
        out["load_average_at_end"] = list(os.getloadavg())
    return out


PIPELINE_NS = (1, 2, 4, 8, 16, 32, 64)


def bench_pipeline(ns=PIPELINE_NS, kinds=None, full_checks: bool = False, progress=None) -> dict:
    """Issue 10: the stages of `adbgen regenerate --n N` per model kind and n, timed one by one:
    derive (scene -> first-order system), checks (the kind's reduction checks, in their proportionate
    form unless full_checks, and the pre-write checks of every program), lower (the intermediate form,
    loop form) and emit (every target rendered), with the emitted sizes."""
    from adbgen import families
    from adbgen.codegen.passes.checks import check_programs, check_start
    from adbgen.codegen.render import render_model
    from adbgen.codegen.spec import build as build_ir
    from adbgen.families.single_plane.model import derive

    kinds = kinds or families.kinds()
    rows = []
    for n in ns:
        for kind, make in kinds.items():
            derive.cache_clear()
            spec = make(n)
            t0 = time.perf_counter()
            system = spec.system()
            t1 = time.perf_counter()
            ran = []
            for check in spec.checks:
                scaled = check.scaled is not None and not full_checks
                result = (check.scaled if scaled else check.run)()
                if not result.passed:
                    raise RuntimeError(f"check failed: {result.name}: {result.detail}")
                ran.append({"name": result.name, "seconds": round(result.seconds, 3), "proportionate": scaled})
            t2 = time.perf_counter()
            ir = build_ir(spec, system)
            t3 = time.perf_counter()
            errors = check_programs(ir, system)
            for model in (ir, ir.autonomous_extension):
                if model is not None and model.start is not None:
                    check_start(model)
            t4 = time.perf_counter()
            files = render_model(ir)
            t5 = time.perf_counter()
            row = {"kind": kind, "n": n, "form": ir.form, "derive_seconds": round(t1 - t0, 3),
                   "reduction_checks_seconds": round(t2 - t1, 3), "reduction_checks": ran,
                   "lower_seconds": round(t3 - t2, 3), "program_checks_seconds": round(t4 - t3, 3),
                   "emit_seconds": round(t5 - t4, 3), "total_seconds": round(t5 - t0, 3),
                   "lowering_errors": {k: float(f"{v:.3g}") for k, v in errors.items()},
                   "files": len(files), "bytes": sum(len(text.encode()) for text in files.values())}
            rows.append(row)
            if progress:
                progress(row)
    return {"rows": rows, "full_checks": full_checks, "ns": list(ns)}


def run(args, out: str) -> int:
    result = bench_derive(tuple(args.n), progress=lambda r: print(
        f"{r['model']:30s} n={r['n']:3d}  {r['seconds']:8.3f} s  eom ops {r['eom_ops']:7d}  first-order ops "
        f"{r['first_order_ops']:7d}", flush=True), pipeline_ns=tuple(args.pipeline_n or PIPELINE_NS),
        pipeline_progress=lambda r: print(
            f"pipeline {r['kind']:20s} n={r['n']:3d}  derive {r['derive_seconds']:.1f} s, reduction checks "
            f"{r['reduction_checks_seconds']:.1f} s, lower {r['lower_seconds']:.1f} s, program checks "
            f"{r['program_checks_seconds']:.1f} s, emit {r['emit_seconds']:.1f} s ({r['bytes']} bytes)", flush=True))
    path = write(result, out)
    print(f"wrote {path}")
    return 0


BENCHMARK = Benchmark("derive", run, (
    BALL_COUNTS.but("ball counts"),
    option("--pipeline-n", type=positive_int, nargs="+", default=None,
           help="n of the regenerate-stage timings (default 1 2 4 8 16 32 64)"),
))
