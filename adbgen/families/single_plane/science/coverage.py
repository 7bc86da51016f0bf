"""The thesis' published results, chapters 3-5, and where docs/reproduction.md recomputes each (issue 36):
the rows of the covered / not covered table (`analysis.reproduction.Coverage`).  A covered row names the
heading that recomputes it; a row not covered says why."""

from __future__ import annotations

from ....analysis.reproduction import Coverage

CH3 = "Thesis, chapter 3: steady states and critical speeds"
CH4 = "Thesis, chapter 4: stability of the balanced state"
ONE_PARAMETER_DIAGRAMS = "Thesis, chapter 4: one-parameter diagrams of every steady state"
COINCIDENT = "Thesis, chapter 4: where the coincident state 2- is stable"
PLANE = "Thesis, Figs. 4.1, 4.5, 4.10: every steady state over (Omega, mu)"
TRANSIENTS = "Thesis, chapter 5: transients"
RANDOM = "Thesis, Figs. 5.1-5.3: random starts of the rotor"
SCANS = "Thesis, Figs. 5.5, 5.7, 5.9: r_max against the starting position"
NAMED = "Thesis, Figs. 5.7(a2), 5.9(a2), 5.9(b2): the named starts the scans do not reach as the thesis says"
TOLERANCE = "Thesis, Fig. 5.10 (and Fig. 5.9(a1)'s named start): outcomes that hang on the tolerance"
LAUNCHES = "Thesis, Figs. 5.10-5.11: balls released at rest in the fixed frame"
LYAPUNOV = "Thesis, Figs. 5.12-5.14 (b): the motion at Omega = 1.6"
BASIN_N3 = "Thesis, section 5.2.2: the n = 3 basin experiment"
BASIN_N2 = "Thesis, Fig. 5.18: basins of attraction of the balanced state, n = 2"
BASIN_N4 = "Thesis, Fig. 5.19: basins of attraction of the balanced state, n = 4"
DAMPING = "Thesis, Figs. 5.20-5.22: damping maps"
SWEEPS = "Thesis, Figs. 5.23-5.25: sweeps in Omega and delta"
PLAIN = "Thesis, Figs. 5.12-5.14: the rotor with and without the balancer"
ORBITS = "Periodic orbits of the single-plane balancer (thesis ch. 4-6)"



def _yes(chapter: str, item: str, where: str) -> Coverage:
    return Coverage("thesis", chapter, item, True, where=where)


def _no(chapter: str, item: str, reason: str) -> Coverage:
    return Coverage("thesis", chapter, item, False, reason=reason)


