"""The derivation notebooks in derive/ run to the end (their asserts are checks)."""

import runpy
from pathlib import Path

import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "derive").glob("*.py"))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_runs(path, capsys):
    runpy.run_path(str(path), run_name="__main__")
    assert "Omega_c1" in capsys.readouterr().out or path.name != "single_plane.py"


def test_there_are_notebooks():
    assert NOTEBOOKS
