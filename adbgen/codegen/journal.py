"""The write step of `adbgen regenerate`: the output folder is replaced as a whole, or not at all.

    write(rendered, out)   build the new tree in a sibling folder, then swap it in with two renames
    recover(out)           finish (or undo) a swap an earlier run was killed in; clear its leftovers
    mismatched(folder, h)  the files of a model folder whose SOURCE_HASH is not its module's

The new tree is built beside `out` in `.<out>.adbgen-new` (unchanged files hard-linked from `out`,
with their `__pycache__` so numba's and Python's caches stay valid; changed files written fresh).
Only when it is complete is the journal `.<out>.adbgen-journal` written (atomically: a temporary file
renamed); then `out` is renamed to `.<out>.adbgen-old`, the new tree to `out`, the journal removed and
the old tree deleted.  A process killed at any point leaves one of:

* no journal: `out` untouched (a half-built new tree or a fully swapped-out old tree may remain; both
  are garbage and `recover` deletes them);
* a journal: the new tree is complete, so `recover` rolls the swap forward (the renames not yet done),
  or back (`.<out>.adbgen-old` renamed to `out`) in the one state where the new tree is gone and
  `out` is missing.

`recover` runs at the start of every `adbgen regenerate` (with `--check` too: it decides on the
finished tree) and when the analysis layer loads a model from the folder.  An flock on the folder
holding `out` keeps two runs from swapping one folder at once.  This guards against
a killed process, not a power loss (nothing is fsync'ed but the journal).

Only the standard library is imported here: the analysis layer calls `recover` without SymPy.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import re
import shutil
import signal
from pathlib import Path

IGNORED_DIRS = {"__pycache__"}
# test hooks (tests/codegen/test_journal.py): SIGKILL this process at write step K (1-based), and/or
# append each step's name to a file, so a test can kill the write phase at chosen points
KILL_AT_STEP = "ADBGEN_TEST_KILL_AT_STEP"
STEP_LOG = "ADBGEN_TEST_STEP_LOG"


class _Steps:
    def __init__(self):
        self.count = 0
        self.kill_at = int(os.environ.get(KILL_AT_STEP, "0") or 0)
        self.log = os.environ.get(STEP_LOG)

    def __call__(self, name: str) -> None:
        self.count += 1
        if self.log:
            with open(self.log, "a") as fh:
                fh.write(f"{self.count} {name}\n")
        if self.count == self.kill_at:
            os.kill(os.getpid(), signal.SIGKILL)


def paths(out: Path) -> dict[str, Path]:
    """The sibling paths of `out` the write step uses."""
    out = Path(out)
    stem = f".{out.name}.adbgen-"
    return {kind: out.parent / (stem + kind) for kind in ("new", "old", "journal")}


@contextlib.contextmanager
def _locked(out: Path):
    """An exclusive flock on the folder that holds `out` (a directory can be locked on Linux; no lock
    file is left behind in a checkout)."""
    out.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(out.parent, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # closing releases the lock


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    elif path.exists() or path.is_symlink():
        path.unlink(missing_ok=True)


def _recover_locked(out: Path) -> str | None:
    p = paths(out)
    new, old, journal = p["new"], p["old"], p["journal"]
    done = None
    if journal.is_file():
        try:
            entry = json.loads(journal.read_text())
        except (OSError, ValueError):
            entry = {}
        if entry.get("phase") == "swap" and new.is_dir():  # the new tree is complete: roll forward
            if out.exists() and not old.exists():
                os.replace(out, old)
            if not out.exists():
                os.replace(new, out)
            done = "rolled forward"
        elif not out.exists() and old.is_dir():  # no new tree and no output: put the old one back
            os.replace(old, out)
            done = "rolled back"
        else:  # the swap had finished; only the journal and the old tree were left
            done = "finished"
        journal.unlink(missing_ok=True)
    for leftover in (new, old, journal.with_name(journal.name + ".tmp")):
        if leftover.exists():
            _remove(leftover)
            done = done or "cleaned"
    # staging folders of the write step before the journal (`.<out>-staging-*`)
    for staging in out.parent.glob(f".{out.name}-staging-*"):
        _remove(staging)
        done = done or "cleaned"
    return done


def recover(out: Path) -> str | None:
    """Finish or undo an interrupted swap of `out` and delete leftovers; returns what was done
    ("rolled forward", "rolled back", "finished", "cleaned") or None when there was nothing to do."""
    out = Path(out)
    p = paths(out)
    if not any(x.exists() for x in p.values()) and not any(out.parent.glob(f".{out.name}-staging-*")):
        return None  # the common case: nothing to do, no lock taken
    with _locked(out):
        return _recover_locked(out)


def _files(folder: Path) -> dict[str, Path]:
    """Every file under `folder` by relative path, __pycache__ and .pyc excluded."""
    found = {}
    if folder.is_dir():
        for path in folder.rglob("*"):
            rel = path.relative_to(folder)
            if path.is_file() and not (set(rel.parts) & IGNORED_DIRS) and path.suffix != ".pyc":
                found[rel.as_posix()] = path
    return found


def changes(files: dict[str, str], out: Path, prune: bool) -> dict[str, str]:
    """{relative path: 'missing' | 'differs' | 'not generated'} of `out` against the rendered `files`
    ('not generated' only with `prune`)."""
    have = _files(out)
    report = {}
    for rel, text in sorted(files.items()):
        if rel not in have:
            report[rel] = "missing"
        elif have[rel].read_bytes() != text.encode():
            report[rel] = "differs"
    for rel in sorted(set(have) - set(files)) if prune else ():
        report[rel] = "not generated"
    return report


def _link_or_copy(src: Path, dst: Path) -> None:
    dst.parent.mkdir(parents=True, exist_ok=True)
    try:
        os.link(src, dst)
    except OSError:  # another file system or no hard links: a copy with its time stamps
        shutil.copy2(src, dst)


def write(files: dict[str, str], out: Path, prune: bool = True) -> list[str]:
    """Replace `out` by a tree holding `files` (relative path -> text), all at once; returns the paths
    that changed.  Files of `out` that were not rendered are dropped with `prune` and kept otherwise."""
    out = Path(out)
    steps = _Steps()
    with _locked(out):
        note = _recover_locked(out)
        if note:
            steps("recover")
        report = changes(files, out, prune)
        if not report:
            return []
        p = paths(out)
        new, old, journal = p["new"], p["old"], p["journal"]
        new.mkdir()
        steps("new folder")
        for rel, path in _files(out).items():
            if report.get(rel) in ("differs", "not generated"):
                continue
            _link_or_copy(path, new / rel)
            steps(f"link {rel}")
        for rel, status in report.items():
            if status in ("missing", "differs"):
                target = new / rel
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_bytes(files[rel].encode())
                steps(f"write {rel}")
        if out.is_dir():  # the caches of folders that stay (numba's index checks the source's time stamp)
            for cache in out.rglob("__pycache__"):
                rel = cache.relative_to(out)
                if (new / rel).parent.is_dir():
                    for f in cache.iterdir():
                        if f.is_file():
                            _link_or_copy(f, new / rel / f.name)
                    steps(f"cache {rel}")
        tmp = journal.with_name(journal.name + ".tmp")
        with open(tmp, "w") as fh:
            json.dump({"phase": "swap", "out": str(out), "new": str(new), "old": str(old)}, fh)
            fh.flush()
            os.fsync(fh.fileno())
        steps("journal written")
        os.replace(tmp, journal)
        steps("journal in place")
        if out.exists():
            os.replace(out, old)
            steps("old tree moved aside")
        os.replace(new, out)
        steps("new tree in place")
        journal.unlink()
        steps("journal removed")
        shutil.rmtree(old, ignore_errors=True)
        steps("old tree deleted")
    return [rel for rel in report]


# --- a model folder whose files come from one run -----------------------------------------------------

_HASH = re.compile(rb"SOURCE_HASH\W{0,4}([0-9a-f]{8,64})")


def file_hash(path: Path) -> str | None:
    """The SOURCE_HASH a generated file's header carries (None: no header hash)."""
    with open(path, "rb") as fh:
        m = _HASH.search(fh.read(4096))
    return m.group(1).decode() if m else None


def mismatched(folder: Path, expected: str) -> dict[str, str]:
    """{file: its hash} of the files of a model folder whose SOURCE_HASH is not `expected` (the
    numba module's).  The files of auto/ belong to the model's autonomous extension, another
    intermediate form: they must agree among themselves."""
    folder = Path(folder)
    bad = {}
    groups = [([p for p in folder.iterdir() if p.is_file()], expected)]
    auto = folder / "auto"
    if auto.is_dir():
        files = sorted(p for p in auto.iterdir() if p.is_file())
        first = next((h for h in map(file_hash, files) if h), None)
        groups.append((files, first))
    for files, want in groups:
        for path in files:
            got = file_hash(path)
            if got is not None and got != want:
                bad[path.relative_to(folder).as_posix()] = got
    return bad
