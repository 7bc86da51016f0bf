"""The two-plane paper's periodic orbits and stability charts recomputed (issue 21 item 6): the criticality of
Fig. 14(a)'s Hopf point, Fig. 14(c, d)'s branch of limit cycles with its inset points, and the charts of
Figs. 10(a), 11, 13(a-d), 14(a, b), each beside the paper's description of it.

    section(out_dir) -> markdown      (figures and the charts' curves as data written into out_dir)

On the generated models through `adbgen.analysis.orbits` (charts: `orbits.charts.compute`); the paper's
parameter sets and ties are stated here, as the command line would give them (`--set`, `--tie`).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ....analysis.reproduction import markdown_section

from . import coverage
from .prose import render
from ..charts import CHARTS, ChartCase, ties  # noqa: F401  (the paper's charts as data; bench times them too)


def chart(case: ChartCase, out: Path, n1: int = 81, n2: int = 25, progress=print):
    from ....analysis.loading import load_model
    from ....analysis.orbits import charts
    from ....analysis.orbits.parameters import ParameterMap

    m = load_model(case.model)
    pmap = ParameterMap(m, m.params(case.sets), ["Omega", "epsilon"], case.ties)
    lam0 = (3.0, 1e-3)
    start = charts.chart_start(m, pmap, lam0)
    c = charts.compute(m, pmap, start, case.range1, case.range2, log2=True, n1=n1, n2=n2, lam1_0=lam0[0],
                       lam2_0=lam0[1])
    name = f"orbits_chart_{case.figure.replace('(', '').replace(')', '')}.png"
    charts.plot(c, out / name, title=f"Fig. {case.figure}: {case.model}, stable region shaded", scale2=case.scale2,
                label2=case.label2, timing=False)
    progress(f"Fig. {case.figure}: {len(c.curves)} curves, {c.wall_s:.0f} s")
    return c, name


def criticality(progress=print) -> list[dict]:
    """The boundary Hopf point of Fig. 14(a) (B losing stability as Omega falls) at eps/R + chi = 0.01 and 1e-4."""
    from ....analysis import equilibrium_scan
    from ....analysis.loading import load_model
    from ....analysis.orbits import hopf
    from ....analysis.orbits.equilibrium import carried_start
    from ....analysis.orbits.parameters import ParameterMap

    m = load_model("two_plane_rotating")
    rows = []
    for total in (0.01, 1e-4):
        eps = total / 2
        pm2 = ParameterMap(m, m.params({"beta": 1.0}), ["Omega", "epsilon"], ties(dynamic=True))
        y = carried_start(m, pm2((4.0, eps)), pm2)
        pm = ParameterMap(m, pm2((4.0, eps)), ["Omega"], ties(dynamic=True))
        sc = equilibrium_scan.scan(m, pm(4.0), y, "Omega", 4.0, 1.5)
        hp = hopf.HopfPoint.at(m, pm, sc.points[0].y, sc.points[0].value)
        rows.append({"total": total, "hopf": hp, "pm": pm})
        progress(f"Fig. 14(a) Hopf at eps/R + chi = {total:g}: Omega = {hp.lam:.8f}, l1 = {hp.l1:.5g} ({hp.criticality})")
    return rows


INSETS = [(3.386, 7.081, True), (3.127, 9.856, False), (2.475, 32.453, False)]


def vibration(model, t, Y, p) -> np.ndarray:
    """The paper's A along samples (times t, states on the rows of Y): the module's "A" measure."""
    from ....analysis.orbits import describe

    return describe.measure(model, "A", t, Y, p)


def fig14cd(hopf_row: dict, out: Path, max_points: int = 3000, progress=print) -> dict:
    """The cycles born at the marked Hopf point (eps/R + chi = 0.01), continued to long periods."""
    from ....analysis.loading import load_model
    from ....analysis.orbits import branches, continuer
    from ....analysis.orbits.flow import Flow
    from ....analysis.orbits.orbit import trace

    m = load_model("two_plane_rotating")
    t0 = time.perf_counter()
    br = branches.from_hopf(m, hopf_row["pm"], hopf_row["hopf"],
                            continuer.Settings(ds=0.01, ds_max=0.05, max_points=max_points, bounds=(1.5, 4.0)))
    wall = time.perf_counter() - t0
    flow = Flow(m)
    lam = np.array([o.p_value for o in br.orbits])
    T = np.array([o.period for o in br.orbits])
    st = np.array([o.stable for o in br.orbits])
    A = []
    for o in br.orbits:
        t, Y = trace(o, flow, 400)
        A.append(float(np.max(vibration(m, t, Y, o.p))))
    A = np.array(A)
    near = []
    for Om, Tp, stab in INSETS:
        d = np.hypot(lam - Om, (T - Tp) / Tp)
        i = int(np.argmin(d))
        near.append({"paper": (Om, Tp, stab), "ours": (float(lam[i]), float(T[i]), bool(st[i])), "index": i,
                     "distance": float(d[i])})
    _plot_14cd(m, br, lam, T, st, A, near, flow, out)
    progress(f"Fig. 14(c, d): {len(br.orbits)} orbits, {wall:.0f} s, {br.end}")
    return {"branch": br, "lam": lam, "T": T, "stable": st, "A": A, "near": near, "wall": wall}


def _plot_14cd(m, br, lam, T, st, A, near, flow, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ....analysis.orbits.orbit import trace

    fig = plt.figure(figsize=(10, 6.5), constrained_layout=True)
    gs = fig.add_gridspec(2, 3)
    ax_c = fig.add_subplot(gs[0, :2])
    ax_d = fig.add_subplot(gs[1, :2])
    zoom = lam > 3.2
    ax_c.plot(lam[zoom], A[zoom], "k-", lw=0.7)
    ax_c.plot(lam[zoom], np.where(st[zoom], A[zoom], np.nan), "k-", lw=2.5)
    ax_d.plot(lam, T, "k-", lw=0.7)
    ax_d.plot(lam, np.where(st, T, np.nan), "k-", lw=2.5)
    for s in br.specials:
        mk = {"torus": "*", "period-doubling": "D", "branch point": "s"}.get(s["kind"])
        if mk:
            ax_d.plot(s["Omega"], s["period"], mk, color="C3", ms=8)
            k = int(np.argmin(np.abs(lam - s["Omega"]) + np.abs(T - s["period"])))
            if zoom[k]:
                ax_c.plot(s["Omega"], A[k], mk, color="C3", ms=8)
    for j, nr in enumerate(near):
        Om, Tp, _ = nr["paper"]
        ax_d.plot(Om, Tp, "o", mfc="none", mec="C0", ms=10)
        ax_d.annotate("(" + "i" * (j + 1) + ")", (Om, Tp), textcoords="offset points", xytext=(6, 6), fontsize=8)
    ax_c.set_ylabel("A-bar")
    ax_c.set_title("(c) near the Hopf point: thick stable", fontsize=8)
    ax_d.set_xlabel("Omega")
    ax_d.set_ylabel("period T")
    ax_d.set_title("(d) the branch continued: * torus, D period-doubling, o the paper's insets", fontsize=8)
    # the insets' whirl orbits (rotating x-y plane of C) at the branch points nearest the paper's
    axes = [fig.add_subplot(gs[0, 2]), fig.add_subplot(gs[1, 2])]
    for j, nr in enumerate(near):
        o = br.orbits[nr["index"]]
        _, Y = trace(o, flow, 1500)
        ax = axes[0] if j == 0 else axes[1]
        ax.plot(Y[:, 0], Y[:, 1], lw=0.8, label="(" + "i" * (j + 1) + f") Omega {o.p_value:.3f}, T {o.period:.3f}")
    for ax in axes:
        inset_style(ax)
    fig.suptitle("Fig. 14(c, d): limit cycles from the Hopf point at eps/R + chi = 0.01 (two_plane_rotating)", fontsize=9)
    fig.savefig(out / "orbits_fig14cd.png", dpi=110)
    plt.close(fig)


def inset_style(ax) -> None:
    """An inset's whirl orbit: equal aspect, at most four x ticks in scientific notation on one offset (the
    x labels of inset (i), ~1e-3 wide, overlapped as plain decimals)."""
    from matplotlib.ticker import MaxNLocator

    ax.set_aspect("equal", "datalim")
    ax.legend(fontsize=6)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(MaxNLocator(4))
    ax.ticklabel_format(style="sci", scilimits=(-2, 2), useMathText=True)
    ax.tick_params(labelsize=7)


def section(out: Path, progress=print, n1: int = 81, n2: int = 25, max_points: int = 3000) -> str:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    crit = criticality(progress)
    f14 = fig14cd(crit[0], out, max_points, progress)
    br, stab = f14["branch"], f14["lam"][f14["stable"]]
    L = render(
        "orbits", criticality=[(f"{r['total']:g}", f"{r['hopf'].lam:.8f}", f"{r['hopf'].omega:.7f}",
                                f"{r['hopf'].l1:.5g}", r["hopf"].criticality) for r in crit],
        n_orbits=len(br.orbits), end=br.end,
        near=[{"paper": (str(nr["paper"][0]), str(nr["paper"][1]), nr["paper"][2]),
               "ours": (f"{nr['ours'][0]:.4f}", f"{nr['ours'][1]:.4f}", nr["ours"][2]),
               "distance": f"{nr['distance']:.1e}"} for nr in f14["near"]],
        stable=(f"{stab.min():.6f}", f"{stab.max():.6f}") if len(stab) else None,
        specials=[(s["kind"], f"{s['Omega']:.7f}", f"{s['period']:.5f}") for s in br.specials], n1=n1, n2=n2) + [""]
    done: dict = {}
    by_figure = {c.figure: c for c in CHARTS}
    for case in CHARTS:
        key = case.same_as or case.figure
        if key not in done:
            done[key] = chart(by_figure[key], out, n1, n2, progress)
        c, name = done[key]
        kinds = {}
        for cv in c.curves:
            kinds[cv.kind] = kinds.get(cv.kind, 0) + 1
        extra = (extra_curves(case, by_figure[EXTRA_CURVES[case.figure]], progress) if case.figure in EXTRA_CURVES
                 else None)
        lim = (limit(case, progress=progress) if case.figure in ("10(a)", "10(c)", "11", "13(b)") else None)
        L += render("chart", figure=case.figure, text=case.text, model=case.model, note=case.note, ties=case.ties,
                    curves=[(v, k) for k, v in kinds.items()], summary=chart_summary(c, case), extra=extra,
                    image=name, limit=lim) + [""]
    # wall times go to the progress lines (`adbgen bench reproduce` records them), never into the document,
    # which must come out byte-identical from run to run
    progress(f"two-plane orbits section: {time.perf_counter() - t0:.0f} s")
    return "\n".join(L)


# The charts whose text says "extra curves are present" against the symmetric chart they are compared with:
# the chart traces B's stability boundary only, so the extra Hopf (torus) curves, where B is already unstable,
# are counted along rows by one-parameter scans (`hopf_rows`).
EXTRA_CURVES = {"10(b)": "10(a)", "13(c)": "13(a)"}
HOPF_ROWS = (1e-4, 1e-3, 1e-2, 0.1)  # eps/R of the rows scanned


def hopf_rows(case: ChartCase, epsilons=HOPF_ROWS, progress=print) -> dict:
    """Every Hopf point of B (the chart's state, `charts.chart_start`) along Omega from the range's top down
    at each eps/R of `epsilons`, B stable or not (`equilibrium_scan.scan`): {eps: [(Omega, changes B's stability),
    ...]}."""
    from ....analysis import equilibrium_scan
    from ....analysis.loading import load_model
    from ....analysis.orbits import charts
    from ....analysis.orbits.parameters import ParameterMap

    m = load_model(case.model)
    pm2 = ParameterMap(m, m.params(case.sets), ["Omega", "epsilon"], case.ties)
    top, bottom = case.range1[1], case.range1[0]
    out = {}
    for eps in epsilons:
        start = charts.chart_start(m, pm2, (top, eps))
        pm = ParameterMap(m, pm2((top, eps)), ["Omega"], case.ties)
        sc = equilibrium_scan.scan(m, pm(top), start, "Omega", top, bottom)
        out[eps] = [(b.value, (b.n_unstable_before == 0) != (b.n_unstable_after == 0)) for b in sc.points
                    if b.kind == "hopf"]
    progress(f"Fig. {case.figure} Hopf points along rows: " + "; ".join(f"{e:g}: {len(v)}" for e, v in out.items()))
    return out


def extra_curves(case: ChartCase, control: ChartCase, progress=print) -> dict:
    """The paper's "extra curves" of `case` against the symmetric `control`: Hopf points of B along rows, as
    prose/chart.md.j2 shows them."""
    ours = hopf_rows(case, progress=progress)  # the rows at the same m/M (the axis: eps/R times scale2)
    theirs = dict(zip(ours, hopf_rows(control, [e * case.scale2 / control.scale2 for e in ours], progress).values()))
    cell = lambda pts: f"{len(pts)}: " + ", ".join(f"{w:.4f}" + ("*" if ch else "") for w, ch in pts)  # noqa: E731
    changes = lambda d: sum(ch for pts in d.values() for _, ch in pts)  # noqa: E731
    return {"top": f"{case.range1[1]:g}", "bottom": f"{case.range1[0]:g}", "control": control.figure,
            "changes_control": changes(theirs), "changes": changes(ours),
            "rows": [(f"{e * case.scale2:g}", cell(theirs[e]), cell(ours[e])) for e in ours],
            "extra": [f"{e * case.scale2:g}" for e in ours if len(ours[e]) > len(theirs[e])]}


def _runs(x: np.ndarray, mask: np.ndarray) -> list[tuple[float, float]]:
    """The stretches of x where mask holds (first and last grid point of each)."""
    out, start = [], None
    for i, ok in enumerate(mask):
        if ok and start is None:
            start = i
        if not ok and start is not None:
            out.append((float(x[start]), float(x[i - 1])))
            start = None
    if start is not None:
        out.append((float(x[start]), float(x[-1])))
    return out


def limit(case: ChartCase, epsilons=(1e-6, 1e-7, 1e-8), progress=print) -> list[tuple[float, list]]:
    """Where B's stability changes along Omega (from the range's top down) at imbalances below the chart's:
    the values the curves tend to as eps/R = m/M -> 0 (the paper: the critical speeds).  A steady state's Hopf
    points and folds (autonomous model), or the torus and period-doubling points of the forced response."""
    from ....analysis import equilibrium_scan
    from ....analysis.loading import load_model
    from ....analysis.orbits import branches, charts, continuer
    from ....analysis.orbits.parameters import ParameterMap

    m = load_model(case.model)
    pm2 = ParameterMap(m, m.params(case.sets), ["Omega", "epsilon"], case.ties)
    top, bottom = case.range1[1], case.range1[0]
    out = []
    for eps in epsilons:
        start = charts.chart_start(m, pm2, (top, eps))
        pm = ParameterMap(m, pm2((top, eps)), ["Omega"], case.ties)
        if m.autonomous:
            sc = equilibrium_scan.scan(m, pm(top), start, "Omega", top, bottom)
            # a change of stability only: stable on one side, unstable on the other (a Hopf point of a state
            # unstable on both sides is a bifurcation of an unstable state)
            out.append((eps, [(b.kind, b.value) for b in sc.points
                              if (b.n_unstable_before == 0) != (b.n_unstable_after == 0)]))
        else:
            br = branches.from_orbit(m, pm, start, -1.0, continuer.Settings(ds=0.02, ds_max=0.05, max_points=2000,
                                                                             bounds=(bottom, top)), amplitude=False)
            out.append((eps, [(sp["kind"], sp["Omega"]) for sp in br.specials if sp.get("stability_change")]))
        progress(f"Fig. {case.figure} limit eps = {eps:g}: " + ", ".join(f"{k} {v:.5f}" for k, v in out[-1][1]))
    return out


def chart_summary(c, case: ChartCase) -> dict:
    """Where the grid found B stable at the smallest and the largest eccentricity row (a certified row: its
    windows' located ends), what is certified, and the curves' lowest points (what the curves asymptote to as the
    imbalance vanishes), as prose/chart.md.j2 says them."""
    rows = c.windows("rows")
    out = []
    for i, what in ((0, "smallest"), (len(c.lam2) - 1, "largest")):
        runs, digits, empty = (rows[i], 4, "no window") if i in rows else (_runs(c.lam1, c.stable[i] == 1), 2,
                                                                          "no grid point")
        out.append({"what": what, "imbalance": f"{c.lam2[i] * case.scale2:.1e}",
                    "windows": ", ".join(f"[{a:.{digits}f}, {b:.{digits}f}]" for a, b in runs) or empty})
    cert = c.to_json(False)["resolution"].get("certified")
    lows = sorted(pt[0] for cv in c.curves for pt in [min(cv.points, key=lambda q: q[1])] if pt[1] <= 1.01 * c.lam2[0])
    return {"found": int((c.stable >= 0).sum()), "size": c.stable.size, "stable": int((c.stable == 1).sum()),
            "missing": int((c.stable == -1).sum()), "absent": int((c.stable == -2).sum()), "rows": out,
            "certified": (f"{cert['Omega']:.4f}", f"{cert['epsilon']:.4f}") if cert and cert["refined"] else None,
            "lows": [f"{v:.3f}" for v in lows]}


REPRODUCTION = markdown_section("two-plane-orbits", "Two-plane paper: periodic orbits and stability charts (issue 21)",
                                section, coverage.ORBITS)
