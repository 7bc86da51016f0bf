"""Starts the thesis names one by one (ch. 5): the random rotor starts of Figs. 5.1-5.3 and the two named
starts of Figs. 5.7(a2), 5.9(a2) that the r_max scans reach by a tie, whose outcome hangs on the last bit of
-pi (issue 36).  The section's prose is a jinja2 template (templates/starts.md.j2); this module computes.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ....analysis.loading import load_model

PI = math.pi
ENGINE = "cyrk-dop853"
RTOL = 1e-10
T_END = 3000.0

# thesis section 5.1.1, Figs. 5.1-5.3: (x(0), y(0), x'(0), y'(0)) drawn from a normal variable (0, 0.1), as printed;
# the balls at the starts (5.3)-(5.5), at rest.  Published: "In all the cases the system achieves the balance in a
# similar time, more or less when t = 600" (n = 2); r_max of "the same order of magnitude"; for n >= 3 the balls end
# at different positions in each panel (a continuum of balanced states)
ROTOR_STARTS = {"a": (-0.0433, 0.0125, -0.1666, 0.0288), "b": (-0.1146, 0.1189, 0.1191, -0.0038),
                "c": (0.0327, -0.0187, 0.0175, 0.0726), "d": (-0.0588, -0.0136, 0.2183, 0.0114)}
BALLS = {2: (PI / 2, -PI / 2), 3: (PI / 3, -PI / 3, PI), 4: (PI / 2, -PI / 2, PI, 0.0)}  # as printed in 5.1.1


def _state(model, n: int, phi, rotor=(0.0, 0.0, 0.0, 0.0)):
    x, y, u, v = rotor
    values = {"x": x, "y": y, "x_dot": u, "y_dot": v}
    values.update({f"phi_{i + 1}": a for i, a in enumerate(phi)})
    return model.state(values)


def _run(model, p, y0, rtol: float = RTOL, t_end: float = T_END):
    """One run and its decided label (`attractors.Classifier.decide`)."""
    from ....analysis.attractors import classifier
    from ....analysis.simulate import simulate

    sim = simulate(model, p, y0, t_end=t_end, rtol=rtol, atol=rtol * 1e-2, engine=ENGINE, check=False)
    outcome = classifier(model, p).decide(sim.status, sim.y_end, -1, engine=ENGINE, rtol=rtol, atol=rtol * 1e-2,
                                          t=t_end)
    return sim, outcome.label


def random_rotor_starts(ns=(2, 3, 4), panels: str = "abcd") -> dict:
    """Figs. 5.1-5.3: each panel's run, (r_max, t_dec, decided label, the balls' final angles wrapped)."""
    out = {}
    for n in ns:
        model = load_model(f"thesis_rotating_n{n}")
        p = model.params({})
        rows = {}
        for k in panels:
            sim, label = _run(model, p, _state(model, n, BALLS[n], ROTOR_STARTS[k]))
            angles = [float((sim.y_end[model.index(f"phi_{i + 1}")] + PI) % (2 * PI) - PI) for i in range(n)]
            rows[k] = {"r_max": float(sim.r_max), "t_dec": sim.t_dec, "label": label, "angles": angles}
        out[n] = rows
    return out


def final_positions_differ(rows: dict, tol: float = 1e-3) -> bool:
    """Do the balls end at different positions in different panels (largest difference of a sorted angle)?"""
    ends = [np.sort(r["angles"]) for r in rows.values()]
    return max(float(np.max(np.abs(a - b))) for a in ends for b in ends) > tol


# Figs. 5.7(a2), 5.9(a2): the panels tie phi_2 = -phi_1 and put the other balls at pi; at phi_1(0) = pi the tie
# gives phi_2(0) = -pi, the same angle, but sin(-pi) = -sin(pi) = -1.2e-16: the balls are not exactly together, the
# exchange symmetry that keeps coincident balls together is broken in the last bit, and the run separates them
TIE_STARTS = {3: ((PI, PI, PI), (PI, -PI, PI)), 4: ((PI, PI, PI, PI), (PI, -PI, PI, PI))}


def tie_bit_runs(ns=(3, 4), rtol: float = 1e-8) -> dict:
    """Every ball at pi, once with phi_2(0) = pi and once with phi_2(0) = -pi (the panels' tie): the decided
    labels (at the scans' rtol 1e-8)."""
    out = {}
    for n in ns:
        model = load_model(f"thesis_rotating_n{n}")
        p = model.params({})
        out[n] = {text: _run(model, p, _state(model, n, phi), rtol)[1]
                  for text, phi in zip(("phi_2(0) = pi", "phi_2(0) = -pi"), TIE_STARTS[n])}
        out[n]["2-"] = coincident_instability(model, p)
    return out


def coincident_instability(model, p) -> tuple[int, float]:
    """The coincident state 2- at p: (unstable eigenvalues, the largest real part): the directions in which the
    balls separate."""
    from ....analysis.attractors import spectrum

    s = spectrum(model, np.asarray(model.steady_state("2-", p), float), p)
    return s.unstable(), s.abscissa


def inline_names_agree(n: int = 4) -> dict:
    """The thesis' 3(4-1)+ and the label 3(4-3)- name one state (the balls renamed): the model's closed forms
    "3(1)+" and "3(3)-" at (5.1), their rotor position (x, y)."""
    model = load_model(f"thesis_rotating_n{n}")
    p = model.params({})
    ix, iy = model.index("x"), model.index("y")
    return {name: (float(model.steady_state(name, p)[ix]), float(model.steady_state(name, p)[iy]))
            for name in ("3(1)+", "3(3)-", "3(1)-", "3(3)+")}


def compute(progress=None) -> dict:
    out = {"random": random_rotor_starts(), "tie": tie_bit_runs(), "inline": inline_names_agree()}
    if progress:
        progress("Figs. 5.1-5.3: " + ", ".join(f"n = {n}: " + " ".join(r["label"] for r in rows.values())
                                               for n, rows in out["random"].items()))
    return out


def summary(rows: dict) -> dict:
    """One n's panels of Figs. 5.1-5.3: how many balance, the range of t_dec and r_max, whether the balls end
    at different positions."""
    from .sweeps import balanced

    t_dec = [r["t_dec"] for r in rows.values() if r["t_dec"] is not None]
    r_max = [r["r_max"] for r in rows.values()]
    return {"balanced": sum(balanced(r["label"]) for r in rows.values()), "panels": len(rows),
            "t_dec": (min(t_dec), max(t_dec)) if t_dec else (math.nan, math.nan), "r_max": (min(r_max), max(r_max)),
            "differ": final_positions_differ(rows)}


def lines(res: dict, root: Path | None = None) -> list[str]:
    from .templates import render

    return render("starts", random=res["random"], tie=res["tie"], inline=res["inline"], rtol=RTOL,
                  t_end=T_END, engine=ENGINE, starts=ROTOR_STARTS,
                  summary={n: summary(rows) for n, rows in res["random"].items()})
