"""`adbgen reproduce [--out FILE] [--figures DIR] [--only SECTION ...]`: every family's reproductions
(`Family.reproductions()`, in the order of the family registry) recomputed into one document, by default
docs/reproduction.md with its figures in docs/reproduction/ (`adbgen.analysis.reproduction`)."""

from __future__ import annotations

from .. import families
from ..analysis.reproduction import Reproduction, build
from ..registry import load


def references() -> dict[str, str]:
    """Every section key -> "module:attribute" of its Reproduction, family by family (nothing imported); a
    section two families share (one derived from the other) counts once."""
    out: dict[str, str] = {}
    for family in families.all_families():
        hook = getattr(family, "reproductions", None)
        for key, ref in (hook() if hook else {}).items():
            if out.get(key, ref) != ref:
                raise ValueError(f"two reproduction sections named {key!r} (family {family.name!r})")
            out[key] = ref
    return out


def sections() -> list[Reproduction]:
    return [load(ref) for ref in references().values()]


def _pinned_rerun(args, only: tuple[str, ...]) -> int:
    """The same command in a child process with glibc's libm variants pinned (see
    `reproduction.PINNED_HWCAPS`): glibc reads its tunables only when a process starts."""
    import subprocess
    import sys

    from ..analysis.reproduction import pinned_environment

    cmd = [sys.executable, "-m", "adbgen.cli", "reproduce", "--only", *only]
    cmd += ["--out", str(args.out)] if args.out else []
    cmd += ["--figures", str(args.figures)] if args.figures else []
    cmd += ["--quiet"] if args.quiet else []
    return subprocess.call(cmd, env=pinned_environment())


def run_reproduce(args) -> int:
    from ..analysis.engines.compiled import libm
    from ..analysis.loading import AnalysisError
    from ..analysis.reproduction import environment_pinned
    from ..outputs import output_file, output_folder
    from ..progress import activity, wanted

    keys = tuple(references())
    only = tuple(k for k in keys if k in args.only)
    every = only == keys
    if libm() != "sleef-cinz":
        raise AnalysisError("adbgen reproduce needs the compiled engines' pinned libm (SLEEF; apt-get install "
                            "libsleef-dev): without it the document depends on the processor")
    # the outputs are checked here, before a pinned child process would start the long work
    out = output_file(args.out or ("docs/reproduction.md" if every else f"docs/reproduction-{'-'.join(only)}.md"),
                      "--out")
    figs = output_folder(args.figures if args.figures else out.parent / "reproduction", "--figures")
    if not environment_pinned():
        return _pinned_rerun(args, only)
    command = "adbgen reproduce" + ("" if every else f" --only {' '.join(only)}")
    with activity("reproduce: " + ", ".join(only), wanted(args.quiet)) as note:
        def progress(line: str) -> None:
            print(line, flush=True)
            note(f"reproduce, after: {line.strip()[:60]}")
        path = build(sections(), only, out, figs, command, progress=progress)
    print(f"wrote {path}")
    return 0


def register(sub) -> None:
    keys = list(references())
    help_ = "recompute the published results (every family's: " + ", ".join(keys) + ") into docs/reproduction.md"
    p = sub.add_parser("reproduce", help=help_, description=help_)
    p.add_argument("--out", default=None, help="the document (default docs/reproduction.md; with --only a part, "
                                               "docs/reproduction-PART.md, so the whole document is kept)")
    p.add_argument("--figures", default=None, help="figure folder (default: docs/reproduction/ beside it)")
    p.add_argument("--only", nargs="+", choices=keys, default=keys, metavar="SECTION",
                   help=f"compute only these sections ({', '.join(keys)}); default all")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(fn=run_reproduce)
