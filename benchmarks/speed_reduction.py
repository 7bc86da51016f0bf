"""Study (not a test): residual imbalance over starts with and without a temporary speed reduction (issue 37,
"a figure a practitioner recognises", and item 5's practical question: which reduction (depth, plateau) brings
the residual imbalance below a target in every start of a sweep).

    python3 -m benchmarks.speed_reduction [--side K] [--out docs/figures]
        -> docs/figures/speed_reduction_residual.png and .json

The rotor is speed_reduction_scene.toml's model (SI) with the values of ROTOR and SCHEDULE set (the file's
eccentricity, c and D are only the generated model's defaults; a change of the file's bytes regenerates the
model, minutes for a stick/slip model): a Jeffcott rotor of M = 1 kg on k = 1000 N/m (omega_n about
31 rad/s), c = 6 N s/m (zeta about 0.09), eccentricity 0.5 mm, two balls of 10 g on a race of R = 50 mm
(balanced state at theta* = 120 deg, cos theta* = -eps M / (2 m R), thesis (3.6)), rolling resistance
mu_r = 0.002 and stiction mu_s = 0.005, a viscous drag of the balls D = 1e-4 N m s/rad (the race's fluid: without
it a ball left at rest as the rotor starts has no normal force, so no friction, and never turns).  Its speed is the prescribed schedule of adbgen.core.speed_schedule
(law = "schedule"): a run-up ramp to omega = 100 rad/s (955 rpm, about 3.2 omega_n) in 2 s, a hold of 2 s at
omega, then the temporary reduction: a fall to omega (1 - depth) at 20 rad/s^2, a plateau of t_plateau, the
recovery at 20 rad/s^2, and omega until t_end.  A stuck ball is released by the race's acceleration a when
|a| > mu_s psi'^2 (about: the stiction cone of a ball on a steady race), so at 20 rad/s^2 the fall frees the
balls only below psi' = sqrt(20 / 0.005) = 63 rad/s, i.e. for depth > 0.37: a reduction shallower than that
does not move a ball stuck at full speed; the recovery at 5 rad/s^2 would free a ball by its rate alone only
below sqrt(5 / 0.005) = 32 rad/s, under every plateau of the grid (depth <= 0.65: 35 rad/s).  A deep reduction
brings the plateau near the resonance, where the vibration of the stuck imbalance is largest.

Each case is one `run_sweep` (`--measure residual`, the hybrid engine the model's stick/slip modes ask for)
over the same grid of starting ball angles phi_1 x phi_2 (`axes`: K x K, the rotor at rest): r at t_end
where every ball is stuck (at rest), the runs with a ball still slipping (undecided) and failed runs counted
apart (`adbgen.analysis.residual`).  "No reduction" is the schedule with depth = 0.  A case is *feasible* for
the target r when every start ended at rest and below it; a case with an undecided or failed start is not
decided (None), never counted as feasible.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SCENE = Path(__file__).with_name("speed_reduction_scene.toml")
FIGURE = "speed_reduction_residual.png"
# values set on the scene's model (SI); the scene file's own values are the generated defaults
ROTOR = {"eps": 5e-4, "c": 6.0, "mu_r": 0.002, "mu_s": 0.005, "D": 1e-4}
SCHEDULE = {"omega": 100.0, "t_ramp": 2.0, "t_hold": 2.0, "drop_rate": 20.0, "recovery_rate": 5.0}
DEPTHS = (0.3, 0.5, 0.65)
PLATEAUS = (0.5, 3.0)  # s
SETTLE = 3.0  # s at omega after the last recovery, before r is read
DEFAULT_SIDE = 32  # 1024 starts per case
RTOL, ATOL = 1e-9, 1e-13
TARGET_FRACTION = 0.1  # the target: a tenth of the rotor's response without balls


def free_response(rotor=ROTOR, omega=SCHEDULE["omega"], M=1.0, k=1000.0, m=0.01, n=2) -> float:
    """r of the rotor with the balls' mass but no balancing at omega: eps M omega^2 / |k - (M + n m) omega^2 + i c
    omega| (the steady whirl of the Jeffcott rotor, thesis (2.27) without the balls' imbalance), m."""
    total = M + n * m
    return rotor["eps"] * M * omega**2 / abs(complex(k - total * omega**2, rotor["c"] * omega))


def t_end_for(depth: float, plateau: float, schedule=SCHEDULE) -> float:
    """The time the schedule is back at omega plus SETTLE (s); the same end for the case without reduction."""
    w = schedule["omega"]
    fall = depth * w / schedule["drop_rate"]
    rise = depth * w / schedule["recovery_rate"]
    return schedule["t_ramp"] + schedule["t_hold"] + fall + plateau + rise + SETTLE


def cases(depths=DEPTHS, plateaus=PLATEAUS) -> list[dict]:
    """No reduction (depth 0) first, then every depth x plateau."""
    return [{"depth": 0.0, "plateau": 0.0}] + [{"depth": d, "plateau": p} for d in depths for p in plateaus]


def feasible(dist: dict, target: float) -> bool | None:
    """True when every start ended at rest with r below target, False when some start at rest is at or above it,
    None (not decided) when no start is above it but some start did not come to rest or failed."""
    top = dist["quantiles"]["max"]
    if top is not None and top >= target:
        return False
    if dist["not_at_rest"] or dist["failed"] or not dist["at_rest"]:
        return None
    return True


def axes(side: int) -> list[str]:
    """phi_1 over [0, 2 pi) in side steps h, phi_2 the same shifted by h / 2: no start has both balls at one place
    (phi_1 = phi_2) or exactly opposite (phi_2 = phi_1 + pi, even side), states the balls' symmetry keeps."""
    return [f"phi_1=0:2*pi*{side - 1}/{side}:{side}", f"phi_2=pi/{side}:pi/{side}+2*pi*{side - 1}/{side}:{side}"]


def every_start_below(dist: dict, starts: int) -> float | None:
    """The smallest target this case meets in every start (its largest r at rest), None unless all starts are at
    rest."""
    return dist["quantiles"]["max"] if dist["at_rest"] == starts else None


def run_case(model, case: dict, side: int, t_end: float, out: Path, workers: int | None = None) -> dict:
    """One sweep over side x side starts; {"case", "t_end", "r" (per start, nan where not at rest), "at_rest"
    (codes), "distribution", "wall_s", "integrated"}."""
    import zarr

    from adbgen.analysis.residual import distribution
    from adbgen.analysis.sweep import SweepSpec, run_sweep

    values = {**ROTOR, **SCHEDULE, "depth": case["depth"], "t_plateau": case["plateau"]}
    spec = SweepSpec(model=str(model.folder), grid=axes(side),
                     measure="residual", set=[f"{k}={v!r}" for k, v in values.items()], t_end=t_end,
                     rtol=RTOL, atol=ATOL)
    t = time.perf_counter()
    summary = run_sweep(spec, out, workers=workers, progress=False, figures=False)
    wall = time.perf_counter() - t
    group = zarr.open_group(str(Path(summary["store"])), mode="r")
    r = np.asarray(group["residual"][...], float).ravel()
    codes = np.asarray(group["at_rest"][...]).ravel()
    return {"case": case, "t_end": t_end, "r": r, "at_rest": codes, "distribution": distribution(r, codes),
            "wall_s": round(wall, 2), "integrated": summary["integrated"]}


def study(side: int = DEFAULT_SIDE, depths=DEPTHS, plateaus=PLATEAUS, workers: int | None = None,
          progress=print) -> tuple[dict, list[dict]]:
    from adbgen.analysis.loading import load_model

    model = load_model(scene=SCENE)
    t_end = max(t_end_for(d, p) for d in (0.0, *depths) for p in (0.0, *plateaus))
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        for i, case in enumerate(cases(depths, plateaus)):
            progress(f"case {i}: depth {case['depth']:g}, plateau {case['plateau']:g} s, {side * side} starts")
            runs.append(run_case(model, case, side, t_end, Path(tmp) / f"case{i}", workers))
            progress(f"  {runs[-1]['wall_s']} s, {runs[-1]['distribution']['quantiles']}")
    target = TARGET_FRACTION * free_response()
    result = {
        "study": "speed_reduction", "scene": str(SCENE.relative_to(ROOT)), "model": model.name,
        "rotor": ROTOR, "schedule": SCHEDULE, "t_end": t_end, "starts": side * side,
        "grid": axes(side), "initial_state": "rotor at rest, balls at rest on the race at phi_1, phi_2",
        "rtol": RTOL, "atol": ATOL, "r_without_balls_m": free_response(),
        "target_m": target, "target": f"{TARGET_FRACTION:g} of r without balls",
        "cases": [{**run["case"], "distribution": run["distribution"], "feasible": feasible(run["distribution"], target),
                   "below_target": int(((run["at_rest"] == 1) & (run["r"] < target)).sum()),
                   "every_start_below_m": every_start_below(run["distribution"], side * side),
                   "wall_s": run["wall_s"], "integrated": run["integrated"]} for run in runs],
    }
    result["feasible_reductions"] = [{"depth": c["depth"], "plateau": c["plateau"]} for c in result["cases"][1:]
                                     if c["feasible"]]
    return result, runs


def check(workers: int | None = 1, side: int = 3) -> list[str]:
    """The study's machinery on the scene's model, small: a reduction of zero depth (a plateau at full speed)
    gives the distribution of no reduction, every start at rest, and the verdict on that sweep is right (above
    its largest residual feasible, at half of it not); negative control: a deep reduction (0.6) moves r by
    more than 1e-3, so the comparison is not void.  Returns the failures (empty when all hold)."""
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.residual import AT_REST

    model = load_model(scene=SCENE)
    t_end = t_end_for(0.6, 0.5)
    fails = []
    with tempfile.TemporaryDirectory() as tmp:
        none = run_case(model, {"depth": 0.0, "plateau": 0.0}, side, t_end, Path(tmp) / "none", workers)
        zero = run_case(model, {"depth": 0.0, "plateau": 0.5}, side, t_end, Path(tmp) / "zero", workers)
        deep = run_case(model, {"depth": 0.6, "plateau": 0.5}, side, t_end, Path(tmp) / "deep", workers)
    d = none["distribution"]
    if d["failed"] or d["at_rest"] != side * side:
        fails.append(f"without reduction {d['at_rest']} of {side * side} starts at rest, {d['failed']} failed")
    if not np.array_equal(none["at_rest"], zero["at_rest"]) or not np.allclose(zero["r"], none["r"], rtol=1e-6,
                                                                                 atol=1e-12, equal_nan=True):
        fails.append("a reduction of zero depth changes the residual distribution")
    top = d["quantiles"]["max"]
    if feasible(d, 2 * top) is not True or feasible(d, top / 2) is not False:
        fails.append("the verdict on the sweep is wrong")
    rest = (none["at_rest"] == AT_REST) & (deep["at_rest"] == AT_REST)
    if not rest.any() or np.max(np.abs(deep["r"][rest] - none["r"][rest]) / none["r"][rest]) <= 1e-3:
        fails.append("negative control: a reduction of depth 0.6 does not move r (the comparison is void)")
    return fails


def draw(result: dict, runs: list[dict], path: Path) -> Path:
    """Left: CDFs of r at rest (mm) per case, the target as a vertical line; right: histograms of the case
    without reduction and of the case with the smallest 99 % quantile, their 50/90/99 % lines."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.6))
    target_mm = result["target_m"] * 1e3
    for run in runs:
        c, d = run["case"], run["distribution"]
        rest = np.sort(run["r"][run["at_rest"] == 1]) * 1e3
        if not rest.size:
            continue
        label = ("no reduction" if c["depth"] == 0 else f"depth {c['depth']:g}, plateau {c['plateau']:g} s")
        label += f" ({d['at_rest']} at rest" + (f", {d['not_at_rest']} moving" if d["not_at_rest"] else "") + \
            (f", {d['failed']} failed" if d["failed"] else "") + ")"
        ax.step(rest, np.arange(1, rest.size + 1) / rest.size, where="post", label=label,
                lw=2.2 if c["depth"] == 0 else 1.3, color="k" if c["depth"] == 0 else None)
    ax.axvline(target_mm, color="r", ls="--", lw=1, label=f"target {target_mm:.3g} mm")
    ax.set_xscale("log")
    ax.set_xlabel("residual imbalance r at rest (mm)")
    ax.set_ylabel("fraction of starts at rest with r below")
    ax.set_title(f"{result['starts']} starts per case: CDF")
    ax.legend(fontsize=7, loc="upper left")
    best = min(runs[1:], key=lambda run: run["distribution"]["quantiles"]["99"] or math.inf)
    top = max(run["distribution"]["quantiles"]["max"] or 0.0 for run in (runs[0], best)) * 1e3
    edges = np.linspace(0.0, top * 1.0001, 41)
    for run, color in ((runs[0], "0.4"), (best, "tab:blue")):
        c, d = run["case"], run["distribution"]
        rest = run["r"][run["at_rest"] == 1] * 1e3
        label = "no reduction" if c["depth"] == 0 else f"depth {c['depth']:g}, plateau {c['plateau']:g} s"
        bx.hist(rest, bins=edges, alpha=0.55, color=color, label=label)
        for q, ls in (("50", "-"), ("90", "--"), ("99", ":")):
            bx.axvline(d["quantiles"][q] * 1e3, color=color, ls=ls, lw=1.2)
    bx.axvline(target_mm, color="r", ls="--", lw=1)
    bx.set_xlabel("residual imbalance r at rest (mm)\nlines: 50 % (solid), 90 % (dashed), 99 % (dotted)")
    bx.set_ylabel("starts")
    bx.set_title("histogram: without and with the best reduction (smallest 99 %)")
    bx.legend(fontsize=8)
    fig.suptitle(f"Jeffcott rotor, eps {ROTOR['eps'] * 1e3:g} mm, 2 x 10 g balls on R = 50 mm, mu_r {ROTOR['mu_r']:g}, "
                 f"mu_s {ROTOR['mu_s']:g}, D {ROTOR['D']:g} N m s/rad, omega {SCHEDULE['omega']:g} rad/s; reductions: fall "
                 f"{SCHEDULE['drop_rate']:g} rad/s^2, recovery {SCHEDULE['recovery_rate']:g} rad/s^2", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m benchmarks.speed_reduction", description=__doc__.splitlines()[0])
    parser.add_argument("--side", type=int, default=DEFAULT_SIDE, help=f"starts per case: side^2 (default {DEFAULT_SIDE})")
    parser.add_argument("--out", default=str(ROOT / "docs" / "figures"), help="folder of the figure and its JSON")
    parser.add_argument("--workers", type=int, default=None, help="Dask workers (default: all cores)")
    parser.add_argument("--check", action="store_true",
                        help="only the check of the machinery on the scene's model (3 x 3 starts); exit 1 on a failure")
    args = parser.parse_args(argv)
    if args.check:
        fails = check(workers=args.workers or 1)
        for line in fails:
            print(f"speed_reduction: check failed: {line}", file=sys.stderr)
        print("speed_reduction: check " + ("failed" if fails else "passed"))
        return 1 if fails else 0
    if args.side < 2:
        print(f"speed_reduction: --side must be >= 2, got {args.side}", file=sys.stderr)
        return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    result, runs = study(args.side, workers=args.workers, progress=lambda line: print(line, flush=True))
    result["wall_s"] = round(time.perf_counter() - started, 1)
    figure = draw(result, runs, out / FIGURE)
    data = out / (Path(FIGURE).stem + ".json")
    data.write_text(json.dumps(result, indent=2, sort_keys=True) + "\n")
    print(f"target r < {result['target_m']:.3g} m in every start: "
          f"{result['feasible_reductions'] or 'no reduction of the grid'}; wrote {figure}, {data}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
