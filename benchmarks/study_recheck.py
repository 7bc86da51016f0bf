"""Re-run cases of a committed residual study on today's engine and compare them with the committed results: did an
engine change move the study's numbers?  (Issue 37: the hybrid driver's start decision, `decide_set` of
adbgen/analysis/engines/hybrid_driver.c, landed after docs/figures/machines2020.json was computed.)

    python3 -m benchmarks.study_recheck [--json docs/figures/machines2020.json] [--case NAME ...] [--workers 1]
    python3 -m benchmarks.study_recheck --friction-bench      benchmarks/friction.json's sweep with stiction

Each case named (default: every case of the JSON) is swept again with the JSON's values, starts, t_end and
tolerances on the study's model (friction_studies.load), and its distribution of r at rest (analysis/residual.py)
and its count of starts below the JSON's target are compared with the committed ones: the counts exactly, the
quantiles to the page's precision (3 significant digits, `DIGITS`) and bit for bit (`exact` says which).  A study
of hundreds of starts per case takes a minute a case, so a subset of cases answers whether the numbers moved
when re-running the whole study does not fit.  Exit 0 when no case moved, 1 when some did (each change printed),
2 on bad input (a case the JSON has not).  `--friction-bench` re-runs the sweep with stiction of the friction
benchmark (benchmarks/friction.py: its starts, t_end and rotor; no timing, which needs a quiet machine) and compares
its residual distribution with the one benchmarks/friction.json records (no target there: the counts of the
distribution and its quantiles).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

from benchmarks import friction_studies as fs

DIGITS = 3  # the pages print quantiles to 3 significant digits (docs/friction-studies.md)
COUNTS = ("at_rest", "not_at_rest", "failed")


def _rounded(x: float | None) -> float | None:
    return None if x is None or x == 0 else round(x, DIGITS - 1 - math.floor(math.log10(abs(x))))


def compare(committed: dict, new: dict) -> dict:
    """{"moved": [what changed: a count, a quantile at the page's precision, the histogram's counts over the same
    bins], "exact": the distribution and count bit for bit equal} of a case's committed and re-run results (each
    with "distribution" and "below_target")."""
    a, b = committed["distribution"], new["distribution"]
    moved = [f"{k} {a[k]} -> {b[k]}" for k in COUNTS if a[k] != b[k]]
    if committed["below_target"] != new["below_target"]:
        moved.append(f"below target {committed['below_target']} -> {new['below_target']}")
    for q, x in a["quantiles"].items():
        y = b["quantiles"][q]
        if _rounded(x) != _rounded(y):
            moved.append(f"{q} % {x!r} -> {y!r}" if q != "max" else f"max {x!r} -> {y!r}")
    ha, hb = a["histogram"], b["histogram"]
    if ha["edges"] == hb["edges"] and ha["counts"] != hb["counts"]:  # same bins: how many starts changed bin
        moved.append(f"histogram: {sum(abs(x - y) for x, y in zip(ha['counts'], hb['counts'])) // 2} starts in "
                     "another bin")
    exact = a == b and committed["below_target"] == new["below_target"]
    return {"moved": moved, "exact": exact}


def recheck(path: Path, names: list[str] | None = None, workers: int | None = 1, progress=print) -> list[dict]:
    """Each named case of the study JSON at `path` re-run and compared (`compare`); a ValueError names a case the
    JSON has not."""
    from adbgen.analysis.residual import AT_REST, distribution

    study = json.loads(path.read_text())
    cases = {c["name"]: c for c in study["cases"]}
    unknown = [n for n in names or [] if n not in cases]
    if unknown:
        raise ValueError(f"{path.name} has no case {', '.join(map(repr, unknown))}; its cases: {', '.join(cases)}")
    side = math.isqrt(study["starts"])
    model = fs.load()
    out = []
    for name in names or list(cases):
        case = cases[name]
        started = time.perf_counter()
        run = fs.sweep(model, case["values"], side, study["t_end"], "residual", rtol=study["rtol"],
                       atol=study["atol"], workers=workers)
        new = {"distribution": distribution(run["value"], run["at_rest"]),
               "below_target": int(((run["at_rest"] == AT_REST) & (run["value"] < study["target_m"])).sum())}
        out.append({"name": name, **compare(case, new), "distribution": new["distribution"],
                    "below_target": new["below_target"], "wall_s": round(time.perf_counter() - started, 1)})
        progress(f"{name}: " + ("unchanged" + (" (bit for bit)" if out[-1]["exact"] else " at the page's precision")
                                if not out[-1]["moved"] else "moved: " + "; ".join(out[-1]["moved"]))
                 + f" ({out[-1]['wall_s']} s)")
    return out


def recheck_friction_bench(path: Path, workers: int | None = 1, progress=print) -> list[dict]:
    """The friction benchmark's sweep with stiction re-run and its residual distribution compared (`compare`)."""
    import tempfile

    from adbgen.analysis.loading import load_model
    from benchmarks import friction as bench

    recorded = json.loads(path.read_text())
    _, axes = bench.grid(recorded["starts"])
    model = load_model(scene=bench.SCENE)
    with tempfile.TemporaryDirectory() as tmp:
        wall, summary = bench._sweep(model, "residual", {**bench.ROTOR, **bench.FRICTION}, axes, recorded["t_end"],
                                     Path(tmp) / "with", workers)
    old = {"distribution": recorded["with_stiction"]["residual"], "below_target": 0}
    new = {"distribution": summary["residual"], "below_target": 0}
    out = [{"name": "friction bench, with stiction", **compare(old, new), "distribution": new["distribution"],
            "wall_s": round(wall, 1)}]
    progress(f"{out[0]['name']}: " + ("moved: " + "; ".join(out[0]["moved"]) if out[0]["moved"] else
                                      "unchanged" + (" (bit for bit)" if out[0]["exact"] else " at 3 digits")))
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m benchmarks.study_recheck", description=__doc__.splitlines()[0])
    parser.add_argument("--json", default=str(fs.FIGURES / "machines2020.json"), help="the committed study JSON")
    parser.add_argument("--case", action="append", help="a case's name (repeat; default: every case)")
    parser.add_argument("--workers", type=int, default=1, help="Dask workers (default 1)")
    parser.add_argument("--friction-bench", action="store_true",
                        help="re-run benchmarks/friction.json's sweep with stiction instead of a study's cases")
    parser.add_argument("--out", help="also write the re-run's results to this JSON file")
    args = parser.parse_args(argv)
    say = (lambda line: print(line, flush=True))
    try:
        results = (recheck_friction_bench(fs.ROOT / "benchmarks" / "friction.json", args.workers, say)
                   if args.friction_bench else recheck(Path(args.json), args.case, args.workers, say))
    except (ValueError, OSError) as exc:
        print(f"study_recheck: {exc}", file=sys.stderr)
        return 2
    if args.out:
        Path(args.out).write_text(json.dumps(results, indent=2, sort_keys=True) + "\n")
    return 1 if any(r["moved"] for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())
