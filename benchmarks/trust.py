"""Benchmark (not a test): what trust costs (issue 34, "Cost in a benchmark").  `adbgen bench trust
[--baseline REV] [--targets charts tolerance] [--charts FIG ...] [--repeats K]` -> ``benchmarks/trust.json``.

Two targets, each timed as the ratio of two runs made in the same benchmark run (this machine is noisy; a
ratio of interleaved runs is what survives a change of load):

* **charts**: every two-parameter chart of docs/reproduction.md (the paper's Figs. 10(a), 11, 13(a-d), 14(a, b),
  `two_plane.charts.CHARTS`, computed by the reproduction's own `periodic_orbits.chart`) and every ch. 4
  stability map (`adbgen sweep thesis_rotating_nN --measure stability` on the reproduction's grids), certified
  (this checkout) against the same computation before certification (a detached worktree of REV, by default
  the commit before the certified charts were merged, which computes the same charts on the same grids).  Target:
  certified / before < 2 for each chart.  Each figure is timed inside its child process after the imports
  (the computation, not Python's start); the sides alternate (before, certified, before, ...) and each
  side's figure is the median of `--repeats` runs after one untimed warm-up run (numba's and the C engines'
  caches filled for both checkouts).
* **tolerance**: `adbgen simulate --check-tolerance` against the same command without it (Fig. 5.10's three
  panels, the runs the audit found sensitive), and `adbgen sweep --measure attractor --check-tolerance`
  against the plain sweep (Fig. 5.11's 100 n = 3 launches), each timed as the whole command a
  user runs.  Target: checked / plain < 3.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from adbgen.cli_types import UsageError

from .registry import REPEATS, Benchmark, option, require_positive_repeats
from .report import closing, opening, write

ROOT = Path(__file__).resolve().parents[1]
# the commit before `Merge branch 'charts'` (certified charts and stability maps, issue 34 item 3)
BASELINE = "a149437^1"
CHART_TARGET = 2.0
TOLERANCE_TARGET = 3.0

# the child's program: one computation timed after the imports, its seconds printed on the last line
_CHART = """
import sys, tempfile, time
from pathlib import Path
from adbgen.families.two_plane.science.periodic_orbits import CHARTS, chart
case = next(c for c in CHARTS if c.figure == sys.argv[1])
with tempfile.TemporaryDirectory() as d:
    t = time.perf_counter()
    chart(case, Path(d), progress=lambda s: None)
    print(time.perf_counter() - t)
"""
_FIGURES = """
from adbgen.families.two_plane.science.periodic_orbits import CHARTS
print(" ".join(c.figure for c in CHARTS))
"""
_MAP = """
import sys, tempfile, time
from pathlib import Path
from adbgen.analysis.sweep import SweepSpec, run_sweep
spec = SweepSpec(model=sys.argv[1], grid=sys.argv[2:], measure="stability")
with tempfile.TemporaryDirectory() as d:
    t = time.perf_counter()
    run_sweep(spec, Path(d) / "map", progress=False)
    print(time.perf_counter() - t)
"""


def _env(checkout: Path) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(checkout)] + [p for p in [os.environ.get("PYTHONPATH")] if p])
    return env


def timed_child(checkout: Path, program: str, args: list[str]) -> float:
    """Seconds the child reports for its computation (run from `checkout`'s package)."""
    proc = subprocess.run([sys.executable, "-c", program, *args], env=_env(checkout), cwd=checkout,
                          capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"{checkout.name}: {' '.join(args)} failed: {proc.stderr.strip().splitlines()[-1:]}")
    return float(proc.stdout.strip().splitlines()[-1])


def timed_command(argv: list[str]) -> float:
    """Wall seconds of a whole `adbgen ...` command as a user runs it (this checkout)."""
    t = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "adbgen.cli", *argv], env=_env(ROOT), cwd=ROOT,
                          capture_output=True, text=True)
    wall = time.perf_counter() - t
    if proc.returncode != 0:
        raise RuntimeError(f"adbgen {' '.join(argv)} failed: {proc.stderr.strip().splitlines()[-1:]}")
    return wall


