"""Figures of a sweep store, PNG and PDF beside it, in the style of the thesis' ch. 4-5 maps.

    basins (attractor)   each grid point coloured by where its trajectory ends (balanced 1 dark, as the
                         thesis shades the balanced state's basin in Fig. 5.18-5.20); undecided runs red,
                         their own class in the legend (with the count), never one of the outcomes
    r_max, t_dec         colour maps (t_dec: grey where r has not settled by t_end)
    stability            regions by the number of unstable eigenvalues (0: stable, shaded dark as the
                         thesis' Fig. 4.1, 4.5, 4.10)

Axes carry the symbols (phi_1(0), Omega, ...), the title the model and the fixed parameter values.
A sweep run with the tolerance check marks every tolerance-sensitive point (a white diamond, the count
in the legend and the title): its outcome there is not a fact of the model.
Two-dimensional grids give maps, one-dimensional grids curves; larger grids are not drawn.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .figure_style import title_lines
from .grid import axis_symbol, tex


def _caption(ds, axes) -> str:
    params = json.loads(ds.attrs.get("parameters", "{}"))
    parts = [f"${tex(k)}$ = {v:g}" for k, v in params.items() if k not in axes]
    states = json.loads(ds.attrs.get("initial_state", "{}"))
    ties = {state: (axis, offset) for state, axis, offset in json.loads(ds.attrs.get("ties", "[]"))}
    parts += [f"{axis_symbol(k, 'state')} = {v:.4g}" for k, v in states.items()
              if k not in axes and k not in ties and v != 0.0]
    parts += [f"{axis_symbol(k, 'state')} = {axis_symbol(a, 'state')} {'+' if o >= 0 else '-'} {abs(o):.4g}"
              for k, (a, o) in ties.items()]
    settings = json.loads(ds.attrs["adbgen_sweep"])
    if settings["measure"] != "stability":
        parts.append(f"$t_{{end}}$ = {settings['t_end']:g}, rtol {settings['rtol']:g}")
    return ", ".join(parts)


def write_figures(store: Path) -> list[Path]:
    """Draw the store's measure; returns the files written (none if the grid is not 1-D or 2-D)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import xarray as xr

    ds = xr.open_zarr(store, consolidated=False)
    measure = ds.attrs["measure"]
    if measure == "residual":  # a distribution over the starts, whatever the grid's dimension
        return _residual_histogram(ds, store)
    dims = [d for d in ds[measure].dims]
    if len(dims) not in (1, 2):
        return []
    da = ds[measure].load()
    done = ds["done"].load().values.astype(bool)
    fig, ax = plt.subplots(figsize=(7.5, 5.0), constrained_layout=True)
    title = f"{ds.attrs['model']}: " + {"r_max": "$r_{max}$", "t_dec": "$t_{dec}$"}.get(measure, measure)
    if measure == "attractor":
        _categorical(fig, ax, da, done, json.loads(ds.attrs["labels"]), dims)
        title = f"{ds.attrs['model']}: basins of attraction"
    elif measure == "stability":
        names = json.loads(ds.attrs["labels"])
        kind = ds["steady_state"].load().values
        start = _start_kind(ds, names)
        other = done & (kind >= 0) & (kind != start)
        failed = None
        if "failure" in ds:  # a failure is "not computed", never "no steady state"
            code = ds["failure"].load().values
            failed = done & ((code == 1) | (code == 3))
        _stability(fig, ax, da, done & ~other & (~failed if failed is not None else True), dims, other, failed)
        if len(dims) == 2 and "windows" in ds.attrs:
            _windows(ax, da, dims, json.loads(ds.attrs["windows"]))
        title = (f"{ds.attrs['model']}: unstable eigenvalues of the steady state"
                 + (f" ({names[start]}, continued from START)" if start >= 0 else ""))
    else:
        failed = done & (ds["failed"].load().values == 1) if "failed" in ds else np.zeros_like(done)
        _continuous(fig, ax, da, done & ~failed, dims, measure, failed)
        if failed.any():  # a failed run has no value: never drawn as one, nor as "not settled"
            title += f" ({int(failed.sum())} failed: no value, marked x)" if len(dims) == 2 else \
                f" ({int(failed.sum())} failed: no value, not drawn)"
    flagged = _mark_sensitive(ax, ds, da, done, dims, measure)
    if flagged:
        title += f" ({flagged} tolerance-sensitive, marked)"
    ax.set_title(title_lines(title, _caption(ds, dims)), fontsize=9)
    return _save(fig, store, measure)


