"""A stability map's stable windows certified to a stated resolution (issue 34 item 3): the thesis' ch. 4 maps
(`adbgen sweep --measure stability` over two parameters) refined between their grid points.

    certify_store(store, model, grid) -> the `resolution` of the sweep's --json summary

Along every row and every column of the map (`windows.certify`), the steady state is re-found by Newton from
the neighbouring sample wherever stability changes between neighbours, the leading real part of the
transverse spectrum heads for zero, or it has an extremum near zero; each change is located and seen on
both sides.  A sample counts only where Newton stays on the state the map continues (the one START is): a
point where it lands on another state, or fails, splits the line.  The windows go into the store's
attribute `windows` ({"rows": [{axis 2: value, "stable": [[a, b], ...]}], "columns": [...]}, drawn by
`sweep_figures`), the certified resolution into `resolution`.
"""

from __future__ import annotations

import json

import numpy as np

from .grid import Grid
from .loading import Model

REFINE = 8  # the certified resolution: the grid's spacing / REFINE along each axis


def certify_store(store, model: Model, grid: Grid, refine: int = REFINE) -> dict:
    import zarr

    from .attractors import labels, name_steady_state, newton, spectrum
    from .windows import Sample, SolveFailed, certify

    group = zarr.open_group(str(store), mode="r+")
    value = np.asarray(group["stability"][...])
    abscissa = np.asarray(group["abscissa"][...])
    kind = np.asarray(group["steady_state"][...])
    y_end = np.asarray(group["y_end"][...])
    names = labels(model)
    start = names.index(name_steady_state(model, model.module.START, model.module.START_PARAMETERS))
    a1, a2 = grid.axes
    k1, k2 = model.param_names.index(a1.name), model.param_names.index(a2.name)
    res = [float(np.max(np.abs(np.diff(a.values)))) / refine if a.count > 1 else 0.0 for a in (a1, a2)]

    def params(v1, v2):
        p = np.array(grid.base_params, float)
        p[k1], p[k2] = v1, v2
        return p

    def sample(x, i, j):
        if value[i, j] < 0 or kind[i, j] != start:
            return None
        return Sample(float(x), float(abscissa[i, j]), int(value[i, j]), y_end[i, j])

    def solver(at):
        def solve(x, near):
            p = at(x)
            y = newton(model, near.state, p)
            if y is None:
                raise SolveFailed("Newton failed")
            if names.index(name_steady_state(model, y, p)) != start:
                raise SolveFailed("Newton reached another steady state")
            s = spectrum(model, y, p)
            return Sample(float(x), float(s.abscissa), int(s.unstable()), y)
        return solve

    out = {"rows": [], "columns": []}
    added = 0
    for j, v2 in enumerate(a2.values):  # rows: along the first axis at each value of the second
        line = certify([sample(x, i, j) for i, x in enumerate(a1.values)], solver(lambda x, v2=v2: params(x, v2)), res[0])
        added += line.inserted
        out["rows"].append({a2.name: float(v2), "stable": [list(w) for w in line.windows]})
    for i, v1 in enumerate(a1.values):
        line = certify([sample(x, i, j) for j, x in enumerate(a2.values)], solver(lambda x, v1=v1: params(v1, x)), res[1])
        added += line.inserted
        out["columns"].append({a1.name: float(v1), "stable": [list(w) for w in line.windows]})
    resolution = {a1.name: res[0], a2.name: res[1], "samples_added": added,
                  "statement": f"every stable window of the continued state wider than {res[0]:.3g} in {a1.name} along "
                               f"each row, and wider than {res[1]:.3g} in {a2.name} along each column, holds a sample: "
                               "refined where stability changes between neighbours, where the leading real part heads "
                               "for zero and at its extrema near zero (assumed: it turns at most once between samples "
                               "the rules leave apart); each change seen on both sides"}
    group.attrs["windows"] = json.dumps(out)
    group.attrs["resolution"] = json.dumps(resolution)
    return resolution
