"""The documentation tests: this folder's helpers (site_helpers.py) on sys.path, as pytest runs with
--import-mode=importlib; the built site once per run."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

import site_helpers  # noqa: E402


@pytest.fixture(scope="session")
def site(tmp_path_factory, worker_id):
    """(output folder, {"returncode", "stdout", "stderr"}) of `adbgen docs --out DIR`, built once per run
    (the pytest-xdist workers share the folder above their own temporary folders)."""
    site_helpers.require_docs_extra()
    base = tmp_path_factory.getbasetemp()
    shared = (base if worker_id == "master" else base.parent) / "adbgen-docs-site"
    return site_helpers.build_site(shared)
