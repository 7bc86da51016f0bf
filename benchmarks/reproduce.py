"""Benchmark (not a test): the whole `adbgen reproduce`, timed, and its document compared with the committed
one (issue 23).  `adbgen bench reproduce [--out FILE] [--sections SECTION ...] [--emulate-older]
[--keep DIR]`
-> ``benchmarks/reproduce.json``.

The command runs in a child process (as a user runs it: it re-runs itself with glibc's libm variants
pinned) into a temporary folder, never into docs/.  Recorded: the wall time and the child's CPU time, the
time at which each progress line arrived (which parts are slow), the load average before and after, and
whether the document and each figure are byte-identical to the committed docs/reproduction.md and
docs/reproduction/*.png (the second-run check of "byte-identical on a second run"; with
``--emulate-older`` glibc's AVX variants are masked as well, a processor without AVX: the second-machine
check).  With ``--sections`` only those sections run (a partial document, compared with nothing).
"""

from __future__ import annotations

import difflib
import hashlib
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .registry import Benchmark, option
from .report import closing, opening, write

ROOT = Path(__file__).resolve().parents[1]
DOCUMENT = ROOT / "docs" / "reproduction.md"
OLDER = ",-AVX"  # masked beside the pinned capabilities: the emulated processor has no AVX


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def snapshot(committed: Path = DOCUMENT) -> dict:
    """The committed document's text and its figures' digests, read before a run (a run kept into docs/
    overwrites them)."""
    figures = committed.parent / "reproduction"
    return {"text": committed.read_bytes() if committed.is_file() else b"",
            "figures": {p.name: _digest(p) for p in _figure_files(figures)} if figures.is_dir() else {}}


def _figure_files(folder: Path) -> list[Path]:
    """The figures and the data written beside them (the charts' curves as .json)."""
    return sorted(p for p in folder.iterdir() if p.suffix in (".png", ".json"))


def relocated(text: str, written_in: Path, docs: Path = DOCUMENT.parent) -> str:
    """The document as `adbgen reproduce` would have written it into docs/: its links to the documentation
    pages are relative to the folder it is written in (`[Periodic orbits](../../x/docs/orbits.md)` from a
    temporary folder, `(./orbits.md)` in docs/), the only text that depends on where it is written; the
    figures' links are relative to their own folder beside the document and do not change."""
    rel = Path(os.path.relpath(docs, written_in)).as_posix()
    return text if rel == "." else text.replace(f"]({rel}/", "](./")


def compare(document: Path, figures: Path, committed: Path | dict = DOCUMENT, docs: Path = DOCUMENT.parent) -> dict:
    """The written document and figures against the committed ones (a path, or its `snapshot` taken before
    the run): identical or not, the lines that differ (first ten, as (line number, committed, new)), the
    figures that differ or are missing.  The document is compared as written into docs/ (`relocated`)."""
    before = committed if isinstance(committed, dict) else snapshot(committed)
    text = relocated(document.read_text(), document.parent, docs)
    new, old = text.splitlines(), before["text"].decode().splitlines()
    # matched as a diff does (an inserted line does not make every later line "differ"): each changed
    # stretch counts its longer side, reported at its first line (new document's numbering)
    differ, count = [], 0
    for op, i1, i2, j1, j2 in difflib.SequenceMatcher(None, old, new, autojunk=False).get_opcodes():
        if op != "equal":
            count += max(i2 - i1, j2 - j1)
            differ.append((j1 + 1, old[i1] if i1 < i2 else "", new[j1] if j1 < j2 else ""))
    figs = [p.name for p in _figure_files(figures)]
    changed = [name for name in figs if before["figures"].get(name) != _digest(figures / name)]
    return {"document_identical": new == old and text.encode() == before["text"],
            "lines": len(new), "committed_lines": len(old), "lines_differing": count,
            "first_differences": differ[:10], "figures": len(figs),
            "figures_differing": changed}


def run_reproduce(folder: Path, sections=None, emulate_older: bool = False, progress=print) -> dict:
    """`adbgen reproduce` in a child process writing into `folder`: wall and CPU seconds, the progress
    lines with the seconds at which they came, the exit status."""
    from adbgen.analysis.reproduction import pinned_environment

    env = pinned_environment({k: v for k, v in os.environ.items() if k != "GLIBC_TUNABLES"})
    if emulate_older:
        env["GLIBC_TUNABLES"] += OLDER
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in [os.environ.get("PYTHONPATH")] if p])
    cmd = [sys.executable, "-m", "adbgen.cli", "reproduce", "--quiet", "--out", str(folder / "reproduction.md")]
    cmd += ["--only", *sections] if sections else []
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    lines = []
    with subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, text=True, cwd=ROOT) as proc:
        for line in proc.stdout:
            lines.append((round(time.perf_counter() - start, 1), line.rstrip()))
            progress(f"[{lines[-1][0]:8.1f} s] {line.rstrip()}")
    wall = time.perf_counter() - start
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (cpu1.ru_utime - cpu0.ru_utime) + (cpu1.ru_stime - cpu0.ru_stime)
    return {"command": " ".join(["adbgen", *cmd[3:]]), "glibc_tunables": env["GLIBC_TUNABLES"],
            "exit_status": proc.returncode, "wall_s": round(wall, 1), "cpu_s": round(cpu, 1), "progress": lines}


def bench_reproduce(sections=None, emulate_older: bool = False, progress=print, keep: Path | None = None) -> dict:
    """The timed run and the comparison; the document is written into `keep` (kept) or a temporary folder."""
    result, started = opening("reproduce")
    with tempfile.TemporaryDirectory(prefix="adbgen-bench-reproduce-") as tmp:
        folder = Path(keep) if keep else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        before = snapshot()  # before the run: --keep docs/ writes over the committed document
        result["run"] = run_reproduce(folder, sections, emulate_older, progress)
        result["emulated_older_processor"] = emulate_older
        document = folder / "reproduction.md"
        if result["run"]["exit_status"] == 0 and not sections and DOCUMENT.is_file():
            result["against_committed"] = compare(document, folder / "reproduction", before)
    return closing(result, started)


def run(args, out: str) -> int:
    result = bench_reproduce(args.sections, args.emulate_older, progress=lambda line: print(line, flush=True),
                             keep=args.keep)
    path = write(result, out)
    same = result.get("against_committed", {}).get("document_identical")
    print(f"wrote {path}: adbgen reproduce {result['run']['wall_s']} s wall, {result['run']['cpu_s']} s CPU, "
          f"exit {result['run']['exit_status']}" + ("" if same is None else f", document identical: {same}"))
    return 0 if result["run"]["exit_status"] == 0 and same is not False else 1


BENCHMARK = Benchmark("reproduce", run, (
    option("--sections", nargs="+", default=None, metavar="SECTION",
           help="only these sections of adbgen reproduce (default: all, compared with the committed document)"),
    option("--emulate-older", action="store_true",
           help="mask glibc's AVX variants too (a processor without AVX: the second-machine check)"),
    option("--keep", default=None, metavar="DIR",
           help="write the document and its figures into DIR and keep them (default: a temporary folder)"),
))


__all__ = ["BENCHMARK", "bench_reproduce", "compare", "run_reproduce", "snapshot"]