def paired(before, after, repeats: int) -> dict:
    """`before()` and `after()` alternated, one warm-up each, then `repeats` timed runs each: both sides'
    runs, medians and the ratio after / before of the medians."""
    before(), after()
    b, a = [], []
    for _ in range(repeats):
        b.append(before())
        a.append(after())
    mb, ma = statistics.median(b), statistics.median(a)
    return {"before_s": [round(x, 3) for x in b], "after_s": [round(x, 3) for x in a],
            "before_median_s": round(mb, 3), "after_median_s": round(ma, 3), "ratio": round(ma / mb, 3)}


class Baseline:
    """A detached worktree of REV in a temporary folder (removed at the end)."""

    def __init__(self, rev: str):
        self.rev = rev
        self.tmp = tempfile.TemporaryDirectory(prefix="adbgen-bench-trust-")
        self.path = Path(self.tmp.name) / "baseline"

    def __enter__(self) -> Path:
        proc = subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(self.path), self.rev],
                              capture_output=True, text=True)
        if proc.returncode != 0:
            raise UsageError(f"--baseline {self.rev}: git worktree add failed: {proc.stderr.strip()[:200]}")
        return self.path

    def __exit__(self, *exc):
        subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(self.path)], capture_output=True)
        self.tmp.cleanup()


def chart_rows(base: Path, figures, repeats: int, progress=print) -> list[dict]:
    from adbgen.families.two_plane.charts import CHARTS

    rows = []
    before = subprocess.run([sys.executable, "-c", _FIGURES], env=_env(base), cwd=base, capture_output=True,
                            text=True).stdout.split()
    for case in CHARTS:
        if figures and case.figure not in figures:
            continue
        if case.figure not in before:  # a chart added since: nothing to compare with
            rows.append({"chart": f"Fig. {case.figure}", "what": "not in the baseline (added since): not compared"})
            progress(f"chart Fig. {case.figure}: not in the baseline")
            continue
        row = {"chart": f"Fig. {case.figure}", "what": f"{case.model}, (Omega, epsilon) 81 x 25"}
        row |= paired(lambda: timed_child(base, _CHART, [case.figure]),
                      lambda: timed_child(ROOT, _CHART, [case.figure]), repeats)
        rows.append(row)
        progress(f"chart Fig. {case.figure}: {row['before_median_s']} s -> {row['after_median_s']} s "
                 f"({row['ratio']}x)")
    from adbgen.families.single_plane.science.reproduce import MAPS

    for n, plane, grid, _ in MAPS:  # the reproduction's own maps and grids
        key = f"fig4_n{n}_{'omega_mu' if 'Omega' in plane else 'zeta_beta'}"
        if figures and key not in figures:
            continue
        row = {"chart": key, "what": f"adbgen sweep thesis_rotating_n{n} --grid {' --grid '.join(grid)} "
                                     "--measure stability"}
        row |= paired(lambda: timed_child(base, _MAP, [f"thesis_rotating_n{n}", *grid]),
                      lambda: timed_child(ROOT, _MAP, [f"thesis_rotating_n{n}", *grid]), repeats)
        rows.append(row)
        progress(f"map {key}: {row['before_median_s']} s -> {row['after_median_s']} s ({row['ratio']}x)")
    return rows


# Fig. 5.10's panels (thesis section 5.1.3: balls released at rest in the fixed frame), as
# `science.sensitivity.RUNS` states them
SIMULATIONS = (
    ("5.10(a)", ["thesis_rotating_n2", "--y0", "phi_1=pi/2", "--y0", "phi_2=-pi/2"], 2),
    ("5.10(b)", ["thesis_rotating_n3", "--y0", "phi_1=pi/3", "--y0", "phi_2=pi", "--y0", "phi_3=-pi/3"], 3),
    ("5.10(c)", ["thesis_rotating_n4", "--y0", "phi_1=pi/2", "--y0", "phi_2=-pi/2", "--y0", "phi_3=pi",
                 "--y0", "phi_4=0"], 4),
)
SWEEP = ["thesis_rotating_n3", "--grid", "phi_1=0:2*pi*99/100:100", "--tie", "phi_2=phi_1+2*pi/3", "--tie",
         "phi_3=phi_1-2*pi/3", *[a for k in (1, 2, 3) for a in ("--y0", f"phi_{k}_dot=-4")], "--measure", "attractor",
         "--t-end", "3000", "--no-figures"]


