"""What `adbgen continue` gains for periodic orbits (the command and its options: adbgen/cli/stability.py, cli/orbit.py).

    adbgen continue MODEL --par NAME [--orbits | --from-hopf VALUE] [--tie NAME=EXPR]... [--y0 NAME=VALUE]...
                    [--max-points N] [--auto-orbits] [--plot FILE] ...

* every Hopf point of the one-parameter run gets `first_lyapunov` and `criticality` ("supercritical" |
  "subcritical") in `points` (exact second and third derivatives: `lyapunov`, `jets`);
* `--orbits`: the cycles born at every Hopf point (`--from-hopf VALUE`: at the one nearest VALUE) are
  continued by Newton shooting on the compiled variational equations (`branches`): JSON `orbits` (one
  object per branch: arrays `parameter`, `period`, `stable`, `amplitude`, and `from`, `windings`, `end`)
  and `orbit_points` ({kind: "fold" | "period-doubling" | "torus", NAME, period, multipliers, branch});
  `--auto-orbits` adds `auto_orbits`, the same branches by AUTO-07p's collocation (IPS = 2 from the HB
  labels), for comparison;
* a periodically forced model (fixed frame) has no steady state: its forced response, the periodic
  orbit at the forcing period (a balanced state is one, with the rotor at rest), is
  continued from START (or --y0) recomputed at the --set parameters, its torus and period-doubling
  points in `orbit_points`;
* `--tie NAME=EXPR` keeps a parameter tied to others along every branch (m/M = eps/R in the paper's
  charts); `--plot FILE` draws the branches (amplitude and period against the parameter, stable solid).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from ..loading import AnalysisError, parse_value
from ..units import assignments, quantity, units
from .equilibrium import carried_start  # noqa: F401  (the command's start along ties)


def parse_range2(text: str | None):
    """--range2 LO:HI -> (lo, hi) with lo < hi (None: not given)."""
    if text is None:
        return None
    lo, sep, hi = text.partition(":")
    if not sep:
        raise AnalysisError(f"--range2: expected LO:HI, got {text!r}")
    out = (parse_value(lo, "--range2 LO"), parse_value(hi, "--range2 HI"))
    if not out[0] < out[1]:
        raise AnalysisError(f"--range2: LO must be below HI, got {text!r}")
    return out


def wants_orbits(args) -> bool:
    return bool(args.orbits or args.from_hopf is not None)


def wants_chart(args) -> bool:
    """--par2 on our own continuation (a chart) rather than AUTO-07p's Hopf and fold curves: with ties, a
    plot, a log scale or a grid asked for."""
    return args.par2 is not None and bool(args.tie or args.plot or args.log2 or args.grid)


def pmap_for(model, p, names, args):
    from .parameters import ParameterMap

    return ParameterMap(model, p, [n for n in names if n is not None], ties=args.tie)


def add_lyapunov(model, points: list[dict], name: str, p: np.ndarray, follower, args) -> None:
    """first_lyapunov, criticality at each HB point of AUTO's run (its state refined at its parameter)."""
    from .first_lyapunov import criticality, first_lyapunov

    k = model.param_names.index(name)
    for row in points:
        if row.get("type") != "HB" or "state" not in row:
            continue
        q = p.copy()
        q[k] = row[name]
        try:
            y = follower(q, np.array([row["state"][s] for s in model.state_names]))
            l1, _ = first_lyapunov(model, q, y, row.get("frequency"))
        except AnalysisError:
            continue
        row["first_lyapunov"] = l1
        row["criticality"] = criticality(l1)


def add_margins(model, points: list[dict], name: str, p: np.ndarray) -> None:
    """margin, margin_uncertainty, marginal (`steady.margin_at`, issue 34 item 5) at each point of AUTO's run
    that carries its state: AUTO's own "stability" is a sign; this says how far from zero, and whether the
    computation can certify it."""
    from .. import steady

    k = model.param_names.index(name)
    for row in points:
        if "state" not in row:
            continue
        q = np.array(p, float)
        q[k] = row[name]
        try:
            row.update(steady.margin_at(model, q, np.array([row["state"][s] for s in model.state_names])).to_json())
        except (AnalysisError, np.linalg.LinAlgError):
            continue


