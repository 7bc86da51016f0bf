"""The thesis' chapter-5 experiments over many starts or parameters, each a sweep on the Dask machinery
(`adbgen.analysis.sweep`): the r_max scans of Figs. 5.5, 5.7, 5.9, the launches at phi' = -Omega of
Figs. 5.10-5.11 (with a tolerance study and the basin's local structure), the n = 3 basin experiment and
Fig. 5.19 (b), (d), the (zeta, beta) maps of Figs. 5.20-5.22, the sweeps in Omega and delta of
Figs. 5.23-5.25.  Every sweep is the command line `adbgen sweep` runs (`command`), run into a temporary
folder and read back.
"""

from __future__ import annotations

import json
import math
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ....analysis.attractors import ALGEBRAIC, UNDECIDED
from ....analysis.sweep import SweepSpec, run_sweep
from ..description import THESIS_NAMES
from ....analysis.loading import load_model
from .balanced import balanced_stable, family_margin, family_zeta_limit

PI = math.pi
BALANCED = THESIS_NAMES["rest"]  # the decided labels (`attractors.Classifier.decide`): balanced (exponential or
# algebraic approach), not balanced, or undecided, never counted as not balanced


def balanced(label: str) -> bool:
    """A balanced outcome, approached exponentially or algebraically."""
    return label in (BALANCED, BALANCED + ALGEBRAIC)
RTOL = 1e-8  # the sweeps' tolerance (atol rtol/100), as the basin maps of Figs. 5.18, 5.19


def sweep(model: str, grid: list[str], measure: str, *, set_=(), y0=(), tie=(), t_end: float = 3000.0,
          rtol: float = RTOL, atol: float | None = None, engine: str = "cyrk-dop853", early_stop: bool = True):
    """(values over the grid, labels or None, coordinates {axis: values}) of one sweep."""
    import xarray as xr

    spec = SweepSpec(model=model, grid=list(grid), measure=measure, set=list(set_), y0=list(y0), tie=list(tie),
                     t_end=t_end, rtol=rtol, atol=rtol * 1e-2 if atol is None else atol, engine=engine,
                     early_stop=early_stop)
    tmp = Path(tempfile.mkdtemp(prefix="adbgen-reproduce-sweep-"))
    try:
        run_sweep(spec, tmp, progress=False, figures=False)
        ds = xr.open_zarr(tmp / "sweep.zarr", consolidated=False)
        values = np.asarray(ds[measure].values)
        labels = json.loads(ds.attrs["labels"]) if measure == "attractor" else None
        coords = {a.split("=")[0]: np.asarray(ds[a.split("=")[0]].values) for a in grid}
        ds.close()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return values, labels, coords


def command(model: str, grid, measure: str, set_=(), y0=(), tie=(), t_end: float = 3000.0) -> str:
    parts = [f"adbgen sweep {model}", *(f"--grid {g}" for g in grid), *(f"--set {s}" for s in set_),
             *(f"--y0 {v}" for v in y0), *(f"--tie {t}" for t in tie), f"--measure {measure}", f"--t-end {t_end:g}"]
    return " ".join(parts)


def named(labels, codes) -> list[str]:
    return [labels[int(c)] if c >= 0 else "not computed" for c in np.ravel(codes)]


def is_balanced(labels) -> np.ndarray:
    """Where the decided label is balanced (exponentially or algebraically)."""
    return np.vectorize(balanced, otypes=[bool])(np.asarray(labels, dtype=object))


def is_open(labels) -> np.ndarray:
    """Where the run is undecided, failed or not computed: neither balanced nor not balanced."""
    return np.isin(np.asarray(labels, dtype=object), [UNDECIDED, "failed", "not computed"])


def count_balanced(labels) -> int:
    return int(is_balanced(labels).sum())


# ------------------------------------------------------------------- Figs. 5.5, 5.7, 5.9: r_max scans

@dataclass(frozen=True)
class Panel:
    figure: str
    n: int
    tie: tuple[str, ...]
    y0: tuple[str, ...] = ()
    text: str = ""


