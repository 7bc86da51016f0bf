"""The single-plane family's commands that run generated models (the analysis layer):

    adbgen demo     [--out DIR]               thesis Fig. 5.4: transients reproduced, plotted
"""

from __future__ import annotations

import math


def cmd_demo(args) -> int:
    from ....analysis.figure_style import amplitude_panel, angle_panel, pyplot
    from ....analysis.loading import load_model
    from ....analysis.simulate import amplitude, simulate
    from ....outputs import output_folder, save_figure
    from .. import steady_states as ss
    from ..verify import rotating
    from .published import FIGURE_5_4

    out = output_folder(args.out, "--out")
    check = rotating(2)
    print(f"rotating-frame model n = 2 derived and checked against (2.25)-(2.27): {'ok' if check.passed else 'FAIL'}")
    print(f"balanced state (3.6)/(5.2): phi_1 = {ss.evaluate(ss.balanced(2, branch=-1), {'mu': 0.05, 'delta': 0.01})['phi_1']:.14f}")
    model = load_model("thesis_rotating_n2")
    runs = {}
    for panel, (phi0, (r_ref, t_ref)) in FIGURE_5_4.items():
        # the figure draws the run: DOP853's dense output at 20001 points (30 a forcing period, so the drawn r
        # peaks at the printed r_max); the default Taylor engine returns its own steps, about 3 a period at 1e-10
        tr = simulate(model, None, {"phi_1": phi0[0], "phi_2": phi0[1]}, t_end=1000.0, rtol=1e-10, atol=1e-12,
                      engine="cyrk-dop853", samples=20001)
        runs[panel] = tr
        print(f"Fig. 5.4({panel}1): r_max = {tr.r_max:.4f} (thesis {r_ref}), t_dec = {tr.t_dec:.2f} (thesis {t_ref})"
              f"  [{tr.engine}, {tr.wall_s * 1e3:.1f} ms]")
    plt = pyplot()
    fig, axes = plt.subplots(2, len(runs), figsize=(4.3 * len(runs), 5.5), sharex=True, constrained_layout=True)
    for col, (panel, tr) in enumerate(runs.items()):
        (phi1, phi2), (r_ref, t_ref) = FIGURE_5_4[panel]
        top, bottom = axes[0, col], axes[1, col]
        amplitude_panel(top, tr.t, amplitude(model, tr.y), tr.threshold, tr.t_dec, "1", "1", "the thesis'", log=False)
        top.set_ylabel("$r$ (in units of the race radius R)")
        top.set_title(f"Fig. 5.4({panel}): $\\phi(0)$ = ({phi1 / math.pi:.3g}$\\pi$, {phi2 / math.pi:.3g}$\\pi$)",
                      fontsize=9)
        # the published values beside the recomputed ones (thesis Fig. 5.4, Matlab ode45 at its defaults)
        top.text(0.97, 0.55, f"$r_{{max}}$ = {tr.r_max:.4f}  (thesis {r_ref})\n$t_{{dec}}$ = {tr.t_dec:.2f}  "
                 f"(thesis {t_ref})", transform=top.transAxes, ha="right", va="center", fontsize=8,
                 bbox=dict(boxstyle="round", fc="white", ec="0.7"))
        angle_panel(bottom, tr.t, tr.y[[2, 3]], ["phi_1", "phi_2"], wrap_angles=True)
        bottom.set_xlabel("$t$ (dimensionless: $\\omega_n t$, thesis (2.15))")
    fig.suptitle("thesis Fig. 5.4: transients of thesis_rotating_n2 at (5.1), mu = 0.05, Omega = 4, "
                 "zeta = beta = delta = 0.01", fontsize=9)
    path = save_figure(fig, out / "fig5_4.png", dpi=120)
    print(f"wrote {path}")
    return 0 if check.passed else 1


def register(sub) -> None:
    m = sub.add_parser("demo", help="reproduce the thesis' Fig. 5.4 transients and plot them")
    m.add_argument("--out", default="out/demo")
    m.set_defaults(fn=cmd_demo)
