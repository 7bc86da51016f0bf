"""`adbgen reproduce`, the thesis (the single-plane family): chapters 4 and 5 recomputed on the generated
models, the thesis' sections of docs/reproduction.md (`REPRODUCTION`, listed by the family's
`reproductions()`).

For every published number: the published value, ours converged in tolerance (DOP853 on the compiled
path at rtol 1e-12, atol 1e-14), the relative difference, and the tolerance study beside it (the value
at rtol 1e-6, 1e-8, 1e-10, 1e-12: it no longer moves as rtol tightens).  Where a trajectory does not
balance, the attractor is named by `attractors.Classifier` (steady state by Newton, limit cycle by a
further window) and the final state compared with the published one.

Covered: what `coverage.THESIS` lists (the covered / not covered table at the top of the document): ch. 3
(chapter3.py), ch. 4's limits, lines and maps, ch. 5's transients, end states, scans, launches, basins,
sweeps (with sweeps.py, sensitivity.py, starts.py, plain.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .balanced import balanced_stable

from ....analysis.loading import load_model
from ....analysis.reproduction import Reproduction
from .published import EQUIDISTANT, TRANSIENTS, Transient, printed_half_unit
from ....analysis.tolerance import MARK

PI = math.pi
RTOLS = (1e-6, 1e-8, 1e-10, 1e-12)
T_END = 3000.0
ENGINE = "cyrk-dop853"  # named: the document must not follow a change of the default engine
ODE45 = ("matlab-ode45", 1e-3, 1e-6)  # the thesis' integrator at its defaults (RelTol, AbsTol)


@dataclass
class Case:
    figure: str
    n: int
    phi0: tuple[float, ...]
    phi0_text: str
    published: dict  # "r_max", "t_dec" -> value; or "attractor" -> name, "state" -> {name: value}
    params: dict = field(default_factory=dict)


CASES = [  # the runs the thesis describes by their attractor or end state (its r_max, t_dec: published.py)
    Case("5.4(b)", 2, (PI / 4, -PI / 4), "(pi/4, -pi/4)", {"attractor": "limit cycle"}),
    Case("5.7 text, 2-", 3, (PI, PI, PI), "(pi, pi, pi)",
         {"attractor": "coincident 2-", "state": {"x": 0.1285, "y": -0.0083, "phi_1": 3.0772}}),
    Case("5.7 text, 3(3-2)-", 3, (0.0, 0.0, PI), "(0, 0, pi)",
         {"attractor": "in-line 3(3-2)-", "state": {"x": 0.0368, "y": -0.0007, "phi_1": -3.16, "phi_3": -0.0184}}),
    Case("5.15(a)", 2, *EQUIDISTANT[2], {"attractor": "balanced 1"}, {"zeta": 0.25}),
    Case("5.16(a)", 3, *EQUIDISTANT[3], {"attractor": "limit cycle"}, {"zeta": 0.25}),
    Case("5.17(a)", 4, *EQUIDISTANT[4], {"attractor": "limit cycle"}, {"zeta": 0.25}),
    # section 5.2.1, Figs. 5.12-5.14 (a) and (d): Omega = 0.5 and mu = 0.0025
    *(Case(f"5.{10 + n}(a)", n, *EQUIDISTANT[n], {"attractor": "coincident 2-"}, {"Omega": 0.5}) for n in (2, 3, 4)),
    Case("5.12(d)", 2, *EQUIDISTANT[2], {"attractor": "coincident 2-"}, {"mu": 0.0025}),
    Case("5.13(d)", 3, *EQUIDISTANT[3], {"attractor": "coincident 2-"}, {"mu": 0.0025}),
    Case("5.14(d)", 4, *EQUIDISTANT[4], {"attractor": "balanced 1"}, {"mu": 0.0025}),
    # section 5.2.2, Figs. 5.15-5.17 (d): Omega = 1.6, zeta = beta = 0.25
    Case("5.15(d)", 2, *EQUIDISTANT[2], {"attractor": "balanced 1"}, {"Omega": 1.6, "zeta": 0.25, "beta": 0.25}),
    Case("5.16(d)", 3, *EQUIDISTANT[3], {"attractor": "limit cycle"}, {"Omega": 1.6, "zeta": 0.25, "beta": 0.25}),
    Case("5.17(d)", 4, *EQUIDISTANT[4], {"attractor": "balanced 1"}, {"Omega": 1.6, "zeta": 0.25, "beta": 0.25}),
]


@dataclass
class Statement:
    """A stability statement of thesis ch. 4 (read off a figure by the text, so approximate)."""

    source: str
    n: int
    text: str  # the thesis' words
    kind: str  # "zeta_limit" (largest stable zeta at fixed Omega, beta), "beta_all" (smallest beta from which
    # the balanced state is stable up to zeta = 0.5, at fixed Omega) or "line" (stable at every point of a line)
    Omega: float
    beta: float | None
    published: float
    line: dict = field(default_factory=dict)  # "line": the swept parameter -> (from, to, count), fixed values


STATEMENTS = [
    Statement("Fig. 4.8(b) text", 3, "for Omega = 3 ... stable only for zeta < 0.02", "zeta_limit", 3.0, 0.01, 0.02),
    Statement("Fig. 4.13(b) text", 4, "when Omega = 3, 1 is only stable for zeta < 0.1", "zeta_limit", 3.0, 0.01,
              0.1),
    Statement("section 5.2.2 text", 3, "for Omega = 4 ... only stable for zeta < 0.02", "zeta_limit", 4.0, 0.01,
              0.02),
    Statement("section 5.2.2 text", 4, "for Omega = 4 ... (only stable for) zeta < 0.1", "zeta_limit", 4.0, 0.01,
              0.1),
    Statement("Fig. 4.9(b) text", 3, "for beta = 0.25 ... for Omega = 3, the state 1 is stable approximately for "
              "zeta < 0.5", "zeta_limit", 3.0, 0.25, 0.5),
    Statement("Fig. 4.9(a) text", 3, "for beta > 0.25 (0.2 in the n = 4 text) stable in the whole range 0 < zeta < 0.5",
              "beta_all", 4.0, None, 0.25),
    Statement("Fig. 4.14(a) text", 4, "when beta is approximately larger than 0.05, 1 is stable for all zeta "
              "in 0 < zeta < 0.5", "beta_all", 4.0, None, 0.05),
]

# "along its line" (issue 23): the Omega > 2.5 statements, each checked on a grid of its diagram's plane
LINES = [
    Statement("Fig. 4.4 text", 2, "it is always stable for Omega > 2.5 (each of delta, zeta, beta varied)", "line",
              2.5, None, 2.5, {"Omega": (2.5, 10.0, 76), "delta": (0.005, 0.1, 20)}),
    Statement("Fig. 4.4(b) text", 2, "it is always stable for Omega > 2.5 (zeta varied)", "line", 2.5, None, 2.5,
              {"Omega": (2.5, 10.0, 76), "zeta": (0.005, 0.5, 20)}),
    Statement("Fig. 4.4(c) text", 2, "it is always stable for Omega > 2.5 (beta varied)", "line", 2.5, None, 2.5,
              {"Omega": (2.5, 10.0, 76), "beta": (0.005, 0.5, 20)}),
    Statement("Fig. 4.13(c) text", 4, "approximately for Omega > 2.5, 1 is stable for all beta values", "line", 2.5,
              None, 2.5, {"Omega": (2.5, 10.0, 76), "beta": (0.005, 0.5, 20)}),
]

SMALL_ZETA = np.geomspace(1e-7, 2.5e-3, 30)  # the scan in zeta starts here: the balanced state is unstable for
# zeta below a bound of order 1e-4 at every beta (the thesis' "whole range 0 < zeta" included)


def _bisect(model, values: dict, a: float, b: float, stable_at_a: bool) -> float:
    for _ in range(40):
        m = 0.5 * (a + b)
        if bool(balanced_stable(model, {**values, "zeta": m})) == stable_at_a:
            a = m
        else:
            b = m
    return 0.5 * (a + b)


def zeta_window(model, Omega: float, beta: float, zmax: float = 0.5) -> tuple[float | None, float | None]:
    """(lower, upper): the balanced state is stable for lower < zeta < upper at (Omega, beta) (scan of
    SMALL_ZETA and 200 points up to zmax, each change refined by bisection); upper None when stable up to
    zmax, lower None when stable down to the scan's 1e-7."""
    zs = np.concatenate([SMALL_ZETA, np.linspace(zmax / 200, zmax, 200)])
    values = {"Omega": Omega, "beta": beta}
    stable = [bool(balanced_stable(model, {**values, "zeta": z})) for z in zs]
    if not any(stable):
        return None, 0.0
    first = stable.index(True)
    last = len(stable) - 1 - stable[::-1].index(True)
    lower = None if first == 0 else _bisect(model, values, zs[first - 1], zs[first], False)
    upper = None if last == len(zs) - 1 else _bisect(model, values, zs[last], zs[last + 1], True)
    return lower, upper


