"""Files of a periodic orbit: `write_orbit` (orbit.csv, orbit.png) for `adbgen orbit --out`."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def write_orbit(o, flow, out: Path) -> None:
    """orbit.csv (t and the states over one period) and orbit.png (r against t and the x-y whirl), written
    under temporary names and renamed."""
    from ...outputs import save_figure, writing
    from ..figure_style import pyplot
    from . import describe
    from .orbit import trace

    out.mkdir(parents=True, exist_ok=True)
    t, Y = trace(o, flow, 1000)
    m = o.model
    with writing(out / "orbit.csv") as fh:
        fh.write(f"# model: {m.name}\n# source_hash: {m.source_hash}\n# period: {o.period!r}\n")
        fh.write(",".join(("t",) + m.state_names) + "\n")
        np.savetxt(fh, np.column_stack([t, Y]), delimiter=",", fmt="%.17g")
    ix, iy = describe.amplitude_indices(m)
    fig, (a1, a2) = pyplot().subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
    a1.plot(t, np.hypot(Y[:, ix], Y[:, iy]), lw=1)
    a1.set_xlabel("t")
    a1.set_ylabel("r")
    a2.plot(Y[:, ix], Y[:, iy], lw=1)
    a2.set_aspect("equal", "datalim")
    a2.set_xlabel(m.state_names[ix])
    a2.set_ylabel(m.state_names[iy])
    fig.suptitle(f"{m.name}: period {o.period:.8g}, {'stable' if o.stable else 'unstable'}", fontsize=9)
    save_figure(fig, out / "orbit.png", dpi=110)
