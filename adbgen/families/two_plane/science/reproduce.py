"""`adbgen reproduce`, the two-plane paper (Rodrigues et al. 2011): section 3.2.3 (B/C3 exchange),
Figure 12(a) (brute-force diagram, anisotropic supports) and section 6 (run-ups, Figures 15, 16).

`compute(fig_dir)` runs everything and draws the figures; `section(results, root)` writes the
markdown (`REPRODUCTION`, listed by the family's `reproductions()`).  The computations are in
`exchange` and `runs`.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from ....analysis.reproduction import Reproduction
from . import coverage
from . import exchange as tx
from .prose import render
from . import runs as tr

FIG12_GRID = (0.2, 5.0, 97)  # Omega from, to, count (step 0.05)
FIG12B_GRID = (0.2, 5.0, 49)  # Figure 12(b): step 0.1
FIG12_TRANSIENT = 4000.0
FLOQUET_GRID = (0.2, 5.0, 49)  # step 0.1, boundaries then refined
RUNUPS = (("Figure 15", "two_plane_ramp", 6000.0), ("Figure 16", "two_plane_hill", 3000.0))
PUBLISHED_11 = (1.0, 1.81)  # (11): Omega_cyl = 1, Omega_con ~ 1.81 (plain rotor, set-up (10))


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(fig, path: Path) -> Path:
    fig.savefig(path, dpi=110)
    _plt().close(fig)
    return path


def _axes_over_omega(ax, ylabel: str, title: str, legend_size: int) -> None:
    ax.set_xlabel(r"$\Omega$")
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=legend_size)
    ax.set_title(title, fontsize=8)


def _rel(ours, pub):
    return (ours - pub) / pub


def kappa_panel(ax, w, k) -> None:
    """kappa(Omega) of section 3.2.3 drawn whole: a symmetric-log axis (linear within |kappa| <= 1), so that the
    pole at Omega_2 and the values beyond +-4 are drawn at their size, not clipped; kappa > 0 shaded."""
    w, k = np.asarray(w, float), np.asarray(k, float)
    ax.plot(w, k, "k.", ms=3, label=r"$\kappa = (a_1 - a_2)/(a_1 + a_2)$, full model's branches")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.fill_between(w, 0, 1, where=k > 0, color="0.85", step="mid", transform=ax.get_xaxis_transform(),
                    label=r"$a_1 > a_2$: B stable, C3 unstable for $m$ just above $m_c$ (37)-(38)")
    ax.set_yscale("symlog", linthresh=1.0)
    top = float(np.nanmax(np.abs(k))) if k.size else 1.0
    ax.set_ylim(-1.5 * top, 1.5 * top)
    ax.set_ylabel(r"$\kappa$ (symmetric log)")


def exchange(fig_dir: Path) -> dict:
    omegas = np.linspace(0.5, 3.0, 101)
    ex = tx.compute(omegas=omegas)
    plt = _plt()
    fig, (a, b) = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True, constrained_layout=True)
    w = np.array(list(ex.curve))
    k = np.array(list(ex.curve.values()))
    kappa_panel(a, w, k)
    for v, ls in zip((ex.omega_1, ex.omega_2), ("-", "-")):
        a.axvline(v, color="C3", lw=0.8, ls=ls)
        b.axvline(v, color="C3", lw=0.8, ls=ls)
    for v in PUBLISHED_11:
        a.axvline(v, color="C0", lw=0.8, ls="--")
    a.legend(fontsize=7, loc="lower right")
    a.set_title(r"paper 3.2.3, set-up (10): $\epsilon/R$ = 0.01, $c$ = 0 at $m = m_c$; red: ours "
                r"($\Omega_1$, $\Omega_2$), blue dashed: (11) 1, 1.81", fontsize=8)
    even = np.array([ex.slow[x]["even"].real for x in w])
    odd = np.array([ex.slow[x]["odd"].real for x in w])
    b.plot(w, even, "C0.-", ms=3, lw=0.6, label="symmetric mode (1, 1) of B (gamma_r-even)")
    b.plot(w, odd, "C1.-", ms=3, lw=0.6, label="mode (1, -1) of B towards C3 (gamma_r-odd)")
    b.axhline(0, color="0.6", lw=0.6)
    b.set_ylim(-0.012, 0.025)
    _axes_over_omega(b, r"Re $\lambda$ (slowest)", r"full damped model (10), B at $m = m_c(1 + 10^{-3})$, "
                     "$\\bar c_b$ = 0.01:\nslowest eigenvalue of each symmetry class", 7)
    path = _save(fig, fig_dir / "two_plane_exchange.png")
    return {"ex": ex, "figure": path, "even": dict(zip(w, even)), "odd": dict(zip(w, odd))}


FIG5A_MASS = (1e-5, 40.0, 400)  # (m - m_c)/m_c from, to, count (logarithmic) for Figure 5(a)


def figure_5a(Omega: float = 3.0) -> dict:
    """Figure 5(a): the balanced state B of set-up (10) (static imbalance eps/R = 0.01, damped) as the ball mass
    grows from m_c at Omega = 3: its spectrum from the generated Jacobian at the exact B (rotor at rest, the
    balls at pi +- arccos(m_c/m)), the changes of stability located on a logarithmic grid of m and refined by
    brentq on the largest real part; each change's pair (a Hopf point when the crossing pair is complex)."""
    from scipy.optimize import brentq

    from ....analysis.loading import load_model

    model = load_model("two_plane_rotating")
    pf = tx.Pitchfork(model, {"Omega": Omega})
    mc = pf.m_c

    def spectrum(m):
        a = math.acos(mc / m)
        ev = np.linalg.eigvals(np.asarray(model.module.jac(0.0, pf.state([math.pi + a, math.pi - a] * 2),
                                                            pf.params(m))))
        return ev

    growth = lambda m: float(spectrum(m).real.max())  # noqa: E731
    ms = mc * (1 + np.geomspace(*FIG5A_MASS[:2], FIG5A_MASS[2]))
    g = [growth(m) for m in ms]
    points = []
    for i in range(len(ms) - 1):
        if (g[i] < 0) != (g[i + 1] < 0):
            m = brentq(growth, ms[i], ms[i + 1], xtol=1e-14, rtol=1e-12)
            ev = spectrum(m)
            lam = ev[np.argmax(ev.real)]
            points.append({"m": m, "frequency": abs(lam.imag), "stable_after": g[i + 1] < 0})
    return {"m_c": mc, "stable_at_pitchfork": g[0] < 0, "points": points, "m_max": float(ms[-1])}