def _beta_all(model, Omega: float) -> float:
    """The smallest beta (to 1e-3) from which the balanced state is stable up to zeta = 0.5."""
    a, b = 0.0, 1.0
    for _ in range(10):
        m = 0.5 * (a + b)
        if zeta_window(model, Omega, m)[1] is None:
            b = m
        else:
            a = m
    return b


def line_check(model, st: Statement) -> dict:
    """The balanced state's stability on the grid of the statement's plane: the unstable points and the
    largest Omega among them."""
    (pa, (a0, a1, na)), (pb, (b0, b1, nb)) = st.line.items()
    bad = []
    for u in np.linspace(a0, a1, na):
        for v in np.linspace(b0, b1, nb):
            if not balanced_stable(model, {pa: float(u), pb: float(v)}):
                bad.append((float(u), float(v)))
    return {"points": na * nb, "unstable": bad, "planes": (pa, pb), "ranges": ((a0, a1, na), (b0, b1, nb))}


def statement_values() -> list[tuple[Statement, object]]:
    out = []
    for st in STATEMENTS + LINES:
        model = load_model(f"thesis_rotating_n{st.n}")
        if st.kind == "zeta_limit":
            value = zeta_window(model, st.Omega, st.beta)
        elif st.kind == "beta_all":
            beta = _beta_all(model, st.Omega)
            value = (beta, zeta_window(model, st.Omega, beta)[0], zeta_window(model, st.Omega, st.published)[0])
        else:
            value = line_check(model, st)
        out.append((st, value))
    return out


def pitchfork_hopf(n: int, damping: float = 0.01) -> list[float]:
    """Where the coincident state 2- at mu = mu_c = delta/n (all balls at pi, x = y = 0: also the balanced
    state there) has a complex pair on the imaginary axis: the codimension-two pitchfork-Hopf points of thesis
    4.1-4.3, from the generated Jacobian (zeta = beta = damping, delta = 0.01)."""
    from scipy.optimize import brentq

    model = load_model(f"thesis_rotating_n{n}")
    y = model.state({f"phi_{i + 1}": PI for i in range(n)})

    def growth(Om):
        p = model.params({"Omega": float(Om), "mu": 0.01 / n, "zeta": damping, "beta": damping})
        ev = np.linalg.eigvals(np.asarray(model.module.jac(0.0, y, p)))
        return float(ev[np.abs(ev.imag) > 1e-9].real.max())

    grid = np.linspace(0.9, 1.5, 121)
    g = [growth(w) for w in grid]
    return [brentq(growth, grid[i], grid[i + 1], xtol=1e-12) for i in range(len(grid) - 1) if g[i] * g[i + 1] < 0]