SCAN_GRID = "phi_1=0:pi:100"  # phi_1(0) = pi k/99: the grid of the starts the thesis names (23 pi/99, 83 pi/99)
PANELS = (
    Panel("5.5(a)", 2, ("phi_2=-phi_1",), text="phi_2 = -phi_1"),
    Panel("5.5(b)", 2, ("phi_2=phi_1+pi",), text="phi_2 = phi_1 + pi"),
    Panel("5.7(a1)", 3, ("phi_2=-phi_1",), ("phi_3=0",), "phi_2 = -phi_1, phi_3 = 0"),
    Panel("5.7(a2)", 3, ("phi_2=-phi_1",), ("phi_3=pi",), "phi_2 = -phi_1, phi_3 = pi"),
    Panel("5.7(b1)", 3, ("phi_2=phi_1+pi",), ("phi_3=0",), "phi_2 = phi_1 + pi, phi_3 = 0"),
    Panel("5.7(b2)", 3, ("phi_2=phi_1+pi",), ("phi_3=pi",), "phi_2 = phi_1 + pi, phi_3 = pi"),
    Panel("5.7(c)", 3, ("phi_2=phi_1+pi/3", "phi_3=phi_1-pi/3"), text="phi_2 = phi_1 + pi/3, phi_3 = phi_1 - pi/3 "
          "(as printed)"),
    Panel("5.7(c), 2pi/3", 3, ("phi_2=phi_1+2*pi/3", "phi_3=phi_1-2*pi/3"), text="phi_2 = phi_1 + 2pi/3, phi_3 = "
          "phi_1 - 2pi/3 (equidistant)"),
    Panel("5.9(a1)", 4, ("phi_2=-phi_1",), ("phi_3=0", "phi_4=0"), "phi_2 = -phi_1, phi_3 = phi_4 = 0"),
    Panel("5.9(a2)", 4, ("phi_2=-phi_1",), ("phi_3=pi", "phi_4=pi"), "phi_2 = -phi_1, phi_3 = phi_4 = pi"),
    Panel("5.9(a3)", 4, ("phi_2=-phi_1",), ("phi_3=0", "phi_4=pi"), "phi_2 = -phi_1, phi_3 = 0, phi_4 = pi"),
    Panel("5.9(b1)", 4, ("phi_2=phi_1+pi",), ("phi_3=0", "phi_4=0"), "phi_2 = phi_1 + pi, phi_3 = phi_4 = 0"),
    Panel("5.9(b2)", 4, ("phi_2=phi_1+pi",), ("phi_3=pi", "phi_4=pi"), "phi_2 = phi_1 + pi, phi_3 = phi_4 = pi"),
    Panel("5.9(b3)", 4, ("phi_2=phi_1+pi",), ("phi_3=0", "phi_4=pi"), "phi_2 = phi_1 + pi, phi_3 = 0, phi_4 = pi"),
    Panel("5.9(c)", 4, ("phi_2=phi_1+pi/2", "phi_3=phi_1+pi", "phi_4=phi_1+3*pi/2"), text="equidistant"),
    Panel("5.9(d)", 4, ("phi_2=-phi_1", "phi_3=-phi_1+pi", "phi_4=phi_1-pi"), text="phi_2 = -phi_1, phi_3 = pi - "
          "phi_1, phi_4 = phi_1 - pi"),
)

# the starts the thesis names, with what it says they reach: (panel, phi_1(0), its words, our label to expect)
NAMED = (
    ("5.7(a1)", 0.0, "phi_1 = phi_2 = phi_3 = 0: a limit cycle", "limit cycle"),
    ("5.7(a2)", PI, "all at pi: the coincident state 2-", "coincident 2-"),
    ("5.7(a2)", 0.0, "(0, 0, pi): the in-line state 3(3-2)-", "in-line 3(3-2)-"),
    ("5.7(b2)", 0.0, "(0, pi, pi): the in-line state 3(3-1)+ (= 3(3-2)- with the balls renamed)", "in-line 3(3-2)-"),
    ("5.9(a1)", 0.0, "all at 0: a limit cycle", "limit cycle"),
    ("5.9(a1)", 23 * PI / 99, "phi_1 = -phi_2 = 0.72986495992490, phi_3 = phi_4 = 0: a limit cycle", "limit cycle"),
    ("5.9(a2)", 83 * PI / 99, "phi_1 = -phi_2 = 2.63386050755508, phi_3 = phi_4 = pi: a limit cycle", "limit cycle"),
    ("5.9(a2)", PI, "all at pi: the coincident state 2-", "coincident 2-"),
    ("5.9(a3)", 0.0, "(0, 0, 0, pi): the in-line state 3(4-3)-", "in-line 3(4-3)-"),
    ("5.9(b1)", 0.0, "(0, pi, 0, 0): the in-line state 3(4-3)-", "in-line 3(4-3)-"),
    ("5.9(b2)", 0.0, "(0, pi, pi, pi): the in-line state 3(4-1)+ (= 3(4-3)- with the balls renamed)",
     "in-line 3(4-3)-"),
)


def scan(panel: Panel) -> dict:
    model = f"thesis_rotating_n{panel.n}"
    r_max, _, coords = sweep(model, [SCAN_GRID], "r_max", y0=panel.y0, tie=panel.tie)
    codes, labels, _ = sweep(model, [SCAN_GRID], "attractor", y0=panel.y0, tie=panel.tie)
    return {"panel": panel, "phi_1": coords["phi_1"], "r_max": r_max, "labels": named(labels, codes),
            "command": command(model, [SCAN_GRID], "r_max", y0=panel.y0, tie=panel.tie)}


def scans() -> list[dict]:
    return [scan(p) for p in PANELS]


# ------------------------------------------------------------- Figs. 5.10-5.11: launches at -Omega

LAUNCH_TIES = {2: ("phi_2=phi_1+pi",), 3: ("phi_2=phi_1+2*pi/3", "phi_3=phi_1-2*pi/3"),
               4: ("phi_2=phi_1+pi/2", "phi_3=phi_1+pi", "phi_4=phi_1+3*pi/2")}