FIG12_CAP = 128000.0  # the longest transient a point of Figure 12 is carried on to (FIG12_TRANSIENT doubled)


def balanced_by(A_bar) -> np.ndarray:
    """The brute force's verdict: the balancer balances where A_bar < 1e-3 eps/R (eps/R = m/M = 1e-4)."""
    return np.asarray(A_bar) < 1e-3 * tr.FIG12_EPS


def settle(omegas, first, second, rerun, stable=None, t_first: float = FIG12_TRANSIENT,
           cap: float = FIG12_CAP) -> list[dict]:
    """Each Omega's converged verdict of the brute force: A_bar after the transient t_first (`first`) and after
    2 t_first (`second`); a point whose verdict changes between them, or (where `stable(Omega)`, B's Floquet
    stability, is given) disagrees with B's stability, is carried on, `rerun(omegas, t)` -> A_bar at the
    transient doubled, until two successive transients agree (and agree with `stable`) or the transient reaches
    `cap`.  Per point: Omega, balanced, A_bar, the transient of the verdict, `settled` (False: still changing
    or against B's stability at the cap) and the verdict at t_first."""
    out, pending = [], []
    for i, w in enumerate(omegas):
        a, b = bool(balanced_by(first[i])), bool(balanced_by(second[i]))
        out.append({"Omega": float(w), "balanced": b, "A_bar": float(second[i]), "t": 2 * t_first, "settled": True,
                    "first": a})
        if a != b or (stable is not None and b != stable(float(w))):
            pending.append(i)
    t = 2 * t_first
    while pending and t < cap:
        t *= 2
        again = rerun([float(omegas[i]) for i in pending], t)
        still = []
        for i, A in zip(pending, again):
            v = bool(balanced_by(A))
            agree = v == out[i]["balanced"] and (stable is None or v == stable(out[i]["Omega"]))
            out[i].update(balanced=v, A_bar=float(A), t=t)
            if not agree:
                still.append(i)
        pending = still
    for i in pending:
        out[i]["settled"] = False
    return out


FIG12A_TITLE = ("paper Fig. 12(a): supports (43), static imbalance\n"
                r"$\epsilon/R = m/M = 10^{-4}$, $\chi$ = 0, $\bar c_b$ = 0.01")
FIG12B_TITLE = ("paper Fig. 12(b): supports (43), dynamic imbalance\n"
                r"$\epsilon/R = \chi = 5\times10^{-5}$, $\beta$ = 1, $m/M = 10^{-4}$, $\bar c_b$ = 0.01")