def _mark_sensitive(ax, ds, da, done, dims, measure) -> int:
    """Mark the points the tolerance check flagged (`tolerance.mark_points`); their number."""
    if "tolerance_sensitive" not in ds:
        return 0
    from .tolerance import mark_points

    flags = done & (ds["tolerance_sensitive"].load().values == 1)
    if not flags.any():
        return 0
    idx = np.nonzero(flags)
    x = da[dims[0]].values[idx[0]]
    if len(dims) == 2:
        y = da[dims[1]].values[idx[1]]
    else:
        y = da.values[idx[0]].astype(float)  # on the plotted curve (the label's code or the value)
    mark_points(ax, x, y)
    if len(dims) == 1 or measure != "attractor":
        ax.legend(loc="best", fontsize=8, frameon=False)
    else:  # the categorical map's legend (outside the axes) with the mark added
        legend = ax.get_legend()
        handles = list(legend.legend_handles) if legend is not None else []
        handles.append(ax.get_lines()[-1])
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8, frameon=False)
    return int(flags.sum())


def _edges(values: np.ndarray) -> np.ndarray:
    if len(values) == 1:
        return np.array([values[0] - 0.5, values[0] + 0.5])
    mid = 0.5 * (values[1:] + values[:-1])
    return np.concatenate([[2 * values[0] - mid[0]], mid, [2 * values[-1] - mid[-1]]])


def _symbol(da, dim: str) -> str:
    return axis_symbol(dim, da[dim].attrs.get("kind", "parameter"))


def _map(ax, da, dims, z, **kw):
    x, y = da[dims[0]].values, da[dims[1]].values
    m = ax.pcolormesh(_edges(x), _edges(y), np.asarray(z).T, **kw)
    ax.set_xlabel(_symbol(da, dims[0]))
    ax.set_ylabel(_symbol(da, dims[1]))
    # two angles of the same period: a square map
    ax.set_aspect("equal" if all(da[d].attrs.get("angle") for d in dims[:2]) else "auto")
    return m


def _categorical(fig, ax, da, done, names, dims):
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    codes = np.where(done, da.values, -1)
    present = sorted(int(c) for c in np.unique(codes) if c >= 0)
    # undecided runs (and failed ones) are their own classes, each with its colour and legend entry: never
    # drawn as an outcome ("unsettled": the label of stores written before outcomes were decided)
    palette = {"balanced 1": "#1b2a49", "balanced 1 (algebraic approach)": "#4a6fa5", "limit cycle": "#e8a33d",
               "desynchronised": "#8c564b", "undecided": "#c44e52", "unsettled": "#c44e52", "failed": "#000000"}
    others = iter(["#7fb3d5", "#76b7a0", "#b07aa1", "#9c755f", "#bab0ac", "#59a14f", "#edc948", "#ff9da7"])
    colours = {c: palette.get(names[c]) or next(others, "#888888") for c in present}
    if len(dims) == 1:
        x = da[dims[0]].values
        for c in present:
            sel = codes == c
            ax.plot(x[sel], np.full(sel.sum(), c), "s", color=colours[c], label=names[c])
        ax.set_xlabel(_symbol(da, dims[0]))
        ax.set_yticks(present, [names[c] for c in present])
        return
    lut = ["#ffffff"] + [colours[c] for c in present]
    index = np.zeros(codes.shape, dtype=int)
    for k, c in enumerate(present, start=1):
        index[codes == c] = k
    cmap = ListedColormap(lut)
    _map(ax, da, dims, index, cmap=cmap, norm=BoundaryNorm(np.arange(len(lut) + 1) - 0.5, len(lut)))
    handles = [Patch(color=colours[c], label=f"{names[c]} ({int((codes == c).sum())})") for c in present]
    if (~done).any():
        handles.append(Patch(facecolor="#ffffff", edgecolor="0.5", label="not computed"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8, frameon=False)


def _start_kind(ds, names) -> int:
    """The label code of the model's START (the state the map continues), -1 if unknown."""
    try:
        from .attractors import name_steady_state
        from .loading import load_model

        model = load_model(json.loads(ds.attrs["adbgen_sweep"])["model"])
        return names.index(name_steady_state(model, model.module.START, model.module.START_PARAMETERS))
    except Exception:  # a store from a model no longer at hand: draw without the distinction
        return -1


def _windows(ax, da, dims, windows: dict) -> None:
    """The certified stable windows (`stability_map`) drawn over the map as the stable shade, each row's as a band
    one cell high, each column's one cell wide: a window narrower than the grid's spacing shows."""
    from matplotlib.patches import Rectangle

    x, y = da[dims[0]].values, da[dims[1]].values
    ex, ey = _edges(x), _edges(y)
    colour = "0.15"
    for j, row in enumerate(windows.get("rows", [])):
        for a, b in row["stable"]:
            ax.add_patch(Rectangle((a, ey[j]), b - a, ey[j + 1] - ey[j], color=colour, lw=0))
    for i, col in enumerate(windows.get("columns", [])):
        for a, b in col["stable"]:
            ax.add_patch(Rectangle((ex[i], a), ex[i + 1] - ex[i], b - a, color=colour, lw=0))


def _stability(fig, ax, da, done, dims, other=None, failed=None):
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    z = np.where(done, da.values.astype(int), -2)
    if other is not None:
        z = np.where(other, -1, z)  # Newton reached another steady state: not the continued one
    top = max(int(z.max()), 1)
    greys = ["#ffffff", "#f4d6d6"] + [str(0.15 + 0.8 * k / (top + 1)) for k in range(top + 1)]
    # -2 not computed (white), -1 no steady state (pink), 0 stable (dark) ... more unstable: lighter
    cmap = ListedColormap(greys[: top + 3])
    norm = BoundaryNorm(np.arange(-2, top + 2) - 0.5, top + 3)
    if len(dims) == 1:
        ax.step(da[dims[0]].values, z, where="mid")
        ax.set_xlabel(_symbol(da, dims[0]))
        ax.set_ylabel("unstable eigenvalues")
        return
    _map(ax, da, dims, z, cmap=cmap, norm=norm)
    handles = [Patch(color=greys[k + 2], label="stable" if k == 0 else f"{k} unstable")
               for k in range(0, top + 1) if (z == k).any()]
    if (z == -1).any():
        handles.append(Patch(color=greys[1], label="state not found (does not exist, or another one)"))
    if failed is not None and failed.any():
        handles.append(Patch(facecolor=greys[0], edgecolor="C3", hatch="xx", label="not computed (Newton failed)"))
        x, y = da[dims[0]].values, da[dims[1]].values
        i, j = np.nonzero(failed)
        ax.plot(x[i], y[j], "x", color="C3", ms=4, ls="none")
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8, frameon=False)


