"""The registry of the analysis layer's commands and what they share (model arguments, JSON output).

Each command module (commands.py: simulate; stability_commands.py: stability, continue; ...)
decorates its argument builder with `@command(name, help)`; `commands.register` adds them all to
`adbgen`'s parser.
"""

from __future__ import annotations

import json
import math

from ..cli_types import count as _positive_int  # noqa: F401  (the commands' whole numbers >= 1)
from .loading import AnalysisError, load_model

# (name, add_arguments, run) of every command here; `register` adds them all
COMMANDS: list = []


def command(name: str, help: str):
    def wrap(add):
        COMMANDS.append((name, help, add))
        return add
    return wrap


def _model_arguments(p) -> None:
    p.add_argument("model", nargs="?", help="a generated model's name (e.g. thesis_rotating_n3) or a folder "
                                            "written by `adbgen regenerate --out`")
    p.add_argument("--scene", help="scene file (TOML): its smallest exact model, generated once into a cache")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="a parameter by name (repeatable); VALUE a number in the model's unit of NAME, an "
                        "expression in pi, or a value with a unit (omega=300rad/s, omega=3000rpm, eps=0.5mm)")


def _load(args, show_progress: bool = False):
    """The command's model; a scene's first generation (seconds) with its progress on stderr."""
    from ..progress import activity

    if args.scene is None:
        return load_model(args.model)
    with activity(f"generating the model of {args.scene} (once; cached)", show_progress) as note:
        return load_model(args.model, scene=args.scene, on_line=note)


def _quantity_text(option: str):
    """An argparse type: the text of a number, an expression in pi or a value with a unit, checked
    now (converted once the model, whose units decide, is loaded)."""
    import argparse

    from .units import check_syntax

    def check(text: str) -> str:
        try:
            return check_syntax(text, option)
        except AnalysisError as exc:
            raise argparse.ArgumentTypeError(str(exc).removeprefix(f"{option}: ")) from None
    check.__name__ = "quantity"
    return check


def _finite_positive(text: str) -> float:
    import argparse

    from .loading import parse_value

    try:
        value = parse_value(text)
    except AnalysisError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def _json_number(v):
    """A JSON value for what json cannot write itself: numpy scalars and arrays as numbers and lists."""
    if hasattr(v, "tolist"):  # numpy scalar or array
        return _plain(v.tolist())
    raise TypeError(f"{type(v).__name__} is not JSON")


def _plain(obj):
    """`obj` with non-finite floats as null (JSON has no NaN) and numpy values as Python ones."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if hasattr(obj, "tolist"):
        return _plain(obj.tolist())
    return obj


def _emit_json(obj) -> None:
    print(json.dumps(_plain(obj), allow_nan=False, default=_json_number))


