"""Where commands write: output paths checked before any work starts, files written whole or not at all.

    output_folder(path, "--out")       refuse a file, an unwritable or read-only place, in one line
    output_file(path, "--out")         the same for a file to be (re)written
    writing(path)                      a temporary file beside `path`, renamed onto it when complete
    save_figure(fig, path)             a matplotlib figure through `writing`
    cache_dir()                        where compiled engines, proofs and scene models are cached

A command checks its outputs first (`adbgen simulate --out afile` fails at once, not after the
integration), and writes each file through a temporary name, so a failure or a kill never leaves a
half-written file in place of a good one.  Only the standard library is imported here.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from .cli_types import UsageError


def _nearest_existing(path: Path) -> Path:
    for candidate in (path, *path.parents):
        try:
            if candidate.exists() or candidate.is_symlink():
                return candidate
        except OSError:  # a name too long, a loop of links: not there
            continue
    return Path(".")


def _probe(folder: Path) -> str | None:
    """Why nothing can be created in `folder` (None: it can): tried, since permission bits do not
    tell root about read-only file systems."""
    try:
        fd, name = tempfile.mkstemp(prefix=".adbgen-probe-", dir=folder)
    except OSError as exc:
        return exc.strerror or str(exc)
    os.close(fd)
    os.unlink(name)
    return None


def _check_names(path: Path, option: str) -> Path:
    """The nearest existing folder of `path`, once no name in `path` is longer than the file system takes."""
    existing = _nearest_existing(path)
    try:
        limit = os.pathconf(existing if existing.is_dir() else existing.parent, "PC_NAME_MAX")
    except (OSError, ValueError):
        limit = 255
    for part in path.parts:
        if len(os.fsencode(part)) > limit:
            raise UsageError(f"{option}: a name in the path is longer than {limit} bytes: {part[:20]}...")
    return existing


def output_folder(path, option: str = "--out") -> Path:
    """`path` as a folder this process can create and write into (it need not exist yet)."""
    if str(path).strip() == "":
        raise UsageError(f"{option}: empty path")
    path = Path(path)
    existing = _check_names(path, option)
    if existing == path and not path.is_dir():
        raise UsageError(f"{option} {path}: is a file, not a folder")
    if not existing.is_dir():
        raise UsageError(f"{option} {path}: {existing} is a file, not a folder")
    why = _probe(existing)
    if why:
        raise UsageError(f"{option} {path}: cannot write in {existing} ({why})")
    return path


def output_file(path, option: str = "--out") -> Path:
    """`path` as a file this process can (re)write: not a folder, its folder creatable and writable."""
    if str(path).strip() == "":
        raise UsageError(f"{option}: empty path")
    path = Path(path)
    if path.name in ("", ".", ".."):
        raise UsageError(f"{option}: not a file name: {str(path)!r}")
    _check_names(path, option)
    if path.is_dir():
        raise UsageError(f"{option} {path}: is a folder, not a file")
    output_folder(path.parent, option)
    return path


@contextlib.contextmanager
def writing(path, mode: str = "w"):
    """Open a temporary file beside `path`; on success it replaces `path` (atomic rename), on any
    failure it is removed and `path` stays as it was."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, mode) as fh:
            yield fh
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def write_text(path, text: str) -> Path:
    with writing(path) as fh:
        fh.write(text)
    return Path(path)


def save_figure(fig, path, dpi: int = 120) -> Path:
    """Write a matplotlib figure whole (its format from the suffix) and close it."""
    import matplotlib.pyplot as plt

    path = Path(path)
    try:
        with writing(path, "wb") as fh:
            fig.savefig(fh, dpi=dpi, format=path.suffix.lstrip(".") or "png")
    finally:
        plt.close(fig)
    return path


def cache_dir() -> Path:
    """$ADBGEN_CACHE, else $XDG_CACHE_HOME/adbgen, else ~/.cache/adbgen."""
    base = os.environ.get("ADBGEN_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "adbgen")
    return Path(base)
