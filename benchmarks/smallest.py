"""Benchmark (not a test): the smallest exact model of a scene against larger exact ones (issue 14,
item 4).  `adbgen bench smallest [--out FILE] [--quick]` -> ``benchmarks/smallest.json`` + PNG.

One physical scene (the thesis' (5.1) realised in SI: M = 1 kg, k = 1e4 N/m, R = 0.05 m, three balls
of 0.05 kg, isotropic, no gravity, omega = 400 rad/s), generated three ways by `adbgen regenerate
--scene` into a temporary folder (never into generated/):

- ``rotating``: what adbgen picks for it (`families/single_plane/selection.py`): the autonomous
  rotating-frame system (2.25)-(2.27) in the thesis' dimensionless variables (time omega_n t,
  lengths / R);
- ``fixed``: the same scene with the speed given as a profile omega(t) = 400 + 0 t, which the selection
  must treat as a prescribed run-up: the fixed-frame equations (2.10), (2.11), (2.13), forced at
  omega (explicit time);
- ``torque``: the spin a degree of freedom (2.12) driven by tau0 - kappa psi' with tau0 = kappa omega,
  so that the motor holds psi' at omega (stiffer for larger kappa): 3 + n coordinates;
- ``two_plane``: the two-plane family's smallest model (rotating frame (7)-(8), tilt phi_x, phi_y
  included) of a one-race rotor without tilt, the race in the plane of the centre of mass (the
  second race empty, as the two-plane scene needs two), in parameters that make it (5.1): its x, y,
  alpha_k are the thesis' x, y, phi_k.

Measured: each model's states, emitted operations are not recomputed here (see bench codegen); ns per
rhs call (numba, jitted loop), rhs evaluations, steps and wall time of the default engine over the
same physical time span (problem A's t_nd in [0, 2000], i.e. t in [0, 20] s), and the agreement of
the trajectories mapped into one frame: x + i y = (X + i Y) / R e^{-i omega t} at t_nd = omega_n t,
ball angles relative to the rotor in both (the fixed frame's phi_i are measured from the rotor).
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from .problems import PROBLEM_A
from .registry import QUICK, Benchmark
from .report import closing, opening, pyplot, save_figure, when, write
from .timing import best_per_call, calibrate, numba_loop

OMEGA = 400.0
OMEGA_N = 100.0  # sqrt(k / M)
R = 0.05
SCENES = {
    "rotating": 'n = 3\n[speed]\nlaw = "constant"\nomega = 400.0\n',
    "fixed": 'n = 3\n[speed]\nlaw = "profile"\nomega = "400.0 + 0*t"\n',
    "torque": 'n = 3\n[speed]\nlaw = "torque"\ntau0 = {tau0}\nmotor_slope = {kappa}\n',
    # two-plane: one race of three balls at the centre plane z = 0, the other race empty, bearings at +-3
    # alike (no tilt is excited: the race and the imbalance sit in the plane of the centre of mass);
    # M = R = 1 and 2k = 1 (omega_n = 1), so mu = m, delta = eps, zeta = c_total / 2, beta = c_b / m and
    # Omega = omega are (5.1) and the model's time is the thesis' t_nd
    "two_plane": """rotor_mass = 1.0