def refine_hopf(model, pmap, y, lam, omega, follower):
    """The Hopf point near (y, lam): lam by Brent's method on the real part of the pair nearest i omega,
    the equilibrium re-solved at each trial (`follower(p, guess)`)."""
    from scipy.optimize import brentq

    from .hopf import HopfPoint
    from .first_lyapunov import hopf_vectors

    state = {"y": np.array(y, float)}

    def g(v):
        state["y"] = follower(pmap(v), state["y"])
        A = np.asarray(model.module.jac(0.0, state["y"], pmap(v)))
        return float(hopf_vectors(A, omega)[0].real)
    d = 1e-6 * max(1.0, abs(lam))
    a, b = lam - d, lam + d
    try:
        ga, gb = g(a), g(b)
        for _ in range(8):
            if ga * gb < 0:
                break
            d *= 4
            a, b = lam - d, lam + d
            ga, gb = g(a), g(b)
        lam = brentq(g, a, b, xtol=1e-13, rtol=4e-16) if ga * gb < 0 else lam
        g(lam)
    except (AnalysisError, ValueError):
        pass
    return HopfPoint.at(model, pmap, state["y"], lam, omega)


def orbit_settings(args, lam0: float, to: float | None):
    from .continuer import Settings

    if args.max_points < 2:
        raise AnalysisError(f"--max-points must be >= 2, got {args.max_points}")
    lo, hi = (min(lam0, to), max(lam0, to)) if to is not None else (-math.inf, math.inf)
    return Settings(ds=0.01, ds_max=0.05, max_points=args.max_points, bounds=(lo, hi))


def continue_orbits(model, args, p, points: list[dict], name: str, to: float | None, follower) -> dict:
    """`orbits` and `orbit_points` from the Hopf points of the one-parameter run (autonomous model)."""
    from . import branches

    pmap = pmap_for(model, p, [name], args)
    start = float(p[pmap.index[0]])
    hb = [row for row in points if row.get("type") == "HB" and "state" in row]
    if args.from_hopf is not None:
        value = parse_value(args.from_hopf, "--from-hopf")
        if not hb:
            raise AnalysisError(f"--from-hopf {value:g}: the run found no Hopf point")
        hb = [min(hb, key=lambda row: abs(row[name] - value))]
    out_branches, out_points = [], []
    for row in hb:
        y = np.array([row["state"][s] for s in model.state_names])
        hp = refine_hopf(model, pmap, y, row[name], row.get("frequency"), follower)
        br = branches.from_hopf(model, pmap, hp, orbit_settings(args, start, to), to=to)
        out_points += br.points_json(len(out_branches))
        out_branches.append(br)
    result = {"orbits": [b.to_json() for b in out_branches], "orbit_points": out_points}
    if args.auto_orbits:
        from .auto_cycles import auto_branches

        result["auto_orbits"] = auto_branches(model, name, p, [row[name] for row in hb], to, args)
    return result, out_branches


def forced_start(model, args, p):
    """The start of a forced model's response at p, refined by Newton shooting: --y0, else START, else the
    first of the module's labelled steady states (STEADY_STATES: a constant solution of the forced model, such
    as B with the rotor at rest) that exists at p."""
    from .orbit import refine

    y0 = None
    if args.y0:
        y0 = model.state(assignments(args.y0, "--y0", units(model).states))
    elif getattr(model.module, "START", None) is not None:
        y0 = np.array(model.module.START, float)
    elif hasattr(model.module, "steady_state"):
        for label in getattr(model.module, "STEADY_STATES", ()):
            y = model.module.steady_state(label, p)
            if y is not None:
                y0 = np.array(y, float)
                break
    if y0 is None:
        raise AnalysisError(f"{model.name} has no START (nor a labelled steady state at these parameters); give the "
                            f"start of its forced response with --y0 NAME=VALUE")
    return refine(model, p, y0, None)