def brute_force_figure(omegas, plain, abb, bands, band_label: str, title: str, step: float):
    """A brute-force diagram of Figure 12: A_bar of the plain rotor (grey) and of the ABB at its converged
    transient (black) over Omega, B's Floquet-stable windows shaded; the title on two lines (one line was cut)."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.4, 3.8), constrained_layout=True)
    for k, (a, b) in enumerate(bands):
        ax.axvspan(a, b, color="C2", alpha=0.15, lw=0, label=band_label if k == 0 else None)
    ax.semilogy(omegas, plain, color="0.6", lw=1.5, label="plain rotor")
    ax.semilogy(omegas, np.maximum(np.asarray(abb, float), 1e-14), "k.-", lw=0.8, ms=3,
                label="ABB (converged transient)")
    _axes_over_omega(ax, r"$\bar A$", f"{title} (grid step {step:g})", 8)
    return fig


def figure_12a(fig_dir: Path) -> dict:
    from scipy.optimize import minimize_scalar

    t0 = time.time()
    omegas = np.linspace(*FIG12_GRID[:2], FIG12_GRID[2])
    res = tr.figure_12a(omegas, t_transient=FIG12_TRANSIENT)
    abb = np.array([o.A_bar for o in res["abb"]])
    plain = np.array([o.A_bar for o in res["plain"]])
    model = res["model"]
    values = {"epsilon": tr.FIG12_EPS, "chi": 0.0, "beta": 0.0, **tr._ball_values(tr.PLAIN_MASS, tr.FIG12_RATIO)}
    refined = []
    for peak in tr.peaks(omegas, plain):
        h = omegas[1] - omegas[0]
        r = minimize_scalar(lambda w: -tr.settled_vibration(model, values, w, 2000.0).A_bar,
                            bounds=(peak - h, peak + h), method="bounded", options={"xatol": 1e-5})
        refined.append((peak, float(r.x)))
    limit = tr.plain_limit()

    def rerun(dynamic):
        return lambda ws, t: [o.A_bar for o in tr.figure_12a(ws, t_transient=t, with_plain=False, dynamic=dynamic)["abb"]]

    longer = tr.figure_12a(omegas, t_transient=2 * FIG12_TRANSIENT, with_plain=False)  # the transient doubled
    points = settle(omegas, abb, [o.A_bar for o in longer["abb"]], rerun(False))
    balanced = np.array([q["balanced"] for q in points])
    abb_conv = np.array([q["A_bar"] for q in points])
    floq = floquet_section(omegas, balanced)
    dyn_omegas = np.linspace(*FIG12B_GRID[:2], FIG12B_GRID[2])
    dyn = tr.figure_12a(dyn_omegas, dynamic=True)
    dyn_abb = np.array([o.A_bar for o in dyn["abb"]])
    dyn_plain = np.array([o.A_bar for o in dyn["plain"]])
    dyn_floq = floquet_section(dyn_omegas, np.zeros(len(dyn_omegas), bool), dynamic=True)
    dyn_stable = lambda w: any(a <= w <= b for a, b in dyn_floq["stable"])  # noqa: E731
    dyn_longer = tr.figure_12a(dyn_omegas, t_transient=2 * FIG12_TRANSIENT, with_plain=False, dynamic=True)
    dyn_points = settle(dyn_omegas, dyn_abb, [o.A_bar for o in dyn_longer["abb"]], rerun(True), stable=dyn_stable)
    dyn_bal = np.array([q["balanced"] for q in dyn_points])
    fig = brute_force_figure(omegas, plain, abb_conv, floq["stable"], "B stable (Floquet)", FIG12A_TITLE, 0.05)
    path = _save(fig, fig_dir / "two_plane_fig12a.png")
    fig = brute_force_figure(dyn_omegas, dyn_plain, [q["A_bar"] for q in dyn_points], dyn_floq["stable"],
                             "B stable (Floquet, dynamic imbalance)", FIG12B_TITLE, 0.1)
    path_b = _save(fig, fig_dir / "two_plane_fig12b.png")
    intervals = _intervals(omegas, balanced)
    worse = [(w, a / p) for w, a, p, ok in zip(omegas, abb_conv, plain, balanced) if not ok]
    return {"omegas": omegas, "abb": abb_conv, "plain": plain, "peaks": refined, "limit": limit, "figure": path,
            "intervals": intervals, "wall": time.time() - t0, "floquet": floq, "points": points,
            "first_intervals": _intervals(omegas, balanced_by(abb)),
            "worst_ratio": max(worse, key=lambda x: x[1]) if worse else None,
            "drift": np.array([o.drift for o in res["abb"]]),
            "figure_b": path_b, "dyn_omegas": dyn_omegas, "dyn_abb": dyn_abb, "dyn_plain": dyn_plain,
            "dyn_points": dyn_points, "dyn_floquet": dyn_floq, "dyn_first_intervals": _intervals(dyn_omegas, balanced_by(dyn_abb)),
            "dyn_intervals": _intervals(dyn_omegas, dyn_bal)}


def _intervals(omegas, ok) -> list[tuple[float, float]]:
    out, start, prev = [], None, None
    for w, good in zip(omegas, ok):
        if good and start is None:
            start = w
        if not good and start is not None:
            out.append((float(start), float(prev)))
            start = None
        prev = w
    if start is not None:
        out.append((float(start), float(omegas[-1])))
    return out


RUN_RTOLS = (1e-7, 1e-9, 1e-11)
PHASES = tuple(k * math.pi / 8 for k in range(8))  # where the opposite pairs start (Figure 16(d) study)  # tolerance study of the run-ups; the last is "converged"


def runup_metrics(runs: dict) -> dict:
    """The numbers the run-up table compares, from {(model, ratio): RunUp} (plain rotor: ratio None)."""
    r15a, r15b = runs["two_plane_ramp", 0.01], runs["two_plane_ramp", 0.1]
    r16a, r16b, plain = runs["two_plane_hill", 0.01], runs["two_plane_hill", 0.1], runs["two_plane_hill", None]
    late = r16a.t > 300
    crit = lambda r: r.A[r.t <= 300]  # noqa: E731  (the passage through the critical speeds)
    return {"stall_15a": stall_speed(r15a), "stall_15b": stall_speed(r15b), "stalls_15a": stalls(r15a),
            "stalls_15b": stalls(r15b),
            "sync_15a": tr.synchronised_from(r15a), "sync_15b": tr.synchronised_from(r15b),
            "end_min_15a": float(np.min(r15a.end_speeds)), "end_A_15b": float(r15b.A[-1]),
            "sync_16a": tr.synchronised_from(r16a), "sync_16b": tr.synchronised_from(r16b),
            "end_A_16a": float(r16a.A[-1]), "end_A_16b": float(r16b.A[-1]),
            "burst_16a": float(r16a.t[late][np.argmax(r16a.A[late])]),
            "crit_16a": float(crit(r16a).max()), "crit_16b": float(crit(r16b).max()),
            "crit_plain": float(crit(plain).max()),
            "t_plain_peak": float(plain.t[plain.t <= 300][np.argmax(crit(plain))]),
            "t_con": float(np.interp(PUBLISHED_11[1], r16a.spin, r16a.t)),
            "ratio_16a": float(crit(r16a).max() / crit(plain).max()),
            "ratio_16b": float(crit(r16b).max() / crit(plain).max())}


def _all_runs(rtol: float) -> dict:
    runs = {}
    for _, name, t_end in RUNUPS:
        for ratio in tr.RATIOS:
            runs[name, ratio] = tr.run_up(name, ratio, t_end, rtol=rtol)
        runs[name, None] = tr.run_up(name, tr.RATIOS[1], t_end, m=tr.PLAIN_MASS, rtol=rtol)
    return runs


def floquet_section(omegas, balanced, dynamic: bool = False) -> dict:
    """B's stability along the section (the paper's Figure 11 through Figure 12(a); `dynamic`: the dynamic
    imbalance of Figure 12(b), eps/R = chi = 5e-5, beta = 1): Floquet multipliers on FLOQUET_GRID, each change
    of stability refined by brentq on log max|mu| (xtol 1e-4); and, at the brute-force grid's balanced points
    where B is unstable, the gamma_r parity of the unstable multiplier's eigenvector (+1 even, -1 odd)."""
    from scipy.optimize import brentq

    from ....analysis.loading import load_model

    model = load_model("two_plane_fixed")
    imbalance = ({"epsilon": tr.FIG12_EPS / 2, "chi": tr.FIG12_EPS / 2, "beta": 1.0} if dynamic
                 else {"epsilon": tr.FIG12_EPS, "chi": 0.0, "beta": 0.0})
    values = {**imbalance, **tr._ball_values(tr.FIG12_EPS, tr.FIG12_RATIO)}
    P = tx.race_swap(model)

    def growth(w):
        mu, _ = tr.floquet(model, values, float(w))
        return float(np.log(np.abs(mu).max()))

    grid = np.linspace(*FLOQUET_GRID[:2], FLOQUET_GRID[2])
    g = [growth(w) for w in grid]
    edges = [brentq(growth, grid[i], grid[i + 1], xtol=1e-4) for i in range(len(grid) - 1) if g[i] * g[i + 1] < 0]
    bounds = [float(grid[0])] + edges + [float(grid[-1])]
    stable = [(a, b) for a, b in zip(bounds, bounds[1:]) if growth(0.5 * (a + b)) < 0]
    parity = {}
    for w, ok in zip(omegas, balanced):
        if ok and not any(a <= w <= b for a, b in stable):
            mu, V = tr.floquet(model, values, float(w))
            v = V[:, int(np.argmax(np.abs(mu)))]
            parity[float(w)] = (float(np.abs(mu).max()), float((np.vdot(v, P @ v) / np.vdot(v, v)).real))
    return {"stable": stable, "parity": parity, "growth": {float(w): v for w, v in zip(grid, g)}}


