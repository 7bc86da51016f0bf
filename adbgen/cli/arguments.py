"""What the commands over generated models share: the model arguments, loading, positive numbers, a pair of
quantities A:B (`quantity_pair`: --range2, --scan, design's LOW:HIGH), JSON output, and `Commands`, the
per-module list of subcommands (`@command(name, help)` on the argument builder; the module's
`register = command.register` adds them to `adbgen`'s parser).
"""

from __future__ import annotations

import json

from ..analysis.loading import AnalysisError, load_model
from ..analysis.results import json_number as _json_number
from ..analysis.results import plain as _plain
from ..cli_types import count as _positive_int  # noqa: F401  (the commands' whole numbers >= 1)


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

    from ..analysis.units import check_syntax

    def check(text: str) -> str:
        try:
            return check_syntax(text, option)
        except AnalysisError as exc:
            raise argparse.ArgumentTypeError(str(exc).removeprefix(f"{option}: ")) from None
    check.__name__ = "quantity"
    return check


def quantity_pair(text: str, unit: str, option: str, form: str, labels: tuple[str, str]) -> tuple[float, float]:
    """``A:B`` (--range2 LO:HI, --scan NAME=FROM:TO, design's LOW:HIGH) -> the two values in `unit`, each a
    number in it, an expression in pi or a value with a unit (`units.quantity`, its errors named by `labels`);
    no colon: "OPTION: expected FORM".  The order each option asks of A and B is its caller's."""
    from ..analysis.units import quantity

    a, sep, b = str(text).partition(":")
    if not sep:
        raise AnalysisError(f"{option}: expected {form}, got {text!r}")
    return quantity(a, unit, labels[0]), quantity(b, unit, labels[1])


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
    print(json.dumps(_plain(obj), allow_nan=False, default=_json_number))


