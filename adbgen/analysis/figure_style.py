"""What every figure of a transient or a branch shares (issue 24 item 7): angles wrapped into
(-pi, pi] with ticks at multiples of pi/2 (or unwrapped, then labelled so), units on the axes,
labelled threshold and t_dec lines, the parameters in the title, published values annotated, and a
log axis clipped above the round-off floor at a stated level.

    pyplot()                                  matplotlib on the file-only backend
    angle_panel(ax, t, angles, names, wrap)   ball angles, wrapped with pi ticks, or unwrapped
    amplitude_panel(ax, t, r, ...)            r on a log axis, threshold and t_dec lines labelled
    title(name, values, units)                "model: omega = 300 rad/s, ..." (what --set changed)
    title_lines(title, caption)               a long title and its caption broken to the figure's width
"""

from __future__ import annotations

import math
import textwrap

import numpy as np

from .units import axis_label, show

# a log axis of r shows at most this many decades below the threshold: the rest is the integrator's
# round-off floor (1e-13 and below), which would otherwise fill the panel
DECADES_BELOW_THRESHOLD = 3


def pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def wrap(angles: np.ndarray) -> np.ndarray:
    """Angles into (-pi, pi]."""
    w = np.mod(np.asarray(angles, float) + np.pi, 2 * np.pi) - np.pi
    return np.where(w == -np.pi, np.pi, w)


def _broken(t: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(t, w) with NaN where a wrapped angle jumps by more than pi, so no line is drawn across."""
    jumps = np.nonzero(np.abs(np.diff(w)) > np.pi)[0]
    if not len(jumps):
        return t, w
    return np.insert(t.astype(float), jumps + 1, np.nan), np.insert(w, jumps + 1, np.nan)


def pi_ticks(ax) -> None:
    ticks = [-math.pi, -math.pi / 2, 0.0, math.pi / 2, math.pi]
    ax.set_yticks(ticks)
    ax.set_yticklabels([r"$-\pi$", r"$-\pi/2$", "0", r"$\pi/2$", r"$\pi$"])
    ax.set_ylim(-math.pi * 1.08, math.pi * 1.08)


def latex_name(name: str) -> str:
    """phi_1 -> $\\phi_{1}$, theta_k likewise; other names as they are, in math."""
    head, _, tail = name.partition("_")
    greek = {"phi", "theta", "alpha", "psi", "omega", "Omega", "mu", "delta", "zeta", "beta", "epsilon"}
    head = f"\\{head}" if head in greek else head
    return f"${head}_{{{tail}}}$" if tail else f"${head}$"


def angle_panel(ax, t, angles, names, wrap_angles: bool = True, unit: str = "rad") -> None:
    """Each ball angle against t: wrapped into (-pi, pi] with pi ticks, or unwrapped and said so."""
    for k, (values, name) in enumerate(zip(angles, names)):
        if wrap_angles:
            tt, w = _broken(np.asarray(t, float), wrap(values))
            ax.plot(tt, w, lw=0.8, color=f"C{k % 10}", label=latex_name(name))
        else:
            ax.plot(t, values, lw=0.8, color=f"C{k % 10}", label=latex_name(name))
    if wrap_angles:
        pi_ticks(ax)
        ax.set_ylabel("ball angle (rad, wrapped)")
    else:
        ax.set_ylabel(f"ball angle ({unit}, unwrapped)")
    ax.legend(loc="best", fontsize=7, ncol=max(1, len(names) // 4))


def amplitude_panel(ax, t, r, threshold: float | None, t_dec: float | None, length: str, time: str,
                    threshold_why: str = "", log: bool = True) -> None:
    """r on a log axis from DECADES_BELOW_THRESHOLD decades under the threshold (the clip is written
    on the panel), or on a linear one (as the thesis draws Fig. 5.4); the threshold and t_dec drawn
    and labelled."""
    r = np.asarray(r, float)
    ax.plot(t, r, lw=0.7, color="C0", label="$r$")
    if not log:
        if threshold is not None and threshold > 0:
            ax.axhline(threshold, color="0.45", lw=0.8, ls="--", label=f"threshold {show(threshold, length, 3)}"
                       + (f" ({threshold_why})" if threshold_why else ""))
        if t_dec is not None:
            ax.axvline(t_dec, color="C3", lw=0.8, ls=":", label=f"$t_{{dec}}$ = {show(t_dec, time, 5)}")
        ax.set_ylabel(axis_label("$r$", length))
        ax.legend(loc="upper right", fontsize=7)
        return
    ax.set_yscale("log")
    positive = r[r > 0]
    top = float(positive.max()) if len(positive) else 1.0
    if threshold is not None and threshold > 0:
        ax.axhline(threshold, color="0.45", lw=0.8, ls="--",
                   label=f"threshold {show(threshold, length, 3)}" + (f" ({threshold_why})" if threshold_why else ""))
        floor = threshold * 10.0 ** -DECADES_BELOW_THRESHOLD
        bottom = max(floor, float(positive.min()) / 2) if len(positive) else floor
        ax.set_ylim(min(bottom, threshold / 2), max(top, threshold) * 2)
        if len(positive) and positive.min() < floor:
            ax.text(0.01, 0.02, f"axis clipped at {show(floor, length, 2)} = threshold / {10 ** DECADES_BELOW_THRESHOLD}",
                    transform=ax.transAxes, ha="left", va="bottom", fontsize=7, color="0.35",
                    bbox=dict(boxstyle="square,pad=0.1", fc="white", ec="none", alpha=0.8))
    if t_dec is not None:
        ax.axvline(t_dec, color="C3", lw=0.8, ls=":", label=f"$t_{{dec}}$ = {show(t_dec, time, 4)}")
    ax.set_ylabel(axis_label("$r$", length))
    ax.legend(loc="upper right", fontsize=7)


def title(name: str, values: dict, param_units: dict, extra: str = "") -> str:
    """The model's name and the parameters the command changed (--set), with their units."""
    given = ", ".join(f"{k} = {show(v, param_units.get(k, '1'), 6)}" for k, v in values.items())
    parts = [name] + ([given] if given else []) + ([extra] if extra else [])
    return "\n".join(parts)


TITLE_WIDTH, CAPTION_WIDTH = 80, 95  # characters a line holds at fontsize 9 on a 7.5-inch figure


def title_lines(title: str, caption: str) -> str:
    """Title and caption fitted to the figure's width (a long one was clipped at the edges, issue 36):
    a long title breaks before its parentheses (each remark whole on its line), the caption between words."""
    head = [title] if len(title) <= TITLE_WIDTH else title.replace(" (", "\n(").split("\n")
    return "\n".join(head + textwrap.wrap(caption, CAPTION_WIDTH))