def runups(fig_dir: Path) -> dict:
    study = {}
    for rtol in RUN_RTOLS:
        all_runs = _all_runs(rtol)
        study[rtol] = runup_metrics(all_runs)
    out = {"study": study, "after": {ratio: tr.after_ramp(ratio, rtol=RUN_RTOLS[-1]) for ratio in tr.RATIOS}}
    out["spin_check"] = spin_angle_check()
    # Figure 15(b) without the exact symmetry: a start not exactly opposite, balls not exactly alike
    out["perturbed"] = {}
    for what, kw in (("offset", {"offset": 1e-6}), ("mass", {"mass_spread": 1e-6})):
        r = tr.run_up("two_plane_ramp", 0.1, 6000.0, samples=6001, rtol=RUN_RTOLS[-1], **kw)
        out["perturbed"][what] = {"A_end": float(r.A[-1]), "coincident_from": tr.coincident_from(r),
                                  "sync": tr.synchronised_from(r)}
    # the paper does not say where on the race the opposite pairs start: Figure 16(d)'s ratio over phases
    plain = all_runs["two_plane_hill", None]
    peak = float(plain.A[plain.t <= 300].max())
    def ratio_at(ratio):
        return lambda ph: float(tr.run_up("two_plane_hill", ratio, 300.0, samples=3001, rtol=RUN_RTOLS[-1],
                                          phase=ph).A.max() / peak)

    out["phases"] = {ratio: [ratio_at(ratio)(ph) for ph in PHASES] for ratio in tr.RATIOS}
    out["worse_phases"] = {ratio: worse_phases(ratio_at(ratio), PHASES, out["phases"][ratio]) for ratio in tr.RATIOS}
    plt = _plt()
    for fig_name, name, t_end in RUNUPS:
        runs = {ratio: all_runs[name, ratio] for ratio in tr.RATIOS}
        plain = all_runs[name, None]
        out[name] = {"runs": runs, "plain": plain, "t_end": t_end, "figure_name": fig_name}
        if name == "two_plane_ramp":
            fig, axes = plt.subplots(1, 2, figsize=(8, 3.6), sharey=True, constrained_layout=True)
            for ax, (ratio, r) in zip(axes, runs.items()):
                for k in range(4):
                    ax.plot(r.spin, r.ball_speeds[k], color="k" if k < 2 else "C0", lw=0.6)
                ax.plot(r.spin, r.spin, color="0.6", lw=0.6, ls="--")
                ax.set_xlabel(r"$\Omega$")
                ax.set_title(rf"({'ab'[tr.RATIOS.index(ratio)]}) $\bar c_b$ = {ratio:g}", fontsize=8)
            axes[0].set_ylabel(r"$\dot\theta_k$")
            fig.suptitle(r"paper Fig. 15: ramp to $\Omega$ = 3.6 over $t$ = 6000, set-up (10), "
                         r"$\epsilon/R = \chi = 5\times10^{-5}$, $\beta$ = 1, $m/M = 10^{-4}$", fontsize=8)
        else:
            fig, axes = plt.subplots(4, 2, figsize=(8, 9), constrained_layout=True)
            for col, (ratio, r) in enumerate(runs.items()):
                ax = axes[0, col]
                pz, zoom = plain.t <= 400, r.t <= 400
                ax.plot(plain.t[pz], plain.A[pz], color="0.6", lw=0.8, label="plain rotor")
                ax.plot(r.t[zoom], r.A[zoom], "k", lw=0.6, label="ABB")
                ax.set_title(rf"$\bar c_b$ = {ratio:g}: ({'ad'[col]}) $A$, detail", fontsize=8)
                ax.legend(fontsize=7)
                ax = axes[1, col]
                ax.semilogy(plain.t, plain.A, color="0.6", lw=0.6)
                ax.semilogy(r.t, np.maximum(r.A, 1e-12), "k", lw=0.5)
                ax.set_ylim(1e-9, 1e-2)
                ax.set_title(f"({'c' if col == 0 else 'd'}) $A$ (log)", fontsize=8)
                ax = axes[2, col]
                for k in range(4):
                    ax.plot(r.t, r.ball_speeds[k] - r.spin, color="k" if k < 2 else "C0", lw=0.5)
                ax.set_title(rf"({'ef'[col]}) $\dot\alpha_k = \dot\theta_k - \Omega$", fontsize=8)
                ax = axes[3, col]
                for k in range(4):
                    ax.plot(r.t, np.mod(r.angles[k], 2 * math.pi), ".", color="k" if k < 2 else "C0", ms=0.5)
                ax.set_title(rf"({'gh'[col]}) $\alpha_k$ mod $2\pi$", fontsize=8)
                ax.set_xlabel(r"$\bar t$")
            fig.suptitle(r"paper Fig. 16: Hill run-up (45), $(\Omega_{max}, \bar t_{1/2}, n)$ = (3.6, 200, 3), "
                         r"set-up (10), $\epsilon/R = \chi = 5\times10^{-5}$, $\beta$ = 1, $m/M = 10^{-4}$", fontsize=8)
        out[name]["figure"] = _save(fig, fig_dir / f"two_plane_{fig_name.split()[1]}.png")
    return out


