"""How the benchmarks time code: calls in a loop (numba or C), Python calls, bursts, CPU clocks.

The loops feed y[0] back from the previous output (by 1e-300 times an output: no effect on the
values), so a compiler cannot hoist the pure computation out of the loop, and consecutive calls are
serialised, as the stages of an integrator are.  A timing is calibrated to take about `target`
seconds per repeat; the figures are the median of the repeats (``ns``) and the fastest (``min_ns``,
less sensitive to a loaded machine), every repeat recorded.  The C loop is the program
``c/rhs_timer.c`` beside this module, compiled with the model's generated C source.
"""

from __future__ import annotations

import math
import resource
import shutil
import subprocess
import time
import timeit
from pathlib import Path
from statistics import median

C_DIR = Path(__file__).with_name("c")  # the benchmarks' C programs (package data)


def c_file(name: str) -> Path:
    """One of the benchmarks' C programs, e.g. "rhs_timer.c"."""
    return C_DIR / name


def c_compiler() -> str | None:
    return shutil.which("gcc") or shutil.which("cc")


# ------------------------------------------------------------------------------------- Python side

def calibrate(run, target: float) -> int:
    """Number of calls of run(calls) taking about `target` seconds."""
    calls = 16
    while True:
        start = time.perf_counter()
        run(calls)
        elapsed = time.perf_counter() - start
        if elapsed > 0.2 * target or calls > 1 << 40:
            return max(1, int(calls * target / elapsed))
        calls *= 4


def numba_loop(fn):
    """A jitted loop over `calls` calls of fn(t, y, p, out), with y[0] fed back (as in c/rhs_timer.c)."""
    from numba import njit

    @njit
    def loop(y0, p, out, calls):
        y = y0.copy()
        flat = out.reshape(-1)
        for _ in range(calls):
            fn(0.0, y, p, out)
            y[0] = y0[0] + 1e-300 * flat[flat.size - 1]
        return flat[flat.size - 1]

    return loop


def _summary(calls: int, times: list) -> dict:
    return {"calls": calls, "repeats_ns": [round(t, 2) for t in times], "ns": round(median(times), 2),
            "min_ns": round(min(times), 2)}


def time_calls(run, target: float, repeats: int) -> dict:
    """ns per call of run(calls): {calls, repeats_ns, ns (median), min_ns}."""
    calls = calibrate(run, target)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run(calls)
        times.append(1e9 * (time.perf_counter() - start) / calls)
    return _summary(calls, times)


def time_python(fn, args, target: float, repeats: int) -> dict:
    """ns per Python call fn(*args) (timeit's loop)."""
    timer = timeit.Timer(lambda: fn(*args))
    return time_calls(lambda calls: timer.timeit(calls), target, repeats)


def paired_loops(loops: dict, target: float, repeats: int) -> dict:
    """ns per call of several loop(calls) functions, their repeats interleaved (the machine's load
    hits them alike)."""
    calls = {k: calibrate(fn, target) for k, fn in loops.items()}
    times: dict = {k: [] for k in loops}
    for _ in range(repeats):
        for k, fn in loops.items():
            start = time.perf_counter()
            fn(calls[k])
            times[k].append(1e9 * (time.perf_counter() - start) / calls[k])
    return {k: _summary(calls[k], v) for k, v in times.items()}


def best_per_call(run, calls: int, bursts: int) -> float:
    """Seconds per call of run(calls), the fastest of `bursts` bursts (short bursts find the quiet
    moments of a shared machine)."""
    best = math.inf
    for _ in range(bursts):
        start = time.perf_counter()
        run(calls)
        best = min(best, (time.perf_counter() - start) / calls)
    return best


# ------------------------------------------------------------------------------------------ C side

def _c_literal(values) -> str:
    return ", ".join(repr(float(v)) for v in values)


def build_c_timer(folder: Path, name: str, y0, p, cc: str = "gcc", flags=("-O2",),
                  suffix: str = "") -> tuple[Path, float]:
    """Compile c/rhs_timer.c for the model's C library in `folder` (``<name>.c``, ``<name>.h``) at the
    state y0 and parameters p: (exe, seconds)."""
    exe = Path(folder) / f"bench_{name}{suffix}"
    macros = {"ADB_MODEL_HEADER": f'"{name}.h"', "ADB_RHS": f"{name}_rhs", "ADB_JAC": f"{name}_jac",
              "ADB_NY": str(len(y0)), "ADB_NP": str(len(p)), "ADB_Y0": _c_literal(y0), "ADB_P": _c_literal(p)}
    start = time.perf_counter()
    subprocess.run([cc, "-std=c99", *flags, f"-I{folder}", *(f"-D{k}={v}" for k, v in macros.items()), "-o", str(exe),
                    str(c_file("rhs_timer.c")), str(Path(folder) / f"{name}.c"), "-lm"],
                   check=True, capture_output=True, text=True)
    return exe, time.perf_counter() - start


def run_c_timer(exe: Path, target: float, repeats: int, jac: bool) -> dict:
    """Run a timing program: {"rhs": {calls, repeats_ns, ns, min_ns}, "jac": ... (if jac)}."""
    res = subprocess.run([str(exe), repr(target), str(repeats), "1" if jac else "0"],
                         check=True, capture_output=True, text=True)
    out: dict = {}
    for line in res.stdout.splitlines():
        label, key, value = line.split()
        if key == "ns":
            out.setdefault(label, {}).setdefault("repeats_ns", []).append(round(float(value), 2))
        elif key == "calls":
            out.setdefault(label, {})["calls"] = int(value)
    for label in ("rhs", "jac"):
        if label in out:
            out[label]["ns"] = round(median(out[label]["repeats_ns"]), 2)
            out[label]["min_ns"] = min(out[label]["repeats_ns"])
    return out


def time_c(folder: Path, name: str, y0, p, target: float, repeats: int, jac: bool, cc: str = "gcc",
           flags=("-O2",), suffix: str = "") -> dict:
    """Build and run the C timing program: {compile_seconds, rhs: ..., jac: ...}."""
    exe, compile_seconds = build_c_timer(folder, name, y0, p, cc, flags, suffix)
    return {"compile_seconds": round(compile_seconds, 3), **run_c_timer(exe, target, repeats, jac)}


# -------------------------------------------------------------------------------------- CPU clocks

def cpu_of_process() -> float:
    """CPU seconds of this process, all threads (with wall time: were the cores really free?)."""
    use = resource.getrusage(resource.RUSAGE_SELF)
    return use.ru_utime + use.ru_stime


def cpu_with_children() -> float:
    """CPU seconds of this process and its finished children (programs run as a child count)."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


__all__ = ["C_DIR", "best_per_call", "build_c_timer", "c_compiler", "c_file", "calibrate", "cpu_of_process",
           "cpu_with_children", "numba_loop", "paired_loops", "run_c_timer", "time_c", "time_calls", "time_python"]
