"""The held-out scenes of `adbgen bench tolerance` (issue 35 item 1): a seeded generator and the files it
writes, one JSON file a scene under ``benchmarks/tolerance_scenes/``.

A scene is a model (a generated model's name, or a scene TOML of ``tolerance_scenes/models/`` for the
five- and six-ball models that generated/ does not hold), parameter overrides (``set``, as `adbgen
simulate --set`), a start (``y0``, states not given are 0) and ``t_end``, with what it covers: ``family``,
``units`` (thesis: dimensionless; SI), ``support`` (isotropic, anisotropic), ``drive`` (forced at a
constant speed, run-up, torque-driven) and ``n`` (balls).  The scenes are never used to learn the auto
engine's table: that is learned on the precision benchmark's problems A and B (`benchmarks.engine_table`),
which no scene repeats (tests/benchmarks/test_tolerance.py).

Re-write the files (deterministic in `SEED`): ``python3 -m benchmarks.tolerance_scenes``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

SEED = 35
HERE = Path(__file__).resolve().parent
FOLDER = HERE / "tolerance_scenes"
MODELS = FOLDER / "models"  # scene TOMLs of the models generated/ does not hold (n = 5, 6)


def _r(x: float, digits: int = 4) -> float:
    return float(f"{x:.{digits}g}")


def _phis(rng, names, spread=True) -> dict:
    return {k: _r(rng.uniform(0.0, 2 * math.pi)) for k in names} if spread else {}


def _thesis(rng, n: int, k: int) -> dict:
    """thesis_rotating_n{n}: thesis units, isotropic, forced (rotating frame), around (5.1)."""
    balls = [f"phi_{i + 1}" for i in range(n)]
    y0 = _phis(rng, balls)
    if k % 2:  # balls released with velocity (the "new user" scenes)
        y0.update({f"{b}_dot": _r(rng.uniform(-0.5, 0.5)) for b in balls})
    return {"model": f"thesis_rotating_n{n}", "family": "single_plane", "units": "thesis", "support": "isotropic",
            "drive": "forced", "n": n, "t_end": float(rng.choice([300.0, 600.0, 1000.0])),
            "set": {"Omega": _r(rng.uniform(2.5, 6.0)), "zeta": _r(rng.uniform(0.005, 0.05)),
                    "beta": _r(rng.uniform(0.005, 0.05)), "mu": _r(rng.uniform(0.02, 0.08)),
                    "delta": _r(rng.uniform(0.005, 0.03))}, "y0": y0}


def _si(rng, n: int, k: int) -> dict:
    """single_plane_fixed_n{n}: SI units, fixed frame, gravity; isotropic (k_Y = k_X) or anisotropic."""
    iso = k % 3 == 0
    kx, cx = _r(rng.uniform(0.8e4, 1.5e4)), _r(rng.uniform(1.0, 4.0))
    aniso = 1.0 if iso else _r(rng.uniform(1.1, 1.5))
    return {"model": f"single_plane_fixed_n{n}", "family": "single_plane", "units": "SI",
            "support": "isotropic" if iso else "anisotropic", "drive": "forced", "n": n,
            "t_end": float(rng.choice([1.0, 2.0])),
            "set": {"omega": _r(rng.uniform(250.0, 600.0)), "k_X": kx, "k_Y": _r(kx * aniso), "c_X": cx,
                    "c_Y": _r(cx * aniso), "m": _r(rng.uniform(0.02, 0.06))},
            "y0": _phis(rng, [f"phi_{i + 1}" for i in range(n)])}


_TWO_PLANE = {  # model: (support, drive, ball angle prefix, t_end choices)
    "two_plane_fixed": ("anisotropic", "forced", "alpha", (300.0, 600.0)),
    "two_plane_rotating": ("isotropic", "forced", "alpha", (300.0, 600.0)),
    "two_plane_hill": ("isotropic", "run-up", "theta", (600.0, 1000.0)),
    "two_plane_ramp": ("isotropic", "run-up", "theta", (600.0, 1000.0)),
    "two_plane_torque": ("isotropic", "torque", "theta", (600.0, 1000.0)),
}


def _two_plane(rng, model: str) -> dict:
    """A two-plane model (paper (10)/(43)): thesis-like dimensionless units, two balls a plane."""
    support, drive, prefix, t_ends = _TWO_PLANE[model]
    m = _r(10 ** rng.uniform(-4, -2.5))
    sets = {"epsilon": _r(10 ** rng.uniform(-4, -2)), "chi": _r(rng.uniform(0.0, 1e-3)),
            "beta": _r(rng.uniform(0.0, 1.0)), **{f"m_{i}": m for i in range(1, 5)},
            "c_bb": _r(m * rng.uniform(0.01, 0.1)), "c_bt": _r(m * rng.uniform(0.01, 0.1))}
    if model == "two_plane_ramp":
        sets["t_ramp"] = _r(rng.uniform(200.0, 500.0))
    if model == "two_plane_hill":
        sets["t_half"] = _r(rng.uniform(100.0, 300.0))
    if model in ("two_plane_fixed", "two_plane_rotating"):
        sets["Omega"] = _r(rng.uniform(2.0, 4.0))
    return {"model": model, "family": "two_plane", "units": "thesis", "support": support, "drive": drive, "n": 4,
            "t_end": float(rng.choice(t_ends)), "set": sets,
            "y0": _phis(rng, [f"{prefix}_{i}" for i in range(1, 5)])}


def _scene_model(rng, n: int) -> dict:
    """The n = 5 (anisotropic, forced) and n = 6 (isotropic, run-up) SI scene models of `MODELS`."""
    toml = f"single_plane_n{n}.toml"
    forced = n == 5
    return {"scene": f"models/{toml}", "family": "single_plane", "units": "SI",
            "support": "anisotropic" if forced else "isotropic", "drive": "forced" if forced else "run-up",
            "n": n, "t_end": 1.0 if forced else 1.5, "set": {},
            "y0": _phis(rng, [f"phi_{i + 1}" for i in range(n)])}


def generate(seed: int = SEED) -> list[dict]:
    """The scenes, in order, each with its `name` (index and model)."""
    rng = np.random.default_rng(seed)
    scenes = []
    for n in (2, 3, 4):
        scenes += [_thesis(rng, n, k) for k in range(4)]
        scenes += [_si(rng, n, k) for k in range(3)]
    for model, count in (("two_plane_fixed", 4), ("two_plane_rotating", 4), ("two_plane_hill", 4),
                         ("two_plane_ramp", 3), ("two_plane_torque", 4)):
        scenes += [_two_plane(rng, model) for _ in range(count)]
    for n in (5, 6):
        scenes += [_scene_model(rng, n) for _ in range(3)]
    for i, s in enumerate(scenes):
        s["name"] = f"{i:02d}_{s.get('model') or Path(s['scene']).stem}"
        s["seed"] = seed
    return scenes


def write_files(seed: int = SEED, folder: Path = FOLDER) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    out = []
    for s in generate(seed):
        path = folder / f"{s['name']}.json"
        path.write_text(json.dumps(s, indent=2, sort_keys=True) + "\n")
        out.append(path)
    return out


def load(folder: Path = FOLDER) -> list[dict]:
    """The committed scenes, in name order."""
    return [json.loads(p.read_text()) for p in sorted(folder.glob("*.json"))]


if __name__ == "__main__":
    for p in write_files():
        print(p.relative_to(HERE.parent))
