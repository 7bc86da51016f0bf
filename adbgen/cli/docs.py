"""`adbgen docs [--out DIR] [--jobs N]`: build the documentation site (`adbgen.docsite`), warnings as errors."""

from __future__ import annotations

import sys
import time
from pathlib import Path

from ..cli_types import positive_int
from ..docsite import DEFAULT_OUT, build, root


def cmd_docs(args) -> int:
    out = Path(args.out) if args.out else root() / DEFAULT_OUT
    t0 = time.perf_counter()
    code = build(out, jobs=args.jobs)
    seconds = time.perf_counter() - t0
    if code != 0:
        print(f"adbgen docs: the build failed (Sphinx exit status {code}; the warnings above); "
              f"{out} left as it was", file=sys.stderr)
        return 1
    print(f"built {out / 'index.html'} in {seconds:.1f} s (no warnings)")
    return 0


def register(sub) -> None:
    p = sub.add_parser("docs", help="build the documentation site (Sphinx, warnings as errors)")
    p.add_argument("--out", metavar="DIR", default=None,
                   help="output folder (default: docs/_build/html of this checkout; replaced only when the build passes)")
    p.add_argument("--jobs", type=positive_int, default=1, help="Sphinx processes (default 1)")
    p.set_defaults(fn=cmd_docs)