transverse_inertia = 3.25
polar_inertia = 0.5
eccentricity = 0.01
misalignment = 0.0
[[races]]
z = 0.0
radius = 1.0
masses = [0.05, 0.05, 0.05]
damping = 5.0e-4
[[races]]
z = -2.0
radius = 1.0
masses = []
damping = 0.0
[bearing_1]
position = 3.0
stiffness = 0.5
damping = 0.01
[bearing_2]
position = 3.0
stiffness = 0.5
damping = 0.01
[speed]
law = "constant"
omega = 4.0
""",
}
KAPPAS = (1.0, 100.0)
RTOL, ATOL = 1e-10, 1e-12


def generate(folder: Path, kind: str, text: str) -> Path:
    """`adbgen regenerate --scene` in a subprocess (this benchmark's analysis side never imports SymPy)."""
    scene = folder / f"{kind}.toml"
    scene.write_text(text)
    out = folder / f"out_{kind}"
    cmd = [sys.executable, "-m", "adbgen.cli", "regenerate", "--scene", str(scene), "--name", f"smallest_{kind}",
           "--out", str(out), "--targets", "numba", "c"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"regenerate {kind} failed: {proc.stderr.strip()[-300:]}")
    return out


def ns_per_rhs(model, y, p, target: float = 0.05) -> float:
    y = np.ascontiguousarray(y, float)
    p = np.ascontiguousarray(p, float)
    buf = np.empty(model.n_states)
    loop = numba_loop(model.module.rhs_inplace)
    loop(y, p, buf, 1)
    calls = calibrate(lambda k: loop(y, p, buf, k), target)
    return 1e9 * best_per_call(lambda k: loop(y, p, buf, k), calls, 5)


def to_rotating(t_si, Y, model) -> dict:
    """Fixed-frame samples (SI) -> the rotating frame's dimensionless x, y and ball angles."""
    X, Yc = Y[model.index("X")], Y[model.index("Y")]
    if "psi" in model.state_names:
        psi = Y[model.index("psi")]
    else:
        psi = OMEGA * np.asarray(t_si)
    w = (X + 1j * Yc) / R * np.exp(-1j * psi)
    return {"x": w.real, "y": w.imag, "phi": np.array([Y[model.index(f"phi_{k}")] for k in (1, 2, 3)])}


def _start(model) -> dict:
    """Problem A's start in the model's names: ball angles phi_k (alpha_k in the two-plane model),
    the motor at omega (torque model)."""
    y0 = dict(PROBLEM_A.y0)
    if "alpha_1" in model.state_names:
        y0 = {name.replace("phi_", "alpha_"): value for name, value in y0.items()}
    if "psi_dot" in model.state_names:
        y0["psi_dot"] = OMEGA
    return y0


def bench_smallest(quick: bool = False, progress=None) -> dict:
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.simulate import simulate
    from .pairs import cyrk_solve

    say = progress or (lambda line: None)
    result, started = opening("smallest")
    t_nd = 200.0 if quick else PROBLEM_A.t_end
    t_si = t_nd / OMEGA_N
    samples = np.linspace(0.0, t_nd, 401)[1:]
    result.update({"quick": quick, "models": {}, "agreement": {},
                   "scene": {"n": 3, "M": 1.0, "k": 1e4, "R": R, "ball_mass": 0.05, "omega": OMEGA, "omega_n": OMEGA_N,
                             "y0": PROBLEM_A.y0, "t_nd_end": t_nd, "t_si_end": t_si, "rtol": RTOL, "atol": ATOL}})
    kappas = KAPPAS[-1:] if quick else KAPPAS
    with tempfile.TemporaryDirectory(prefix="adbgen-smallest-") as tmp:
        folder = Path(tmp)
        models = {}
        for kind in ("rotating", "fixed"):
            start = time.perf_counter()
            models[kind] = (load_model(generate(folder, kind, SCENES[kind])), None)
            say(f"generated {kind} in {time.perf_counter() - start:.1f} s")
        start = time.perf_counter()
        models["two_plane"] = (load_model(generate(folder, "two_plane", SCENES["two_plane"])), None)
        say(f"generated two_plane in {time.perf_counter() - start:.1f} s")
        for kappa in kappas:
            kind = f"torque_kappa{kappa:g}"
            models[kind] = (load_model(generate(folder, kind, SCENES["torque"].format(tau0=kappa * OMEGA,
                                                                                     kappa=kappa))), kappa)
        runs = {}
        for kind, (model, kappa) in models.items():
            p = model.params()
            y0 = model.state(_start(model))
            t_end = t_nd if kind in ("rotating", "two_plane") else t_si
            sims = [simulate(model, p, y0, t_end=t_end, rtol=RTOL, atol=ATOL, keep_trajectory=False)
                    for _ in range(1 if quick else 5)]
            best = min(sims, key=lambda s: s.wall_s)
            t_eval = samples if kind in ("rotating", "two_plane") else samples / OMEGA_N
            traj = cyrk_solve(model.module.rhs_inplace, model.n_states, y0, p, t_end, RTOL, ATOL, t_eval=t_eval)
            runs[kind] = (model, traj)
            rec = {"model_kind": model.module.REFERENCE, "states": model.n_states, "autonomous": bool(model.autonomous),
                   "parameters": dict(zip(model.param_names, map(float, p))), "t_end": t_end,
                   "engine": best.engine, "n_rhs": int(best.n_rhs), "n_steps": int(best.n_steps),
                   "wall_s": best.wall_s, "runs_s": [s.wall_s for s in sims], "status": best.status,
                   "ns_per_rhs": ns_per_rhs(model, y0, p)}
            rec["rhs_cost_s"] = rec["n_rhs"] * rec["ns_per_rhs"] * 1e-9
            if kappa is not None:
                rec["kappa"] = kappa
                rec["tau0"] = kappa * OMEGA
                wdev = np.asarray(traj["y"][model.index("psi_dot")]) - OMEGA
                rec["max_speed_deviation_rad_s"] = float(np.max(np.abs(wdev)))
            result["models"][kind] = rec
            say(f"{kind:22s} states {rec['states']:2d} steps {rec['n_steps']:8d} rhs {rec['n_rhs']:9d} "
                f"{rec['ns_per_rhs']:.0f} ns/rhs wall {1e3 * rec['wall_s']:.2f} ms")
        rot_model, rot = runs["rotating"]
        ref = {"x": rot["y"][rot_model.index("x")], "y": rot["y"][rot_model.index("y")],
               "phi": np.array([rot["y"][rot_model.index(f"phi_{k}")] for k in (1, 2, 3)])}
        for kind, (model, traj) in runs.items():
            if kind == "rotating":
                continue
            if kind == "two_plane":
                mapped = {"x": traj["y"][model.index("x")], "y": traj["y"][model.index("y")],
                          "phi": np.array([traj["y"][model.index(f"alpha_{k}")] for k in (1, 2, 3)])}
                result["models"][kind]["max_tilt"] = float(np.max(np.abs(traj["y"][[model.index("phi_x"),
                                                                                     model.index("phi_y")]])))
            else:
                mapped = to_rotating(traj["t"], traj["y"], model)
            dxy = np.hypot(mapped["x"] - ref["x"], mapped["y"] - ref["y"])
            dphi = np.max(np.abs(mapped["phi"] - ref["phi"]), axis=0)
            result["agreement"][kind] = {"max_dxy_over_R": float(np.max(dxy)), "max_dphi": float(np.max(dphi)),
                                         "r_scale": float(np.max(np.hypot(ref["x"], ref["y"]))),
                                         "curve": {"t_nd": samples.tolist(), "dxy": dxy.tolist(), "dphi": dphi.tolist()}}
            say(f"agreement {kind:20s} max |d(x,y)|/R {np.max(dxy):.3e}  max |dphi| {np.max(dphi):.3e}")
    rot = result["models"]["rotating"]
    result["savings"] = {kind: {"wall_ratio": rec["wall_s"] / rot["wall_s"], "n_rhs_ratio": rec["n_rhs"] / rot["n_rhs"],
                                "ns_per_rhs_ratio": rec["ns_per_rhs"] / rot["ns_per_rhs"],
                                "extra_states": rec["states"] - rot["states"]}
                         for kind, rec in result["models"].items() if kind != "rotating"}
    return closing(result, started)


def chart(result: dict, path: Path) -> Path:
    plt = pyplot()

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    models = result["models"]
    names = list(models)
    axes[0].bar(range(len(names)), [1e3 * models[k]["wall_s"] for k in names], color="C0")
    for i, k in enumerate(names):
        axes[0].text(i, 1e3 * models[k]["wall_s"], f"{models[k]['n_rhs']} rhs\n{models[k]['states']} states",
                     ha="center", va="bottom", fontsize=7)
    axes[0].set_xticks(range(len(names)), names, fontsize=7)
    axes[0].set_yscale("log")
    axes[0].set_ylabel("wall time, cyrk-dop853 [ms] (log)")
    axes[0].set_title("one scene, t_nd in [0, %g]" % result["scene"]["t_nd_end"], fontsize=9)
    for kind, rec in result["agreement"].items():
        c = rec["curve"]
        axes[1].semilogy(c["t_nd"], np.maximum(c["dxy"], 1e-18), label=f"{kind}: |d(x, y)| / R")
    axes[1].set_xlabel("t_nd = omega_n t")
    axes[1].set_ylabel("difference from the rotating-frame run")
    axes[1].legend(fontsize=7)
    fig.suptitle(f"Smallest model: {when(result)} UTC, load "
                 f"{result['machine']['load_average_at_start']}, rtol {result['scene']['rtol']:g}", fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path, dpi=110)


def run(args, out: str) -> int:
    result = bench_smallest(quick=args.quick, progress=lambda line: print(line, flush=True))
    path = write(result, out)
    png = chart(result, Path(out).with_suffix(".png"))
    print(f"wrote {path} and {png} ({result['seconds']} s)")
    return 0


BENCHMARK = Benchmark("smallest", run, (QUICK.but("short runs (checks the machinery)"),))


__all__ = ["BENCHMARK", "bench_smallest", "chart", "to_rotating"]
