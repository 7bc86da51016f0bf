"""The thesis' periodic orbits recomputed (issue 21 item 6): the Fig. 5.4(b) limit cycle, the cycles born at
H1 for n = 2, 3, 4 at (5.1)'s other parameters, and the desynchronised orbits of section 5.2.2.

    section(out_dir) -> markdown      (figures written into out_dir)
    lines(a, h1, ds, b) -> markdown   the section from those results (templates/periodic_orbits.md.j2)

On the generated models through the analysis layer's orbit machinery (`adbgen.analysis.orbits`); this
module only knows which of the thesis' cases to run and what the thesis says about them.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from ....analysis.reproduction import markdown_section

PI = math.pi
CH4 = {"mu": 0.05, "zeta": 0.01, "beta": 0.01, "delta": 0.01}  # (5.1) without Omega: the ch. 4 parameters
FIG54B = {"phi_1": PI / 4, "phi_2": -PI / 4}
ENGINE = "cyrk-dop853"  # named: the document must not follow a change of the default engine (issue 23)


def _model(n: int):
    from ....analysis.loading import load_model

    return load_model(f"thesis_rotating_n{n}")


def simulated_period(model, p, y0, o, t_end: float = 6000.0, t_from: float = 4000.0) -> tuple[float, int]:
    """The period a long run of ENGINE (named: not the default) settles on: its returns to the orbit's section
    (through o.y, normal to the flow), located by cubic Hermite interpolation between accepted steps, over
    [t_from, t_end]; (period, returns counted)."""
    from scipy.optimize import brentq

    from ....analysis.orbits.orbit import wrapped
    from ....analysis.simulate import simulate

    sim = simulate(model, p, y0, t_end=t_end, rtol=1e-12, atol=1e-13, engine=ENGINE)
    t, Y = sim.t, sim.y.T
    f0 = np.asarray(model.module.rhs(0.0, o.y, o.p))
    D = wrapped(model, Y - o.y)
    g = D @ f0
    cross = []
    for i in np.nonzero((g[:-1] < 0) & (g[1:] >= 0) & (t[:-1] > t_from))[0]:
        w = g[i] / (g[i] - g[i + 1])
        if np.linalg.norm(D[i] + w * (D[i + 1] - D[i])) > 0.1:
            continue
        h = t[i + 1] - t[i]
        d0 = f0 @ np.asarray(model.module.rhs(0.0, Y[i], p)) * h
        d1 = f0 @ np.asarray(model.module.rhs(0.0, Y[i + 1], p)) * h
        a, b = g[i], g[i + 1]
        cross.append(t[i] + h * brentq(lambda s: (2 * s**3 - 3 * s**2 + 1) * a + (s**3 - 2 * s**2 + s) * d0
                                       + (3 * s**2 - 2 * s**3) * b + (s**3 - s**2) * d1, 0.0, 1.0, xtol=1e-15))
    cross = np.array(cross)
    count = int(round((cross[-1] - cross[0]) / o.period))
    return float((cross[-1] - cross[0]) / count), count


def fig54b(out: Path, progress=print) -> dict:
    """Fig. 5.4(b): the n = 2 run from (pi/4, -pi/4) at (5.1) ends on a limit cycle."""
    from ....analysis import auto07p
    from ....analysis.orbits import auto_cycles, orbit
    from ....analysis.orbits.flow import Flow

    m = _model(2)
    p = m.params()
    y0 = m.state(FIG54B)
    t0 = time.perf_counter()
    o = orbit.find(m, p, y0, 2000.0)
    wall = time.perf_counter() - t0
    T_sim, count = simulated_period(m, p, y0, o)
    res = {"orbit": o, "wall": wall, "T_sim": T_sim, "returns": count}
    if not auto07p.missing_tools():
        a = auto_cycles.auto_orbit(m, o, "Omega")
        ours = orbit.refine(m, m.params({"Omega": a["Omega"]}), o.y, o.period)
        res["auto"] = a
        res["auto_ours"] = ours
    progress(f"Fig. 5.4(b): period {o.period:.10f}, simulate {T_sim:.10f}")
    # figure: one period of the orbit and the long simulation's last stretch, r and the x-y whirl
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ....analysis.simulate import simulate

    t, Y = orbit.trace(o, Flow(m), 800)
    sim = simulate(m, p, y0, t_end=2000.0 + 3 * o.period, rtol=1e-10, atol=1e-12, samples=4001, engine=ENGINE)
    keep = sim.t > 2000.0
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
    a1.plot(sim.t[keep] - sim.t[keep][0], np.hypot(sim.y[0, keep], sim.y[1, keep]), color="0.6", lw=3,
            label="simulate, t > 2000")
    a1.plot(t, np.hypot(Y[:, 0], Y[:, 1]), "C3", lw=1, label=f"orbit, T = {o.period:.6f}")
    a1.set_xlabel("t (from a point on the orbit)")
    a1.set_ylabel("r")
    a1.legend(fontsize=7)
    a2.plot(sim.y[0, keep], sim.y[1, keep], color="0.6", lw=3)
    a2.plot(Y[:, 0], Y[:, 1], "C3", lw=1)
    a2.set_xlabel("x")
    a2.set_ylabel("y")
    a2.set_aspect("equal", "datalim")
    fig.suptitle("Fig. 5.4(b): n = 2, (5.1), phi(0) = (pi/4, -pi/4): the limit cycle", fontsize=9)
    fig.savefig(out / "orbits_fig5_4b.png", dpi=110)
    plt.close(fig)
    return res


def h1_cycles(out: Path, progress=print) -> list[dict]:
    """The cycles born at H1 (the Hopf point where the balanced state stabilises as Omega grows) for n = 2, 3,
    4 at mu = 0.05, zeta = beta = delta = 0.01."""
    from ....analysis import equilibrium_scan
    from ....analysis.orbits import branches, continuer, hopf
    from ....analysis.orbits.parameters import ParameterMap

    rows = []
    for n in (2, 3, 4):
        m = _model(n)
        p = m.params({"Omega": 4.0, **CH4})
        sc = equilibrium_scan.scan(m, p, m.module.START, "Omega", 4.0, 0.5)
        h1 = sc.points[0]
        pm = ParameterMap(m, p, ["Omega"])
        hp = hopf.HopfPoint.at(m, pm, h1.y, h1.value)
        t0 = time.perf_counter()
        br = branches.from_hopf(m, pm, hp, continuer.Settings(ds=0.01, ds_max=0.05, max_points=300, bounds=(0.5, 4.0)))
        row = {"n": n, "hopf": hp, "branch": br, "wall": time.perf_counter() - t0,
               "every_hopf": every_hopf(m, pm, sc)}
        if len(br.orbits) <= 1:
            row["drift"] = drift_past_h1(m, pm, h1.y, hp.lam)
        rows.append(row)
        progress(f"H1 n = {n}: Omega = {hp.lam:.8f}, l1 = {hp.l1:.4g}, {len(br.orbits)} orbits ({br.end})")
    _plot_h1(rows, out)
    return rows


DRIFT_RTOLS = (1e-10, 1e-12)


def drift_past_h1(model, pm, y_h1, lam: float, t_end: float = 20000.0) -> dict:
    """The free angles drift: a run just past H1 (Omega = H1 - 0.01) from the balanced state at H1 with x moved
    by 1e-3, on ENGINE at DRIFT_RTOLS: r at the end and the largest change of a free angle, at each rtol.

    For n >= 4 the followed member has free balls at the same angle (phi_3 = phi_4 = pi).  Balls at one angle
    are an invariant set of the equations (the right-hand side is symmetric in them), unstable here: a start on
    it stays on it only while round-off keeps the balls bit-for-bit equal, which one solver setting does and
    another does not (the flow at rtol 1e-11, atol 1e-12 leaves it after t ~ 500 and the balls lap, r = 0.41;
    at the rtols below the runs stay on it, r = 0.040).  So the drift is reported with `split`: the same run
    with the coincident balls moved apart by SPLIT (a generic start), the answer a real rotor gives (None when
    no two free balls coincide)."""
    from ....analysis.simulate import simulate

    q = pm(lam - 0.01)
    y = np.array(y_h1, float)
    y[0] += 1e-3
    free = list(model.angle_indices)[2:]
    runs = {}
    for rtol in DRIFT_RTOLS:
        sim = simulate(model, q, y, t_end=t_end, rtol=rtol, atol=rtol * 1e-2, engine=ENGINE, check=False)
        runs[rtol] = (float(np.hypot(sim.y_end[0], sim.y_end[1])), float(np.max(np.abs(sim.y_end[free] - y[free]))))
    r_end, change = runs[DRIFT_RTOLS[-1]]
    return {"Omega": lam - 0.01, "r_end": r_end, "angle_change": change, "runs": runs,
            "split": _split_run(model, q, y, free, t_end)}


SPLIT = 1e-9  # rad between coincident balls: far above round-off, far below anything physical


def _split_run(model, q, y, free, t_end: float):
    """The drift run with coincident free balls moved apart: the k-th ball of a group at one angle by k SPLIT."""
    from ....analysis.simulate import simulate

    ys = np.array(y, float)
    moved = False
    for k, i in enumerate(free):
        same = sum(1 for j in free[:k] if y[j] == y[i])  # earlier balls at this ball's angle
        if same:
            ys[i] += same * SPLIT
            moved = True
    if not moved:
        return None
    rtol = DRIFT_RTOLS[-1]
    sim = simulate(model, q, ys, t_end=t_end, rtol=rtol, atol=rtol * 1e-2, engine=ENGINE, check=False)
    return {"size": SPLIT, "rtol": rtol, "r_end": float(np.hypot(sim.y_end[0], sim.y_end[1])),
            "angle_change": float(np.max(np.abs(sim.y_end[free] - ys[free])))}


def every_hopf(model, pm, scan) -> list:
    """Every Hopf point of the scan (the balanced state followed from Omega = 4 down to 0.5), not H1 alone: its
    Omega, frequency and first Lyapunov coefficient l1 (`hopf.HopfPoint.at`)."""
    from ....analysis.orbits import hopf

    return [hopf.HopfPoint.at(model, pm, pt.y, pt.value) for pt in scan.points if getattr(pt, "kind", "") == "hopf"]


def special_index(lam, period, special: dict) -> int:
    """The branch point nearest a special point in (Omega, period), each scaled by its range over the branch:
    by Omega alone a branch that folds back put the marker on the wrong sheet (issue 36: the torus point near
    1.607 drawn on different sheets in the two panels)."""
    lam, period = np.asarray(lam, float), np.asarray(period, float)
    span = lambda v: max(float(np.ptp(v)), 1e-12)  # noqa: E731
    d = ((lam - special["Omega"]) / span(lam)) ** 2 + ((period - special["period"]) / span(period)) ** 2
    return int(np.argmin(d))


def _plot_h1(rows, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
    for row in rows:
        br = row["branch"]
        if len(br.orbits) <= 1:
            continue
        j = br.to_json()
        lam, amp, per, st = (np.array(j[k]) for k in ("parameter", "amplitude", "period", "stable"))
        for ax, v in ((a1, amp), (a2, per)):
            ax.plot(lam, v, "-", color=f"C{row['n']}", lw=0.7)
            ax.plot(lam, np.where(st, v, np.nan), "-", color=f"C{row['n']}", lw=2.4, label=f"n = {row['n']}")
        for s in br.specials:
            k = special_index(lam, per, s)
            # every special the cycle branch reports is drawn (a branch point too: a real multiplier through +1)
            mk = {"torus": "*", "period-doubling": "D", "fold": "s", "branch point": "^"}.get(s["kind"], "x")
            a1.plot(lam[k], amp[k], mk, color="k", ms=6)
            a2.plot(lam[k], per[k], mk, color="k", ms=6)
    a1.set_xlabel("Omega")
    a1.set_ylabel("r_max")
    a2.set_xlabel("Omega")
    a2.set_ylabel("period")
    a1.legend(fontsize=7)
    fig.suptitle("Cycles born at H1 (mu = 0.05, zeta = beta = delta = 0.01): thick stable; * torus, D period-doubling, "
                 "s fold, ^ branch point", fontsize=8)
    fig.savefig(out / "orbits_h1.png", dpi=110)
    plt.close(fig)


def desynchronised(out: Path, progress=print) -> list[dict]:
    """Section 5.2.2 (Fig. 5.16(a), 5.17(a)): zeta = 0.25, the n = 3 and n = 4 runs end on limit cycles; here
    the balls lap the rotor on them (windings), and the orbits are continued in Omega."""
    from ....analysis.orbits import branches, continuer, orbit
    from ....analysis.orbits.parameters import ParameterMap

    rows = []
    for n, phi in ((3, (PI / 3, -PI / 3, PI)), (4, (PI / 2, -PI / 2, PI, 0.0))):
        m = _model(n)
        p = m.params({"zeta": 0.25})
        o = orbit.find(m, p, m.state({f"phi_{i + 1}": v for i, v in enumerate(phi)}), 3000.0)
        br = branches.from_orbit(m, ParameterMap(m, p, ["Omega"]), o, -1.0,
                                 continuer.Settings(ds=0.02, ds_max=0.1, max_points=150, bounds=(1.0, 6.0)))
        rows.append({"n": n, "orbit": o, "branch": br})
        progress(f"desynchronised n = {n}: period {o.period:.8f}, windings {o.windings}")
    return rows


FIG510B = {"phi_1": PI / 3, "phi_2": PI, "phi_3": -PI / 3, **{f"phi_{i}_dot": -4.0 for i in (1, 2, 3)}}


def fig510b(progress=print) -> dict:
    """Fig. 5.10(b): n = 3 released at rest in the fixed frame (phi_i'(0) = -Omega) from (pi/3, pi, -pi/3) at
    (5.1) ends on a limit cycle on which the balls keep lapping: the orbit (shooting after t = 3000), its
    windings and how far apart the balls are on it."""
    from ....analysis.orbits import orbit

    m = _model(3)
    o = orbit.find(m, m.params(), m.state(FIG510B), 3000.0)
    angles = np.array([o.y[m.index(f"phi_{i}")] for i in (1, 2, 3)])
    spread = float(np.max(np.abs(np.angle(np.exp(1j * (angles - angles[0]))))))
    progress(f"Fig. 5.10(b): period {o.period:.8f}, windings {o.windings}")
    return {"orbit": o, "spread": spread}


def section(out: Path, progress=print) -> str:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    a = fig54b(out, progress)
    h1 = h1_cycles(out, progress)
    ds = desynchronised(out, progress)
    b = fig510b(progress)
    text = lines(a, h1, ds, b)
    # wall times go to the progress lines (`adbgen bench reproduce` records them), never into the document,
    # which must come out byte-identical from run to run
    progress(f"thesis orbits section: {time.perf_counter() - t0:.0f} s (the Fig. 5.4(b) orbit {a['wall']:.1f} s)")
    return text


def lines(a: dict, h1: list[dict], ds: list[dict], b: dict) -> str:
    """The section's Markdown (templates/periodic_orbits.md.j2) from the results of fig54b, h1_cycles,
    desynchronised and fig510b."""
    from .templates import render

    o = a["orbit"]
    values = {"o": o, "a": a, "engine": ENGINE, "simulated_difference": abs(a["T_sim"] - o.period) / o.period,
              "has_auto": "auto" in a, "auto": a.get("auto"), "ob": b["orbit"], "spread": b["spread"]}
    if "auto" in a:
        au, ours = a["auto"], a["auto_ours"]
        values.update(auto_ours=ours, auto_difference=abs(au["period"] - ours.period) / ours.period,
                      auto_moduli=np.sort(np.abs([complex(x, y) for x, y in au["multipliers"]]))[::-1])
    rows = []
    for row in h1:
        br = row["branch"]
        out = {"n": row["n"], "hopf": row["hopf"], "every_hopf": row["every_hopf"], "branch": None,
               "drift": row.get("drift")}
        if len(br.orbits) > 1:
            j = br.to_json()
            out.update(branch=j, orbits=len(br.orbits), specials=br.specials,
                       stable=[lam for lam, s in zip(j["parameter"], j["stable"]) if s])
        rows.append(out)
    desync = [{"n": row["n"], "orbit": row["orbit"], "branch": row["branch"].to_json()} for row in ds]
    return "\n".join(render("periodic_orbits", h1=rows, desynchronised=desync, **values)) + "\n"


from .coverage import ORBIT_ROWS  # noqa: E402

REPRODUCTION = markdown_section("thesis-orbits", "Thesis: periodic orbits (issue 21)", section, ORBIT_ROWS)