def wedge_tip_spectrum(n: int, past: float = 0.0) -> list[complex]:
    """The three eigenvalues nearest 0 of that state at the wedge tip (4.1)-(4.2), (mu_c, 1/sqrt(1 + delta)),
    or `past` beyond it in Omega."""
    model = load_model(f"thesis_rotating_n{n}")
    y = model.state({f"phi_{i + 1}": PI for i in range(n)})
    p = model.params({"Omega": 1.0 / math.sqrt(1.01) + past, "mu": 0.01 / n})
    ev = np.linalg.eigvals(np.asarray(model.module.jac(0.0, y, p)))
    return sorted(ev, key=lambda z: (abs(z), z.imag))[:4]


# the thesis' stability maps recomputed, each with its own figure number: the (Omega, mu) diagrams of Figs. 4.1,
# 4.5, 4.10 (n = 2, 3, 4) and the (zeta, beta) diagrams of Figs. 4.9(a), 4.14(a) (n = 3, 4; the thesis has no
# n = 2 (zeta, beta) diagram: there the balanced state is stable on the whole square)
MAPS = (
    (2, "(Omega, mu)", ("Omega=0.2:4:39", "mu=0.001:0.1:34"), "4.1"),
    (3, "(Omega, mu)", ("Omega=0.2:4:39", "mu=0.001:0.1:34"), "4.5"),
    (4, "(Omega, mu)", ("Omega=0.2:4:39", "mu=0.001:0.1:34"), "4.10"),
    (3, "(zeta, beta)", ("zeta=0.005:0.5:34", "beta=0.005:0.5:34"), "4.9(a)"),
    (4, "(zeta, beta)", ("zeta=0.005:0.5:34", "beta=0.005:0.5:34"), "4.14(a)"),
)


def map_caption(n: int, plane: str, figure: str) -> str:
    return f"n = {n}: unstable eigenvalues of the balanced state over {plane} (thesis Fig. {figure})"


def _maps(fig_dir: Path) -> list[tuple[str, Path]]:
    """Stability maps of the balanced state by `adbgen sweep --measure stability` (figures copied)."""
    import shutil
    import tempfile

    from ....analysis.sweep import SweepSpec, run_sweep

    out = []
    tmp = Path(tempfile.mkdtemp(prefix="adbgen-reproduce-"))
    try:
        for n, plane, grid, figure in MAPS:
            key = f"fig4_n{n}_{'omega_mu' if 'Omega' in plane else 'zeta_beta'}"
            spec = SweepSpec(model=f"thesis_rotating_n{n}", grid=list(grid), measure="stability", set=[])
            run_sweep(spec, tmp / key, progress=False)
            target = fig_dir / f"{key}.png"
            shutil.copyfile(tmp / key / "stability.png", target)
            out.append((map_caption(n, plane, figure), target))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return out


BASIN_ZETAS = (0.01, 0.1, 0.2, 0.25)  # thesis Fig. 5.18(a)-(d): Omega = 4, beta = delta = 0.01, mu = 0.05


def _basins(fig_dir: Path, size: int = 40) -> list[dict]:
    """Fig. 5.18: basin maps of n = 2 over (phi_1(0), phi_2(0)) for the four zeta of the figure."""
    import json
    import shutil
    import tempfile

    import xarray as xr

    from ....analysis.sweep import SweepSpec, run_sweep

    out = []
    tmp = Path(tempfile.mkdtemp(prefix="adbgen-reproduce-basins-"))
    try:
        for k, zeta in enumerate(BASIN_ZETAS):
            grid = [f"phi_1=0:2*pi*{size - 1}/{size}:{size}", f"phi_2=0:2*pi*{size - 1}/{size}:{size}"]
            spec = SweepSpec(model="thesis_rotating_n2", grid=grid, measure="attractor", set=[f"zeta={zeta}"],
                             t_end=2000.0, engine=ENGINE)
            run_sweep(spec, tmp / str(k), progress=False)
            ds = xr.open_zarr(tmp / str(k) / "sweep.zarr", consolidated=False)
            names = json.loads(ds.attrs["labels"])
            codes = ds["attractor"].values
            target = fig_dir / f"fig5_18{'abcd'[k]}.png"
            shutil.copyfile(tmp / str(k) / "attractor.png", target)
            counts = {names[c]: int((codes == c).sum()) for c in np.unique(codes)}
            p1, p2 = np.meshgrid(ds["phi_1"].values, ds["phi_2"].values, indexing="ij")
            near_inline = np.abs(_wrap_array(p2 - p1 - PI)) < PI / 3  # about phi_2 = phi_1 +- pi
            balanced = _balanced_codes(names, codes)
            out.append({"zeta": zeta, "panel": "abcd"[k], "counts": counts, "figure": target,
                        "balanced": float(balanced.mean()),
                        "inline_share": float(near_inline[balanced].mean()) if balanced.any() else None})
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return out


def _balanced_codes(names, codes) -> np.ndarray:
    """Where the decided label is balanced (exponential or algebraic approach; undecided runs are not)."""
    from .sweeps import balanced

    return np.isin(codes, [k for k, name in enumerate(names) if balanced(name)])


