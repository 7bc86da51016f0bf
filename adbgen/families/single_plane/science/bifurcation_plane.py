"""Thesis Figs. 4.1, 4.5, 4.10: every steady state over the (Omega, mu) plane, zeta = beta = delta = 0.01 (issue
36: the bifurcation curves of the coincident and in-line states, and where 2- is stable).

The thesis continues each curve with AUTO; here the plane is cut into ROWS of constant total ball mass n mu,
the same rows for n = 2, 3, 4 (so the thesis' statement that the coincident states' curves coincide in
(Omega, n mu) is checked on equal rows), and along each row every steady state of the generated module (its
closed forms, `model.steady_states`) is evaluated on OMEGA.  Wherever a state appears or disappears (a
saddle-node or pitchfork of the diagram) or its number of unstable eigenvalues changes (a Hopf point when the
eigenvalue on the imaginary axis there is a complex pair, a real crossing otherwise) the change is bisected to
TOL in Omega and classified; an end of existence names the state it meets there (the nearest other steady
state, the thesis' "SN2+-" or "PF1,2-").  The thesis' curves are these points joined across rows: what is
certified is each row (every change wider than one Omega step is found and located), not the curve between
rows.  The balanced family of n >= 3 is judged by its transverse spectrum (`attractors.spectrum`).  Prose:
templates/bifurcation_plane.md.j2.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ....analysis.loading import load_model

DELTA = 0.01
PLANES = ((2, "4.1"), (3, "4.5"), (4, "4.10"))
# rows of total ball mass n mu: fine below 0.03 (the thesis' zoomed panels (b)) and coarse to 0.2; none is
# n mu_c = delta, where the balanced state is born (a row on the pitchfork line would sit on it)
ROWS = tuple(float(v) for v in np.round(np.concatenate([np.arange(0.0005, 0.03, 0.001),
                                                        np.arange(0.0325, 0.2, 0.005)]), 10))
OMEGA = tuple(float(v) for v in np.round(np.linspace(0.02, 3.0, 150), 10))  # step 0.02
TOL = 1e-7  # every change located to this in Omega
IMAGINARY = 1e-6  # a crossing eigenvalue with |Im| above this is a Hopf pair
MEETS = 1e-2  # an ending state meets the nearest other state when their states are this close
MAX_CHANGES = 6  # changes located inside one Omega cell before the cell is reported as unresolved


def _count(model, state: str, mu: float, Omega: float) -> int:
    """-1 where the state's closed form has no solution, else its number of unstable eigenvalues."""
    from ....analysis.attractors import spectrum

    p = model.params({"Omega": Omega, "mu": mu})
    y = model.steady_state(state, p)
    if y is None:
        return -1
    return spectrum(model, np.asarray(y, float), p).unstable()


def _changes(f, xs, counts) -> tuple[list[tuple[float, int, int]], list[float]]:
    """Every change of f along xs (from the counts on the grid), each bisected to TOL: [(x, before, after)],
    and the cells where more than MAX_CHANGES were found (unresolved)."""
    out, unresolved = [], []
    for i in range(len(xs) - 1):
        a, ca, cb = xs[i], counts[i], counts[i + 1]
        found = 0
        while ca != cb:
            if found == MAX_CHANGES:
                unresolved.append(xs[i])
                break
            lo, hi = a, xs[i + 1]
            while hi - lo > TOL:  # f(lo) == ca and f(hi) != ca throughout
                m = 0.5 * (lo + hi)
                if f(m) == ca:
                    lo = m
                else:
                    hi = m
            after = f(hi)
            out.append((0.5 * (lo + hi), ca, after))
            a, ca, found = hi, after, found + 1
    return out, unresolved


def _distance(model, y1, y2) -> float:
    from ....analysis.attractors import balls

    d = np.asarray(y1, float) - np.asarray(y2, float)
    k = balls(model)
    d[k] = np.angle(np.exp(1j * d[k]))
    return float(np.max(np.abs(d)))