def tolerance_rows(repeats: int, progress=print) -> list[dict]:
    rows = []
    for figure, argv, n in SIMULATIONS:
        argv = ["simulate", *argv, *[a for i in range(n) for a in ("--y0", f"phi_{i + 1}_dot=-4")],
                "--t-end", "3000", "--json", "--quiet"]
        row = {"command": f"Fig. {figure}: adbgen {' '.join(argv)}"}
        row |= paired(lambda: timed_command(argv), lambda: timed_command([*argv, "--check-tolerance"]), repeats)
        rows.append(row)
        progress(f"simulate Fig. {figure}: {row['before_median_s']} s -> {row['after_median_s']} s ({row['ratio']}x)")
    with tempfile.TemporaryDirectory(prefix="adbgen-bench-trust-") as tmp:
        counter = iter(range(10**6))

        def sweep(extra):
            return timed_command(["sweep", *SWEEP, "--out", str(Path(tmp) / f"s{next(counter)}"), *extra])
        row = {"command": f"Fig. 5.11's 100 n = 3 launches: adbgen sweep {' '.join(SWEEP)} --out DIR"}
        row |= paired(lambda: sweep([]), lambda: sweep(["--check-tolerance"]), repeats)
        rows.append(row)
        progress(f"sweep: {row['before_median_s']} s -> {row['after_median_s']} s ({row['ratio']}x)")
    return rows


def bench_trust(baseline: str = BASELINE, parts=("charts", "tolerance"), figures=None, repeats: int = 3,
                progress=print) -> dict:
    result, started = opening("trust")
    result["repeats"] = repeats
    targets = []
    if "charts" in parts:
        with Baseline(baseline) as base:
            rev = subprocess.run(["git", "-C", str(base), "rev-parse", "HEAD"], capture_output=True, text=True)
            result["baseline"] = {"rev": baseline, "commit": rev.stdout.strip()}
            rows = chart_rows(base, figures, repeats, progress)
        result["charts"] = rows
        worst = max((r for r in rows if "ratio" in r), key=lambda r: r["ratio"])
        targets.append({"target": "certified charts", "goal": f"each chart certified / before < {CHART_TARGET}",
                        "worst": worst["chart"], "worst_ratio": worst["ratio"],
                        "passed": worst["ratio"] < CHART_TARGET})
    if "tolerance" in parts:
        rows = tolerance_rows(repeats, progress)
        result["tolerance"] = rows
        worst = max(rows, key=lambda r: r["ratio"])
        targets.append({"target": "--check-tolerance", "goal": f"checked / plain < {TOLERANCE_TARGET}",
                        "worst": worst["command"], "worst_ratio": worst["ratio"],
                        "passed": worst["ratio"] < TOLERANCE_TARGET})
    result["targets"] = targets
    return closing(result, started)


PARTS = ("charts", "tolerance")


def run(args, out: str) -> int:
    require_positive_repeats(args)
    parts = tuple(args.targets or PARTS)
    result = bench_trust(args.baseline, parts, args.charts, args.repeats or 3,
                         progress=lambda line: print(line, flush=True))
    path = write(result, out)
    for t in result["targets"]:
        print(f"{t['target']}: worst {t['worst_ratio']}x ({t['worst'][:60]}), {t['goal']}: "
              f"{'passed' if t['passed'] else 'FAILED'}")
    print(f"wrote {path}")
    return 0 if all(t["passed"] for t in result["targets"]) else 1


BENCHMARK = Benchmark("trust", run, (
    option("--baseline", default=BASELINE, metavar="REV",
           help=f"the commit whose charts are the time before certification (default {BASELINE}, the commit "
                "before the certified charts were merged)"),
    option("--targets", nargs="+", choices=PARTS, default=None, help="which targets to time (default both)"),
    option("--charts", nargs="+", default=None, metavar="FIG",
           help="only these charts: a CHARTS figure (11, 13(b), ...) or a map (fig4_n2_omega_mu, ...)"),
    REPEATS.but("timed runs of each side after one warm-up (default 3; the median is compared)"),
))
