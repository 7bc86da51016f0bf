"""`adbgen two-plane ...`: the two-plane family's commands (registered through `family.FAMILY`).

    adbgen two-plane verify                      every two-plane check (also part of `adbgen verify`)
    adbgen two-plane derive [--preset P | --scene F] [--form fixed|rotating|first-order] [--format text|latex|json]
    adbgen two-plane steady [--preset P | --scene F] [--eps E] [--Omega W] [--m M]
"""

from __future__ import annotations

import math

from ...cli_types import finite


def _scene(args):
    from .scene import TwoPlaneScene

    if args.scene:
        return TwoPlaneScene.load(args.scene)
    return TwoPlaneScene.from_mapping({"preset": args.preset})


def cmd_verify(args) -> int:
    from .. import get
    from ..verification import run_verify

    return run_verify((get("two-plane"),), ())


def cmd_derive(args) -> int:
    from .model import derive
    from .reductions import first_order, rotating_frame

    scene = _scene(args)
    if args.form == "fixed":
        model = derive(scene)
    elif args.form == "rotating":
        model = rotating_frame(scene)
    else:
        fixed = args.form == "first-order-fixed" or not scene.isotropic or scene.speed.law != "constant"
        model = first_order(derive(scene) if fixed else rotating_frame(scene))
    from ...core.printing import print_model

    return print_model(model, args.format)


def cmd_steady(args) -> int:
    """Critical speeds, the normal form's a_1, a_2 and the predicted stability (35)-(38) at one speed;
    for the symmetric set-up also the balanced state B and its eigenvalues in the full model."""
    from dataclasses import replace

    import numpy as np

    from ...errors import SceneError
    from . import critical_speeds as cs
    from . import normal_form as nf
    from .branches import FullSteadyStates
    from .symbols import R, k, l, z

    scene = _scene(args)
    eps = scene.eccentricity if args.eps is None else args.eps
    Om = scene.speed.omega if args.Omega is None else args.Omega
    if not (math.isfinite(eps) and eps > 0):
        raise SceneError("eccentricity", f"must be positive for the normal form, got {eps!r}")
    if not (math.isfinite(Om) and Om > 0):
        raise SceneError("speed.omega", f"must be positive, got {Om!r}")
    scene = replace(scene, eccentricity=eps, speed=replace(scene.speed, law="constant", omega=Om))
    plain = cs.critical_speeds(scene, with_balls=False)
    print(f"critical speeds, plain rotor: {', '.join(f'{v:.6f}' for v in plain)}")
    print(f"critical speeds with the balls: {', '.join(f'{v:.6f}' for v in cs.critical_speeds(scene))}")
    if not scene.symmetric:
        print("the D4 normal form (section 3) needs the symmetric set-up: equal balls, mirror races, equal "
              "isotropic bearings")
        return 0
    r0 = scene.races[0]
    s = nf.symmetric_model().s
    vals = {s.M: scene.rotor_mass, s.eps: eps, R: r0.radius, s.Jt: scene.transverse_inertia, s.Jp: scene.polar_inertia,
            k: scene.bearing_1.xy("stiffness")[0], l: scene.bearing_1.position, z: r0.z, s.Omega: Om}
    co = nf.coefficients()
    a_1, a_2 = (float(co[key].xreplace(vals)) for key in ("a1", "a2"))
    m_c = float(nf.critical_mass().xreplace(vals))
    kap = float(nf.kappa_at_critical_mass().xreplace(vals))
    print(f"m_c = M eps/(4R) = {m_c:.6g}; kappa(Omega) (32) = {kap:.6g}; a_1 = {a_1:.6g}, a_2 = {a_2:.6g} (34)")
    print(f"normal form, mu > 0: B {'stable' if a_1 > a_2 else 'unstable'} (38), "
          f"C3 {'stable' if a_2 > a_1 else 'unstable'} (37)")
    mass = r0.masses[0] if args.m is None else args.m
    if not (math.isfinite(mass) and mass > 0):
        raise SceneError("races[0].masses", f"must be positive, got {mass!r}")
    if mass < m_c:
        print(f"m = {mass:.6g} < m_c: no balanced state B")
        return 0
    alpha = math.acos(m_c / mass)  # B of (9): alpha = pi +- arccos(M eps/(4 m R))
    full = FullSteadyStates(scene, epsilon=eps, Omega=Om, chi=0.0, beta=0.0)
    q = np.array([0, 0, 0, 0, math.pi + alpha, math.pi - alpha, math.pi + alpha, math.pi - alpha])
    p = full.parameters(mass)
    residual = float(np.abs(full.lin.residual(q, p)).max())
    spec = full.lin.spectrum(q, p)
    print(f"B at m = {mass:.6g}: alpha_hat = {alpha:.9f} (residual {residual:.1e}); full model: "
          f"{'stable' if spec.stable else f'unstable ({spec.n_unstable})'}, leading eigenvalue {spec.leading():.6g}")
    return 0


def register(sub) -> None:
    """Register `two-plane` and its commands on the main parser's subparsers."""
    from .scene import PRESETS

    tp = sub.add_parser("two-plane", help="the two-plane rigid rotor (Rodrigues et al. 2011)")
    tsub = tp.add_subparsers(dest="two_plane_command", required=True, parser_class=type(tp))
    v = tsub.add_parser("verify", help="every two-plane check")
    v.set_defaults(fn=cmd_verify)
    for name, fn, helptext in (("derive", cmd_derive, "derive and print the model"),
                               ("steady", cmd_steady, "critical speeds, normal form, balanced state")):
        p = tsub.add_parser(name, help=helptext)
        p.add_argument("--preset", choices=PRESETS, default="paper-10")
        p.add_argument("--scene", help="scene file (TOML)")
        p.set_defaults(fn=fn)
        if name == "derive":
            p.add_argument("--form", choices=("fixed", "rotating", "first-order", "first-order-fixed"),
                           default="first-order")
            p.add_argument("--format", choices=("text", "latex", "json"), default="text")
        else:
            p.add_argument("--eps", type=finite)
            p.add_argument("--Omega", type=finite)
            p.add_argument("--m", type=finite, help="ball mass (default: the scene's)")
