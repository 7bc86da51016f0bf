"""The long prose of the two-plane paper's reproduction sections as Markdown/jinja2 templates (package data,
`*.md.j2` beside this file; issue 33 item 6): the science modules compute and pass numbers, the words are here.
Read as every Markdown template of the package is (`analysis.prose`: its convention, `{##}` ends a line that
goes on in the next).

    render(name, **values) -> list of markdown lines
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

from .....analysis.prose import environment, read

FOLDER = Path(__file__).parent


@lru_cache(maxsize=1)
def _environment():
    return environment(FOLDER)


def render(name: str, **values) -> list[str]:
    """The template `name` (without .md.j2) rendered with `values`, as lines (analysis.prose)."""
    return read(_environment(), name, values)


__all__ = ["render"]