FIG5_19_ZETAS = (0.01, 0.1, 0.2, 0.25)  # thesis Fig. 5.19(a)-(d): n = 4, phi_3 = phi_1 + pi, phi_4 = phi_2 + pi


def _basins_n4(fig_dir: Path, size: int = 16, panels: str = "abcd") -> list[dict]:
    """Fig. 5.19 (a)-(d) (those of `panels`): basin maps of n = 4 with the third and fourth balls opposite the
    first two."""
    import json
    import shutil
    import tempfile

    import xarray as xr

    from ....analysis.sweep import SweepSpec, run_sweep

    out = []
    tmp = Path(tempfile.mkdtemp(prefix="adbgen-reproduce-n4-"))
    try:
        for zeta, panel in ((z, q) for z, q in zip(FIG5_19_ZETAS, "abcd") if q in panels):
            grid = [f"phi_1=0:2*pi*{size - 1}/{size}:{size}", f"phi_2=0:2*pi*{size - 1}/{size}:{size}"]
            spec = SweepSpec(model="thesis_rotating_n4", grid=grid, measure="attractor", set=[f"zeta={zeta}"],
                             tie=["phi_3=phi_1+pi", "phi_4=phi_2+pi"], t_end=3000.0, engine=ENGINE)
            run_sweep(spec, tmp / panel, progress=False)
            ds = xr.open_zarr(tmp / panel / "sweep.zarr", consolidated=False)
            names = json.loads(ds.attrs["labels"])
            codes = ds["attractor"].values
            target = fig_dir / f"fig5_19{panel}.png"
            shutil.copyfile(tmp / panel / "attractor.png", target)
            balanced = _balanced_codes(names, codes)
            diagonal = np.eye(size, dtype=bool)
            p1, p2 = np.meshgrid(ds["phi_1"].values, ds["phi_2"].values, indexing="ij")
            centres = [(a, b) for a in (PI / 2, 3 * PI / 2) for b in (PI / 2, 3 * PI / 2)]
            near = np.zeros_like(balanced)
            for a, b in centres:
                near |= np.hypot(_wrap_array(p1 - a), _wrap_array(p2 - b)) < 0.6
            off = balanced & ~diagonal
            out.append({"zeta": zeta, "panel": panel, "figure": target, "size": size,
                        "counts": {names[c]: int((codes == c).sum()) for c in np.unique(codes)},
                        "balanced": float(balanced.mean()), "diagonal": float(balanced[diagonal].mean()),
                        "off_diagonal_balanced": int(off.sum()),
                        "off_diagonal_near_centres": int((off & near).sum()),
                        "near_share_of_grid": float(near[~diagonal].mean()),
                        "off_diagonal_on_shifted": int((off & (np.abs(_wrap_array(p2 - p1 - PI)) < 1e-9)).sum())})
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return out


def _basin_rows(basins, root: Path) -> list[dict]:
    """The basin panels with their other attractors' cell and their figure's link, for the templates."""
    from .sweeps import balanced

    return [{**b, "others": ", ".join(f"{k} {v}" for k, v in b["counts"].items() if not balanced(k)) or "none",
             "link": b["figure"].relative_to(root).as_posix()} for b in basins]


def _basin_n4_section(basins, root: Path) -> list[str]:
    """Fig. 5.19's section (templates/basins_n4.md.j2)."""
    from .templates import render

    if not basins:
        return []
    rows = _basin_rows(basins, root)
    b = rows[1]
    b["not_balancing"] = b["size"] ** 2 - round(b["balanced"] * b["size"] ** 2)
    return render("basins_n4", basins=rows, size=rows[0]["size"], a=rows[0], b=b, c=rows[2],
                  d=rows[3])


def _simulate(n: int, phi0, params: dict, rtol: float, atol: float | None = None, engine: str = ENGINE,
              keep: bool = False, threshold: float = 1e-3):
    from ....analysis.simulate import simulate

    model = load_model(f"thesis_rotating_n{n}")
    y0 = model.state({f"phi_{i + 1}": v for i, v in enumerate(phi0)})
    return model, simulate(model, model.params(params), y0, t_end=T_END, rtol=rtol,
                           atol=rtol * 1e-2 if atol is None else atol, engine=engine, keep_trajectory=keep,
                           threshold=threshold, check=False)


def _run(case, rtol: float, keep: bool = False, threshold: float = 1e-3):
    return _simulate(case.n, case.phi0, case.params, rtol, keep=keep, threshold=threshold)


def _ode45(row, rtol: float = ODE45[1], atol: float = ODE45[2], keep: bool = False):
    return _simulate(row.n, row.phi0, row.params, rtol, atol, engine=ODE45[0], keep=keep)[1]


def transient(row: Transient) -> dict:
    """A published transient recomputed: converged (ENGINE at every RTOLS), the ode45 emulation at MATLAB's
    defaults; where neither gives the printed t_dec, the study that locates the difference: the threshold
    moved by 1 %, the emulation at tighter RelTol, the emulation's output points about its t_dec."""
    from .sensitivity import check_transient

    sims = {r: _simulate(row.n, row.phi0, row.params, r)[1] for r in RTOLS}
    ode45 = _ode45(row, keep=True)
    out = {"row": row, "sims": sims, "ode45": ode45,
           "check": check_transient(row.n, row.phi0, row.params, sims, ENGINE)}
    conv = sims[RTOLS[-1]]
    if not (_printed(conv.t_dec, row.t_dec) or _printed(ode45.t_dec, row.t_dec)):
        r = np.hypot(ode45.y[0], ode45.y[1])
        k = int(np.searchsorted(ode45.t, ode45.t_dec))
        out["output_points"] = (float(ode45.t[k]), float(ode45.t[k + 1]) if k + 1 < len(ode45.t) else None,
                                float(r[k + 1]) if k + 1 < len(r) else None)
        out["ode45_tight"] = {rt: _ode45(row, rt, rt * 1e-3).t_dec for rt in (1e-4, 1e-5)}
        out["threshold"] = {h: _simulate(row.n, row.phi0, row.params, RTOLS[-1], threshold=h)[1].t_dec
                            for h in (0.99e-3, 1.01e-3)}
    return out


