"""Transients of a generated model: one trajectory or many (thesis ch. 5).

    simulate(model, params={"Omega": 4}, y0={"phi_1": pi/2}, t_end=1000)   -> Simulation
    simulate_many(model, P, Y0, t_end=1000, threads=2)                      -> Ensemble
    write_trajectory(model, sim, out)        trajectory.npz, trajectory.csv and trajectory.png in out

The default engine is compiled end to end (see `engines`); `engine="scipy-dop853"` etc. select
the others.  A failed, stalled or non-finite integration raises `IntegrationError` naming the time
it failed at (``check=False`` returns the result with its status instead).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from .engines import engine_for
from .loading import AnalysisError, Model
from .results import Ensemble, Simulation

MAX_STEPS = 10_000_000


def _settings(t_end, rtol, atol, threshold, max_steps=1):
    if not isinstance(max_steps, int) or max_steps < 1:
        raise AnalysisError(f"max_steps must be a whole number >= 1, got {max_steps!r}")
    for name, value in (("t_end", t_end), ("rtol", rtol), ("atol", atol), ("threshold", threshold)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise AnalysisError(f"{name} must be a finite number > 0, got {value!r}")
    if rtol < 1e-15:
        raise AnalysisError(f"rtol {rtol} is below what double precision resolves (1e-15)")


def _vector(model: Model, values, kind: str) -> np.ndarray:
    if values is None or isinstance(values, dict):
        return model.params(values) if kind == "parameter" else model.state(values)
    return model.check_vector(values, kind)


def simulate(model: Model, params=None, y0=None, *, t_end: float = 1000.0, rtol: float = 1e-8,
             atol: float = 1e-10, engine: str | None = None, threshold: float = 1e-3, keep_trajectory: bool = True,
             samples: int = 2001, max_steps: int = MAX_STEPS, check: bool = True) -> Simulation:
    """One trajectory of `model` from `y0` (dict by name, states not given are 0, or a full vector).

    t_dec = sup{t <= t_end : r(t) >= threshold} on the continuous solution (None if r(t_end) >= it)."""
    _settings(t_end, rtol, atol, threshold, max_steps)
    eng = engine_for(model, engine)
    p = _vector(model, params, "parameter")
    y = _vector(model, y0, "state")
    out = eng.run(model, p, y, float(t_end), float(rtol), float(atol), float(threshold), int(max_steps),
                  keep_trajectory=keep_trajectory, samples=samples)
    t_dec = out["t_dec"]
    sim = Simulation(
        model=model.name, engine=eng.name, rtol=float(rtol), atol=float(atol), t_end=float(t_end),
        threshold=float(threshold), status=out["status"], t=out["t"], y=out["y"],
        r_max=float(out["r_max"]), t_dec=None if t_dec is None or not math.isfinite(t_dec) else float(t_dec),
        y_end=np.asarray(out["y_end"], float), n_rhs=out["n_rhs"], n_steps=out["n_steps"], wall_s=out["wall_s"],
        state_names=model.state_names, parameters=dict(zip(model.param_names, map(float, p))),
        t_fail=out["t_fail"], message=out.get("message", ""), picked=out.get("picked"),
        stuck=None if out.get("stuck") is None else tuple(out["stuck"]), r_end=out.get("r_end"))
    return sim.raise_for_status() if check else sim


def simulate_many(model: Model, P, Y0, *, t_end: float = 1000.0, rtol: float = 1e-8, atol: float = 1e-10,
                  engine: str | None = None, threshold: float = 1e-3, threads: int | None = None,
                  max_steps: int = MAX_STEPS, check_dt: float = 0.0, targets=(), measures: bool = True) -> Ensemble:
    """Trajectory k from row k of Y0 (N x states) with row k of P (N x parameters, or one row for all).

    Runs on `threads` cores inside the compiled library (no Python per trajectory).  Early stop
    (sweeps): every `check_dt` a trajectory inside a target region (centre, W: e'We <= 1, or centre,
    weights w: W = diag(w^2)) stops there with status "stopped" and `target` its index; the compiled
    engines run in segments of `check_dt` with or without targets.  `measures=False`: r_max and t_dec
    are not computed (NaN), which spares the CyRK engines their refinement and the stored steps.
    Failures are reported per trajectory in `status`."""
    _settings(t_end, rtol, atol, threshold, max_steps)
    eng = engine_for(model, engine)
    Y0 = np.atleast_2d(np.asarray(Y0, float))
    P = np.atleast_2d(np.asarray(P, float))
    model.check_vector(Y0, "state")
    model.check_vector(P, "parameter")
    if len(Y0) == 0:
        raise AnalysisError("no trajectories to run")
    if len(P) == 1 and len(Y0) > 1:
        P = np.repeat(P, len(Y0), axis=0)
    if len(P) != len(Y0):
        raise AnalysisError(f"{len(Y0)} initial states but {len(P)} parameter rows")
    out = eng.run_many(model, P, Y0, float(t_end), float(rtol), float(atol), float(threshold), int(max_steps),
                       threads=threads, check_dt=float(check_dt), targets=tuple(targets), measures=bool(measures))
    return Ensemble(engine=eng.name, status=out["status"], r_max=np.asarray(out["r_max"], float),
                    t_dec=np.asarray(out["t_dec"], float), y_end=np.asarray(out["y_end"], float),
                    t_last=np.asarray(out["t_last"], float), target=np.asarray(out["target"]),
                    n_rhs=np.asarray(out["n_rhs"]), n_steps=np.asarray(out["n_steps"]), wall_s=out["wall_s"],
                    picked=out.get("picked"), stuck=out.get("stuck"), r_end=out.get("r_end"))


def amplitude(model: Model, y: np.ndarray) -> np.ndarray:
    """r = sqrt(x^2 + y^2) of the rotor centre along a trajectory (states on the rows)."""
    ix, iy, _, _ = model.amplitude_indices
    return np.hypot(y[ix], y[iy])


def simulation_units(model, sim) -> dict:
    """The unit of each number of `Simulation.to_json` ("1": dimensionless)."""
    from .units import units

    u = units(model)
    return {"t_end": u.time, "threshold": u.length, "r_max": u.length, "t_dec": u.time, "t_fail": u.time,
            "wall_s": "s", "y_end": dict(u.states), "parameters": dict(u.params)}


def write_trajectory(model, sim, out: Path, values: dict | None = None, scene: str | None = None,
                     wrap_angles: bool = True, threshold_why: str = "", note: str | None = None,
                     sensitive: bool = False) -> None:
    """trajectory.npz (t, y, names, metadata), trajectory.csv (metadata header) and trajectory.png (r
    and the ball angles), each written whole (a temporary file renamed).  `note` (the label) and
    `sensitive` (`tolerance.check_simulation` found the outcome tolerance-sensitive) go into the plot's
    title, and `sensitive` into the metadata."""
    import io

    from ..outputs import save_figure, writing
    from .figure_style import amplitude_panel, angle_panel, pyplot, title
    from .results import json_number
    from .units import axis_label, show, units

    u = units(model)
    out.mkdir(parents=True, exist_ok=True)
    meta = {k: v for k, v in sim.to_json().items() if k != "y_end"}
    meta["source_hash"] = model.source_hash
    meta["units"] = simulation_units(model, sim)
    if note is not None:
        meta["label"] = note
        meta["tolerance_sensitive"] = bool(sensitive)
    with writing(out / "trajectory.npz", "wb") as fh:
        np.savez_compressed(fh, t=sim.t, y=sim.y, state_names=np.array(sim.state_names),
                            metadata=json.dumps(meta, default=json_number))
    r = amplitude(model, sim.y)
    header = "\n".join(f"# {k}: {json.dumps(v, default=json_number)}" for k, v in meta.items())
    table = np.column_stack([sim.t, r, sim.y.T])
    body = io.StringIO()
    np.savetxt(body, table, delimiter=",", fmt="%.17g")
    with writing(out / "trajectory.csv") as fh:
        fh.write(header + "\n")
        fh.write(",".join(["t", "r", *sim.state_names]) + "\n")
        fh.write(body.getvalue())
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7.5, 5.5), sharex=True, constrained_layout=True)
    amplitude_panel(a1, sim.t, r, sim.threshold, sim.t_dec, u.length, u.time, threshold_why)
    angles = list(model.angle_indices)
    angle_panel(a2, sim.t, sim.y[angles], [model.state_names[i] for i in angles], wrap_angles)
    a2.set_xlabel(axis_label("$t$", u.time))
    name = f"{Path(scene).name} ({model.name})" if scene else model.name
    summary = (f"$r_{{max}}$ = {show(sim.r_max, u.length, 4)}, $t_{{dec}}$ = "
               f"{'not settled' if sim.t_dec is None else show(sim.t_dec, u.time, 4)}")
    if note:
        summary += f", {note}"
    if sensitive:
        summary += " — TOLERANCE-SENSITIVE (!)"
    a1.set_title(title(name, values or {}, u.params, summary), fontsize=8)
    save_figure(fig, out / "trajectory.png", dpi=120)
