"""adbgen.progress: tqdm on stderr after two seconds, off with --quiet, --json or no terminal (item 6)."""

from __future__ import annotations

import io
import json
import subprocess
import sys
import time

from adbgen import progress


def test_wanted(monkeypatch):
    monkeypatch.delenv(progress.FORCE, raising=False)
    monkeypatch.setattr(sys, "stderr", io.StringIO())  # not a terminal
    assert not progress.wanted()
    monkeypatch.setenv(progress.FORCE, "1")
    assert progress.wanted() and not progress.wanted(quiet=True) and not progress.wanted(json=True)


def test_a_quick_step_prints_nothing_a_slow_one_a_bar(monkeypatch):
    monkeypatch.delenv(progress.FORCE, raising=False)
    monkeypatch.setattr(progress, "DELAY", 0.3)
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    with progress.bar(10, "quick", True) as update:
        update(10)
    with progress.activity("quick", True):
        time.sleep(0.05)
    assert err.getvalue() == ""
    with progress.bar(10, "slow scan", True) as update:
        time.sleep(0.4)
        update(1)
        time.sleep(0.2)  # tqdm redraws at most every 0.1 s
        update(5)
    with progress.activity("slow call", True) as note:
        time.sleep(1.0)
        note("still at it")
        time.sleep(0.7)
    text = err.getvalue()
    assert "slow scan:  50%" in text and "slow call" in text and "still at it" in text


def test_a_long_scan_shows_progress_on_stderr_and_json_stays_clean():
    """End to end: a scan longer than the delay, forced progress (not a terminal here)."""
    cmd = [sys.executable, "-m", "adbgen.cli", "stability", "thesis_rotating_n2", "--scan", "Omega=4:0.5"]
    env = {**__import__("os").environ, progress.FORCE: "1"}
    r = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 0 and "thesis_rotating_n2: Omega from 4 to 0.5" in r.stderr and "%|" in r.stderr
    assert "stable for Omega in" in r.stdout and "%|" not in r.stdout
    r = subprocess.run(cmd + ["--json"], capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 0 and r.stderr == "" and json.loads(r.stdout)["complete"] is True