LAUNCH_PUBLISHED = {2: 32, 3: 28, 4: 24}  # balanced runs of 100 (section 5.1.3)
LAUNCH_GRID = "phi_1=0:2*pi*99/100:100"
LAUNCH_RTOLS = (1e-6, 1e-8, 1e-10)
ODE45 = ("matlab-ode45", 1e-3, 1e-6)  # the thesis' integrator at MATLAB's defaults (RelTol, AbsTol)


def launches() -> dict:
    """Fig. 5.11: 100 equidistant starts with every ball at phi' = -Omega (at rest in the fixed frame);
    the balanced count at each tolerance, and where the label changes with the tolerance, a fine scan of
    phi_1(0) around that start (the basin's local structure)."""
    out = {}
    for n, ties in LAUNCH_TIES.items():
        model = f"thesis_rotating_n{n}"
        y0 = tuple(f"phi_{k}_dot=-4" for k in range(1, n + 1))
        by_tol = {}
        for rtol in LAUNCH_RTOLS:
            codes, labels, coords = sweep(model, [LAUNCH_GRID], "attractor", y0=y0, tie=ties, rtol=rtol)
            by_tol[rtol] = named(labels, codes)
        phi = coords["phi_1"]
        changes = [k for k in range(len(phi)) if len({by_tol[r][k] for r in LAUNCH_RTOLS}) > 1]
        local = []
        h = phi[1] - phi[0]
        for k in changes[:3]:  # the basin about the first three such starts
            grid = f"phi_1={float(phi[k] - h / 2)!r}:{float(phi[k] + h / 2)!r}:41"
            codes, labels, fine = sweep(model, [grid], "attractor", y0=y0, tie=ties, rtol=LAUNCH_RTOLS[-1])
            names = named(labels, codes)
            switches = sum(a != b for a, b in zip(names, names[1:]))
            local.append({"phi_1": float(phi[k]), "balanced": count_balanced(names), "points": len(names),
                          "switches": switches})
        # the thesis' solver at its defaults beside the converged counts: its 32 / 28 / 24 are ode45's
        codes, labels, _ = sweep(model, [LAUNCH_GRID], "attractor", y0=y0, tie=ties, rtol=ODE45[1], atol=ODE45[2],
                                 engine=ODE45[0], early_stop=False)  # ode45 has no early stop
        out[n] = {"phi_1": phi, "labels": by_tol, "changes": [float(phi[k]) for k in changes], "local": local,
                  "ode45": named(labels, codes),
                  "command": command(model, [LAUNCH_GRID], "attractor", y0=y0, tie=ties)}
    return out


# ---------------------------------------------------- n = 3 basin experiment, Fig. 5.19 (b), (d)

BASIN_ZETAS = (0.01, 0.1, 0.2, 0.25)
N3_PUBLISHED = {0.01: "all but phi_1(0) = phi_2(0)", 0.1: "2 of 1600", 0.2: "none", 0.25: "none"}
# long enough for the runs to settle: at zeta = 0.01 the balls creep along the n = 3 family of balanced states
# (a neutral direction), so at t = 2000 all but 18 of 1600 runs were still undecided and at t = 3000 455
# were (1104 balanced, 41 in-line): the count is the run length's, not the basin's, until the runs settle
N3_T_END = 6000.0


def basins_n3(size: int = 40) -> list[dict]:
    """The thesis' n = 3 experiment (section 5.2.2, described in words): phi_1(0), phi_2(0) over [0, pi] on 40
    equidistant values each, phi_3(0) = phi_1(0) + pi, beta = 0.01."""
    out = []
    grid = [f"phi_1=0:pi:{size}", f"phi_2=0:pi:{size}"]
    for zeta in BASIN_ZETAS:
        codes, labels, _ = sweep("thesis_rotating_n3", grid, "attractor", set_=(f"zeta={zeta}",),
                                 tie=("phi_3=phi_1+pi",), t_end=N3_T_END)
        names = np.array(named(labels, codes)).reshape(codes.shape)
        diag = np.eye(size, dtype=bool)
        ok = is_balanced(names)
        out.append({"zeta": zeta, "balanced": int(ok.sum()), "points": names.size,
                    "undecided": int(is_open(names).sum()),
                    "off_diagonal_balanced": int((ok & ~diag).sum()),
                    "diagonal_balanced": int((ok & diag).sum()),
                    "counts": {k: int((names == k).sum()) for k in sorted(set(names.ravel()))},
                    "family": family_margin(load_model("thesis_rotating_n3"), {"zeta": zeta})})
    return out


# ----------------------------------------------------------------- Figs. 5.20-5.22: (zeta, beta)

ZB_GRID = ["zeta=0.01:0.25:13", "beta=0.01:0.25:13"]
EQUIDISTANT_Y0 = {2: ("phi_1=pi/2", "phi_2=-pi/2"), 3: ("phi_1=pi/3", "phi_2=-pi/3", "phi_3=pi"),
                  4: ("phi_1=pi/2", "phi_2=-pi/2", "phi_3=pi", "phi_4=0")}


