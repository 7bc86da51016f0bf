"""The single-plane family's commands that run generated models (the analysis layer):

    adbgen demo     [--out DIR]               thesis Fig. 5.4: transients reproduced, plotted
"""

from __future__ import annotations

from pathlib import Path


def cmd_demo(args) -> int:
    from ....analysis.loading import load_model
    from ....analysis.simulate import amplitude, simulate
    from .. import steady_states as ss
    from ..verify import rotating
    from .published import FIGURE_5_4

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    check = rotating(2)
    print(f"rotating-frame model n = 2 derived and checked against (2.25)-(2.27): {'ok' if check.passed else 'FAIL'}")
    print(f"balanced state (3.6)/(5.2): phi_1 = {ss.evaluate(ss.balanced(2, branch=-1), {'mu': 0.05, 'delta': 0.01})['phi_1']:.14f}")
    model = load_model("thesis_rotating_n2")
    runs = {}
    for panel, (phi0, (r_ref, t_ref)) in FIGURE_5_4.items():
        tr = simulate(model, None, {"phi_1": phi0[0], "phi_2": phi0[1]}, t_end=1000.0, rtol=1e-10, atol=1e-12)
        runs[panel] = tr
        print(f"Fig. 5.4({panel}1): r_max = {tr.r_max:.4f} (thesis {r_ref}), t_dec = {tr.t_dec:.2f} (thesis {t_ref})"
              f"  [{tr.engine}, {tr.wall_s * 1e3:.1f} ms]")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(runs), figsize=(4 * len(runs), 5), sharex=True, constrained_layout=True)
    for col, (panel, tr) in enumerate(runs.items()):
        axes[0, col].plot(tr.t, amplitude(model, tr.y), lw=0.6)
        axes[0, col].set_title(f"Fig. 5.4({panel}): $\\phi(0)$ = ({FIGURE_5_4[panel][0][0]:.2f}, {FIGURE_5_4[panel][0][1]:.2f})")
        axes[0, col].set_ylabel("$r$")
        for i in range(2):
            axes[1, col].plot(tr.t, tr.y[2 + i], lw=0.8, label=f"$\\phi_{i + 1}$")
        axes[1, col].set_xlabel("$t$")
        axes[1, col].legend(loc="best")
    path = out / "fig5_4.png"
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")
    return 0 if check.passed else 1


def register(sub) -> None:
    m = sub.add_parser("demo", help="reproduce the thesis' Fig. 5.4 transients and plot them")
    m.add_argument("--out", default="out/demo")
    m.set_defaults(fn=cmd_demo)
