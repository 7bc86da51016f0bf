"""What `adbgen design` writes (issue 39 item 4): the design's JSON, a one-page Markdown report and its figure.

    to_json(design)                 the --json object (keys: docs/design.md, `adbgen design --help`)
    write(design, folder, command)  FOLDER/design.json, FOLDER/report.md, FOLDER/design.png

The figure: one varied parameter, the worst margin over the box against it (every design assessed), the
feasible intervals shaded and the boundaries marked by kind; two, the chart (each assessed design feasible,
infeasible or beyond the capacity; the located boundary points by kind); more, the optimiser's designs by
evaluation.  The best design is a star.  An infeasible or not-computed design is never drawn as feasible.
"""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

from .design import Design
from .design_transients import START_STATE, STARTS
from .prose import render

# what the command does not do yet (issue 39), said in its output rather than left out silently
NOT_COVERED = ["the ball count with a generated model's name (--balls needs a scene file: the count is a scene's n)",
               "Dask for every evaluation: the chart's grid and its certified lines, and the optimiser's first designs "
               "and each of its designs' box lines, go to the local cluster, but a single line's refinement and the "
               "optimiser's path (COBYLA: one design after another) run in the command's process (all are journalled: "
               "a killed design resumes)",
               "boundaries of periodic orbits other than the balancing state (a coexisting limit cycle's fold, torus or "
               "period doubling) and basin boundaries",
               "a forced model (a rotor in the fixed frame, anisotropic supports): its balancing orbit is designed "
               "(existence, Floquet margin, intervals, chart, optimiser, verification runs) only where the module's "
               "closed form gives it (e.g. without gravity: with gravity the rotor is not at rest and no closed form "
               "is given); the sensitivities are finite differences only (no jac_p perturbation of a multiplier), "
               "and the run-up objective and verification need a run model (--runs) as for any model"]
# which boundaries the feasibility chart (and the intervals) locate and certify, said in every output: the
# balancing steady state's losses only; a boundary of a periodic orbit (torus, period doubling: analysis/orbits/)
# is not computed, so a region the chart calls feasible may hold such an orbit's bifurcation
BOUNDARY_TYPES = {"certified": ["capacity limit (the balancing state's closed form ceases to exist)",
                                "Hopf (a complex pair of the balancing state crosses)",
                                "real eigenvalue (fold or pitchfork of the balancing state)",
                                "torus (a complex pair of the forced model's balancing orbit's Floquet multipliers "
                                "leaves the unit circle)",
                                "fold (a multiplier of the balancing orbit through +1)",
                                "period doubling (a multiplier of the balancing orbit through -1)",
                                "range end"],
                  "not_certified": ["torus (Neimark-Sacker) or period doubling of a periodic orbit",
                                    "fold of periodic orbits", "a basin boundary (a coexisting attractor)"],
                  # the orbits' boundaries above are those of other orbits: the balancing state's own, seen from the
                  # fixed frame, are its Hopf and real crossings here (Floquet-Lyapunov, below)
                  "scope": "the balancing state as an equilibrium of an autonomous model, or, for a periodically forced "
                           "model (a rotor in the fixed frame, anisotropic supports), as the periodic orbit of period "
                           "T = 2 pi / Omega through the same closed form (the rotor at rest, the balls turning with "
                           "it), checked over one period, its margin the leading non-trivial Floquet multiplier's "
                           "log|mu| / T (the balancing family's multipliers 1 removed) and its boundaries named torus, "
                           "fold or period doubling. "
                           "Where the model's frame turns with the rotor at the constant speed Omega, the same state "
                           "seen from the fixed frame is a periodic orbit of period T = 2 pi / Omega whose Floquet "
                           "multipliers are exp(lambda T), lambda its eigenvalues here (Floquet-Lyapunov: the frame's "
                           "rotation is T-periodic): that orbit's torus (Neimark-Sacker; period doubling where the "
                           "pair crosses at +-i Omega/2) is the Hopf boundary and its fold the real-eigenvalue "
                           "boundary, certified with them. The not-certified types are those of other periodic "
                           "orbits and of basins."}
# the short form drawn under the figure and kept in its PNG metadata (Description)
BOUNDARY_NOTE = ("Boundaries certified: " + "; ".join(b.split(" (")[0] for b in BOUNDARY_TYPES["certified"])
                 + " (the balancing state's; in the fixed frame its orbit's torus and fold). Not computed (other orbits than "
                 "the balancing state, basins): " + "; ".join(BOUNDARY_TYPES["not_certified"]) + ".")

RUN_UP_FIGURE = "run-up.png"
MARKERS = {"capacity limit": ("s", "tab:purple"), "Hopf": ("o", "tab:red"), "real eigenvalue": ("^", "tab:orange"),
           "torus": ("D", "tab:red"), "fold": ("v", "tab:orange"), "period doubling": ("P", "tab:brown"),
           "not located": ("x", "k")}