def worse_phases(ratio_at, phases=PHASES, values=None, xtol: float = 1e-3) -> list[tuple[float, float]]:
    """The starting phases of the opposite pairs (mod pi: the pair at phase and phase + pi is the same pair of
    equal balls) where the ABB's vibration at the critical speeds exceeds the plain rotor's, ratio_at(phase) > 1
    (Figure 16(d)'s "worse than plain"): the sign changes of ratio - 1 between neighbouring `phases` (values:
    ratio_at there, if known; the last neighbour is phase 0 again at pi) located by brentq (xtol), as intervals of
    [0, pi)."""
    from scipy.optimize import brentq

    values = [ratio_at(p) for p in phases] if values is None else list(values)
    ph, v = list(phases) + [math.pi], values + [values[0]]
    edges = [brentq(lambda x: ratio_at(x) - 1.0, ph[i], ph[i + 1], xtol=xtol)
             for i in range(len(phases)) if (v[i] > 1) != (v[i + 1] > 1)]
    out, start = [], 0.0 if v[0] > 1 else None
    for e in edges:
        if start is None:
            start = e
        else:
            out.append((start, e))
            start = None
    if start is not None:
        out.append((start, math.pi))
    return out


def spin_angle_check(t_end: float = 3000.0) -> float:
    """|theta_0(t_end) - integral of the Hill spin law (45)|: the emitted closed form against adaptive
    quadrature of the emitted spin rate."""
    from scipy.integrate import quad

    from ....analysis.loading import load_model

    hill = load_model("two_plane_hill")
    p = hill.params()
    rate = lambda s: float(tr.spin_law(hill, p, np.array([s]))[1][0])  # noqa: E731
    exact = sum(quad(rate, a, b, epsabs=1e-12, epsrel=1e-13, limit=400)[0]
                for a, b in zip(np.linspace(0, t_end, 31)[:-1], np.linspace(0, t_end, 31)[1:]))
    return abs(float(tr.spin_law(hill, p, np.array([t_end]))[0][0]) - exact)


