"""Study (not a test): item 5's practical question of issue 37 pursued beyond the grid of benchmarks/machines2020.py:
which temporary speed reduction brings the residual imbalance below the target in every start?  The grid (depth
0.3 to 0.8 x plateau 0.5 to 3 s, fall 20 and recovery 5 rad/s^2) reaches it in no case, its closest worst start
9.9 times the target (depth 0.8, plateau 0.5 s).  These cases go where its table points: deeper, a shorter
plateau at depth 0.8 (where a longer one was worse), and a slower recovery (the recovery's rate is a tangential
load of m R omega' on every ball, which shifts where stiction holds it; a slower one also passes the resonance
slowly, where the rotor's response is largest and moves stuck balls).

    python3 -m benchmarks.machines2020_extension [--out docs/figures]    -> machines2020_extension.json

Same model, rotor, friction, starts (16 x 16), tolerances, target and labels as machines2020.py (its scene's values
with the case's schedule changed).  r is read at t_end = the grid study's 30 s, or the case's schedule end plus
machines2020.SETTLE where that is later (a slow recovery ends after 27 s); every start's balls must be at rest
then, or the case is undecided (speed_reduction.feasible), never feasible.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

from benchmarks import friction_studies as fs
from benchmarks import machines2020 as m20

GRID_T_END = 30.0  # s: machines2020.json's t_end (its longest schedule, depth 0.8 with a 3 s plateau, + SETTLE)
# (depth, plateau s, recovery rate rad/s^2), the grid's fall rate (20 rad/s^2) kept: the first four chosen from the
# grid's table (docs/friction-studies.md); the last four after their run, around its best (depth 0.5 with the
# recovery halved: 207 of 256 starts below the target): a slower recovery still, a shallower and a deeper
# plateau, a longer one
CASES = ((0.8, 0.5, 2.5), (0.5, 0.5, 2.5), (0.8, 0.0, 5.0), (0.9, 0.5, 5.0),
         (0.5, 0.5, 1.0), (0.4, 0.5, 2.5), (0.6, 0.5, 2.5), (0.5, 3.0, 2.5))


def cases(base: dict, table=CASES) -> list[dict]:
    """The scene's rotor with each (depth, plateau, recovery rate) of `table`."""
    return [{"name": f"depth {d:g}, plateau {p:g} s, recovery {a:g} rad/s^2", "group": "extension",
             "values": {**base, "depth": d, "t_plateau": p, "recovery_rate": a}} for d, p, a in table]


def t_end_for(values: dict) -> float:
    """The grid study's t_end, or the schedule's end plus machines2020.SETTLE where that is later."""
    return max(GRID_T_END, fs.schedule_end(values) + m20.SETTLE)


def study(side: int = m20.DEFAULT_SIDE, workers: int | None = 1, progress=print, table=CASES) -> dict:
    model = fs.load()
    base = fs.scene_values(m20.SCENE)
    target = m20.TARGET_FRACTION * fs.free_response(base)
    keep = ("name", "group", "values", "distribution", "feasible", "below_target", "every_start_below_m", "wall_s")
    out = []
    for case in cases(base, table):
        t_end = t_end_for(case["values"])
        run = m20.run_case(model, case, side, t_end, target, workers)
        out.append({**{k: run[k] for k in keep}, "t_end": t_end})
        dist = run["distribution"]
        progress(f"{case['name']}: {dist['at_rest']} at rest, {dist['not_at_rest']} moving, {dist['failed']} failed, "
                 f"{dist['quantiles']}, {run['below_target']} below target, {run['wall_s']} s")
    return {"study": "machines2020_extension", "scene": str(m20.SCENE.relative_to(fs.ROOT)), "model": model.name,
            "values": base, "starts": side * side, "grid": fs.axes(side), "rtol": m20.RTOL, "atol": m20.ATOL,
            "target_m": target, "cases": out,
            "feasible_reductions": [c["name"] for c in out if c["feasible"]]}


def main(argv=None) -> int:
    import argparse

    parser = argparse.ArgumentParser(prog="python3 -m benchmarks.machines2020_extension",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(fs.FIGURES), help="folder of the JSON")
    parser.add_argument("--workers", type=int, default=1, help="Dask workers (default 1)")
    args = parser.parse_args(argv)
    started = time.perf_counter()
    result = study(workers=args.workers, progress=lambda line: print(line, flush=True))
    result["wall_s"] = round(time.perf_counter() - started, 1)
    path = Path(args.out) / "machines2020_extension.json"
    path.write_text(json.dumps(result, indent=2, sort_keys=True) + "\n")
    print(f"feasible for r < {result['target_m']:.3g} m in every start: {result['feasible_reductions'] or 'none'}; "
          f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
