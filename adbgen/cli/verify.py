"""`adbgen verify [--n N ...] [--model FAMILY|all]`: every registered family's checks, one line each,
non-zero exit on a failure (`adbgen.families.verification`)."""

from __future__ import annotations

from ..cli_types import positive_int
from ..families import all_families, get, names
from ..families.verification import run_verify


def cmd_verify(args) -> int:
    chosen = all_families() if args.model == "all" else (get(args.model),)
    return run_verify(chosen, args.n)


def register(sub) -> None:
    v = sub.add_parser("verify", help="check every reduction against the references, every family")
    v.add_argument("--n", type=positive_int, nargs="+", default=[1, 2, 3, 4, 6],
                   help="numbers of balls for the checks that take one (single-plane)")
    v.add_argument("--model", choices=names() + ("all",), default="all", help="one family, or all")
    v.set_defaults(fn=cmd_verify)
    from ..families.scene_reference import register as register_scenes

    register_scenes(sub)