def zeta_beta() -> dict:
    out = {}
    for n in (2, 3, 4):
        model = f"thesis_rotating_n{n}"
        codes, labels, coords = sweep(model, ZB_GRID, "attractor", y0=EQUIDISTANT_Y0[n])
        r_max, _, _ = sweep(model, ZB_GRID, "r_max", y0=EQUIDISTANT_Y0[n])
        t_dec, _, _ = sweep(model, ZB_GRID, "t_dec", y0=EQUIDISTANT_Y0[n])
        out[n] = {"labels": np.array(named(labels, codes)).reshape(codes.shape), "r_max": r_max, "t_dec": t_dec,
                  "zeta": coords["zeta"], "beta": coords["beta"],
                  "command": command(model, ZB_GRID, "attractor", y0=EQUIDISTANT_Y0[n])}
    return out


# ------------------------------------------------------ Figs. 5.23-5.25: sweeps in Omega and delta

STARTS = "phi_1=0:{top}*{k}/10:10"  # ten equidistant configurations, phi_1(0) over the symmetry period 2 pi/n
EQUI_TIES = LAUNCH_TIES
TOP = {2: "pi", 3: "2*pi/3", 4: "pi/2"}


def _starts(n: int) -> str:
    return f"phi_1=0:{TOP[n]}*9/10:10"


def omega_sweep(omegas: str = "Omega=0.5:20:40") -> dict:
    """Fig. 5.23: r_max and t_dec over Omega for ten equidistant starts, mu = 6 mu_c = 0.06/n."""
    out = {}
    for n in (2, 3, 4):
        model = f"thesis_rotating_n{n}"
        grid = [omegas, _starts(n)]
        set_ = (f"mu={0.06 / n!r}",)
        r_max, _, coords = sweep(model, grid, "r_max", set_=set_, tie=EQUI_TIES[n])
        t_dec, _, _ = sweep(model, grid, "t_dec", set_=set_, tie=EQUI_TIES[n])
        codes, labels, _ = sweep(model, grid, "attractor", set_=set_, tie=EQUI_TIES[n])
        out[n] = {"Omega": coords["Omega"], "r_max": r_max, "t_dec": t_dec,
                  "labels": np.array(named(labels, codes)).reshape(codes.shape),
                  "command": command(model, grid, "r_max", set_=set_, tie=EQUI_TIES[n])}
    return out


def delta_sweep(total: float, count: int = 20) -> dict:
    """Figs. 5.24 (total ball mass 0.03), 5.25 (0.12): r_max and t_dec over delta in (0, total] for ten
    equidistant starts, mu = total/n, Omega = 4."""
    out = {}
    for n in (2, 3, 4):
        model = f"thesis_rotating_n{n}"
        grid = [f"delta={total / count!r}:{total!r}:{count}", _starts(n)]
        set_ = (f"mu={total / n!r}",)
        r_max, _, coords = sweep(model, grid, "r_max", set_=set_, tie=EQUI_TIES[n])
        t_dec, _, _ = sweep(model, grid, "t_dec", set_=set_, tie=EQUI_TIES[n])
        out[n] = {"delta": coords["delta"], "r_max": r_max, "t_dec": t_dec,
                  "command": command(model, grid, "r_max", set_=set_, tie=EQUI_TIES[n])}
    return out


# Fig. 5.23's "For Omega < 2.04": the thesis plots Omega on [0, 20] at 50 points (20 k/49; 2.04 is k = 5), so its
# 2.04 is a grid value, not a threshold: the onset lies between the grid point below it and 2.0408
THESIS_OMEGA_GRID = np.linspace(0.0, 20.0, 50)
THESIS_ONSET = 2.04


def thesis_grid_bracket(onset: float, grid=THESIS_OMEGA_GRID) -> tuple[float, float]:
    """The two points of the thesis' Omega grid about `onset` (the last below, the first at or above)."""
    k = int(np.searchsorted(grid, onset))
    return float(grid[k - 1]), float(grid[k])


def consistent_with_grid(points: dict) -> bool:
    """Does "For Omega < 2.04, ... the balance is not stable" hold on the thesis' grid, by the runs at its grid
    points (`grid_points_check`): some start fails at the point below 2.04 and every start balances at 2.0408?"""
    below, at = points[min(points)], points[max(points)]
    return below["balanced"] < below["starts"] and at["balanced"] == at["starts"]


def grid_points_check(n: int) -> dict:
    """The thesis' grid points about its 2.04 (k = 4, 5: 1.6327, 2.0408) and 1.8 between them: the ten starts of
    Fig. 5.23 at each, decided labels (how many balance)."""
    k = int(round(THESIS_ONSET * 49 / 20))
    omegas = (float(THESIS_OMEGA_GRID[k - 1]), 1.8, float(THESIS_OMEGA_GRID[k]))
    out = {}
    for w in omegas:
        codes, labels, _ = sweep(f"thesis_rotating_n{n}", [f"Omega={w!r}:{w!r}:1", _starts(n)], "attractor",
                                 set_=(f"mu={0.06 / n!r}",), tie=EQUI_TIES[n])
        names = named(labels, codes)
        out[w] = {"balanced": count_balanced(names), "undecided": int(is_open(names).sum()), "starts": len(names)}
    return out


