"""The family's science runs generated models on the compiled engines, which gcc builds."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from toolchain import require_tool


@pytest.fixture(autouse=True)
def _needs_gcc():
    require_tool(shutil.which("gcc") is not None, "gcc")


DOCUMENT = Path(__file__).resolve().parents[4] / "docs" / "reproduction.md"


@pytest.fixture
def published_section():
    """`published_section(heading)`: the lines of the committed docs/reproduction.md from the line `heading` up to
    the next heading of its level or above (the templates' tests compare what they render from fixed inputs with it)."""
    lines = DOCUMENT.read_text().splitlines()

    def section(heading: str, before: int = 0) -> list[str]:
        """`before`: that many lines above the heading too (a part's opening written before its first heading)."""
        at = lines.index(heading)
        level = len(heading.split(" ")[0])
        end = next((k for k in range(at + 1, len(lines))
                    if lines[k].startswith("#") and len(lines[k].split(" ")[0].strip("#")) == 0
                    and len(lines[k].split(" ")[0]) <= level), len(lines))
        return lines[at - before:end]

    return section
