"""What the commands over generated models share: the model arguments, loading, positive numbers, JSON
output, and `Commands`, the per-module list of subcommands (`@command(name, help)` on the argument
builder; the module's `register = command.register` adds them to `adbgen`'s parser).
"""

from __future__ import annotations

import json

from ..analysis.loading import AnalysisError, load_model
from ..analysis.results import json_number as _json_number


class Commands:
    """A module's subcommands: ``command = Commands()``, ``@command(name, help)`` on each argument
    builder (it sets the run function), ``register = command.register``."""

    def __init__(self):
        self.entries: list = []

    def __call__(self, name: str, help: str):
        def wrap(add):
            self.entries.append((name, help, add))
            return add
        return wrap

    def register(self, sub) -> None:
        for name, help_, add in self.entries:
            p = sub.add_parser(name, help=help_, description=help_)
            add(p)


def _model_arguments(p) -> None:
    p.add_argument("model", nargs="?", help="a generated model's name (one of generated/) or a folder "
                                            "written by `adbgen regenerate --out`")
    p.add_argument("--scene", help="scene file (TOML): its smallest exact model, generated once into a cache")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="a parameter by name (repeatable); VALUE a number or an expression in pi")


def _load(args):
    return load_model(args.model, scene=args.scene)


def _finite_positive(text: str) -> float:
    import argparse

    from ..analysis.loading import parse_value

    try:
        value = parse_value(text)
    except AnalysisError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def _emit_json(obj) -> None:
    print(json.dumps(obj, allow_nan=False, default=_json_number))