def common_deltas(small: dict, large: dict) -> list[dict]:
    """Fig. 5.25's "the r_max and t_dec values in the range delta in [0, 0.03] are the same than for m~ = 0.03":
    at every delta both sweeps ran (`delta_sweep` grids), the median over the ten starts of r_max and t_dec
    for each total ball mass and the relative differences (large - small) / small."""
    rows = []
    for i, d in enumerate(small["delta"]):
        j = np.nonzero(np.isclose(large["delta"], d, rtol=1e-12, atol=0.0))[0]
        if not len(j):
            continue
        a = {q: float(np.nanmedian(small[q][i])) for q in ("r_max", "t_dec")}
        b = {q: float(np.nanmedian(large[q][j[0]])) for q in ("r_max", "t_dec")}
        rows.append({"delta": float(d), "small": a, "large": b,
                     "rel": {q: (b[q] - a[q]) / a[q] for q in ("r_max", "t_dec")}})
    return rows


@dataclass
class Everything:
    scans: list = field(default_factory=list)
    launches: dict = field(default_factory=dict)
    basins_n3: list = field(default_factory=list)
    zeta_beta: dict = field(default_factory=dict)
    omega: dict = field(default_factory=dict)
    delta: dict = field(default_factory=dict)
    family_limit: float | None = None  # the zeta from which no member of the n = 3 balanced family is stable


# ----------------------------------------------------------------------------- Omega < 2.04 (Fig. 5.23)

def stability_onset(n: int, mu: float, lo: float = 0.5, hi: float = 6.0, count: int = 111) -> float | None:
    """The largest Omega in [lo, hi] at which the balanced state (the closed form's family member, see
    `balanced_stable`) changes stability (the last Hopf point H1 of thesis ch. 4), refined by bisection; None
    if it does not change.  A grid point where the state is not found is an error, not "unstable"."""
    from ....analysis.loading import AnalysisError, load_model

    model = load_model(f"thesis_rotating_n{n}")
    ws = np.linspace(lo, hi, count)
    found = [balanced_stable(model, {"Omega": float(w), "mu": mu}) for w in ws]
    if any(v is None for v in found):
        raise AnalysisError(f"the balanced state of n = {n} at mu = {mu:g} was not found at Omega = "
                            f"{ws[[v is None for v in found]][0]:g}")
    st = [bool(v) for v in found]
    ch = [i for i in range(count - 1) if st[i] != st[i + 1]]
    if not ch:
        return None
    a, b = ws[ch[-1]], ws[ch[-1] + 1]
    sa = st[ch[-1]]
    for _ in range(40):
        m = 0.5 * (a + b)
        if bool(balanced_stable(model, {"Omega": float(m), "mu": mu})) == sa:
            a = m
        else:
            b = m
    return 0.5 * (a + b)


# ------------------------------------------------------------------------------------------- compute

def compute(progress=None) -> Everything:
    def say(text):
        if progress:
            progress(text)

    out = Everything()
    out.scans = scans()
    say("Figs. 5.5, 5.7, 5.9: r_max scans done")
    out.launches = launches()
    say("Figs. 5.10-5.11: " + ", ".join(f"n = {n}: {count_balanced(v['labels'][LAUNCH_RTOLS[-1]])} balanced"
                                         for n, v in out.launches.items()))
    for n, v in out.launches.items():
        v["r_max"] = sweep(f"thesis_rotating_n{n}", [LAUNCH_GRID], "r_max",
                           y0=tuple(f"phi_{k}_dot=-4" for k in range(1, n + 1)), tie=LAUNCH_TIES[n])[0]
    out.basins_n3 = basins_n3()
    out.family_limit = family_zeta_limit(load_model("thesis_rotating_n3"))
    say("n = 3 basins: " + ", ".join(f"zeta {b['zeta']:g}: {b['balanced']}" for b in out.basins_n3)
        + f"; no member of the family stable from zeta = {out.family_limit}")
    out.zeta_beta = zeta_beta()
    say("Figs. 5.20-5.22 done")
    out.omega = omega_sweep()
    for n in (2, 3, 4):
        out.omega[n]["onset"] = stability_onset(n, 0.06 / n)
        out.omega[n]["grid_points"] = grid_points_check(n)
    say("Fig. 5.23: onsets " + ", ".join(f"{out.omega[n]['onset']}" for n in (2, 3, 4)))
    out.delta = {0.03: delta_sweep(0.03), 0.12: delta_sweep(0.12)}
    say("Figs. 5.24, 5.25 done")
    return out


# ------------------------------------------------------------------------------------------- figures