def following_lag(r: tr.RunUp) -> np.ndarray:
    """The lag the drive itself imposes on balls that follow it: a ball in its race, m R^2 theta_k'' =
    c_b (Omega - theta_k') + ... (paper (3)), turning with the accelerating rotor lags it by
    Omega'(t) m R^2 / c_b (the start-up lag: 0.06 for Figure 15(a)'s ramp Omega' = 6e-4 at c_b/m = 0.01, 0.006
    at 0.1)."""
    return np.gradient(r.spin, r.t) * r.radius**2 / r.ratio


def stalls(r: tr.RunUp, lag: float = 0.05, shortest: float = 100.0) -> list[tuple[float, float, float]]:
    """The stalls of a run-up: each stretch of time (at least `shortest` long) over which the balls' mean speed
    lags the rotor by more than 5 % of its speed beyond the lag the drive itself imposes (`following_lag`), as
    (median ball speed over it, Omega at its start, at its end).  Measured against the drive's own scale, not
    the start-up lag: a bare relative lag counts the start-up lag as a stall wherever Omega is small (Figure
    15(b) got one at Omega 0-0.12, Figure 15(a)'s was reported from Omega = 0 instead of about 1.1)."""
    mean = r.ball_speeds.mean(axis=0)
    mask = (r.spin - mean - np.maximum(following_lag(r), 0.0)) > lag * np.maximum(r.spin, 1e-12)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    out = []
    for a, b in zip(edges[::2], edges[1::2]):
        if r.t[b - 1] - r.t[a] >= shortest:
            out.append((float(np.median(mean[a:b])), float(r.spin[a]), float(r.spin[b - 1])))
    return out


def stall_speed(r: tr.RunUp, lag: float = 0.05) -> float | None:
    """Median ball speed over the first stall (see `stalls`)."""
    found = stalls(r, lag)
    return found[0][0] if found else None


def compute(fig_dir: Path, progress=None) -> dict:
    out = {}
    t0 = time.time()
    out["exchange"] = exchange(fig_dir)
    out["exchange_wall"] = time.time() - t0
    if progress:
        ex = out["exchange"]["ex"]
        progress(f"two-plane 3.2.3: Omega_1 = {ex.omega_1:.9f}, Omega_2 = {ex.omega_2:.9f}")
    out["fig5a"] = figure_5a()
    if progress:
        progress("two-plane Fig. 5(a): Hopf points of B at m = " + ", ".join(f"{p['m']:.6g}" for p in out["fig5a"]["points"]))
    out["fig12"] = figure_12a(fig_dir)
    if progress:
        f12 = out["fig12"]
        progress(f"two-plane Fig. 12(a) ({f12['wall']:.0f} s): plain peaks {f12['peaks']}, ABB balances on "
                 f"{f12['intervals']}")
    t0 = time.time()
    out["runups"] = runups(fig_dir)
    out["runup_wall"] = time.time() - t0
    if progress:
        progress(f"two-plane run-ups and studies: {out['runup_wall']:.1f} s")
    return out


def _t(v) -> str:
    return "—" if v is None else f"{v:.0f}"


def _stall_list(v) -> str:
    return "; ".join(f"{m:.4f} ({a:.2f}-{b:.2f})" for m, a, b in v) or "none"


def figure_5a_lines(r: dict) -> list[str]:
    """Figure 5(a)'s Hopf points of B (prose/figure_5a.md.j2): the first three, below 2.5 m_c, are the paper's."""
    pts, mc = r["points"], r["m_c"]
    first = [p for p in pts if p["m"] < 2.5 * mc]
    return render(
        "figure_5a", m_max=f"{r['m_max']:.3g}", m_c=f"{mc:.6g}", stable_at_pitchfork=r["stable_at_pitchfork"],
        points=[{"m": f"{p['m']:.6g}", "ratio": f"{p['m'] / mc:.4f}", "frequency": f"{p['frequency']:.5f}",
                 "stable_after": p["stable_after"]} for p in pts],
        m_first=f"{2.5 * mc:.4g}", first=[f"{p['m'] / mc:.3f}" for p in first],
        later=[f"{p['m'] / mc:.1f}" for p in pts[len(first):]]) + [""]


def _pct(x):
    return f"{100 * x:+.2f} %"


def _spans(iv, digits: int = 2) -> list[str]:
    return [f"[{a:.{digits}f}, {b:.{digits}f}]" for a, b in iv]