def to_json(design: Design, objective: str = "margin") -> dict:
    pr = design.problem
    best = design.best
    return {"model": pr.model.name, "balancing_state": pr.label, "objective": objective,
            "box": [a.to_json() for a in pr.box], "imbalance_parameter": pr.eccentricity,
            "imbalance_floor": pr.floor,
            "varied": [a.to_json() for a in pr.varied], "method": design.method,
            "feasible": best is not None and best.feasible,
            "feasible_intervals": [list(w) for w in design.feasible_intervals],
            "boundaries": [b.to_json() for b in design.boundaries],
            "best": best.to_json(pr) if best is not None else None,
            "active_boundary": design.active.to_json() if design.active is not None else None,
            "sensitivity": design.sensitivity, "chart": design.chart, "resolution": design.resolution,
            "evaluations": design.evaluations, "evaluations_resumed": design.resumed, "objective_runs": design.objective_runs,
            "verification": design.verification, "verification_start": START_STATE,
            "verification_run_up": ({k: v for k, v in design.verification_run_up.items() if k != "trace"}
                                    if design.verification_run_up is not None else None),
            "verification_run_up_note": design.verification_run_up_note, "not_covered": NOT_COVERED,
            "boundary_types": BOUNDARY_TYPES, "residual": design.residual}


def _fmt(x) -> str:
    return "—" if x is None or (isinstance(x, float) and not math.isfinite(x)) else f"{x:.6g}"


def report(design: Design, command: str, objective: str = "margin", balls: list | None = None,
           choice: dict | None = None) -> str:
    """report.md (prose/design_report.md.j2): the problem, the ball counts, the best design, the boundaries, the
    sensitivity, the objective's runs, the verification runs and run-up, what is certified and what is not."""
    pr = design.problem
    run = design.verification_run_up
    return "\n".join(render(
        "design_report", fmt=_fmt, model=pr.model.name, command=command, label=pr.label,
        eccentricity=pr.eccentricity, imbalance_high=pr.imbalance.high, box=pr.box, floor=pr.floor,
        varied=pr.varied, balls=balls, choice=choice, objective=objective, start=STARTS[0], start_state=START_STATE,
        best=to_json(design, objective)["best"] if design.best is not None and design.best.feasible else None,
        best_design=design.best.design if design.best is not None else (),
        none_feasible=not design.feasible_intervals and not any(v.feasible for v in design.verdicts),
        intervals=design.feasible_intervals, boundaries=design.boundaries, active=design.active,
        sensitivity=design.sensitivity, runs=design.objective_runs, verification=design.verification, run=run,
        run_note=design.verification_run_up_note, resolution=design.resolution, types=BOUNDARY_TYPES,
        not_covered=NOT_COVERED, residual=design.residual,
        run_figure=RUN_UP_FIGURE if run is not None and run["trace"]["t"] else None))


def run_up_figure(design: Design, path: Path) -> None:
    """r(t) through the chosen design's run-up, the schedule's end and the threshold marked.  A run-up whose r has
    not settled below the threshold by t_end (design_runs.run_up_trace's `settled`) says so in the title, as
    `simulate --out` says TOLERANCE-SENSITIVE: the figure alone must not pass for a settled run-up.  The title is
    also the PNG's Title."""
    from .figure_style import pyplot

    plt = pyplot()
    run = design.verification_run_up
    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    ax.plot(run["trace"]["t"], run["trace"]["r"], color="tab:blue", lw=0.8, label="r(t)")
    ax.axvline(run["schedule_end"], color="k", ls="--", lw=0.8, label="schedule at its final speed")
    ax.axhline(run["threshold"], color="tab:red", ls=":", lw=0.8, label="threshold")
    if run["t_dec"] is not None:
        ax.axvline(run["t_dec"], color="tab:green", ls="-.", lw=0.8, label=f"t_dec = {run['t_dec']:.4g}")
    ax.set_yscale("log")
    ax.set_xlabel("t")
    ax.set_ylabel("rotor amplitude r")
    title = (f"{run['run_model']}: run-up of the chosen design "
             + ", ".join(f"{k} = {v:.4g}" for k, v in run["design"].items()))
    if not run["settled"]:
        title += f"\nr NOT SETTLED below the threshold by t_end = {run['t_end']:.4g} (!)"
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110, metadata={"Title": title})
    plt.close(fig)