def _classify(model, state: str, mu: float, x: float, before: int, after: int) -> dict:
    """What a located change is: the end of the state's existence (and the state it meets), or a crossing of
    the imaginary axis (Hopf or real) from the spectrum at the change."""
    from ....analysis.attractors import spectrum

    if before == -1 or after == -1:
        side = x + TOL if before == -1 else x - TOL
        p = model.params({"Omega": side, "mu": mu})
        y = model.steady_state(state, p)
        near = []
        for other in model.steady_states:
            z = model.steady_state(other, p) if other != state else None
            if z is not None:
                near.append((_distance(model, y, z), other))
        d, other = min(near) if near else (math.inf, "")
        return {"kind": "exists" if before == -1 else "ends", "meets": other if d < MEETS else ""}
    p = model.params({"Omega": x, "mu": mu})
    ev = spectrum(model, np.asarray(model.steady_state(state, p), float), p).eigenvalues
    lead = ev[np.argmin(np.abs(ev.real))]
    return {"kind": "Hopf" if abs(lead.imag) > IMAGINARY else "real", "frequency": float(abs(lead.imag))}


def _segments(xs, counts, changes) -> list[tuple[float, float, int]]:
    """The row as (from, to, unstable count) pieces, -1 where the state does not exist."""
    ends = [xs[0]] + [c[0] for c in changes] + [xs[-1]]
    values = [counts[0]] + [c[2] for c in changes]
    return [(ends[k], ends[k + 1], values[k]) for k in range(len(values))]


def _merge(pieces) -> list[tuple[float, float]]:
    out = []
    for a, b in pieces:
        if out and abs(out[-1][1] - a) <= 2 * TOL:
            out[-1] = (out[-1][0], b)
        else:
            out.append((a, b))
    return out


def plane(n: int) -> dict:
    """Every state of the n-ball model along every row: where it exists, where it is stable, its changes."""
    model = load_model(f"thesis_rotating_n{n}")
    xs = list(OMEGA)
    rows = []
    for total in ROWS:
        mu = total / n
        states = {}
        for state in model.steady_states:
            f = lambda x, s=state: _count(model, s, mu, x)  # noqa: E731
            counts = [f(x) for x in xs]
            changes, unresolved = _changes(f, xs, counts)
            pieces = _segments(xs, counts, changes)
            states[state] = {
                "exists": _merge([(a, b) for a, b, c in pieces if c >= 0]),
                "stable": _merge([(a, b) for a, b, c in pieces if c == 0]),
                "changes": [{"Omega": x, "before": c1, "after": c2, **_classify(model, state, mu, x, c1, c2)}
                            for x, c1, c2 in changes],
                "unresolved": unresolved}
        rows.append({"total": total, "mu": mu, "states": states})
    return {"n": n, "mu_c": DELTA / n, "states": list(model.steady_states), "rows": rows}


def compute() -> dict:
    return {"planes": [dict(plane(n), figure=figure) for n, figure in PLANES]}


# ------------------------------------------------------------------------------ the thesis' statements

def _rows(pl, below: bool | None = None):
    """The plane's rows below (True) or above (False) mu_c, or all."""
    return [r for r in pl["rows"] if below is None or (r["mu"] < pl["mu_c"]) == below]


def _whole(intervals) -> bool:
    return len(intervals) == 1 and intervals[0][0] == OMEGA[0] and intervals[0][1] == OMEGA[-1]


def _stable_states(row) -> set[str]:
    return {s for s, v in row["states"].items() if v["stable"]}


def _inline(pl) -> list[str]:
    return [s for s in pl["states"] if s.startswith("3")]