def fig12_lines(f: dict, root: Path) -> list[str]:
    """Figures 12(a), (b): the converged brute force beside the paper's words and B's Floquet stability
    (prose/fig12.md.j2)."""
    (p1g, p1), (p2g, p2) = f["peaks"][:2]
    lim = f["limit"]
    carried = [{"Omega": f"{q['Omega']:.2f}", "first": q["first"], "balanced": q["balanced"],
                "t": f"{q['t']:g}", "settled": q["settled"]}
               for q in f["points"] if q["t"] > 2 * FIG12_TRANSIENT or q["first"] != q["balanced"]]
    limits = sorted(lim.items())
    par = f["floquet"]["parity"]
    stable = lambda w, iv: any(a <= w <= b for a, b in iv)  # noqa: E731
    static_agree = sum(q["balanced"] == stable(q["Omega"], f["floquet"]["stable"]) for q in f["points"])
    growth = f["dyn_floquet"]["growth"]
    rows, slow = [], None
    for q in f["dyn_points"]:
        b_stable = stable(q["Omega"], f["dyn_floquet"]["stable"])
        if q["t"] > 2 * FIG12_TRANSIENT or q["first"] != q["balanced"] or q["balanced"] != b_stable:
            rows.append({"Omega": f"{q['Omega']:.1f}", "first": q["first"], "t": f"{q['t']:g}", "settled": q["settled"],
                         "A_bar": f"{q['A_bar']:.3g}", "balanced": q["balanced"], "stable": b_stable})
            g = growth.get(q["Omega"])
            if g is not None and g < 0 and (slow is None or q["t"] > slow["t_raw"]):
                slow = {"Omega": f"{q['Omega']:.1f}", "mu": f"{math.exp(g):.5f}",
                        "time": f"{2 * math.pi / q['Omega'] / -g:.0f}", "t": f"{q['t']:g}", "t_raw": q["t"]}
    dyn_agree = sum(q["balanced"] == stable(q["Omega"], f["dyn_floquet"]["stable"]) for q in f["dyn_points"])
    disagree = [q["Omega"] for q in f["dyn_points"] if q["balanced"] != stable(q["Omega"], f["dyn_floquet"]["stable"])]
    return render(
        "fig12", grid=FIG12_GRID, step=f"{(FIG12_GRID[1] - FIG12_GRID[0]) / (FIG12_GRID[2] - 1):g}", t1=f"{FIG12_TRANSIENT:g}", t2=f"{2 * FIG12_TRANSIENT:g}", cap=f"{FIG12_CAP:g}",
        carried=carried, intervals=_spans(f["intervals"]), first_intervals=_spans(f["first_intervals"]),
        peak_1=(f"{p1:.5f}", f"{p1g:.3f}", _pct(_rel(p1, 1.0))), peak_2=(f"{p2:.5f}", f"{p2g:.3f}", _pct(_rel(p2, 2.24))),
        limits=[(f"{v:.4g}", f"{k:g}") for k, v in limits], limit_diffs=[_pct(_rel(v, 1e-4)) for _, v in limits],
        peaks=[f"{b:.3f}" for _, b in f["peaks"]], floquet=_spans(f["floquet"]["stable"], 4),
        parity_speeds=[f"{w:.2f}" for w in par], parity_count=len(par),
        parity_min=f"{min((m for m, _ in par.values()), default=float('nan')):.5f}",
        parity_max=f"{max((m for m, _ in par.values()), default=float('nan')):.5f}",
        parity_signs=sorted({f"{s:+.0f}" for _, s in par.values()}),
        limit_note=[(_pct(1 / (1 - 5 / k**2) - 1), f"{k:g}") for k in sorted(lim)],
        grid_end=(f"{f['omegas'][-1]:g}", f"{f['plain'][-1]:.4g}"),
        worst=f"{f['worst_ratio'][1]:.0f}", worst_at=f"{f['worst_ratio'][0]:.2f}",
        figure=f["figure"].relative_to(root).as_posix(), figure_b=f["figure_b"].relative_to(root).as_posix(),
        dyn_floquet=_spans(f["dyn_floquet"]["stable"], 4), dyn_rows=rows,
        dyn_intervals=_spans(f["dyn_intervals"], 1), dyn_first=_spans(f["dyn_first_intervals"], 1),
        dyn_agree=dyn_agree, dyn_total=len(f["dyn_points"]),
        dyn_disagree=[f"{w:.1f}" for w in disagree],
        static_agree=static_agree, static_total=len(f["points"]), slow=slow,
        better_agreement=better_agreement(dyn_agree, len(f["dyn_points"]), static_agree, len(f["points"])),
        extra_peaks=len(f["peaks"]) != 2) + [""]


def better_agreement(dyn_agree: int, dyn_total: int, static_agree: int, static_total: int) -> bool:
    """The paper's "better agreement with the stability results of Figure 11" for Figure 12(b): the dynamic
    imbalance's brute force agrees with its B's Floquet stability at a larger share of the grid than Figure
    12(a)'s symmetric run with its B (dyn_agree / dyn_total > static_agree / static_total, compared without
    division)."""
    return dyn_agree * static_total > static_agree * dyn_total


def exchange_lines(r: dict, root: Path) -> list[str]:
    """The page's heading and section 3.2.3 (prose/exchange.md.j2): kappa's zero and pole against (11) and the
    frozen-ball critical speeds (32), the full damped model's slow eigenvalues, the approach to m_c."""
    ex = r["ex"]
    cyl, con = ex.frozen
    eps, s1, s2 = ex.small_eps
    at = lambda d, x: d[min(d, key=lambda v: abs(v - x))]  # noqa: E731
    dash = lambda v: "—" if v is None else f"{v:.4f}"  # noqa: E731
    return render(
        "exchange", m_c=f"{ex.m_c:g}",
        omega_1=[f"{ex.omega_1:.9f}", _pct(_rel(ex.omega_1, 1.0)), f"{cyl:.9f}", f"{ex.omega_1 - cyl:.1e}"],
        omega_2=[f"{ex.omega_2:.9f}", _pct(_rel(ex.omega_2, 1.81)), f"{con:.9f}", f"{ex.omega_2 - con:.1e}"],
        frozen_diff=f"{max(abs(ex.omega_1 - cyl), abs(ex.omega_2 - con)):.0e}", small_eps=f"{eps:g}",
        small_m_c=f"{eps / 4:g}", small_1=f"{s1:.6f} ({100 * _rel(s1, 1.0):+.4f} %)",
        small_2=f"{s2:.6f} ({100 * _rel(s2, 1.81):+.3f} %)",
        ratio_06=f"{at(r['odd'], 0.6) / at(r['even'], 0.6):.4f}", kappa_06=f"{at(ex.curve, 0.6):.4f}",
        study=[(f"{rel:g}", dash(e), dash(o)) for rel, (e, o) in ex.study.items()],
        limit=(f"{cyl:.4f}", f"{con:.4f}"), figure=r["figure"].relative_to(root).as_posix()) + [""]