def run_forced(args, model, emit) -> int:
    """`adbgen continue` on a periodically forced model: its forced response continued in --par (and, with
    --par2, its torus and period-doubling curves)."""
    from . import branches

    if not (wants_orbits(args) or args.par2 is not None):
        raise AnalysisError(f"{model.name} is periodically forced: it has periodic orbits, not steady states; continue "
                            f"its forced response with --orbits (or --par2 for its torus and period-doubling curves)")
    values = assignments(args.set, "--set", units(model).params)
    p = model.params({**_start_parameters(model), **values})
    for name in (args.par, args.par2):
        if name is not None and name not in model.param_names:
            raise AnalysisError(f"{name!r} is not a parameter of {model.name}; parameters: {', '.join(model.param_names)}")
    pmap = pmap_for(model, p, [args.par], args)
    p = pmap(p[pmap.index[0]])
    k = model.param_names.index(args.par)
    to = quantity(args.to, units(model).params[args.par], "--to") if args.to is not None else \
        (0.5 * p[k] if p[k] > 0 else p[k] - 1.0)
    if to == p[k]:
        raise AnalysisError(f"--to must differ from the start value {args.par} = {p[k]:g}")
    start = forced_start(model, args, p)
    from ..identify import identify

    # what the branch starts on: a labelled steady state (a constant solution, e.g. balanced with the rotor at
    # rest) or an unlabelled periodic response (issue 34 item 4)
    followed = identify(model, start.y, p).to_json()
    if args.par2 is not None:
        return chart_command(args, model, p, start, lambda out: emit({**out, **followed}))
    br = branches.from_orbit(model, pmap, start, 1.0 if to > p[k] else -1.0, orbit_settings(args, float(p[k]), to), to=to)
    out = {"model": model.name, "parameter": args.par, "ties": list(args.tie), "points": [],
           "orbits": [br.to_json()], "orbit_points": br.points_json(0), **followed}
    if args.plot:
        plot_branches(Path(args.plot), model, args.par, [br])
    emit(out)
    return 0


def _start_parameters(model) -> dict:
    sp = getattr(model.module, "START_PARAMETERS", None)
    return {} if sp is None else dict(zip(model.param_names, map(float, sp)))


def plot_branches(path: Path, model, name: str, branches_) -> None:
    """Amplitude and period against the parameter: stable solid, unstable thin, special points marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, constrained_layout=True)
    marks = {"torus": ("*", "C3"), "period-doubling": ("D", "C2"), "fold": ("s", "C1")}
    for i, br in enumerate(branches_):
        j = br.to_json()
        lam, amp, per, st = (np.array(j[k]) for k in ("parameter", "amplitude", "period", "stable"))
        if len(lam) == 0:
            continue
        for ax, v in ((a1, amp), (a2, per)):
            ax.plot(lam, v, "-", color=f"C{i % 10}", lw=0.7)
            ax.plot(lam, np.where(st, v, np.nan), "-", color=f"C{i % 10}", lw=2.2)
        for sp in br.specials:
            mk, c = marks.get(sp["kind"], ("o", "k"))
            k = int(np.argmin(np.abs(lam - sp[name])))
            a1.plot(sp[name], amp[k], mk, color=c, ms=8)
            a2.plot(sp[name], sp["period"], mk, color=c, ms=8)
    a1.set_ylabel("amplitude r_max")
    a2.set_ylabel("period T")
    a2.set_xlabel(name)
    a1.set_title(f"{model.name}: periodic orbits (thick stable; * torus, D period-doubling, s fold)", fontsize=9)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name("." + path.name + ".tmp")
    fig.savefig(tmp, dpi=120, format=path.suffix.lstrip(".") or "png")
    plt.close(fig)
    os.replace(tmp, path)


def chart_command(args, model, p, start, emit) -> int:
    """`adbgen continue MODEL --par NAME --par2 NAME2 [--tie ...] [--range2 LO:HI] [--log2] [--plot FILE]` on our
    own continuation (forced models; autonomous ones with --tie, --plot or --log2)."""
    from .charts import compute, plot
    from .parameters import ParameterMap

    pmap = ParameterMap(model, p, [args.par, args.par2], ties=args.tie)
    k1, k2 = pmap.index
    v1, v2 = float(p[k1]), float(p[k2])
    to = quantity(args.to, units(model).params[args.par], "--to") if args.to is not None else None
    range1 = (min(v1, to), max(v1, to)) if to is not None else (0.5 * v1, 1.5 * v1)
    range2 = parse_range2(args.range2) or ((0.1 * v2, 10 * v2) if v2 > 0 else (v2 - 1.0, v2 + 1.0))
    log2 = bool(getattr(args, "log2", False))
    n1, n2 = 81, 25
    if getattr(args, "grid", None):
        a, sep, b = args.grid.partition(":")
        try:
            n1, n2 = int(a), int(b)
        except ValueError:
            raise AnalysisError(f"--grid: expected N1:N2 (whole numbers), got {args.grid!r}") from None
        if not sep or n1 < 3 or n2 < 2:
            raise AnalysisError(f"--grid: expected N1:N2 with N1 >= 3 and N2 >= 2, got {args.grid!r}")
    chart = compute(model, pmap, start, range1, range2, log2=log2, n1=n1, n2=n2)
    if args.plot:
        plot(chart, Path(args.plot))
    emit(chart.to_json())
    return 0