CONVERGED = 1e-3  # the two tightest rtols of the ladder agree to this (relative) or the value is not converged


def not_converged(values) -> tuple[float, float] | None:
    """The tolerance ladder's values of one quantity (ascending precision): None where the two tightest agree to
    CONVERGED (relative), else the range over the ladder's rtols from the second on (what a converged value
    would have to be stated with: Fig. 5.14(c)'s t_dec moves by several time units from rtol to rtol)."""
    v = [float(x) for x in values if x is not None and math.isfinite(x)]
    if len(v) < 2:
        return None
    if abs(v[-1] - v[-2]) <= CONVERGED * max(abs(v[-1]), abs(v[-2])):
        return None
    tail = v[1:]
    return min(tail), max(tail)


def _printed(ours, published) -> bool:
    """ours equals the published number to its printed digits."""
    return ours is not None and math.isfinite(ours) and abs(ours - published) <= printed_half_unit(published)


def _wrap(a: float) -> float:
    return (a + PI) % (2 * PI) - PI


def _wrap_array(a: np.ndarray) -> np.ndarray:
    return np.remainder(a + PI, 2 * PI) - PI


def _printed_half_unit(value: float) -> float:
    """Half a unit in the last digit the thesis prints (0.0007 -> 5e-5, 1330.20 -> 5e-3)."""
    text = repr(float(value))
    decimals = len(text.split(".")[1]) if "." in text and "e" not in text else 0
    return 0.5 * 10.0 ** (-decimals)


def study(case: Case) -> dict:
    """The case at every tolerance; the attractor and final state at the tightest."""
    from ....analysis.attractors import classifier

    rows = {}
    for rtol in RTOLS:
        model, sim = _run(case, rtol)
        rows[rtol] = sim
    best = rows[RTOLS[-1]]
    clf = classifier(model, model.params(case.params))
    # the classifier integrates on to tell a cycle and to decide a run not named at T_END by its approach: on
    # the pinned engine too (it had taken the default, whose coarser steps put the band test of Fig. 5.4(b)'s
    # cycle over its 1 %)
    outcome = clf.decide(best.status, best.y_end, -1, engine=ENGINE, rtol=RTOLS[-1], atol=RTOLS[-1] * 1e-2,
                         t=T_END)
    from .sensitivity import check_transient

    out = {"model": model, "sims": rows, "label": outcome.label, "outcome": outcome,
           "check": check_transient(case.n, case.phi0, case.params, rows, ENGINE)}
    if outcome.approach == "algebraic" or outcome.label == "undecided":
        out["slow"] = slow_approach(model, model.params(case.params), best.y_end)
    return out


SLOW_CHECKPOINTS = (30000.0, 100000.0)


def slow_approach(model, p, y_end, checkpoints=SLOW_CHECKPOINTS) -> dict:
    """An end state the classifier does not name at t = T_END, integrated on to the checkpoints: the band
    of r over the last tenth of each stretch, the exponent k of r ~ t^-k between the last two, how far apart
    the balls' angles are, and the number of neutral directions of the linearisation at the last state (the
    balanced family's tangent).  A power law in t, not an exponential, is the signature of a non-hyperbolic
    attractor (Fig. 5.14(d): n = 4 at mu = mu_c, where the balanced family shrinks to the balls together)."""
    from ....analysis import steady
    from ....analysis.attractors import balls, spectrum
    from ....analysis.simulate import simulate

    ix, iy, _, _ = model.amplitude_indices
    angles = balls(model)
    rows, y, t = [], np.asarray(y_end, float), T_END
    for t_next in checkpoints:
        sim = simulate(model, p, y, t_end=t_next - t, rtol=RTOLS[-1], atol=RTOLS[-1] * 1e-2, engine=ENGINE,
                       keep_trajectory=True, check=False)
        r = np.hypot(sim.y[ix], sim.y[iy])[sim.t >= 0.9 * (t_next - t)]
        phi = _wrap_array(sim.y_end[angles] - sim.y_end[angles[0]])
        rows.append({"t": t_next, "r_max": float(r.max()), "r_min": float(r.min()),
                     "spread": float(phi.max() - phi.min())})
        y, t = sim.y_end, t_next
    first, last = rows[-2], rows[-1]
    k = -math.log(last["r_max"] / first["r_max"]) / math.log(last["t"] / first["t"])
    # the state the run tends to: the rotor at rest at the centre, every ball at the balls' mean angle
    mean = float(np.angle(np.exp(1j * y[angles]).mean()))
    limit = np.zeros_like(y)
    limit[angles] = mean
    return {"checkpoints": rows, "exponent": k, "limit_angle": mean,
            "limit_residual": float(np.max(np.abs(steady.residual(model, limit, p)))),
            "neutral": spectrum(model, limit, p).neutral, "free_angles": len(angles) - 2,
            "r_start": float(np.hypot(y_end[ix], y_end[iy]))}


def _fmt(v, digits=5):
    return "—" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.{digits}g}"


def _rel(ours, published):
    if ours is None or not math.isfinite(ours):
        return None
    return (ours - published) / published


