"""`adbgen regenerate`: derive, check and emit every registered target for the models the families offer.

    adbgen regenerate [--check] [--n N ...] [--scene F [--name NAME]] [--family F ...] [--out DIR]
                      [--targets numba c cvode auto] [--skip-checks] [--full-checks]
                      [--form loops|unrolled] [--quiet]

Without --n/--scene: every family's default set into the repository's generated/.  --n: each chosen
family's model kinds for those n; --scene: the smallest exact model of the scene, from the family
whose scene format the file is (or --family).  --check writes nothing and exits 1, printing a
unified diff (truncated) of every stale file.
"""

from __future__ import annotations

import sys
from pathlib import Path

from .. import families
from ..cli_types import UsageError, model_name, positive_int
from ..errors import AdbgenError, SceneError
from ..codegen import journal, targets
from ..codegen.passes.lowering import DEFAULT_FORM, FORMS
from ..outputs import output_folder


def _family_for_scene(path: str, chosen: tuple[str, ...] | None):
    """(family, scene): the chosen family's, or the one family whose scene format accepts the file."""
    if not Path(path).is_file():
        raise SceneError("<file>", f"no scene file at {path}")
    candidates = [families.get(n) for n in chosen] if chosen else list(families.all_families())
    accepted, errors = [], []
    for family in candidates:
        try:
            accepted.append((family, family.load_scene(path)))
        except AdbgenError as exc:
            errors.append((family, exc))
    if len(accepted) == 1:
        return accepted[0]
    if not accepted:
        raise _error_of_the_scenes_family(path, errors)
    raise UsageError(f"{path}: a scene of several families ({', '.join(f.name for f, _ in accepted)}): "
                     "choose one with --family")


def _unknown_top_level(exc) -> str | None:
    """The key a family's scene format does not know, when that is why it refused the file."""
    field = getattr(exc, "field", "")
    return field if isinstance(exc, SceneError) and str(exc).endswith("unknown option") and "." not in field \
        and not field.startswith("<") else None


def _error_of_the_scenes_family(path: str, errors: list):
    """One error, the one of the family the file is written for: a family that refused it for a key it does
    not know is not the file's family when another family knows its keys and refused a value (issue 24:
    no "...; two-plane: scene.n: unknown option" after a single-plane scene's own complaint)."""
    if len(errors) == 1:
        return errors[0][1]
    own = [(f, exc) for f, exc in errors if _unknown_top_level(exc) is None]
    if own:
        return own[0][1]
    keys = {_unknown_top_level(exc) for _, exc in errors}
    if len(keys) == 1:  # every family refuses the same key: a typo, or no scene at all
        key = keys.pop()
        return SceneError(key, f"unknown option (not a key of a {' or a '.join(f.name for f, _ in errors)} scene)")
    # each family stops at another unknown key: the one that got further in the sorted keys knows more of them
    family, exc = max(errors, key=lambda fe: _unknown_top_level(fe[1]))
    return SceneError(exc.field, f"unknown option (read as a {family.name} scene, the format that knows most of its keys)")


def _resize(family, scene, n: int):
    """The scene with n balls (single-plane scenes; others refuse)."""
    import dataclasses

    if not any(f.name == "n" for f in dataclasses.fields(scene)):
        raise UsageError(f"--n cannot resize a {family.name} scene")
    data = {f.name: getattr(scene, f.name) for f in dataclasses.fields(scene)}
    for key in ("ball_mass", "ball_damping"):
        if isinstance(data.get(key), tuple):
            raise SceneError("n", f"--n cannot resize a scene with per-ball {key}")
    return type(scene).from_mapping({**data, "n": n})