def statements(res: dict) -> list[dict]:
    """The thesis' sentences about Figs. 4.1, 4.5, 4.10, each checked on every row it speaks of: holds, and
    the first row (n mu) where it does not."""
    by_n = {pl["n"]: pl for pl in res["planes"]}
    out = []

    def check(n, text, rows, test):
        bad = [r["total"] for r in rows if not test(r)]
        out.append({"n": n, "text": text, "rows": len(rows), "holds": not bad, "first_failure": bad[0] if bad else None})

    for n, pl in by_n.items():
        check(n, "for mu < mu_c the balanced state 1 does not exist", _rows(pl, True),
              lambda r: not r["states"]["1"]["exists"])
        check(n, "for mu > mu_c the balanced state 1 always exists", _rows(pl, False),
              lambda r: _whole(r["states"]["1"]["exists"]))
        check(n, "for mu < mu_c the only stable steady state is the coincident state 2-", _rows(pl, True),
              lambda r: _stable_states(r) == {"2-"})
        check(n, "the coincident state 2+ is always unstable", _rows(pl), lambda r: not r["states"]["2+"]["stable"])
        check(n, "the in-line states are always unstable", _rows(pl),
              lambda r, pl=pl: not any(r["states"][s]["stable"] for s in _inline(pl)))
    two = by_n.get(2)
    if two:
        check(2, "the in-line state 3 always exists", _rows(two),
              lambda r, two=two: all(_whole(r["states"][s]["exists"]) for s in _inline(two)))
    three = by_n.get(3)
    if three:
        check(3, "1 is stable only to the right of the last Hopf curve H1 (no second region at intermediate "
              "Omega)", _rows(three, False),
              lambda r: all(b == OMEGA[-1] for a, b in r["states"]["1"]["stable"]))
        check(3, "for mu < delta/(2m - n) = 0.01 both in-line states 3+- always exist",
              [r for r in _rows(three) if r["mu"] < 0.01],
              lambda r, three=three: all(_whole(r["states"][s]["exists"]) for s in _inline(three)))
    for n in (2, 4):
        if n in by_n:
            pl = by_n[n]
            rows = _rows(pl, False)
            second = [r["total"] for r in rows if any(b < OMEGA[-1] for a, b in r["states"]["1"]["stable"])]
            out.append({"n": n, "text": "1 has a second region of stability at intermediate Omega (for large enough mu)",
                        "rows": len(rows), "holds": bool(second), "first_failure": None,
                        "from_total": second[0] if second else None})
    return out


def coincident_agreement(res: dict) -> dict:
    """The thesis (after Fig. 4.10): in the (Omega, n mu) plane the coincident states' bifurcation curves are
    the same for n = 2, 3, 4.  Compared on equal rows of n mu: the changes of 2+ and 2- (their ends of
    existence and their Hopf points, in order; the unstable counts differ with n, more balls adding modes),
    the largest difference in Omega between matched changes, and the rows whose changes differ in number or
    kind."""
    planes = res["planes"]
    worst, differing = 0.0, []
    for k, total in enumerate(ROWS):
        for state in ("2+", "2-"):
            seqs = [[(c["Omega"], c["kind"]) for c in pl["rows"][k]["states"][state]["changes"]] for pl in planes]
            ref = seqs[0]
            for other, pl in zip(seqs[1:], planes[1:]):
                if [c[1] for c in other] != [c[1] for c in ref]:
                    differing.append({"total": total, "state": state, "n": pl["n"], "n2": [c[1] for c in ref],
                                      "other": [c[1] for c in other]})
                else:
                    worst = max([worst] + [abs(a[0] - b[0]) for a, b in zip(ref, other)])
    return {"worst": worst, "differing": differing, "rows": len(ROWS),
            "compared": [pl["n"] for pl in planes]}


# ------------------------------------------------------------------------------------------ the figure

# (label, kinds, which states, marker, colour): the thesis draws the in-line states' curves broken
GROUPS = (("end of existence (SN, PF)", ("exists", "ends"), "all", "s", "tab:blue"),
          ("Hopf of 1, 2+-", ("Hopf",), "main", "o", "tab:red"),
          ("Hopf of an in-line state", ("Hopf",), "inline", "o", "tab:orange"),
          ("real crossing", ("real",), "all", "^", "tab:green"))


def _in_group(state: str, which: str) -> bool:
    return which == "all" or (which == "inline") == state.startswith("3")
SHADE = {"1": "0.45"}  # dark: the balanced state; light (LIGHT): every other stable state (2-)
LIGHT = "0.82"