THESIS = (
    _yes("3", "(3.6), (5.2): balanced positions", CH3),
    _yes("3", "Fig. 3.1, (3.16): critical speeds of 2+-", CH3),
    _yes("3", "Fig. 3.2, (3.18): critical speeds of 3(3-2)+-", CH3),
    _yes("4", "Fig. 4.1: n = 2, (Omega, mu), balanced state", CH4),
    _yes("4", "(4.1)-(4.2): the end of H2- and the pitchfork-Hopf points", CH4),
    _no("4", "(4.3), (4.4): wedge tips of the in-line states",
        "the thesis' closed forms, re-evaluated by `adbgen verify` (docs/checks.md), not located on the model"),
    _yes("4", "Figs. 4.1, 4.5, 4.10: where 2- is stable (the lines mu = 0.05, 0.0025 the text reads)", COINCIDENT),
    _yes("4", "Figs. 4.1, 4.5, 4.10: the bifurcation curves of the coincident and in-line states, located on rows "
         "of n mu (not continued between them), and the stability region of 2-", PLANE),
    _yes("4", "Figs. 4.2, 4.3 (n = 2): one-parameter diagrams", ONE_PARAMETER_DIAGRAMS),
    _yes("4", "Fig. 4.4: n = 2, Omega > 2.5 in (Omega, delta), (Omega, zeta), (Omega, beta)", CH4),
    _yes("4", "Fig. 4.5: n = 3, (Omega, mu), balanced state", CH4),
    _yes("4", "Figs. 4.6, 4.7 (n = 3): one-parameter diagrams", ONE_PARAMETER_DIAGRAMS),
    _yes("4", "Fig. 4.8(b): n = 3, zeta limit at Omega = 3", CH4),
    _yes("4", "Fig. 4.9(a), (b): n = 3, (zeta, beta)", CH4),
    _yes("4", "Fig. 4.10: n = 4, (Omega, mu), balanced state", CH4),
    _yes("4", "Figs. 4.11, 4.12 (n = 4): one-parameter diagrams", ONE_PARAMETER_DIAGRAMS),
    _yes("4", "Fig. 4.13(b), (c): n = 4, zeta limit and Omega > 2.5", CH4),
    _yes("4", "Fig. 4.14(a): n = 4, (zeta, beta)", CH4),
    _yes("5", "Figs. 5.1-5.3: random rotor starts", RANDOM),
    _yes("5", "Fig. 5.4 (a), (c), (d): r_max, t_dec", TRANSIENTS),
    _yes("5", "Fig. 5.4(b): the limit cycle", ORBITS),
    _yes("5", "Fig. 5.5: r_max scans, n = 2", SCANS),
    _yes("5", "Fig. 5.6: r_max, t_dec, n = 3", TRANSIENTS),
    _yes("5", "Fig. 5.7: r_max scans, n = 3, and the runs its text names", SCANS),
    _yes("5", "Fig. 5.7(a2), 5.9(a2), 5.9(b2): the named starts' outcomes", NAMED),
    _yes("5", "Fig. 5.8: r_max, t_dec, n = 4", TRANSIENTS),
    _yes("5", "Fig. 5.9: r_max scans, n = 4", SCANS),
    _yes("5", "Fig. 5.10 (a)-(c): launches at rest in the fixed frame", TOLERANCE),
    _yes("5", "Fig. 5.10(b): the desynchronised n = 3 orbit", ORBITS),
    _yes("5", "Fig. 5.11: balanced launches of 100 (32 / 28 / 24)", LAUNCHES),
    _yes("5", "Figs. 5.12-5.14 (a), (d): end states", TRANSIENTS),
    _yes("5", "Figs. 5.12-5.14 (b): the motion at Omega = 1.6", LYAPUNOV),
    _yes("5", "Figs. 5.12-5.14 (c): r_max, t_dec at Omega = 20", TRANSIENTS),
    _yes("5", "Figs. 5.12-5.14: the rotor without balls beside", PLAIN),
    _yes("5", "Figs. 5.15-5.17: damping runs", TRANSIENTS),
    _yes("5", "Fig. 5.18: basins, n = 2", BASIN_N2),
    _yes("5", "Section 5.2.2: the n = 3 basin experiment", BASIN_N3),
    _yes("5", "Fig. 5.19: basins, n = 4", BASIN_N4),
    _yes("5", "Figs. 5.20-5.22: (zeta, beta) maps", DAMPING),
    _yes("5", "Fig. 5.23: sweep in Omega (\"Omega < 2.04\")", SWEEPS),
    _yes("5", "Figs. 5.24, 5.25: sweeps in delta (and 5.25's values on [0, 0.03])", SWEEPS),
)

# every figure of thesis ch. 3-5 (3.1-3.2, 4.1-4.14, 5.1-5.25): each must be named by some row
FIGURES = tuple(f"{c}.{k}" for c, count in ((3, 2), (4, 14), (5, 25)) for k in range(1, count + 1))


def _named(item: str) -> set[str]:
    """The figure numbers a row's item names: "Figs. 5.12-5.14" names 5.12, 5.13, 5.14."""
    import re

    out = set()
    for a, b in re.findall(r"(\d\.\d+)(?:-(\d\.\d+))?", item):
        out.add(a)
        if b:
            c, lo, hi = a.split(".")[0], int(a.split(".")[1]), int(b.split(".")[1])
            out |= {f"{c}.{k}" for k in range(lo, hi + 1)}
    return out


def missing(rows=THESIS) -> list[str]:
    """The thesis' ch. 3-5 figures no row names (each must be covered or say why not)."""
    named = set().union(*(_named(c.item) for c in rows if "Fig" in c.item))
    return [f for f in FIGURES if f not in named]


ORBIT_ROWS = tuple(c for c in THESIS if c.where == ORBITS)
SECTION_ROWS = tuple(c for c in THESIS if c.where != ORBITS)
