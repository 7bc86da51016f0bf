"""Figs. 5.12-5.14: the rotor with the balancer beside the rotor without it (the thesis' grey curves).

Without balls (mu = 0) the rotor is a linear oscillator driven by its eccentricity: in the rotating frame it
settles at r = delta Omega^2 / sqrt((1 - Omega^2)^2 + (2 zeta Omega)^2) (the model at mu = 0 gives it to 1e-12,
tests/families/single_plane/science/test_plain.py).  The thesis: (a) Omega = 0.5, the balls' coincident state 2-
"results in a much greater radial vibration r than would be the case without the ADB", larger as n grows; (b)
Omega = 1.6, r "much larger" than without; (d) mu = 0.0025, n = 2, 3: the coincident state 2- "is preferable to
the final state obtained without the ADB".  Prose: templates/plain.md.j2.
"""

from __future__ import annotations

import math

PARAMETERS = {"Omega": 4.0, "zeta": 0.01, "delta": 0.01}  # (5.1)


def plain_rotor_r(Omega: float, zeta: float = 0.01, delta: float = 0.01) -> float:
    """The steady whirl radius of the rotor without balls (mu = 0)."""
    return delta * Omega**2 / math.hypot(1.0 - Omega**2, 2.0 * zeta * Omega)


def rows(results, lyapunov: dict | None) -> list[dict]:
    """Each run of Figs. 5.12-5.14 (a), (d) (final r at the tightest rtol) and (b) (largest r over the Lyapunov
    window), with the plain rotor's r at the same parameters and the ratio."""
    out = []
    for case, res in results:
        if not case.figure.startswith(("5.12(", "5.13(", "5.14(")):
            continue
        sim = res["sims"][min(res["sims"])]
        model = res["model"]
        r = math.hypot(sim.y_end[model.index("x")], sim.y_end[model.index("y")])
        values = {**PARAMETERS, **case.params}
        plain = plain_rotor_r(values["Omega"], values["zeta"], values["delta"])
        out.append({"figure": case.figure, "n": case.n, "what": "final r", "label": res["label"], "r": r,
                    "plain": plain, "ratio": r / plain})
    for name, v in (lyapunov or {}).items():
        if name.startswith("5.1") and "(b)" in name:
            plain = plain_rotor_r(1.6)
            out.append({"figure": name.split(",")[0], "n": int(name.split("= ")[1]), "what": "largest r, t in "
                        "[1000, 5000]", "label": "", "r": v["r_window"], "plain": plain, "ratio": v["r_window"] / plain})
    for row in out:
        row.update(judged(row))
    return sorted(out, key=lambda x: (x["figure"][-2], x["n"]))


def judged(row: dict) -> dict:
    """The thesis' statement a row is compared with and whether the numbers bear it out: (a), (b) "larger with"
    the balancer (ratio > 1); (d) at n = 2, 3 "smaller with" (ratio < 1); (d) at n = 4 the balls balance, no
    statement to judge (holds None)."""
    if "(a)" in row["figure"] or "(b)" in row["figure"]:
        return {"statement": "larger with", "holds": row["ratio"] > 1}
    if row["n"] < 4:
        return {"statement": "smaller with", "holds": row["ratio"] < 1}
    return {"statement": "balances", "holds": None}


def lines(results, lyapunov) -> list[str]:
    from .templates import render

    table = rows(results, lyapunov)
    at_a = [r["r"] for r in sorted((r for r in table if "(a)" in r["figure"]), key=lambda r: r["n"])]
    grows = len(at_a) > 1 and all(a < b for a, b in zip(at_a, at_a[1:]))
    return render("plain", rows=table, grows=grows, at_a=at_a)
