"""The registry of the analysis layer's commands and what they share (model arguments, JSON output).

Each command module (commands.py: simulate; stability_commands.py: stability, continue; ...)
decorates its argument builder with `@command(name, help)`; `commands.register` adds them all to
`adbgen`'s parser.
"""

from __future__ import annotations

import json
import math

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
                   help="a parameter by name (repeatable); VALUE a number or an expression in pi")


def _load(args):
    return load_model(args.model, scene=args.scene)


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
    return None if v is None or (isinstance(v, float) and not math.isfinite(v)) else v


def _emit_json(obj) -> None:
    print(json.dumps(obj, allow_nan=False, default=_json_number))