def runup_table_lines(study: dict, spin_check: float) -> list[str]:
    """Section 6's set-up and its table (prose/runups.md.j2): each metric converged (rtol RUN_RTOLS[-1]), its
    difference to a published number where the paper prints one, and at every rtol of the study."""
    M = study[RUN_RTOLS[-1]]
    t = lambda v: "never" if v is None else f"{v:.0f}"  # noqa: E731
    f4, f1, g3 = (lambda v: f"{v:.4f}"), (lambda v: f"{v:.1f}"), (lambda v: f"{v:.3g}")  # noqa: E731
    formats = {"stalls_15a": _stall_list, "sync_15a": t, "end_min_15a": lambda v: f"{v / 3.6:.4f}",
               "stalls_15b": _stall_list, "sync_15b": t, "end_A_15b": g3, "t_plain_peak": f1, "sync_16a": t,
               "end_A_16a": g3, "burst_16a": f1, "sync_16b": t, "ratio_16b": f4, "ratio_16a": f4}
    published = {"burst_16a": 800.0}  # the one number the paper prints ("around t = 800")
    cells = {key: " | ".join([fmt(M[key]), _pct(_rel(M[key], published[key])) if key in published else "—"]
                             + [fmt(study[r][key]) for r in RUN_RTOLS]) for key, fmt in formats.items()}
    return render("runups", engine=tr.ENGINE, rtols=[f"{r:g}" for r in RUN_RTOLS], spin_check=f"{spin_check:.1e}",
                  t_con=f"{M['t_con']:.1f}", cells=cells) + [""]


def section(res: dict, root: Path) -> list[str]:
    L = exchange_lines(res["exchange"], root)
    L += figure_5a_lines(res["fig5a"])
    L += fig12_lines(res["fig12"], root)
    ru = res["runups"]
    ramp, hill = ru["two_plane_ramp"], ru["two_plane_hill"]
    study = ru["study"]
    M = study[RUN_RTOLS[-1]]
    L += runup_table_lines(study, res["runups"]["spin_check"])
    after = ru["after"]
    a1, a0 = after[0.1], after[0.01]
    ph = ru["phases"]
    worse = ru["worse_phases"]
    spans = lambda iv: [f"({a / math.pi:.3f} pi, {b / math.pi:.3f} pi)" for a, b in iv]  # noqa: E731
    off, mass = ru["perturbed"]["offset"], ru["perturbed"]["mass"]
    notes = render(
        "runup_notes", burst=f"{M['burst_16a']:.1f}", burst_diff=_pct(_rel(M["burst_16a"], 800.0)),
        end_A_15b=f"{M['end_A_15b']:.3g}",
        coincident="—" if a1["coincident_from"] is None else
        f"{a1['coincident_from']:.0f} (Omega = {3.6 * a1['coincident_from'] / 6000:.3f})",
        as_is=f"{a1['as_is']['A_end']:.3g}", moved="—" if a1["moved"] is None else f"{a1['moved']:.0e}",
        n_unstable=a1["unstable"],
        leading=None if a1["unstable"] is None else [f"{z.real:.4f}" for z in a1["leading"]],
        kick=f"{a1['kick']:g}", kicked=f"{a1['kicked']['A_end']:.2g}", offset_coincident=_t(off["coincident_from"]),
        offset_A=f"{off['A_end']:.3g}", mass_A=f"{mass['A_end']:.3g}", mass_sync=None if mass["sync"] is None else f"{mass['sync']:.0f}",
        low_as_is=f"{a0['as_is']['A_end']:.2g}", span_high=f"{min(ph[0.1]):.2f}-{max(ph[0.1]):.2f}",
        n_above=sum(v > 1 for v in ph[0.1]), span_low=f"{min(ph[0.01]):.3f}-{max(ph[0.01]):.3f}",
        worse_high=spans(worse[0.1]), worse_share=f"{sum(b - a for a, b in worse[0.1]) / math.pi:.0%}",
        worse_low=spans(worse[0.01]), default_ratio=f"{M['crit_16b'] / M['crit_plain']:.3f}",
        figure_15=ramp["figure"].relative_to(root).as_posix(), figure_16=hill["figure"].relative_to(root).as_posix())
    return L + notes


REPRODUCTION = Reproduction("two-plane", "Two-plane paper", compute, section, coverage=coverage.SECTION)