def figure(design: Design, path: Path, scene: str | None = None) -> None:
    """The design's figure, titled by the scene file where there is one (its model's name alone is a hash),
    as `simulate --out` titles its plot; the title is also the PNG's Title."""
    from .figure_style import pyplot

    plt = pyplot()
    pr = design.problem
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    if design.method == "interval":
        name = pr.varied[0].name
        pts = sorted((v.design[0], v) for v in design.verdicts)
        for cls, colour, label in ((True, "tab:green", "feasible"), (False, "tab:red", "unstable in the box")):
            xs = [x for x, v in pts if v.exists and not v.failures and v.feasible == cls and math.isfinite(v.margin)]
            ys = [-v.margin for x, v in pts if v.exists and not v.failures and v.feasible == cls and math.isfinite(v.margin)]
            ax.plot(xs, ys, ".", color=colour, label=label)
        gone = [x for x, v in pts if not v.exists]
        if gone:
            ax.plot(gone, [0.0] * len(gone), "s", color="tab:purple", mfc="none", label="beyond the capacity")
        for a, b in design.feasible_intervals:
            ax.axvspan(a, b, color="tab:green", alpha=0.12)
        for kind, (mk, colour) in MARKERS.items():
            for k, bd in enumerate(b for b in design.boundaries if b.kind == kind):
                ax.axvline(bd.values[name], color=colour, ls="--", lw=1, label=f"boundary: {kind}" if k == 0 else None)
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_xlabel(name)
        ax.set_ylabel("worst decay rate over the box (-margin)")
    elif design.method == "chart":
        n1, n2 = pr.varied[0].name, pr.varied[1].name
        for cls, (mk, colour, label) in {"feasible": ("o", "tab:green", "feasible"),
                                         "unstable": ("o", "tab:red", "unstable in the box"),
                                         "capacity": ("s", "tab:purple", "beyond the capacity"),
                                         "failed": ("x", "0.5", "not computed")}.items():
            sel = [v for v in design.verdicts if _class(v) == cls]
            if sel:
                ax.plot([v.design[0] for v in sel], [v.design[1] for v in sel], mk, color=colour, ms=3, alpha=0.5,
                        label=label)
        for kind, (mk, colour) in MARKERS.items():
            sel = [b for b in design.boundaries if b.kind == kind]
            if sel:
                ax.plot([b.values[n1] for b in sel], [b.values[n2] for b in sel], mk, color=colour, ms=7, mfc="none",
                        label=f"boundary: {kind}")
        ax.set_xlabel(n1)
        ax.set_ylabel(n2)
    else:
        ys = [-v.margin if math.isfinite(v.margin) else math.nan for v in design.verdicts]
        ax.plot(range(len(ys)), ys, ".", color="tab:blue", label="designs assessed")
        ax.set_xlabel("design assessed")
        ax.set_ylabel("worst decay rate over the box (-margin)")
    best = design.best
    if best is not None and best.feasible:
        if design.method == "interval":
            ax.plot([best.design[0]], [-best.margin], "*", color="gold", mec="k", ms=14, label="best design")
        elif design.method == "chart":
            ax.plot([best.design[0]], [best.design[1]], "*", color="gold", mec="k", ms=14, label="best design")
    name = f"{Path(scene).name} ({pr.model.name})" if scene else pr.model.name
    title = f"{name}: design of {', '.join(a.name for a in pr.varied)}"
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    fig.text(0.01, 0.01, textwrap.fill(BOUNDARY_NOTE, 130), fontsize=5.5, va="bottom")
    fig.savefig(path, dpi=110, metadata={"Title": title, "Description": BOUNDARY_NOTE})
    plt.close(fig)


def _plain(x):
    return float(x) if isinstance(x, (int, float)) or hasattr(x, "__float__") else str(x)


def _class(v) -> str:
    if not v.exists:
        return "capacity"
    if v.failures or not math.isfinite(v.margin):
        return "failed"
    return "feasible" if v.feasible else "unstable"


def write(design: Design, folder: Path, command: str, objective: str = "margin", balls: list | None = None,
          choice: dict | None = None, scene: str | None = None) -> dict:
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out = to_json(design, objective)
    if balls is not None:
        out["balls"] = balls
    if choice is not None:
        out["chosen_balls"], out["balls_choice"] = choice["chosen"], choice
    (folder / "design.json").write_text(json.dumps(out, indent=1, allow_nan=False, default=_plain) + "\n")
    (folder / "report.md").write_text(report(design, command, objective, balls, choice))
    figure(design, folder / "design.png", scene)
    files = {"report": str(folder / "report.md"), "figure": str(folder / "design.png"),
             "json": str(folder / "design.json")}
    if design.verification_run_up is not None and design.verification_run_up["trace"]["t"]:
        run_up_figure(design, folder / RUN_UP_FIGURE)
        files["run_up_figure"] = str(folder / RUN_UP_FIGURE)
    return files