def _residual_histogram(ds, store: Path) -> list[Path]:
    """The residual imbalance at rest over the sweep's starts (residual.distribution), its quantiles marked;
    runs not at rest and failed runs are counted in the title, not drawn."""
    import matplotlib.pyplot as plt

    from .residual import distribution

    done = ds["done"].load().values.astype(bool)
    d = distribution(ds["residual"].load().values[done], ds["at_rest"].load().values[done])
    fig, ax = plt.subplots(figsize=(7.5, 5.0), constrained_layout=True)
    edges, counts = np.asarray(d["histogram"]["edges"]), np.asarray(d["histogram"]["counts"])
    if len(counts):
        ax.stairs(counts, edges, fill=True, alpha=0.6)
        for q, style in (("50", "-"), ("90", "--"), ("99", ":")):
            ax.axvline(d["quantiles"][q], color="k", ls=style, lw=1, label=f"{q} %: {d['quantiles'][q]:.3g}")
        ax.legend(fontsize=8)
    measure = ds["residual"].attrs.get("measure", "r")  # the model's residual measure (r, or e.g. A), as stored
    ax.set_xlabel(f"residual imbalance ${measure}$ at rest" if measure.isalpha() and len(measure) == 1
                  else f"residual imbalance {measure} at rest")
    ax.set_ylabel("starts")
    title = (f"{ds.attrs['model']}: residual imbalance at rest, {d['at_rest']} starts "
             f"({d['not_at_rest']} not at rest by $t_{{end}}$, {d['failed']} failed: not drawn)")
    ax.set_title(title_lines(title, _caption(ds, [d_ for d_ in ds["residual"].dims])), fontsize=9)
    return _save(fig, store, "residual")


def _save(fig, store: Path, name: str) -> list[Path]:
    """The figure as name.png and name.pdf beside the store, closed."""
    import matplotlib.pyplot as plt

    out = []
    for ext in ("png", "pdf"):
        path = store.parent / f"{name}.{ext}"
        fig.savefig(path, dpi=150)
        out.append(path)
    plt.close(fig)
    return out


def _continuous(fig, ax, da, done, dims, measure, failed):
    """r_max or t_dec over the grid at the points `done` (computed and not failed); grey where t_dec is NaN (r
    not settled by t_end) or not computed; the `failed` runs (no value) marked x in red on a map."""
    z = np.where(done, da.values, np.nan)
    label = {"r_max": "$r_{max}$", "t_dec": "$t_{dec}$"}[measure]
    if len(dims) == 1:
        ax.plot(da[dims[0]].values, z, ".-")
        ax.set_xlabel(_symbol(da, dims[0]))
        ax.set_ylabel(label)
        return
    import matplotlib

    cmap = matplotlib.colormaps["viridis"].copy()
    cmap.set_bad("0.8")  # t_dec: not settled by t_end (or not computed)
    m = _map(ax, da, dims, np.ma.masked_invalid(z), cmap=cmap)
    fig.colorbar(m, ax=ax, label=label + (" (grey: not settled)" if measure == "t_dec" else ""))
    if failed.any():
        i, j = np.nonzero(failed)
        ax.plot(da[dims[0]].values[i], da[dims[1]].values[j], "x", color="C3", ms=6, ls="none", label="failed run")
        ax.legend(loc="best", fontsize=8, frameon=False)