def compute(fig_dir: Path, progress=print) -> dict:
    """Every case, statement and map of the thesis' sections; the panels drawn into fig_dir."""
    transients = []
    for row in TRANSIENTS:
        transients.append(transient(row))
        if progress:
            t = transients[-1]
            progress(f"Fig. {row.figure:8s} n = {row.n}: t_dec published {row.t_dec:g}, converged "
                     f"{_fmt(t['sims'][RTOLS[-1]].t_dec, 6)}, ode45 emulation {_fmt(t['ode45'].t_dec, 6)}")
    results = []
    for case in CASES:
        results.append((case, study(case)))
        if progress:
            progress(f"Fig. {case.figure:16s} n = {case.n} phi(0) = {case.phi0_text}: {results[-1][1]['label']}")
    figures = _figures(fig_dir)
    statements = statement_values()
    if progress:
        for st, v in statements:
            progress(f"{st.source:22s} n = {st.n}: {st.kind} published {st.published:g}, ours "
                     f"{v if st.kind != 'line' else len(v['unstable'])}")
    from . import sweeps

    more = sweeps.compute(progress)
    more_paths = sweeps.draw(more, fig_dir)
    lyap = lyapunov_runs()
    if progress:
        progress("Omega = 1.6 Lyapunov exponents: " + ", ".join(f"{k} {v['exponent']:.3f}" for k, v in lyap.items()))
    pitchfork = {"damped": {n: pitchfork_hopf(n) for n in (2, 3, 4)},
                 "limit": {n: pitchfork_hopf(n, 1e-4) for n in (2, 3, 4)}, "tip": wedge_tip_spectrum(2),
                 "past": wedge_tip_spectrum(2, 0.001)}
    from . import sensitivity

    tolerance = sensitivity.compute(fig_dir, sensitivity.Ladder(ENGINE, RTOLS, T_END, ODE45), progress)
    from . import starts

    named = starts.compute(progress)
    from . import chapter3

    ch3 = chapter3.compute()
    from . import one_parameter

    diagrams = one_parameter.compute()
    from . import bifurcation_plane

    planes = bifurcation_plane.compute()
    planes["figures"] = bifurcation_plane.draw(planes, fig_dir)
    if progress:
        for c in bifurcation_plane.statements(planes):
            progress(f"Fig. 4.1/4.5/4.10 n = {c['n']}: {c['text']}: {'holds' if c['holds'] else 'does not hold'}")
    maps = _maps(fig_dir)
    basins = _basins(fig_dir)
    basins_n4 = _basins_n4(fig_dir)
    if progress:
        for b in basins:
            progress(f"Fig. 5.18({b['panel']}) zeta = {b['zeta']:g}: {b['counts']}")
        for b in basins_n4:
            progress(f"Fig. 5.19({b['panel']}) zeta = {b['zeta']:g}: {b['counts']}")
    return {"transients": transients, "results": results, "figures": figures, "statements": statements,
            "maps": maps, "basins": basins, "basins_n4": basins_n4, "pitchfork": pitchfork, "sweeps": more,
            "sweep_figures": more_paths, "lyapunov": lyap, "sensitivity": tolerance, "starts": named,
            "chapter3": ch3, "one_parameter": diagrams, "bifurcation_plane": planes}


def lines(res: dict, root: Path) -> list[str]:
    from . import sensitivity, sweeps

    L = _document(res["transients"], res["results"], res["figures"], root, res["statements"], res["maps"],
                  res["basins"], res["basins_n4"], res.get("pitchfork"))
    at = L.index("## Thesis, chapter 4: stability of the balanced state")
    L = L[:at] + sweeps.lines(res["sweeps"], res["sweep_figures"], root, res["lyapunov"]) + L[at:]
    if "sensitivity" in res:  # every transient checked (issue 34), and Fig. 5.10 before the launches
        checked = [(t["row"].figure, t["row"].phi0_text, t["check"]) for t in res["transients"]]
        checked += [(case.figure, case.phi0_text, r["check"]) for case, r in res["results"]]
        at = L.index("## Figures")
        L = L[:at] + sensitivity.transient_lines(checked) + L[at:]
        launches = [k for k, line in enumerate(L) if line.startswith("## Thesis, Figs. 5.10-5.11")]
        at = launches[0] if launches else L.index("## Thesis, chapter 4: stability of the balanced state")
        L = L[:at] + sensitivity.lines(res["sensitivity"], root) + L[at:]
    if "starts" in res:  # Figs. 5.1-5.3 and the named starts' explanations, after the scans that name them
        from . import starts

        at = next(k for k, line in enumerate(L) if line.startswith("## Thesis, Fig")
                  and k > L.index("## Thesis, Figs. 5.5, 5.7, 5.9: r_max against the starting position"))
        L = L[:at] + starts.lines(res["starts"]) + [""] + L[at:]
    if "results" in res and "lyapunov" in res:  # the rotor without balls beside Figs. 5.12-5.14
        from . import plain

        # after the Omega = 1.6 section (its r over the window is the (b) row), before the n = 3 basins
        at = next((k for k, line in enumerate(L) if line.startswith("## Thesis, section 5.2.2")),
                  L.index("## Thesis, chapter 4: stability of the balanced state"))
        L = L[:at] + plain.lines(res["results"], res["lyapunov"]) + [""] + L[at:]
    if "chapter3" in res:
        from . import chapter3

        at = L.index("## Thesis, chapter 4: stability of the balanced state")
        L = L[:at] + chapter3.lines(res["chapter3"]) + [""] + L[at:]
    if "one_parameter" in res:
        from . import one_parameter

        at = L.index("## Thesis, chapter 4: stability of the balanced state")
        L = L[:at] + one_parameter.lines(res["one_parameter"]) + [""] + L[at:]
    if "bifurcation_plane" in res:
        from . import bifurcation_plane

        at = L.index("## Thesis, chapter 4: stability of the balanced state")
        planes = res["bifurcation_plane"]
        L = L[:at] + bifurcation_plane.lines(planes, planes["figures"], root) + [""] + L[at:]
    return L


