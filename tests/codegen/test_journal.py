"""The write step of `adbgen regenerate` (issue 24 item 4): generated/ is replaced as a whole.

A process SIGKILLed at 20 random points of the write phase leaves a tree that, after the next run's
recovery, is either entirely the old one or entirely the new one (what `regenerate --check` decides:
`stale` is `journal.changes`); the killed runs are real processes killed by the test hook of
`journal` at a chosen step.  And a model folder whose files carry different SOURCE_HASHes is refused
when loaded.
"""

from __future__ import annotations

import json
import os
import random
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from adbgen.codegen import journal
from adbgen.codegen.regenerate import render_all
from adbgen.families.single_plane import models

ADBGEN = [sys.executable, "-m", "adbgen.cli"]
WRITE = ("import json, sys; from adbgen.codegen import journal; "
         "journal.write(json.load(open(sys.argv[1])), sys.argv[2], prune=True)")


def tree(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and "__pycache__" not in p.parts}


@pytest.fixture(scope="module")
def versions(tmp_path_factory):
    """Two renderings of three small models (loops, unrolled: every code file differs, the index and
    README do not), as JSON files a subprocess writes from, and the old tree on disk."""
    base = tmp_path_factory.mktemp("journal")
    specs = [models.thesis_rotating(2), models.thesis_rotating(3), models.single_plane_fixed(2)]
    out = {}
    for form in ("loops", "unrolled"):
        files = render_all(specs, ("numba", "c", "cvode"), run_checks=False, form=form).files
        path = base / f"{form}.json"
        path.write_text(json.dumps(files))
        out[form] = (files, path)
    old = base / "old"
    journal.write(out["loops"][0], old)
    (old / "thesis_rotating_n2" / "__pycache__").mkdir()
    (old / "thesis_rotating_n2" / "__pycache__" / "cache.nbi").write_bytes(b"numba's index")
    (old / "stray.txt").write_text("not generated: pruned by the new tree")
    return out, old


def _write(src: Path, out: Path, **env) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", WRITE, str(src), str(out)], capture_output=True, text=True,
                          timeout=120, env=dict(os.environ, **env))


def test_the_write_is_whole_and_keeps_caches(versions, tmp_path):
    (old_files, _), (new_files, new_json) = versions[0]["loops"], versions[0]["unrolled"]
    out = tmp_path / "gen"
    shutil.copytree(versions[1], out)
    log = tmp_path / "steps.log"
    r = _write(new_json, out, **{journal.STEP_LOG: str(log)})
    assert r.returncode == 0, r.stderr
    assert tree(out) == {k: v.encode() for k, v in new_files.items()}
    assert (out / "thesis_rotating_n2" / "__pycache__" / "cache.nbi").read_bytes() == b"numba's index"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["gen", "steps.log"]
    steps = log.read_text().splitlines()
    assert steps[-4:] == [f"{len(steps) - 3} old tree moved aside", f"{len(steps) - 2} new tree in place",
                          f"{len(steps) - 1} journal removed", f"{len(steps)} old tree deleted"]
    # unchanged files are hard links of the old ones (no copy), changed ones written fresh
    assert journal.changes(new_files, out, prune=True) == {}
    assert journal.changes(old_files, out, prune=True) != {}


def test_sigkill_at_20_random_points_of_the_write_phase_leaves_old_or_new(versions, tmp_path):
    (old_files, _), (new_files, new_json) = versions[0]["loops"], versions[0]["unrolled"]
    log = tmp_path / "count.log"
    first = tmp_path / "count"
    shutil.copytree(versions[1], first)
    assert _write(new_json, first, **{journal.STEP_LOG: str(log)}).returncode == 0
    n_steps = len(log.read_text().splitlines())
    assert n_steps >= 25  # links, writes, caches, journal, renames: enough points to kill at
    points = sorted(random.Random(24).sample(range(1, n_steps + 1), 20))
    outcomes = {}
    for k in points:
        out = tmp_path / f"kill{k}" / "gen"
        shutil.copytree(versions[1], out)
        r = _write(new_json, out, **{journal.KILL_AT_STEP: str(k)})
        assert r.returncode == -signal.SIGKILL, (k, r.returncode, r.stderr)
        what = journal.recover(out)
        old = journal.changes(old_files, out, prune=False) == {} and (out / "stray.txt").exists()
        new = journal.changes(new_files, out, prune=True) == {}
        assert old != new, f"killed at step {k}: the tree is {'both' if old else 'neither'} old and new ({what})"
        outcomes[k] = "new" if new else "old"
        assert sorted(p.name for p in out.parent.iterdir()) == ["gen"], k
    # the kills fell on both sides of the swap
    assert set(outcomes.values()) == {"old", "new"}, outcomes


def test_a_killed_regenerate_is_finished_by_the_next_check(versions, tmp_path):
    """End to end: `adbgen regenerate` killed inside its swap; the next `regenerate --check` rolls the
    swap forward, reports it, and finds the tree current."""
    out = tmp_path / "gen"
    shutil.copytree(versions[1], out)
    (out / "stray.txt").unlink()
    log = tmp_path / "steps.log"
    common = ["--n", "2", "--family", "single-plane", "--targets", "numba", "c", "--skip-checks", "--quiet",
              "--out", str(out)]
    r = subprocess.run(ADBGEN + ["regenerate", "--form", "unrolled"] + common, capture_output=True, text=True,
                       timeout=600, env=dict(os.environ, **{journal.STEP_LOG: str(log)}))
    assert r.returncode == 0, r.stderr
    swap = next(int(line.split()[0]) for line in log.read_text().splitlines() if line.endswith("old tree moved aside"))
    r = subprocess.run(ADBGEN + ["regenerate"] + common, capture_output=True, text=True, timeout=600,
                       env=dict(os.environ, **{journal.KILL_AT_STEP: str(swap)}))
    assert r.returncode == -signal.SIGKILL and not out.exists()  # killed between the two renames
    r = subprocess.run(ADBGEN + ["regenerate", "--check"] + common, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "was rolled forward" in r.stderr and out.is_dir()


def test_stale_staging_folders_of_before_are_removed(tmp_path):
    out = tmp_path / "gen"
    out.mkdir()
    (tmp_path / ".gen-staging-abc123").mkdir()
    (tmp_path / ".gen.adbgen-new").mkdir()  # a new tree without a journal: incomplete, garbage
    assert journal.recover(out) == "cleaned"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["gen"]
    assert journal.recover(out) is None


def test_a_model_whose_files_disagree_is_refused(tmp_path, capsys):
    from adbgen.analysis.loading import AnalysisError, load_model
    from adbgen.cli import main

    src = Path(load_model("thesis_rotating_n2").folder)
    out = tmp_path / "models" / "thesis_rotating_n2"
    shutil.copytree(src, out, ignore=shutil.ignore_patterns("__pycache__"))
    assert load_model(str(out)).name == "thesis_rotating_n2"  # negative control: a whole copy loads
    c_file = out / "thesis_rotating_n2.c"
    c_file.write_text(c_file.read_text().replace(journal.file_hash(c_file), "0123456789abcdef", 1))
    with pytest.raises(AnalysisError, match=r"thesis_rotating_n2.c \(0123456789abcdef\)"):
        load_model(str(out))
    assert main(["simulate", str(out), "--t-end", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "different runs of `adbgen regenerate`" in err
