"""The work-precision benchmark's charts (`adbgen bench precision`): per problem, error against CPU
time, a curve per pathway; problem A's loosest reliable tolerances; ns per call against n.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .precision_curves import TDEC_DT
from .precision_sweep import TIME
from .report import pyplot, save_figure, when

_KIND_STYLE = {"engine": "-", "ivp": "--", "cvode-main": "-.", "peer": ":"}
_PEER_COLOURS = {"peer:jitcode-dop853": "#2ca02c", "peer:heyoka": "#9467bd"}


HEADLINE = ("cyrk-dop853", "cyrk-vern8", "cvode-bdf", "cvode-main", "scipy-dop853", "ivp:numba-dop853",
            "ivp:handwritten-dop853", "ivp:lambdify-rk45", "ivp:lambdify-dop853", "peer:jitcode-dop853", "peer:heyoka")


def chart(result: dict, label: str, path: str | Path, only=None) -> Path:
    """Work-precision chart of one problem: error (y) against wall time (x), log-log, a curve per pathway
    (`only`: just these pathways, e.g. `HEADLINE`).  Failed runs, and errors above 1 (a run that ended
    on another attractor), are left off."""
    plt = pyplot()

    prob = result["problems"][label]
    default = result["default_engine"]
    fig, ax = plt.subplots(figsize=(11, 7))
    palette = [c for i, c in enumerate(plt.get_cmap("tab20").colors) if i not in (4, 5, 6, 7, 8, 9)]
    # (greens and purples are the peers', red the default's)
    k = 0
    for rec in prob["curves"]:
        if only is not None and rec["name"] not in only:
            continue
        pts = sorted(((q[TIME], q["error"], q["tol"]) for q in rec["points"] if q.get(TIME) and q.get("error")
                      and q["error"] <= 1.0 and q.get("status") == "success"), key=lambda v: -v[2])
        if not pts:
            continue
        xs, ys = [v[0] for v in pts], [v[1] for v in pts]
        if rec["name"] == default:
            ax.plot(xs, ys, "-o", color="#d62728", lw=3, ms=5, label=f"{rec['name']} (default)", zorder=5)
        else:
            colour = _PEER_COLOURS.get(rec["name"], "#2ca02c") if rec["kind"] == "peer" else \
                palette[k % len(palette)]
            k += rec["kind"] != "peer"
            marker = "s" if rec["kind"] == "peer" else ("^" if rec["kind"] == "ivp" else ".")
            ax.plot(xs, ys, _KIND_STYLE.get(rec["kind"], "-"), marker=marker, color=colour,
                    lw=2.2 if rec["kind"] == "peer" else 1.1, ms=5, label=rec["name"])
    res = prob["reference"].get("check_difference")
    if res:
        ax.axhspan(1e-18, 10 * res, color="#cccccc", alpha=0.4, lw=0)
        ax.text(0.99, 10 * res, "reference resolution x 10", transform=ax.get_yaxis_transform(), ha="right",
                va="bottom", fontsize=7, color="#555555")
    ax.set_xscale("log")
    ax.set_yscale("log")
    errs = [q["error"] for r in prob["curves"] for q in r["points"] if q.get("error") and q["error"] <= 1.0
            and (only is None or r["name"] in only)]
    if errs:
        ax.set_ylim(max(min(errs) / 3, 1e-16), max(errs) * 3)
    ax.set_xlabel("CPU time of the integration [s] (best of the repeats, log)")
    ax.set_ylabel("global error: max |y(t_end) - y_ref(t_end)| (log)")
    load = prob.get("load_average_before_timing") or [None]
    pr = prob["problem"]
    ax.set_title(f"Problem {label}: {prob['what']}\n{pr['model']}, t in [0, {pr['t_end']:g}], tolerances "
                 f"{min(result['settings']['tols']):g}..{max(result['settings']['tols']):g}; "
                 f"{when(result)} UTC, load {load[0]} on {result['machine'].get('cpus')} "
                 "cores", fontsize=9)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    return save_figure(fig, path, dpi=110)


def chart_reliable(result: dict, path: str | Path) -> Path:
    """Problem A: per pathway, the loosest tolerance from which on runs reach the right attractor with
    t_dec within 1 % (bars: -log10 tol; a pathway with none shown empty)."""
    plt = pyplot()

    prob = result["problems"]["A"]
    rows = sorted(prob["loosest_reliable"].items(), key=lambda kv: (kv[1]["tol"] is None, -(kv[1]["tol"] or 0)))
    fig, ax = plt.subplots(figsize=(8, 0.28 * len(rows) + 1.5))
    y = np.arange(len(rows))
    vals = [-math.log10(v["tol"]) if v["tol"] else 0.0 for _, v in rows]
    ax.barh(y, vals, color=["#d62728" if k == result["default_engine"] else "#1f77b4" for k, _ in rows])
    for i, (_, v) in enumerate(rows):
        ax.text(vals[i] + 0.1, i, f"{v['tol']:g}" if v["tol"] else (v.get("why") or "none"), va="center", fontsize=7)
    ax.set_yticks(y, [k for k, _ in rows], fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("-log10 of the loosest reliable tolerance (smaller bar = looser tolerance suffices)")
    ax.set_title(f"Problem A: loosest tolerance reaching the reference attractor with t_dec within 1 %\n"
                 f"(reference t_dec = {prob['reference'].get('t_dec') or float('nan'):.2f}; engines: t_dec from "
                 f"their events, others: from a grid of {TDEC_DT:g})", fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path, dpi=110)


def chart_percall(result: dict, path: str | Path) -> Path:
    """ns per call against n (log-log): generated numba and C, hand-written, lambdify; rhs and jac."""
    plt = pyplot()

    rows = result["percall"]["rows"]
    series = [("numba_rhs_loop", "generated numba rhs (jitted loop)", "#d62728", "-o"),
              ("c_rhs_loop", "generated C rhs (C loop, -O2)", "#1f77b4", "-o"),
              ("handwritten_rhs_loop", "hand-written numba rhs, thesis App. A", "#2ca02c", "-s"),
              ("numba_rhs_python", "generated numba rhs called from Python", "#ff7f0e", "--o"),
              ("lambdify_math", "lambdify math, cse (from Python)", "#7f7f7f", "-^"),
              ("lambdify_numpy", "lambdify numpy, cse (from Python)", "#bcbd22", "-^"),
              ("numba_jac_loop", "generated numba jac (jitted loop)", "#d62728", ":x"),
              ("c_jac_loop", "generated C jac (C loop)", "#1f77b4", ":x"),
              ("lambdify_jac_math", "lambdify math jac (from Python)", "#7f7f7f", ":^")]
    fig, ax = plt.subplots(figsize=(9, 6))
    for key, label, colour, style in series:
        pts = [(r["n"], r[key]["ns"]) for r in rows if isinstance(r.get(key), dict)]
        if pts:
            ax.plot(*zip(*pts), style, color=colour, label=label)
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("number of balls n (thesis model, 2n + 4 states)")
    ax.set_ylabel("ns per call (median of the repeats)")
    load = result.get("load_average_before_percall") or [None]
    ax.set_title(f"Cost per call, {when(result)} UTC, load {load[0]}", fontsize=9)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return save_figure(fig, path, dpi=110)




__all__ = ["HEADLINE", "chart", "chart_percall", "chart_reliable"]