def lyapunov_runs() -> dict:
    """The largest Lyapunov exponent of Figs. 5.12-5.14 (b) (Omega = 1.6, starts (5.3)-(5.5)) and of the
    limit cycle of Fig. 5.4(b) as the control."""
    from .lyapunov_exponents import largest_exponent

    out = {}
    runs = [(f"5.{10 + n}(b), n = {n}", n, EQUIDISTANT[n][0], {"Omega": 1.6}) for n in (2, 3, 4)]
    runs.append(("5.4(b), n = 2 (control: a limit cycle)", 2, (PI / 4, -PI / 4), {}))
    for name, n, phi0, params in runs:
        model = load_model(f"thesis_rotating_n{n}")
        y0 = model.state({f"phi_{i + 1}": v for i, v in enumerate(phi0)})
        out[name] = largest_exponent(model, model.params(params), y0, t_transient=1000.0, t_average=4000.0)
    return out


THESIS_PITCHFORK_HOPF = 0.9950372  # thesis (4.1)-(4.2): (mu_c, 1/sqrt(1 + n mu_c))


def _chapter4(statements, maps, root: Path, pitchfork=None) -> list[str]:
    """Ch. 4's limits of the balanced state, the statements along a line, (4.1)-(4.2) and the maps
    (templates/chapter4_balanced.md.j2)."""
    from .templates import render

    lines = []
    for st, v in statements:
        if st.kind == "line":
            at = {w for _, w in v["unstable"]}
            lines.append({**v, "st": st, "largest": max((u for u, _ in v["unstable"]), default=None),
                          "at": sorted({f"{w:.3g}" for w in at})[:6], "more": len(at) > 6})
    if pitchfork:
        pf = pitchfork["damped"]
        rows = []
        for n in sorted(pf):
            first, second = pf[n]
            rows.append({"n": n, "first": first, "second": second, "limit": pitchfork["limit"][n],
                         "rel": 100 * (first - THESIS_PITCHFORK_HOPF) / THESIS_PITCHFORK_HOPF})
        first = pf[min(pf)][0]
        pitchfork = {**pitchfork, "rows": rows, "first": first, "above": first - THESIS_PITCHFORK_HOPF}
    return render("chapter4_balanced", statements=statements, lines=lines, pitchfork=pitchfork,
                  maps=[(title, path.relative_to(root).as_posix()) for title, path in maps])


def _basin_section(basins, root: Path) -> list[str]:
    """Fig. 5.18's section (templates/basins_n2.md.j2)."""
    from .templates import render

    if not basins:
        return []
    shrink = all(basins[i]["balanced"] >= basins[i + 1]["balanced"] for i in range(2))
    return render("basins_n2", basins=_basin_rows(basins, root), shrink=shrink)


def _transient_section(transients) -> list[str]:
    """The document's opening and ch. 5's transients with their tolerance study and the published values neither
    run gives, explained where the runs explain them (templates/transients.md.j2)."""
    from .templates import render

    rows, notes = [], []
    for t in transients:
        row, conv, ode = t["row"], t["sims"][RTOLS[-1]], t["ode45"]
        mark = f" {MARK}" if "check" in t and t["check"].sensitive else ""
        for q, digits in (("r_max", 4), ("t_dec", 2)):
            pub = getattr(row, q)
            ours, emu = getattr(conv, q), getattr(ode, q)
            spread = not_converged([getattr(t["sims"][r], q) for r in RTOLS])
            why = ("below" if spread is not None else "printed" if _printed(ours, pub) else "ode45"
                   if _printed(emu, pub) else "below")
            rows.append({"figure": row.figure + mark, "n": row.n, "q": q, "published": pub, "why": why,
                         "start": row.phi0_text + "".join(f", {k} = {v:g}" for k, v in row.params.items()),
                         "converged": _fmt(ours, 6), "rel": _rel(ours, pub), "emulation": f"{emu:.{digits}f}",
                         "spread": None if spread is None else (_fmt(spread[0], 6), _fmt(spread[1], 6)),
                         "spread_rel": None if spread is None else [100 * _rel(x, pub) for x in spread]})
            if why == "below":
                notes.append(_note(t, q, spread))
    study = [(t["row"].figure, q, [_fmt(getattr(t["sims"][r], q), 6) for r in RTOLS])
             for t in transients for q in ("r_max", "t_dec")]
    return render("transients", engine=ENGINE, rows=rows, study=study, notes=notes, rtols=RTOLS,
                  count=len(transients),
                  printed_t_dec=sum(_printed(t["ode45"].t_dec, t["row"].t_dec) for t in transients),
                  printed_r_max=sum(_printed(t["ode45"].r_max, t["row"].r_max) for t in transients))


def _note(t: dict, q: str, spread) -> dict:
    """A published value neither run gives: the numbers its explanation reads (the emulation's output points
    about its t_dec, the threshold moved, tighter RelTol) and which explanation they support."""
    row, conv, ode = t["row"], t["sims"][RTOLS[-1]], t["ode45"]
    pub, emu = getattr(row, q), getattr(ode, q)
    note = {"figure": row.figure, "q": q, "published": pub, "emulation": emu, "converged": _fmt(getattr(conv, q), 6),
            "spread": None if spread is None else (_fmt(spread[0], 6), _fmt(spread[1], 6)), "points": None}
    if q == "t_dec" and "output_points" in t:
        at, nxt, _ = t["output_points"]
        close = abs(emu - pub) < 0.01 * pub
        note.update(points=t["output_points"], threshold=[_fmt(v, 6) for v in t["threshold"].values()],
                    tight=[_fmt(v, 6) for v in t["ode45_tight"].values()],
                    case="between" if nxt is not None and at <= pub <= nxt else "close" if close else "unexplained")
        if note["case"] == "close":
            note["emulation_off"] = 100 * abs(emu - pub) / pub
            if spread is None:
                note["converged_off"] = 100 * abs(getattr(conv, q) - pub) / pub
            else:
                note["spread_off"] = [100 * (x - pub) / pub for x in spread]
    return note