def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _dots(ax, x, y, labels):
    """The thesis' markers: '.' where the run balances, 'x' where it does not; an undecided (or failed) run
    is its own class, a red triangle with its own legend entry, never an 'x'."""
    ok, open_ = is_balanced(labels), is_open(labels)
    x, y = np.asarray(x), np.asarray(y)
    ax.plot(x[ok], y[ok], "k.", ms=3, label=f"balanced ({int(ok.sum())})")
    ax.plot(x[~ok & ~open_], y[~ok & ~open_], "kx", ms=4, label=f"not balanced ({int((~ok & ~open_).sum())})")
    if open_.any():
        ax.plot(x[open_], y[open_], "^", color="#c44e52", ms=4, label=f"undecided ({int(open_.sum())})")
        ax.legend(fontsize=6, loc="best")


PANEL_TITLE_WIDTH = 34  # characters a line of a panel title holds at 3 inches, fontsize 7


def panel_title(panel: Panel) -> str:
    """"(a1) phi_2 = -phi_1, ..." wrapped to the panel's width (unwrapped, Fig. 5.7's titles ran into each
    other, issue 36)."""
    import textwrap

    return "\n".join(textwrap.wrap(f"({panel.figure.split('(')[1]} {panel.text}", PANEL_TITLE_WIDTH))


def draw_scans(scans_: list[dict], fig_name: str, fig_dir: Path) -> Path:
    """Fig. 5.5, 5.7 or 5.9 (`fig_name`): r_max against phi_1(0), each panel's starts marked by their decided
    labels (`_dots`); fig_dir/fig5_N.png."""
    plt = _plt()
    panels = [s for s in scans_ if s["panel"].figure.startswith(fig_name + "(")]
    cols = min(len(panels), 4)
    rows = math.ceil(len(panels) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.0 * cols, 2.5 * rows), constrained_layout=True, squeeze=False)
    for ax, s in zip(axes.ravel(), panels):
        _dots(ax, s["phi_1"], s["r_max"], s["labels"])
        ax.set_title(panel_title(s["panel"]), fontsize=7)
        ax.set_xlabel(r"$\phi_1(0)$", fontsize=8)
        ax.set_ylabel(r"$r_{max}$", fontsize=8)
    for ax in axes.ravel()[len(panels):]:
        ax.set_visible(False)
    fig.suptitle(f"thesis Fig. {fig_name}: n = {panels[0]['panel'].n}, (5.1); '.' balanced, 'x' not, red "
                 "triangle undecided (rtol 1e-8; decided labels)", fontsize=9)
    path = fig_dir / f"fig{fig_name.replace('.', '_')}.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def draw(res: Everything, fig_dir: Path) -> dict[str, Path]:
    plt = _plt()
    paths = {fig_name: draw_scans(res.scans, fig_name, fig_dir) for fig_name in ("5.5", "5.7", "5.9")}
    fig, axes = plt.subplots(1, 3, figsize=(9, 2.8), constrained_layout=True)
    for ax, (n, v) in zip(axes, res.launches.items()):
        _dots(ax, v["phi_1"], v["r_max"], v["labels"][LAUNCH_RTOLS[-1]])
        ax.set_title(f"({'abc'[n - 2]}) n = {n}", fontsize=8)
        ax.set_xlabel(r"$\phi_1(0)$", fontsize=8)
    axes[0].set_ylabel(r"$r_{max}$")
    fig.suptitle(r"thesis Fig. 5.11: balls released at $\dot\phi_i(0) = -\Omega$, equidistant; '.' balanced, 'x' "
                 "not, red triangle undecided (rtol 1e-10)", fontsize=9)
    paths["5.11"] = fig_dir / "fig5_11.png"
    fig.savefig(paths["5.11"], dpi=110)
    plt.close(fig)
    fig, axes = plt.subplots(3, 3, figsize=(9, 8), constrained_layout=True)
    for col, (n, v) in enumerate(res.zeta_beta.items()):
        Z, B = np.meshgrid(v["zeta"], v["beta"], indexing="ij")
        ok = is_balanced(v["labels"])
        axes[0, col].plot(Z[ok], B[ok], "k.", ms=4)
        axes[0, col].plot(Z[is_open(v["labels"])], B[is_open(v["labels"])], "^", color="#c44e52", ms=4)
        axes[0, col].set_title(f"5.{20}({'abc'[col]}): n = {n}, balanced", fontsize=8)
        for row, (key, fig_no) in enumerate((("r_max", 21), ("t_dec", 22)), start=1):
            im = axes[row, col].pcolormesh(v["zeta"], v["beta"], np.asarray(v[key]).T, shading="nearest")
            fig.colorbar(im, ax=axes[row, col])
            axes[row, col].set_title(f"5.{fig_no}({'abc'[col]}): {key}", fontsize=8)
        for row in range(3):
            axes[row, col].set_xlabel(r"$\zeta$", fontsize=8)
            axes[row, col].set_ylabel(r"$\beta$", fontsize=8)
    fig.suptitle(r"thesis Figs. 5.20-5.22: $\Omega$ = 4, $\delta$ = 0.01, $\mu$ = 0.05, starts (5.3)-(5.5)", fontsize=9)
    paths["5.20"] = fig_dir / "fig5_20_22.png"
    fig.savefig(paths["5.20"], dpi=110)
    plt.close(fig)
    for key, title, data, xname in (("5.23", r"Fig. 5.23: $\mu = 6\mu_c$", res.omega, "Omega"),
                                    ("5.24", r"Fig. 5.24: $n\mu$ = 0.03", res.delta[0.03], "delta"),
                                    ("5.25", r"Fig. 5.25: $n\mu$ = 0.12", res.delta[0.12], "delta")):
        fig = parameter_sweep_figure(data, xname, title)
        paths[key] = fig_dir / f"fig{key.replace('.', '_')}.png"
        fig.savefig(paths[key], dpi=110)
        plt.close(fig)
    return paths


