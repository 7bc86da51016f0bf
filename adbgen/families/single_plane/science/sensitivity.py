"""Which of the thesis' transient outcomes hang on the tolerance (issue 34, item 2): every transient of the
reproduction through `analysis.tolerance`'s check, and the runs the audit found sensitive, Fig. 5.10's
three panels (thesis section 5.1.3: balls released at rest in the fixed frame, phi_i'(0) = -Omega) and the
named start 23 pi/99 of Fig. 5.9(a1), each with its outcome at every tolerance, the check's verdict and
the thesis' solver (`matlab-ode45` at ode45's defaults) beside the converged run; and every start the thesis
names in Figs. 5.7, 5.9 checked on its panel's own sweep (`adbgen sweep --check-tolerance`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ....analysis.loading import load_model
from ....analysis.tolerance import MARK, REL_TOL, TIGHTEN, check_simulation

PI = math.pi
CHECKED = 1e-8  # the run checked: the launches' sweeps of Fig. 5.11 run at it (sweeps.RTOL)
LAP_WINDOW = 500.0  # a ball laps when its angle moves by more than a turn over the run's last 500 time units


@dataclass(frozen=True)
class Ladder:
    """How the reproduction runs a transient (its `reproduce.ENGINE`, `RTOLS`, `T_END`, `ODE45`, passed in)."""

    engine: str
    rtols: tuple[float, ...]  # ascending in precision; atol = rtol/100
    t_end: float
    ode45: tuple[str, float, float]  # the thesis' integrator at its defaults (engine, RelTol, AbsTol)


@dataclass(frozen=True)
class Run:
    figure: str
    n: int
    phi0: tuple[float, ...]
    phi0_text: str
    rate: float  # every ball's phi'(0)
    thesis: str  # what the thesis shows


RUNS = (  # thesis section 5.1.3, Fig. 5.10 (text and caption); section 5.1.2, Fig. 5.9(a1)
    Run("5.10(a)", 2, (PI / 2, -PI / 2), "(pi/2, -pi/2)", -4.0,
        "a limit cycle; one ball stops lapping and oscillates (a2)"),
    Run("5.10(b)", 3, (PI / 3, PI, -PI / 3), "(pi/3, pi, -pi/3)", -4.0, "a limit cycle; the three balls keep lapping"),
    Run("5.10(c)", 4, (PI / 2, -PI / 2, PI, 0.0), "(pi/2, -pi/2, pi, 0)", -4.0,
        "a limit cycle; one ball stops lapping and oscillates (c2)"),
    Run("5.9(a1), 23pi/99", 4, (23 * PI / 99, -23 * PI / 99, 0.0, 0.0), "(23pi/99, -23pi/99, 0, 0)", 0.0,
        "a limit cycle"),
)


def _start(model, run: Run) -> np.ndarray:
    values = {f"phi_{i + 1}": v for i, v in enumerate(run.phi0)}
    values.update({f"phi_{i + 1}_dot": run.rate for i in range(run.n)})
    return model.state(values)


def laps(model, sim) -> int:
    """How many balls still lap the rotor at the end: angle moved by more than 2 pi over LAP_WINDOW."""
    from ....analysis.attractors import balls

    keep = sim.t >= sim.t[-1] - LAP_WINDOW
    moved = [float(np.ptp(sim.y[k][keep])) for k in balls(model)]
    return sum(m > 2 * PI for m in moved)


def study(run: Run, ladder: Ladder) -> dict:
    """The run at every rtol of the ladder (label, r_max, t_dec, balls lapping), ode45 at its defaults, and the
    check of the run at CHECKED (tighter: the ladder's next rtol, a factor TIGHTEN; second engine)."""
    from ....analysis.simulate import simulate
    from ....analysis.tolerance import label_of

    model = load_model(f"thesis_rotating_n{run.n}")
    p, y0 = model.params({}), _start(model, run)

    def go(engine, rtol, atol):
        return simulate(model, p, y0, t_end=ladder.t_end, rtol=rtol, atol=atol, engine=engine, keep_trajectory=True,
                        samples=6001, check=False)

    engine = ladder.engine
    sims = {r: go(engine, r, r * 1e-2) for r in ladder.rtols}
    ode45 = go(*ladder.ode45)
    steps = {r: {"label": label_of(model, p, s, engine, r, r * 1e-2), "laps": laps(model, s), "r_max": s.r_max,
                 "t_dec": s.t_dec} for r, s in sims.items()}
    tight = min(ladder.rtols, key=lambda r: abs(math.log(r * TIGHTEN / CHECKED)))  # the ladder's rtol/100
    check = check_simulation(model, p, y0, sims[CHECKED], t_end=ladder.t_end, threshold=1e-3, engine=engine,
                             tight=sims[tight], shown=[("thesis' solver", ladder.ode45[0], ode45)])
    return {"run": run, "model": model, "sims": sims, "ode45": ode45, "ladder": steps,
            "ode45_laps": laps(model, ode45), "check": check}


def compute(fig_dir: Path, ladder: Ladder, progress=None) -> dict:
    out = {"runs": [], "figure": None, "ladder": ladder}
    for run in RUNS:
        out["runs"].append(study(run, ladder))
        if progress:
            c = out["runs"][-1]["check"]
            progress(f"Fig. {run.figure}: {c.text()}")
    out["figure"] = figure(out["runs"], fig_dir, ladder.engine)
    out["named"] = named_starts()
    if progress:
        progress("named starts of Figs. 5.7, 5.9: " + ", ".join(
            f"{r['figure']} {r['phi_1']:.4f} {'sensitive' if r['sensitive'] else 'robust'}" for r in out["named"]))
    return out


def figure(studies, fig_dir: Path, engine: str) -> Path:
    """r(t) and the ball angles of each run at CHECKED and of ode45; a tolerance-sensitive run's title says so."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ....analysis.attractors import balls
    from ....analysis.figure_style import angle_panel
    from ....analysis.simulate import amplitude

    fig, axes = plt.subplots(3, len(studies), figsize=(3.3 * len(studies), 7.0), sharex=True,
                             constrained_layout=True)
    for k, st in enumerate(studies):
        model, check = st["model"], st["check"]
        ours, ode = st["sims"][CHECKED], st["ode45"]
        axes[0, k].plot(ours.t, amplitude(model, ours.y), lw=0.4, color="k", label=f"rtol {CHECKED:g}")
        axes[0, k].plot(ode.t, amplitude(model, ode.y), lw=0.4, color="tab:orange", alpha=0.7, label="ode45")
        for row, (sim, name) in enumerate(((ours, f"rtol {CHECKED:g}"), (ode, "ode45")), start=1):
            idx = balls(model)
            angle_panel(axes[row, k], sim.t, sim.y[idx], [model.state_names[i] for i in idx])
            axes[row, k].set_ylabel(f"angles, {name}", fontsize=7)
        head = f"Fig. {st['run'].figure}: {check.runs[0].label}"
        if check.sensitive:
            head += f"\n{MARK} TOLERANCE-SENSITIVE"
        axes[0, k].set_title(head, fontsize=8, color="tab:red" if check.sensitive else "black")
        axes[0, k].legend(fontsize=6, loc="upper right")
        axes[2, k].set_xlabel("$t$")
    axes[0, 0].set_ylabel("$r$")
    fig.suptitle(f"Fig. 5.10 and 5.9(a1)'s named start, {engine} at rtol {CHECKED:g} and ode45 at its defaults",
                 fontsize=9)
    path = fig_dir / "fig5_10_tolerance.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def lines(res: dict, root: Path) -> list[str]:
    """Fig. 5.10's section (templates/tolerance.md.j2) and the named starts' table."""
    from .templates import render

    return render("tolerance", ladder=res["ladder"], runs=res["runs"], checked=CHECKED, tighten=TIGHTEN,
                  rel_tol=REL_TOL, mark=MARK, lap_window=LAP_WINDOW,
                  figure=res["figure"].relative_to(root).as_posix()) + named_lines(res.get("named", []))


# ------------------------------------------------------------------------ every transient, checked

def check_transient(n: int, phi0, params: dict, sims: dict, engine: str):
    """The check of a reproduction transient already run on a ladder of tolerances `sims` (rtol -> Simulation
    on `engine`): the run at the second tightest rtol against the tightest (tighter by TIGHTEN in the
    reproduction's ladder) and against the second engine at the same rtol."""
    model = load_model(f"thesis_rotating_n{n}")
    y0 = model.state({f"phi_{i + 1}": v for i, v in enumerate(phi0)})
    rtols = sorted(sims)
    base = sims[rtols[1]]
    return check_simulation(model, model.params(params), y0, base, t_end=base.t_end, threshold=base.threshold,
                            engine=engine, tight=sims[rtols[0]])


def transient_lines(items) -> list[str]:
    """The check of every transient of the chapter-5 tables: (figure, phi(0) text, ToleranceCheck)
    (templates/transient_check.md.j2)."""
    from .templates import render

    return render("transient_check", items=items, flagged=[(f, t, c) for f, t, c in items if c.sensitive],
                  runs=items[0][2].runs if items else [], tighten=TIGHTEN, rel_tol=REL_TOL, mark=MARK)


# ------------------------------------------------------------- the named starts of Figs. 5.7, 5.9

def named_starts(workers: int | None = None) -> list[dict]:
    """The starts the thesis names in Figs. 5.7, 5.9 (`sweeps.NAMED`) on the scans' own sweep path (the panel's
    attractor sweep, `adbgen sweep ... --check-tolerance`) at the scan's grid point bit for bit (a one-point
    grid at its value: the trajectories of a sweep do not depend on each other): each start's label, its
    labels tighter and on the second engine, and the flag."""
    import json
    import shutil
    import tempfile

    import xarray as xr

    from ....analysis.sweep import SweepSpec, prepare, run_sweep
    from . import sweeps

    panels = {p.figure: p for p in sweeps.PANELS}
    out = []
    for figure, value, words, expect in sweeps.NAMED:
        panel = panels[figure]

        def spec(grid, check):
            return SweepSpec(model=f"thesis_rotating_n{panel.n}", grid=[grid], measure="attractor",
                             y0=list(panel.y0), tie=list(panel.tie), t_end=3000.0, rtol=sweeps.RTOL,
                             atol=sweeps.RTOL * 1e-2, engine="cyrk-dop853", check_tolerance=check)

        axis = prepare(spec(sweeps.SCAN_GRID, False))[1].axes[0]
        phi = float(axis.values[int(np.argmin(np.abs(axis.values - value)))])
        tmp = Path(tempfile.mkdtemp(prefix="adbgen-reproduce-named-"))
        try:
            summary = run_sweep(spec(f"{axis.name}={phi!r}:{phi!r}:1", True), tmp, progress=False, figures=False,
                                workers=workers)
            ds = xr.open_zarr(tmp / "sweep.zarr", consolidated=False).load()
            names = json.loads(ds.attrs["labels"])
            label = {key: names[int(ds[var].values[0])] for key, var in (
                ("as run", "attractor"), ("tighter", "attractor_tighter"),
                ("second engine", "attractor_second_engine"))}
            out.append({"figure": figure, "phi_1": phi, "words": words, "expect": expect, "labels": label,
                        "sensitive": bool(ds["tolerance_sensitive"].values[0] == 1),
                        "check": summary["tolerance_check"]})
            ds.close()
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    return out


def named_lines(rows: list[dict]) -> list[str]:
    """The named starts' table (templates/named_checked.md.j2)."""
    from .templates import render

    if not rows:
        return []
    return render("named_checked", rows=rows, check=rows[0]["check"], tighten=TIGHTEN, mark=MARK)
