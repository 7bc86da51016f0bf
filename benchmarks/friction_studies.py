"""What the two reproduction studies of issue 37 item 5 share (benchmarks/machines2020.py, benchmarks/wright_peng.py):
a study scene's values set on one generated model, and one sweep over starting ball angles.

Each study keeps its values in a scene file of its own (machines2020_scene.toml, wright_peng_scene.toml: every value
with the paper's section it comes from, or the reason it was chosen).  Both scenes have the structure of
speed_reduction_scene.toml (n = 2 equal balls, isotropic support, no gravity, the prescribed `schedule` speed law,
rolling resistance and stiction), and every value of the generated model is a run-time parameter, so both
studies run that scene's generated model (cached by its bytes: generating a stick/slip model takes minutes) with
their own values set (`scene_values`), not a model of their own file.  A study scene of another structure is
refused (`check_structure`): its values would be set on a model that is not its own.  Wright and Peng's balls
have no friction: their scene sets mu_r = mu_s = 0, where the stick/slip model is the frictionless one (the
check `friction, zero limit` of `adbgen verify`).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
MODEL_SCENE = Path(__file__).with_name("speed_reduction_scene.toml")
FIGURES = ROOT / "docs" / "figures"


def check_structure(scene) -> None:
    """Raise ValueError unless `scene` has the structure of MODEL_SCENE (the model its values are set on)."""
    why = []
    if scene.n != 2:
        why.append(f"n = {scene.n}, not 2")
    if not scene.equal_balls:
        why.append("unequal balls")
    if not scene.isotropic:
        why.append("an anisotropic support")
    if scene.gravity:
        why.append("gravity")
    if scene.speed.law != "schedule":
        why.append(f"speed law {scene.speed.law!r}, not 'schedule'")
    if not scene.stiction:
        why.append("no static_friction (the stick/slip model)")
    if why:
        raise ValueError(f"a study scene must have the structure of {MODEL_SCENE.name}: " + ", ".join(why))


def scene_values(path: Path) -> dict:
    """The model's parameter values from a study scene (SI): M, k, c, m, R, eps, D, mu_r, mu_s and the schedule's
    omega, t_ramp, t_hold, depth, drop_rate, t_plateau, recovery_rate."""
    from adbgen.core.speed_schedule import NAMES
    from adbgen.families.single_plane.scene import Scene

    scene = Scene.load(path)
    check_structure(scene)
    one = (lambda v: v[0] if isinstance(v, tuple) else v)
    values = {"M": scene.rotor_mass, "k": one(scene.stiffness), "c": one(scene.damping), "m": one(scene.ball_mass),
              "R": scene.race_radius, "eps": scene.eccentricity, "D": one(scene.ball_damping),
              "mu_r": one(scene.rolling_resistance), "mu_s": one(scene.static_friction)}
    for key, value in scene.speed.schedule:
        values[NAMES.get(key, key)] = value
    return {k: float(v) for k, v in values.items()}


def schedule_end(values: dict) -> float:
    """The time the schedule is back at omega for good (s): ramp, hold, fall, plateau, recovery."""
    w, d = values["omega"], values["depth"]
    return (values["t_ramp"] + values["t_hold"] + d * w / values["drop_rate"] + values["t_plateau"]
            + d * w / values["recovery_rate"])


def free_response(values: dict, n: int = 2) -> float:
    """r of the rotor with the balls' mass and no balancing at omega (m): eps M omega^2 / |k - (M + n m) omega^2
    + i c omega|, the Jeffcott rotor's steady whirl (thesis (2.27) without the balls' imbalance)."""
    w = values["omega"]
    return values["eps"] * values["M"] * w**2 / abs(complex(values["k"] - (values["M"] + n * values["m"]) * w**2,
                                                            values["c"] * w))


def axes(side: int) -> list[str]:
    """The starts: phi_1 over [0, 2 pi) in side steps h, phi_2 the same shifted by h / 2 (no start with both balls
    at one place or exactly opposite), as benchmarks/speed_reduction.py."""
    from benchmarks.speed_reduction import axes as grid

    return grid(side)


def sweep(model, values: dict, side: int, t_end: float, measure: str, *, y0=(), threshold: float = 1e-3,
          rtol: float = 1e-9, atol: float = 1e-13, workers: int | None = 1) -> dict:
    """One `run_sweep` over side x side starts with `values` set; the store's arrays, flattened:
    {"value" (the measure), "failed", "y_end" (starts x states), "state" (names), plus "at_rest" for residual}."""
    import zarr

    from adbgen.analysis.sweep import SweepSpec, run_sweep

    spec = SweepSpec(model=str(model.folder), grid=axes(side), measure=measure,
                     set=[f"{k}={v!r}" for k, v in values.items()], y0=list(y0), t_end=t_end, rtol=rtol, atol=atol,
                     threshold=threshold)
    with tempfile.TemporaryDirectory() as tmp:
        summary = run_sweep(spec, Path(tmp) / "sweep", workers=workers, progress=False, figures=False)
        group = zarr.open_group(str(Path(summary["store"])), mode="r")
        out = {"value": np.asarray(group[measure][...], float).ravel(),
               "failed": np.asarray(group["failed"][...]).ravel().astype(bool),
               "y_end": np.asarray(group["y_end"][...], float).reshape(side * side, -1),
               "state": [str(s) for s in np.asarray(group["state"][...]).ravel()]}
        if "at_rest" in group:
            out["at_rest"] = np.asarray(group["at_rest"][...]).ravel()
    return out


def save(fig, path: Path) -> Path:
    """Write a study's figure (tight layout, 100 dpi) and close it."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def load():
    """The generated model of MODEL_SCENE (the scene cache)."""
    from adbgen.analysis.loading import load_model

    return load_model(scene=MODEL_SCENE)


def main(name: str, description: str, argv, *, default_side: int, study, check, draw, figure: str, summary) -> int:
    """A study's command line: `--check` runs its tiny version (exit 1 on a failure); otherwise the study over
    side x side starts, its figure and JSON (with `wall_s`) in --out, and `summary(result)` printed."""
    parser = argparse.ArgumentParser(prog=f"python3 -m benchmarks.{name}", description=description)
    parser.add_argument("--side", type=int, default=default_side, help=f"starts per case: side^2 (default {default_side})")
    parser.add_argument("--out", default=str(FIGURES), help="folder of the figure and its JSON")
    parser.add_argument("--workers", type=int, default=1, help="Dask workers (default 1)")
    parser.add_argument("--check", action="store_true", help="only the tiny version (3 x 3 starts); exit 1 on a failure")
    args = parser.parse_args(argv)
    if args.check:
        fails = check(workers=args.workers)
        for line in fails:
            print(f"{name}: check failed: {line}", file=sys.stderr)
        print(f"{name}: check " + ("failed" if fails else "passed"))
        return 1 if fails else 0
    if args.side < 2:
        print(f"{name}: --side must be >= 2, got {args.side}", file=sys.stderr)
        return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    result, runs = study(args.side, args.workers, progress=lambda line: print(line, flush=True))
    result["wall_s"] = round(time.perf_counter() - started, 1)
    path = draw(result, runs, out / figure)
    data = out / (Path(figure).stem + ".json")
    data.write_text(json.dumps(result, indent=2, sort_keys=True) + "\n")
    print(f"{summary(result)}; wrote {path}, {data}")
    return 0