def parameter_sweep_figure(data: dict, xname: str, title: str):
    """Figs. 5.23-5.25: r_max and t_dec over Omega or delta, n = 2, 3, 4 side by side, on linear axes as the
    thesis draws them (it describes r_max growing linearly; a log axis hid that)."""
    plt = _plt()
    fig, axes = plt.subplots(2, 3, figsize=(9, 5), constrained_layout=True, sharex=True)
    for col, (n, v) in enumerate(data.items()):
        x = np.repeat(v[xname][:, None], v["r_max"].shape[1], axis=1)
        axes[0, col].plot(x.ravel(), v["r_max"].ravel(), "k.", ms=2)
        axes[1, col].plot(x.ravel(), v["t_dec"].ravel(), "k.", ms=2)
        axes[0, col].set_title(f"n = {n}", fontsize=8)
        axes[1, col].set_xlabel(r"$\Omega$" if xname == "Omega" else r"$\delta$")
    axes[0, 0].set_ylabel(r"$r_{max}$")
    axes[1, 0].set_ylabel(r"$t_{dec}$")
    fig.suptitle(f"thesis {title}, ten equidistant starts per point", fontsize=9)
    return fig


# ------------------------------------------------------------------------------------------- document

def _rel_link(path: Path, root: Path) -> str:
    return path.relative_to(root).as_posix()


def _stats(values) -> str:
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    return "—" if not len(v) else f"{v.min():.4g} / {np.median(v):.4g} / {v.max():.4g}"


def lines(res: Everything, paths: dict, root: Path, lyapunov: dict | None = None) -> list[str]:
    """The scans, launches, Omega = 1.6, n = 3 basin, damping map and Omega/delta sweep sections."""
    L = scans_lines(res, paths, root) + launches_lines(res, paths, root) + [""]
    if lyapunov:
        L += lyapunov_lines(lyapunov)
    L += basins_n3_lines(res) + [""]
    return L + damping_lines(res, paths, root) + omega_delta_lines(res, paths, root)


def scans_lines(res: Everything, paths: dict, root: Path) -> list[str]:
    """Figs. 5.5, 5.7, 5.9's section (templates/scans.md.j2)."""
    from .templates import render

    rows = []
    for s in res.scans:
        lab = s["labels"]
        good, open_ = is_balanced(lab), is_open(lab)
        bad = {k: lab.count(k) for k in sorted(set(lab)) if not balanced(k) and not is_open([k])[0]}
        rows.append({"figure": s["panel"].figure, "text": s["panel"].text, "balanced": int(good.sum()),
                     "others": ", ".join(f"{k} {v}" for k, v in bad.items()) or "none", "undecided": int(open_.sum()),
                     "stats": _stats([r for r, g in zip(s["r_max"], good) if g])})
    by = {s["panel"].figure: s for s in res.scans}
    named_rows = []
    for fig, phi, words, expect in NAMED:
        s = by[fig]
        k = int(np.argmin(np.abs(s["phi_1"] - phi)))
        named_rows.append({"figure": fig, "words": words, "label": s["labels"][k], "phi_1": s["phi_1"][k],
                           "same": s["labels"][k] == expect})
    eq = [("5.5(b)", "n = 2, in line"), ("5.7(c), 2pi/3", "n = 3, equidistant"), ("5.9(c)", "n = 4, equidistant")]
    return render("scans", command=res.scans[0]["command"], scans=rows, named=named_rows,
                  equidistant=[(t, np.median(by[f]["r_max"])) for f, t in eq],
                  figures=[(key, _rel_link(paths[key], root)) for key in ("5.5", "5.7", "5.9")])


def lyapunov_lines(lyapunov: dict) -> list[str]:
    """Figs. 5.12-5.14 (b)'s section (templates/lyapunov.md.j2): each run's exponent and its verdict."""
    from .templates import render

    runs = []
    for name, v in lyapunov.items():
        # chaotic: both halves of the window positive; regular: the exponent ~ 0 (a cycle or torus); else undecided
        verdict = "chaotic" if min(v["first_half"], v["second_half"]) > 0.01 else (
            "regular" if abs(v["exponent"]) < 0.005 else "undecided")
        runs.append((name, {**v, "verdict": verdict}))
    return render("lyapunov", runs=runs)