def summary(pl: dict) -> list[dict]:
    """Per state: the rows (mu) on which it is stable somewhere and its Omega extent there, its changes by
    kind, and the states its ends of existence meet."""
    out = []
    for state in pl["states"]:
        stable = [(r["mu"], v["stable"]) for r in pl["rows"] for s, v in r["states"].items() if s == state and v["stable"]]
        changes = [c for r in pl["rows"] for c in r["states"][state]["changes"]]
        out.append({"state": state,
                    "stable_mu": (stable[0][0], stable[-1][0]) if stable else None,
                    "stable_omega": (min(iv[0][0] for _, iv in stable), max(iv[-1][1] for _, iv in stable))
                    if stable else None,
                    "counts": {k: sum(c["kind"] in kinds for c in changes) for k, kinds, which, *_ in GROUPS
                               if _in_group(state, which)},
                    "meets": sorted({c["meets"] for c in changes if c.get("meets")}),
                    "unresolved": sum(len(r["states"][state]["unresolved"]) for r in pl["rows"])})
    return out


def points(pl: dict) -> dict:
    """The figure's data (written beside it as JSON): every located change, by state."""
    return {"n": pl["n"], "rows_n_mu": list(ROWS), "omega_grid": [OMEGA[0], OMEGA[-1], len(OMEGA)], "tolerance": TOL,
            "changes": {s: [[round(r["mu"], 12), round(c["Omega"], 9), c["kind"], c["before"], c["after"],
                             c.get("meets", "")] for r in pl["rows"] for c in r["states"][s]["changes"]]
                        for s in pl["states"]}}


def draw(res: dict, fig_dir: Path) -> list[Path]:
    import json

    from ....analysis.figure_style import pyplot

    plt = pyplot()
    paths = []
    totals = np.array(ROWS)
    edges = np.concatenate([[0.0], 0.5 * (totals[1:] + totals[:-1]), [totals[-1] + 0.0025]])
    for pl in res["planes"]:
        n = pl["n"]
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.6))
        for ax, top in zip(axes, (edges[-1] / n, 0.03 / n)):
            for k, row in enumerate(pl["rows"]):
                lo, hi = edges[k] / n, edges[k + 1] / n
                for state, v in row["states"].items():
                    for a, b in v["stable"]:
                        ax.fill_between([a, b], lo, hi, color=SHADE.get(state, LIGHT), linewidth=0)
            for label, kinds, which, marker, colour in GROUPS:
                pts = [(c["Omega"], row["mu"]) for row in pl["rows"] for s, v in row["states"].items()
                       for c in v["changes"] if c["kind"] in kinds and _in_group(s, which)]
                if pts:
                    xs, ys = zip(*pts)
                    ax.plot(xs, ys, marker, color=colour, markersize=2.5, linestyle="none", label=label)
            ax.axhline(pl["mu_c"], color="k", linewidth=0.6, linestyle=":")
            ax.set_xlim(OMEGA[0], OMEGA[-1])
            ax.set_ylim(0, top)
            ax.set_xlabel("Omega")
            ax.set_ylabel("mu")
        axes[0].set_title(f"(a) n = {n}: every state's changes along rows of n mu", fontsize=10)
        axes[1].set_title(f"(b) zoom, n mu < 0.03 (mu_c = {pl['mu_c']:.4g} dotted)", fontsize=10)
        axes[0].legend(loc="upper left", fontsize=8, framealpha=0.9)
        fig.suptitle(f"thesis Fig. {pl['figure']} recomputed: shaded dark where 1 is stable, light where 2- is",
                     fontsize=10)
        fig.tight_layout()
        path = fig_dir / f"fig4_n{n}_bifurcation_omega_mu.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        path.with_suffix(".json").write_text(json.dumps(points(pl), sort_keys=True) + "\n")
        paths.append(path)
    return paths


def lines(res: dict, paths: list[Path], root: Path) -> list[str]:
    from .templates import render

    rel = [p.relative_to(root).as_posix() for p in paths]
    return render("bifurcation_plane", planes=[dict(pl, summary=summary(pl)) for pl in res["planes"]],
                  checks=statements(res), agreement=coincident_agreement(res), figures=rel, rows=ROWS,
                  omega=OMEGA, tol=TOL)