def specs_for(args) -> list:
    chosen = tuple(args.family) if args.family else None
    if args.scene is not None:
        family, scene = _family_for_scene(args.scene, chosen)
        if args.n is not None:
            if len(args.n) != 1:
                raise UsageError("--scene takes one --n")
            scene = _resize(family, scene, args.n[0])
        return [family.model_for_scene(scene, args.name)]
    picked = [families.get(n) for n in chosen] if chosen else list(families.all_families())
    if args.n is not None:
        specs = [kind(n) for n in args.n for family in picked for kind in family.kinds().values()]
        if not specs:
            raise UsageError(f"no model of {', '.join(f.name for f in picked)} is offered by number of balls")
        return specs
    return [spec for family in picked for spec in family.models()]


def cmd_regenerate(args) -> int:
    from ..codegen.names import validate_name
    from ..codegen.regenerate import DEFAULT_OUT, IN_SOURCE_CHECKOUT, diff, render_all, stale, write

    custom = args.scene is not None or args.n is not None or bool(args.family)
    if custom and args.out is None:
        raise UsageError("--scene/--n/--family generate models outside the default set: give --out DIR "
                         "(generated/ holds the default set only)")
    if args.out is None and not IN_SOURCE_CHECKOUT:
        raise UsageError("adbgen is installed, not run from its source checkout: give --out DIR")
    if args.name is not None and args.scene is None:
        raise UsageError("--name names the model of --scene")
    out = Path(args.out) if args.out is not None else DEFAULT_OUT
    output_folder(out, "--out")  # before minutes of derivation, not after
    note = journal.recover(out)
    if note:
        print(f"{out}: an interrupted `adbgen regenerate` was {note} (its journal)" if note != "cleaned" else
              f"{out}: removed what an interrupted `adbgen regenerate` left beside it", file=sys.stderr)
    specs = specs_for(args)
    for spec in specs:
        validate_name(spec.name)
    all_targets = set(args.targets) == set(targets.names())
    log = (lambda line: None) if args.quiet else (lambda line: print(line, file=sys.stderr, flush=True))
    rendered = render_all(specs, tuple(args.targets), run_checks=not args.skip_checks, progress=log,
                          full_checks=args.full_checks, form=args.form)
    if args.check:
        report = stale(rendered, out, extra=all_targets)
        for rel, status in report.items():
            print(f"stale: {out / rel} ({status})")
            if status in ("differs", "missing"):
                sys.stdout.write(diff(rendered, out, rel))
        if report:
            print(f"{len(report)} file(s) out of date: run `adbgen regenerate`", file=sys.stderr)
            return 1
        print(f"{out}: {len(rendered.files)} files up to date")
        return 0
    changed = write(rendered, out, prune=all_targets and not custom)
    print(f"{out}: {len(rendered.files)} files, {len(changed)} changed")
    return 0


def register(sub) -> None:
    r = sub.add_parser("regenerate", help="derive, check and emit the generated code (" + ", ".join(targets.names()) + ")")
    r.add_argument("--check", action="store_true",
                   help="write nothing; exit 1 naming the files that are out of date, with a diff of each")
    r.add_argument("--scene", help="scene file (TOML): its smallest exact model (needs --out)")
    r.add_argument("--n", type=positive_int, nargs="+", help="the families' model kinds for these n (needs --out)")
    r.add_argument("--family", nargs="+", choices=families.names(),
                   help="only these families (default: every one; for --scene: the one that reads the file)")
    r.add_argument("--name", type=model_name, help="model name for --scene")
    r.add_argument("--out", help="output folder (default: the repository's generated/)")
    r.add_argument("--targets", nargs="+", choices=targets.names(), default=list(targets.names()))
    r.add_argument("--skip-checks", action="store_true", help="skip the reduction checks (the lowering check and the proofs of the emitted files stay)")
    r.add_argument("--full-checks", action="store_true",
                   help="run every reduction check in its exact form (default: proportionate forms at large n)")
    r.add_argument("--form", choices=FORMS, default=DEFAULT_FORM,
                   help="the generated code's form: loops over the balls (default) or every ball unrolled")
    r.add_argument("--quiet", action="store_true", help="no progress lines")
    r.set_defaults(fn=cmd_regenerate)
