"""The single-plane family's commands (top level, as the first family had them):

    adbgen derive   [--scene F] [--n N] [--form fixed|nondimensional|rotating|first-order] [--format text|latex|json]
    adbgen steady   [--n N] [--mu ..] [--Omega ..] [--zeta ..] [--delta ..] [--beta ..]

`adbgen demo` runs the generated models: it is the family's science (`science/commands.py`).
"""

from __future__ import annotations

from ...cli_types import finite, positive_int
from ...core.printing import print_model
from ...errors import SceneError


def _scene(args):
    from .scene import Scene

    data = {}
    if getattr(args, "scene", None):
        scene = Scene.load(args.scene)
        if args.n is None:
            return scene
        import dataclasses

        data = {f.name: getattr(scene, f.name) for f in dataclasses.fields(scene)}
        for key in ("ball_mass", "ball_damping"):
            if isinstance(data[key], tuple):
                raise SceneError("n", f"--n cannot resize a scene with per-ball {key}")
    if args.n is not None:
        data["n"] = args.n
    return Scene.from_mapping(data)


def _form(scene, form: str):
    from . import reductions
    from .model import derive
    from .selection import smallest_model

    if form == "fixed":
        return derive(scene)
    if form == "nondimensional":
        return reductions.nondimensionalise(scene)
    if form == "rotating":
        return reductions.rotating_frame(scene)
    if form == "first-order":
        return smallest_model(scene).system
    raise AssertionError(form)


def cmd_derive(args) -> int:
    return print_model(_form(_scene(args), args.form), args.format)


def cmd_steady(args) -> int:
    import sympy as sp

    from .scene import Scene
    from . import steady_states as ss
    from .reductions import rotating_frame
    from ...core.linearisation import Linearisation

    n = args.n or 2
    p = {"mu": args.mu, "Omega": args.Omega, "zeta": args.zeta, "delta": args.delta, "beta": args.beta}
    for name in ("mu", "Omega", "delta"):
        if p[name] <= 0:
            raise SceneError(name, f"must be positive, got {p[name]}")
    if p["zeta"] <= 0:
        raise SceneError("zeta", "the closed forms (3.9)-(3.10) need zeta > 0")
    if p["beta"] < 0:
        raise SceneError("beta", f"must be non-negative, got {p['beta']}")
    lin = Linearisation(rotating_frame(Scene(n=n)))
    pvec = lin.parameters(**p)
    print(f"n = {n}, " + ", ".join(f"{k} = {v:g}" for k, v in p.items()) + f", K = {1 - p['Omega']**2 * (1 + n * p['mu']):.6g}")
    rows = []
    if n >= 2:  # the thesis' representative of the family: phi_3 = ... = phi_n = pi (ch. 4)
        try:
            state = ss.evaluate(ss.balanced(n, [sp.pi] * (n - 2), branch=-1), p)
        except ValueError:  # arccos of more than 1: no balanced state with these free angles
            state = None
        rows.append(("1 (3.6)" + (", phi_3.. = pi" if n > 2 else ""), state))
    for m in range(n, 0, -1):
        for sign in (1, -1):
            label = f"2{'+' if sign > 0 else '-'} (3.9)" if m == n else f"3({n}-{m}){'+' if sign > 0 else '-'} (3.10)"
            ok = ss.inline_exists(n, m, p["mu"], p["Omega"], p["zeta"], p["delta"])
            rows.append((label, ss.evaluate(ss.inline(n, m, sign), p) if ok else None))
    for label, state in rows:
        if state is None:
            print(f"  {label:22s} does not exist here")
            continue
        spectrum = lin.spectrum(lin.point(state), pvec)
        verdict = "stable" if spectrum.stable else f"unstable ({spectrum.n_unstable})"
        text = "  ".join(f"{k} = {v:+.9f}" for k, v in state.items())
        print(f"  {label:22s} {verdict:14s} {text}")
    for m in range(n, 0, -1):
        speeds = ss.critical_speeds(n, m, p["mu"], p["zeta"], p["delta"])
        name = "2+-" if m == n else f"3({n}-{m})+-"
        if speeds:
            print(f"  {name} absent for {speeds[0]:.6f} < Omega < {speeds[1]:.6f}  ((3.16)/(3.18))")
    return 0


def register(sub) -> None:
    d = sub.add_parser("derive", help="derive and print a model")
    d.add_argument("--scene", help="scene file (TOML)")
    d.add_argument("--n", type=positive_int)
    d.add_argument("--form", choices=("fixed", "nondimensional", "rotating", "first-order"), default="first-order",
                   help="first-order = the smallest exact model for the scene")
    d.add_argument("--format", choices=("text", "latex", "json"), default="text")
    d.set_defaults(fn=cmd_derive)

    s = sub.add_parser("steady", help="closed-form steady states and where they exist (thesis ch. 3)")
    s.add_argument("--n", type=positive_int)
    for name, default in (("mu", 0.05), ("Omega", 4.0), ("zeta", 0.01), ("delta", 0.01), ("beta", 0.01)):
        s.add_argument(f"--{name}", type=finite, default=default)
    s.set_defaults(fn=cmd_steady)
