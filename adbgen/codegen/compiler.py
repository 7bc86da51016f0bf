"""The C toolchain the proofs of the emitted files build with (gcc, SUNDIALS CVODE, AUTO-07p's header).

Every emitted C file is compiled with `STRICT_CFLAGS` (the flags the tests use, issue 4: -Werror, so a
warning refuses the model) before anything is written; a shared library is linked with
``-Wl,--no-undefined`` so that a reference to a function nobody defines fails here rather than when a
user loads it.  A failed build raises `BuildFailed` with gcc's first diagnostic on one line.

`missing(what)` says why a tool is not usable (None: it is): regenerate then refuses to write the
files that need it (leave that target out with --targets) rather than write them unproven.
"""

from __future__ import annotations

import functools
import hashlib
import os
import shutil
import subprocess
from pathlib import Path

from ..errors import AdbgenError

# the flags for the emitted C: every target's C compiles cleanly with them (tests/codegen too)
STRICT_CFLAGS = ("-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic")
SUNDIALS_LIBS = ("-lsundials_cvode", "-lsundials_nvecserial", "-lsundials_sunmatrixdense",
                 "-lsundials_sunlinsoldense")
AUTO_DIR = Path(os.environ.get("AUTO_DIR", "/usr/lib/auto-07p"))
TIMEOUT = 300  # s per gcc run (a two-plane model's C compiles in about 1 s)


class BuildFailed(AdbgenError):
    """gcc refused an emitted file (an error or, under -Werror, a warning)."""


class ToolMissing(AdbgenError):
    """A tool a proof needs is not installed."""


@functools.lru_cache(maxsize=1)
def gcc() -> str | None:
    return shutil.which(os.environ.get("CC", "gcc")) or shutil.which("gcc")


def auto_include() -> Path | None:
    """The folder of AUTO-07p's auto_f2c.h (Debian's auto-07p: /usr/include)."""
    for folder in (AUTO_DIR / "include", Path("/usr/include")):
        if (folder / "auto_f2c.h").is_file():
            return folder
    return None


def _sundials_config() -> Path | None:
    for folder in (Path("/usr/include"), Path("/usr/local/include")):
        if (folder / "sundials" / "sundials_config.h").is_file() and (folder / "cvode" / "cvode.h").is_file():
            return folder / "sundials" / "sundials_config.h"
    return None


def missing(what: str) -> str | None:
    """Why `what` ("gcc", "sundials", "auto") cannot be used here, or None."""
    if gcc() is None:
        return "gcc not found (Debian package gcc)"
    if what == "sundials" and _sundials_config() is None:
        return "SUNDIALS CVODE headers not found (Debian package libsundials-dev)"
    if what == "auto" and auto_include() is None:
        return "AUTO-07p's auto_f2c.h not found (Debian package auto-07p)"
    return None


def require(what: str, target: str) -> None:
    why = missing(what)
    if why:
        raise ToolMissing(f"cannot prove the {target} files: {why}; install it, or leave the target out "
                          f"(--targets)")


@functools.lru_cache(maxsize=1)
def identity() -> str:
    """What a proof's verdict depends on besides the files: gcc's version and the headers compiled against."""
    h = hashlib.sha256()
    cc = gcc()
    if cc is not None:
        r = subprocess.run([cc, "--version"], capture_output=True, text=True, timeout=60)
        h.update(r.stdout.encode())
    for path in (_sundials_config(), (auto_include() or Path("/nonexistent")) / "auto_f2c.h"):
        if path is not None and path.is_file():
            h.update(path.read_bytes())
    return h.hexdigest()


def _first_diagnostic(stderr: str) -> str:
    lines = [line.strip() for line in stderr.splitlines() if line.strip()]
    for line in lines:
        if "error" in line or "warning" in line or "undefined reference" in line:
            return line
    return lines[0] if lines else "(no diagnostic)"


def run_gcc(args: list, cwd: Path, what: str) -> None:
    """gcc `args` in `cwd`; BuildFailed naming `what` unless it exits 0 with nothing on stderr."""
    cc = gcc()
    if cc is None:
        raise ToolMissing("gcc not found (Debian package gcc)")
    r = subprocess.run([cc, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=TIMEOUT)
    if r.returncode != 0 or r.stderr.strip():
        raise BuildFailed(f"{what}: gcc {' '.join(STRICT_CFLAGS)}: {_first_diagnostic(r.stderr)}")


def compile_object(source: Path, out: Path, what: str, include=(), defines=(), flags=STRICT_CFLAGS) -> Path:
    args = [*flags, "-fPIC", "-c", *(f"-I{d}" for d in include), *(f"-D{d}" for d in defines), "-o", out, source]
    run_gcc(args, out.parent, what)
    return out


def link(objects, out: Path, what: str, shared: bool, libs=()) -> Path:
    args = ["-shared", "-Wl,--no-undefined"] if shared else []
    run_gcc([*args, "-o", out, *objects, *libs, "-lm"], out.parent, what)
    return out
