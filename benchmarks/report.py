"""What every benchmark writes and how: the results file, its charts, the record of the machine, and
the issue's targets as pass/fail lines.

A results file is JSON with sorted keys written through a temporary file (`write`), so a failed run
leaves the committed one as it was; a chart likewise (`save_figure`).  `opening` and `closing` give
every benchmark the same head (benchmark, date, machine with the load average at the start, versions)
and tail (load average at the end, seconds).
"""

from __future__ import annotations

import datetime
import json
import math
import os
import platform
import shutil
import subprocess
import time
from pathlib import Path

import numpy as np


def write(result: dict, path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(json.dumps(result, indent=2, sort_keys=True) + "\n")
    tmp.replace(path)
    return path


def save_figure(fig, path: str | Path, dpi: int = 120) -> Path:
    """Write a matplotlib figure through a temporary file (a failed write leaves the old chart)."""
    import matplotlib.pyplot as plt

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".tmp" + path.suffix)
    fig.savefig(tmp, dpi=dpi)
    plt.close(fig)
    tmp.replace(path)
    return path


def pyplot():
    """matplotlib's pyplot on the file-only backend (benchmarks draw charts, never windows)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def jsonable(obj):
    """A result made of plain JSON types: numpy scalars and arrays converted, non-finite floats None."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [jsonable(v) for v in obj.tolist()]
    if isinstance(obj, (np.floating, float)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj


def load_average() -> list | None:
    return [round(v, 2) for v in os.getloadavg()] if hasattr(os, "getloadavg") else None


def utc_now() -> str:
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


def _compiler() -> str:
    cc = shutil.which("gcc") or shutil.which("cc")
    if not cc:
        return "none"
    res = subprocess.run([cc, "--version"], capture_output=True, text=True)
    return res.stdout.splitlines()[0] if res.returncode == 0 and res.stdout else cc


def machine() -> dict:
    import numba
    import sympy as sp

    cpu = platform.processor() or ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"platform": platform.platform(), "cpu": cpu, "cpus": os.cpu_count(),
            "python": f"{platform.python_implementation()} {platform.python_version()}",
            "sympy": sp.__version__, "numpy": np.__version__, "numba": numba.__version__,
            "cc": _compiler(), "c_flags": "-std=c99 -O2 (c_native: -O2 -march=native)",
            "load_average_at_start": list(os.getloadavg()) if hasattr(os, "getloadavg") else None}


def versions() -> dict:
    """Versions of the libraries the integrations run on (SUNDIALS from its header; the peers')."""
    import importlib

    out = {}
    for name in ("CyRK", "scipy", "numpy", "numba", "matplotlib"):
        try:
            out[name] = importlib.import_module(name).__version__
        except ImportError:
            out[name] = None
    sundials = Path("/usr/include/sundials/sundials_config.h")
    if sundials.is_file():
        for line in sundials.read_text().splitlines():
            if "SUNDIALS_VERSION " in line:
                out["sundials"] = line.split()[-1].strip('"')
    from .peers import peer_versions

    out.update(peer_versions())
    return out


def opening(benchmark: str) -> tuple[dict, float]:
    """The head of a timed benchmark's result and its start (perf_counter): name, date, the machine
    (load average at the start, rounded), versions."""
    started = time.perf_counter()
    mach = machine()
    mach["load_average_at_start"] = load_average()
    return {"benchmark": benchmark, "date": utc_now(), "machine": mach, "versions": versions()}, started


def closing(result: dict, started: float) -> dict:
    """The tail: the load average at the end and the seconds the benchmark took; JSON-ready."""
    result["machine"]["load_average_at_end"] = load_average()
    result["seconds"] = round(time.perf_counter() - started, 1)
    return jsonable(result)


def target(name: str, goal: str, ratio: float | None, need: float, detail: str) -> dict:
    """One of the issue's targets: measured_ratio >= required_ratio passes, `by` = measured / required."""
    passed = None if ratio is None else bool(ratio >= need)
    return {"target": name, "goal": goal, "measured_ratio": None if ratio is None else round(ratio, 3),
            "required_ratio": need, "passed": passed,
            "by": None if ratio is None else round(ratio / need, 3), "detail": detail}


def describe_targets(result: dict) -> list[str]:
    lines = []
    for t in result.get("targets", []):
        mark = {True: "PASS", False: "FAIL", None: "n/a "}[t["passed"]]
        ratio = "-" if t["measured_ratio"] is None else f"{t['measured_ratio']:.2f} (need {t['required_ratio']})"
        lines.append(f"{mark} {t['target']}: {ratio}; {t['detail']}")
    return lines


def when(result: dict) -> str:
    """The date of a result as charts print it, "YYYY-MM-DD HH:MM"."""
    return result.get("date", "")[:16].replace("T", " ")


__all__ = ["closing", "describe_targets", "jsonable", "load_average", "machine", "opening", "pyplot", "save_figure",
           "target", "utc_now", "versions", "when", "write"]