def damping_lines(res: Everything, paths: dict, root: Path) -> list[str]:
    """Figs. 5.20-5.22's section (templates/damping_maps.md.j2)."""
    from .templates import render

    rows = []
    corners = [(0, 0), (-1, 0), (0, -1), (-1, -1)]
    for n, v in res.zeta_beta.items():
        ok = is_balanced(v["labels"]) | is_open(v["labels"])  # "not balanced where": decided runs only
        rows.append({"n": n, "balanced": int(is_balanced(v["labels"]).sum()),
                     "undecided": int(is_open(v["labels"]).sum()),
                     "zeta": None if ok.all() else v["zeta"][np.nonzero(~ok)[0]].min(),
                     "beta": None if ok.all() else v["beta"][np.nonzero(~ok)[1]].max(),
                     "r_max": [v["r_max"][i, j] for i, j in corners], "t_dec": [v["t_dec"][i, j] for i, j in corners]})
    return render("damping_maps", command=res.zeta_beta[2]["command"], rows=rows,
                  figure=_rel_link(paths["5.20"], root))


def omega_delta_lines(res: Everything, paths: dict, root: Path) -> list[str]:
    """Figs. 5.23-5.25's section (templates/sweeps_omega_delta.md.j2): the numbers computed here, the prose there."""
    from .templates import render

    k = int(round(THESIS_ONSET * 49 / 20))
    below, at = float(THESIS_OMEGA_GRID[k - 1]), float(THESIS_OMEGA_GRID[k])
    onset_rows = []
    for n, v in res.omega.items():
        bad = v["Omega"][np.any(~is_balanced(v["labels"]) & ~is_open(v["labels"]), axis=1)]
        onset, pts = v["onset"], v.get("grid_points", {})
        onset_rows.append({
            "n": n, "onset": onset, "bracket": None if onset is None else thesis_grid_bracket(onset),
            "where": None if onset is None else ("between" if below <= onset < at else
                                                 "below" if onset < below else "above"),
            "consistent": None if not pts else consistent_with_grid(pts),
            "points": [(x["balanced"], x["undecided"]) for x in pts.values()],
            "bad": float(bad.max()) if len(bad) else None})
    spreads = []
    for fig, data in (("5.23", res.omega), ("5.24", res.delta[0.03]), ("5.25", res.delta[0.12])):
        for n, v in data.items():
            spread = np.nanmax(v["t_dec"], axis=1) - np.nanmin(v["t_dec"], axis=1)
            spreads.append((fig, n, float(np.nanmedian(v["r_max"][-1])), float(np.nanmedian(spread))))
    common = [(n, row) for n in res.delta[0.03] for row in common_deltas(res.delta[0.03][n], res.delta[0.12][n])]
    worst = {q: max((abs(r["rel"][q]) for _, r in common), default=0.0) for q in ("r_max", "t_dec")}
    return render("sweeps_omega_delta", command=res.omega[2]["command"], published=THESIS_ONSET, below=below,
                  at=at, onsets=onset_rows, spreads=spreads, common=common, worst=worst,
                  figures=[(k, _rel_link(paths[k], root)) for k in ("5.23", "5.24", "5.25")])


def basins_n3_lines(res: Everything) -> list[str]:
    """The n = 3 basin experiment's section (templates/basins_n3.md.j2)."""
    from .templates import render

    rows = [{**b, "others": ", ".join(f"{k} {v}" for k, v in b["counts"].items()
                                      if not balanced(k) and not is_open([k])[0]) or "none"} for b in res.basins_n3]
    return render("basins_n3", basins=rows, published=N3_PUBLISHED, t_end=N3_T_END,
                  limit=getattr(res, "family_limit", None),
                  any_balanced_unstable=any(b["balanced"] and b["family"][0] > 0 for b in rows))


def _count_cell(labels) -> str:
    return f"{count_balanced(labels)}" + (f" ({int(is_open(labels).sum())} undecided)" if is_open(labels).any() else "")


def launches_lines(res: Everything, paths: dict, root: Path) -> list[str]:
    """Figs. 5.10-5.11's launches section (templates/launches.md.j2)."""
    from .templates import render

    rows = []
    for n, v in res.launches.items():
        counts = [count_balanced(v["labels"][r]) for r in LAUNCH_RTOLS]
        rows.append({"n": n, "published": LAUNCH_PUBLISHED[n], "counts": [_count_cell(v["labels"][r]) for r in LAUNCH_RTOLS],
                     "low": min(counts), "high": max(counts),
                     "published_in_range": min(counts) <= LAUNCH_PUBLISHED[n] <= max(counts),
                     "ode45": "—" if v.get("ode45") is None else _count_cell(v["ode45"]), "changes": len(v["changes"]),
                     "local": "; ".join(f"{x['phi_1']:.4f}: {x['balanced']}, {x['switches']}" for x in v["local"]) or "—"})
    rtols = [f"1e{round(math.log10(r))}" for r in LAUNCH_RTOLS]  # as the tolerances are written: 1e-6, not 1e-06
    return render("launches", command=next(iter(res.launches.values()))["command"], rtols=rtols, rows=rows,
                  figure=_rel_link(paths["5.11"], root))