def _document(transients, results, figures, root: Path, statements=(), maps=(), basins=(), basins_n4=(),
              pitchfork=None) -> list[str]:
    """The thesis' chapter-5 and chapter-4 sections (templates/transients.md.j2, end_states.md.j2 and the
    basin and chapter 4 sections')."""
    from .sweeps import balanced
    from .templates import render

    rows, flagged = [], []
    for case, res in results:
        sims = res["sims"]
        head = {"figure": case.figure, "n": case.n, "phi0": case.phi0_text, "params": list(case.params.items())}
        if "attractor" in case.published:
            ok = res["label"] == case.published["attractor"] or (balanced(res["label"])
                                                                 and balanced(case.published["attractor"]))
            mark = f" {MARK}" if "check" in res and res["check"].sensitive else ""
            rows.append({"attractor": True, "head": head, "published": case.published["attractor"], "ok": ok,
                         "label": res["label"], "mark": mark})
            if not ok:
                flagged.append((case.figure, "attractor", res["label"]))
        model = res["model"]
        for name, pub in case.published.get("state", {}).items():
            v = float(sims[RTOLS[-1]].y_end[model.index(name)])
            vals = [float(sims[r].y_end[model.index(name)]) for r in RTOLS]
            if name.startswith("phi"):  # a final angle compared wrapped to (-pi, pi]
                v, target, vals = _wrap(v), _wrap(pub), [_wrap(x) for x in vals]
                rel = (v - target) / abs(target)
            else:
                target = pub
                rel = (v - pub) / abs(pub)
            within = abs(v - target) <= _printed_half_unit(pub)
            rows.append({"attractor": False, "head": head, "name": name, "published": pub, "value": v, "rel": rel,
                         "within": within, "large": abs(rel) > 0.01, "values": vals})
            if not within and abs(rel) > 0.01:
                flagged.append((case.figure, name, v))
    slow = [_slow_text(case, res["slow"]) for case, res in results if "slow" in res]
    L = _transient_section(transients)
    L += render("end_states", rows=rows, differences=flagged, slow=slow,
                figures=[(title, path.relative_to(root).as_posix()) for title, path in figures])
    L += _basin_section(basins, root)
    L += _basin_n4_section(basins_n4, root)
    L += _chapter4(statements, maps, root, pitchfork)
    return L


def _slow_text(case, slow: dict) -> str:
    """How an attractor row not named at t = T_END approaches its end, from `slow_approach`'s numbers
    (templates/slow_approach.md.j2)."""
    from .templates import render

    pts = slow["checkpoints"]
    falls = all(q["r_max"] < p["r_max"] for p, q in zip(pts, pts[1:])) and pts[0]["r_max"] < slow["r_start"]
    balances = (falls and slow["exponent"] > 0.5 and pts[-1]["spread"] < pts[0]["spread"]
                and slow["limit_residual"] < 1e-9 and slow["neutral"] > slow["free_angles"])
    return "\n".join(render("slow_approach", figure=case.figure, t_end=T_END, rtol=RTOLS[-1], slow=slow,
                   balances=balances)).rstrip("\n")


def _figures(fig_dir: Path) -> list[tuple[str, Path]]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ....analysis.simulate import amplitude

    out = []
    runs = [*TRANSIENTS, *CASES]
    for fig_name in ("5.4", "5.6", "5.8"):
        cases = sorted((c for c in runs if c.figure.startswith(fig_name + "(")), key=lambda c: c.figure)
        fig, axes = plt.subplots(2, len(cases), figsize=(3.2 * len(cases), 4.8), sharex=True,
                                 constrained_layout=True)
        for k, case in enumerate(cases):
            model, sim = _run(case, 1e-10, keep=True)
            r = amplitude(model, sim.y)
            axes[0, k].plot(sim.t, r, lw=0.5, color="k")
            axes[0, k].set_title(f"({chr(97 + k)}) $\\phi(0)$ = {case.phi0_text}", fontsize=8)
            for i in model.angle_indices:
                axes[1, k].plot(sim.t, sim.y[i], lw=0.6, label=f"$\\phi_{{{model.state_names[i][4:]}}}$")
            axes[1, k].set_xlabel("$t$")
        axes[0, 0].set_ylabel("$r$")
        axes[1, 0].set_ylabel("ball angles")
        axes[1, -1].legend(fontsize=7, loc="best")
        fig.suptitle(f"thesis Fig. {fig_name}: n = {cases[0].n}, (5.1): $\\Omega$ = 4, $\\zeta = \\beta = "
                     f"\\delta$ = 0.01, $\\mu$ = 0.05 (rtol 1e-10)", fontsize=9)
        path = fig_dir / f"fig{fig_name.replace('.', '_')}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        out.append((f"Fig. {fig_name} (n = {cases[0].n})", path))
    return out


from .coverage import SECTION_ROWS  # noqa: E402  (the table's rows beside the section that computes them)

REPRODUCTION = Reproduction("thesis", "Thesis", compute, lines, coverage=SECTION_ROWS)
